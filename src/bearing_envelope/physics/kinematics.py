"""Rolling-element bearing fault frequencies from geometry.

The classical rigid-body kinematics of a bearing with a rotating inner ring and a stationary
outer ring, pure rolling (no slip):

.. math::

    \\mathrm{BPFO} = \\frac{n f_r}{2}\\left(1 - \\frac{d}{D}\\cos\\varphi\\right),\\quad
    \\mathrm{BPFI} = \\frac{n f_r}{2}\\left(1 + \\frac{d}{D}\\cos\\varphi\\right),

.. math::

    \\mathrm{FTF} = \\frac{f_r}{2}\\left(1 - \\frac{d}{D}\\cos\\varphi\\right),\\quad
    \\mathrm{BSF} = \\frac{D}{2d} f_r\\left(1 - \\left(\\frac{d}{D}\\cos\\varphi\\right)^2\\right),

with ``n`` rolling elements per row, ``d`` their diameter, ``D`` the pitch diameter, ``phi`` the
contact angle and ``f_r`` the shaft rate. The rows of a double-row bearing roll at the same
rates, so ``n`` is the count of one row.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..checks import check_positive

__all__ = ["FaultFrequencies", "fault_frequencies", "RADIAL_CONTACT_ANGLE_DEG"]

#: Contact angle (deg) when none is given: a radial (deep-groove) bearing, 0 deg.
RADIAL_CONTACT_ANGLE_DEG = 0.0


@dataclass(frozen=True)
class FaultFrequencies:
    """Characteristic bearing frequencies in Hz.

    Attributes
    ----------
    fr : float
        Shaft rotation rate (Hz).
    bpfo, bpfi : float
        Ball-pass frequencies of the outer and inner race (Hz).
    ftf : float
        Fundamental train (cage) frequency (Hz).
    bsf : float
        Ball (roller) spin frequency (Hz).
    """

    fr: float
    bpfo: float
    bpfi: float
    ftf: float
    bsf: float

    def orders(self) -> dict[str, float]:
        """Return the frequencies as multiples of the shaft rate.

        Returns
        -------
        dict of str to float
            ``{"bpfo", "bpfi", "bsf", "ftf"}`` -> frequency / shaft rate.
        """
        return {k: getattr(self, k) / self.fr for k in ("bpfo", "bpfi", "ftf", "bsf")}


def fault_frequencies(
    fr: float,
    n_rollers: int,
    roller_diameter: float,
    pitch_diameter: float,
    contact_angle_deg: float = RADIAL_CONTACT_ANGLE_DEG,
) -> FaultFrequencies:
    """Fault frequencies of a bearing with rotating inner ring.

    Parameters
    ----------
    fr : float
        Shaft rate (Hz), > 0.
    n_rollers : int
        Rolling elements per row, >= 1.
    roller_diameter : float
        Rolling-element diameter ``d`` (m, or any unit shared with ``pitch_diameter``).
    pitch_diameter : float
        Pitch diameter ``D`` (same unit as ``roller_diameter``); must exceed ``d``.
    contact_angle_deg : float, optional
        Contact angle ``phi`` in degrees, in [0, 90).

    Returns
    -------
    FaultFrequencies
        BPFO, BPFI, FTF and BSF in Hz.

    Examples
    --------
    SKF 6205 (9 balls, d = 7.94 mm, D = 39.04 mm): BPFI = 5.4152 fr.

    >>> ff = fault_frequencies(1.0, 9, 7.94e-3, 39.04e-3)
    >>> round(ff.bpfi, 4)
    5.4152
    """
    fr = check_positive(fr, "fr")
    if int(n_rollers) != n_rollers or n_rollers < 1:
        raise ValueError(f"n_rollers must be an integer >= 1, got {n_rollers!r}")
    d = check_positive(roller_diameter, "roller_diameter")
    pd = check_positive(pitch_diameter, "pitch_diameter")
    if d >= pd:
        raise ValueError(
            f"roller_diameter ({d}) must be smaller than pitch_diameter ({pd})"
        )
    phi = float(contact_angle_deg)
    if not (0.0 <= phi < 90.0):
        raise ValueError(f"contact_angle_deg must be in [0, 90), got {contact_angle_deg!r}")
    r = d / pd * math.cos(math.radians(phi))
    n = int(n_rollers)
    return FaultFrequencies(
        fr=fr,
        bpfo=0.5 * n * fr * (1.0 - r),
        bpfi=0.5 * n * fr * (1.0 + r),
        ftf=0.5 * fr * (1.0 - r),
        bsf=pd / (2.0 * d) * fr * (1.0 - r * r),
    )
