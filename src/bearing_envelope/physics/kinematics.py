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

:func:`bearing_rates` is the one function that returns every rate (BPFO, BPFI, FTF, BSF and
2 x BSF, :func:`spin_events`), with the override rule: a stated BPFI (a catalogue entry's
``bpfi_override_hz``, a case file's) sets the cage rate ``f_c = f_r - BPFI/n`` and every other
rate follows from it (BPFO ``= n f_c``, FTF ``= f_c``, BSF ``= f_c (D + d cos phi)/d``, the
element's spin relative to the cage), as the simulated history runs them; without one these
are the geometric rates above.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..checks import check_positive

__all__ = ["FaultFrequencies", "fault_frequencies", "bearing_rates", "spin_events", "RATE_NAMES",
           "RADIAL_CONTACT_ANGLE_DEG"]

#: The rates :func:`bearing_rates` returns, in order.
RATE_NAMES = ("fr", "bpfi", "bpfo", "ftf", "bsf", "bsf2")

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
    bsf2 : float
        2 x BSF (:func:`spin_events`): the rate a defect on a rolling element meets a race.
    """

    fr: float
    bpfo: float
    bpfi: float
    ftf: float
    bsf: float
    bsf2: float

    def orders(self) -> dict[str, float]:
        """Return the frequencies as multiples of the shaft rate.

        Returns
        -------
        dict of str to float
            ``{"bpfi", "bpfo", "ftf", "bsf", "bsf2"}`` -> frequency / shaft rate.
        """
        return {k: getattr(self, k) / self.fr for k in RATE_NAMES[1:]}

    def as_dict(self) -> dict[str, float]:
        """Every rate by name (what :func:`bearing_rates` returns).

        Returns
        -------
        dict of str to float
            :data:`RATE_NAMES` -> Hz.
        """
        return {k: getattr(self, k) for k in RATE_NAMES}


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
    return FaultFrequencies(**bearing_rates(fr, n_rollers, roller_diameter, pitch_diameter,
                                            contact_angle_deg))


def spin_events(bsf: float) -> float:
    """Rate (Hz) at which a defect on a rolling element meets a race: 2 x BSF (it touches the
    outer race and the inner race once each per spin turn relative to the cage).

    Parameters
    ----------
    bsf : float
        Ball (roller) spin frequency, Hz.

    Returns
    -------
    float
        ``2 bsf``, Hz.
    """
    return 2.0 * bsf


def bearing_rates(fr: float, n_rollers: int, roller_diameter: float, pitch_diameter: float,
                  contact_angle_deg: float = RADIAL_CONTACT_ANGLE_DEG, *, bpfi: float | None = None
                  ) -> dict[str, float]:
    """Every rate of a bearing with a rotating inner ring: the one builder of fault frequencies.

    Parameters
    ----------
    fr : float
        Shaft rate (Hz), > 0.
    n_rollers : int
        Rolling elements per row, >= 1.
    roller_diameter, pitch_diameter : float
        ``d`` and ``D``, one unit (``d < D``).
    contact_angle_deg : float, optional
        Contact angle in degrees, in [0, 90).
    bpfi : float, optional
        A stated BPFI (Hz; the override): the cage rate is then ``fr - bpfi/n`` and BPFO, FTF,
        BSF follow from it. None: the geometric rates.

    Returns
    -------
    dict of str to float
        :data:`RATE_NAMES`: ``fr``, ``bpfi``, ``bpfo``, ``ftf``, ``bsf``, ``bsf2`` (Hz).

    Examples
    --------
    The CWRU drive-end SKF 6205-2RS (9 balls, d = 7.94 mm, D = 39.04 mm), per unit shaft rate:

    >>> r = bearing_rates(1.0, 9, 7.94, 39.04)
    >>> [round(r[k], 4) for k in ("bpfo", "bpfi", "ftf", "bsf", "bsf2")]
    [3.5848, 5.4152, 0.3983, 2.3567, 4.7135]
    """
    fr = check_positive(fr, "fr")
    if isinstance(n_rollers, bool) or int(n_rollers) != n_rollers or n_rollers < 1:
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
    n = int(n_rollers)
    if bpfi is not None:   # the stated BPFI sets the cage rate; the others follow from it
        f_c = fr - check_positive(bpfi, "bpfi") / n
        bsf = f_c * (pd + d * math.cos(math.radians(phi))) / d
        return {"fr": fr, "bpfi": float(bpfi), "bpfo": n * f_c, "ftf": f_c, "bsf": bsf,
                "bsf2": spin_events(bsf)}
    r = d / pd * math.cos(math.radians(phi))
    bsf = pd / (2.0 * d) * fr * (1.0 - r * r)
    return {"fr": fr, "bpfi": 0.5 * n * fr * (1.0 + r), "bpfo": 0.5 * n * fr * (1.0 - r),
            "ftf": 0.5 * fr * (1.0 - r), "bsf": bsf, "bsf2": spin_events(bsf)}
