"""Load distribution over the rollers of a radially loaded bearing, and the load zone.

Deflection-based equilibrium of one row (Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed.,
2007, vol. 1 ch. 7; Stribeck 1901). The inner ring is displaced radially by ``delta_r`` towards the
load direction (``psi = 0``). The roller at angle ``psi`` is compressed along its contact normal
(contact angle ``alpha``) by

.. math::

    \\delta(\\psi) = \\left(\\delta_r\\cos\\psi - \\tfrac{P_d}{2}\\right)\\cos\\alpha ,

with ``P_d`` the radial (diametral) internal clearance, and carries

.. math::

    Q(\\psi) = K\\,\\langle\\delta(\\psi)\\rangle_+^{\\,n},\\qquad n = 10/9\\ \\text{(line contact)},

with ``K`` the roller's load-deflection constant (both raceway contacts in series). Equilibrium of
the row, solved numerically for ``delta_r`` (Brent's method):

.. math::

    \\sum_j Q(\\psi_j)\\cos\\psi_j\\cos\\alpha = F_{row} .

This is equivalent to the load-zone law
``Q(psi) = Q_max [1 - (1 - cos psi)/(2 eps)]^n`` with
``eps = (1 - P_d/(2 delta_r))/2``. With zero clearance ``eps = 1/2`` and, for many rollers,
``Q_max = F_row / (Z J_r(1/2) cos(alpha))`` with ``1/J_r(1/2) = 4.08`` for line contact (4.37 for
point contact, n = 3/2) -- Harris & Kotzalas (2007) table 7.1 / Stribeck's constant. Stribeck's
design rule ``Q_max ~ 4.6 F/(Z cos alpha)`` (rollers) or 5 (balls) allows for some clearance.

``K`` from Palmgren's line-contact deflection (Harris & Kotzalas 2007, eq. 6.40):
``delta = 3.84e-5 Q^0.9 / l^0.8`` (mm, N, mm) per raceway contact, two contacts in series:
``Q = K delta^(10/9)``. It only matters with clearance (the shape of the load zone).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from ..contact import hertz

__all__ = ["LoadDistribution", "palmgren_stiffness", "solve_row", "row_load_distribution",
           "load_zone_integral", "scene_load_distribution", "hertz_point_stiffness", "contact_law",
           "LINE_CONTACT_EXPONENT", "POINT_CONTACT_EXPONENT"]


def palmgren_stiffness(length_m: float, contacts: int = 2) -> float:
    """Roller load-deflection constant ``K`` (N m^-10/9) of ``Q = K delta^(10/9)``.

    Palmgren's line contact ``delta = 3.84e-5 Q^0.9 / l^0.8`` (delta, l in mm; Q in N) per contact,
    ``contacts`` contacts (inner + outer raceway) in series.
    """
    lmm = length_m * 1e3
    c = contacts * 3.84e-5 / lmm ** 0.8          # delta_mm = c * Q^0.9
    # Q = (delta_mm / c)^(1/0.9) = (1e3 delta_m / c)^(10/9)
    return (1e3 / c) ** (10.0 / 9.0)


def load_zone_integral(eps: float, n: float = 10.0 / 9.0) -> float:
    """Sjovall's radial integral ``J_r(eps) = 1/(2 pi) int (1 - (1-cos psi)/(2 eps))^n cos psi dpsi``.

    ``Q_max = F / (Z J_r cos(alpha))`` for many rollers. ``1/J_r(0.5) = 4.08`` (n = 10/9),
    ``4.37`` (n = 3/2).
    """
    lim = math.pi if eps >= 1 else math.acos(max(-1.0, 1.0 - 2.0 * eps))

    def f(p):
        return max(0.0, 1.0 - (1.0 - math.cos(p)) / (2.0 * eps)) ** n * math.cos(p)

    return quad(f, -lim, lim, limit=200)[0] / (2.0 * math.pi)


@dataclass(frozen=True)
class LoadDistribution:
    """Solved load distribution of one row.

    Attributes
    ----------
    force_row : float
        Radial load on the row (N).
    n_rollers : int
    contact_angle_rad : float
    clearance : float
        Radial internal clearance ``P_d`` (m).
    stiffness : float
        ``K`` (N m^-n).
    exponent : float
        ``n``.
    delta_r : float
        Radial displacement of the inner ring (m).
    psi : ndarray
        Roller angles used in the equilibrium (rad), roller 0 at ``psi = 0``.
    q : ndarray
        Roller loads at those angles (N).
    """

    force_row: float
    n_rollers: int
    contact_angle_rad: float
    clearance: float
    stiffness: float
    exponent: float
    delta_r: float
    psi: np.ndarray
    q: np.ndarray

    @property
    def q_max(self) -> float:
        """Load of the roller at ``psi = 0`` (N)."""
        return float(self.load_at(0.0))

    @property
    def epsilon(self) -> float:
        """Load-zone parameter ``eps = (1 - P_d/(2 delta_r))/2``."""
        return 0.5 * (1.0 - self.clearance / (2.0 * self.delta_r))

    @property
    def half_angle(self) -> float:
        """Half extent of the load zone ``psi_l = arccos(P_d / (2 delta_r))`` (rad)."""
        return math.acos(min(1.0, self.clearance / (2.0 * self.delta_r)))

    def load_at(self, psi):
        """Roller load ``Q(psi)`` (N) at angle(s) ``psi`` (rad) from the load direction."""
        d = (self.delta_r * np.cos(psi) - 0.5 * self.clearance) * math.cos(self.contact_angle_rad)
        return self.stiffness * np.clip(d, 0.0, None) ** self.exponent

    def shape(self, psi):
        """``Q(psi) / Q_max``."""
        return self.load_at(psi) / self.q_max


def solve_row(force_row: float, n_rollers: int, contact_angle_deg: float = 0.0,
              clearance: float = 0.0, stiffness: float = 1e10, exponent: float = 10.0 / 9.0,
              phase: float = 0.0) -> LoadDistribution:
    """Solve the radial equilibrium of one row for ``delta_r``.

    Parameters
    ----------
    force_row : float
        Radial load on the row (N), > 0.
    n_rollers : int
        Rollers in the row ``Z``.
    contact_angle_deg : float
        Contact angle (deg).
    clearance : float
        Radial internal clearance ``P_d`` (m), >= 0.
    stiffness : float
        ``K`` of ``Q = K delta^n`` (N m^-n); with zero clearance it does not change ``Q``.
    exponent : float
        ``n`` (10/9 line contact, 3/2 point contact).
    phase : float
        Angle of roller 0 from the load direction (rad).

    Returns
    -------
    LoadDistribution
    """
    if not (force_row > 0):
        raise ValueError(f"force_row must be > 0, got {force_row!r}")
    if int(n_rollers) != n_rollers or n_rollers < 1:
        raise ValueError(f"n_rollers must be an integer >= 1, got {n_rollers!r}")
    if clearance < 0:
        raise ValueError(f"clearance must be >= 0, got {clearance!r}")
    ca = math.radians(contact_angle_deg)
    psi = phase + 2.0 * math.pi * np.arange(n_rollers) / n_rollers

    def residual(dr):
        d = (dr * np.cos(psi) - 0.5 * clearance) * math.cos(ca)
        q = stiffness * np.clip(d, 0.0, None) ** exponent
        return float(np.sum(q * np.cos(psi)) * math.cos(ca) - force_row)

    lo = 0.5 * clearance / max(np.max(np.cos(psi)), 1e-12)
    hi = max(lo, 1e-9) * 2 + 1e-9
    while residual(hi) < 0:
        hi *= 2.0
        if hi > 1.0:
            raise ValueError("load distribution: no equilibrium found (check stiffness/clearance)")
    dr = brentq(residual, lo, hi, xtol=1e-18, rtol=1e-14, maxiter=500)
    d = (dr * np.cos(psi) - 0.5 * clearance) * math.cos(ca)
    q = stiffness * np.clip(d, 0.0, None) ** exponent
    return LoadDistribution(float(force_row), int(n_rollers), ca, float(clearance), float(stiffness),
                            float(exponent), float(dr), psi, q)


#: Load-deflection exponents ``n`` of ``Q = K delta^n``: line contact (Palmgren, rollers) and
#: point contact (Hertz, balls): Harris & Kotzalas 2007, eqs. 7.1-7.2.
LINE_CONTACT_EXPONENT = 10.0 / 9.0
POINT_CONTACT_EXPONENT = 1.5

#: Probe load (N) of :func:`hertz_point_stiffness`: the Hertz approach scales exactly as
#: ``Q^(2/3)``, so any positive load gives the same constant.
_PROBE_LOAD_N = 1.0


def hertz_point_stiffness(bearing, e_star: float) -> float:
    """Ball load-deflection constant ``K`` (N m^-3/2) of ``Q = K delta^(3/2)``.

    Each raceway contact follows Hertz, ``delta_j = c_j Q^(2/3)`` with ``c_j`` the approach of
    the contact at 1 N (:func:`bearing_envelope.contact.hertz.elliptical` with the race's
    ``R_x``, ``R_y``); the inner and outer contacts in series,
    ``K = (c_i + c_o)^(-3/2)`` (Harris & Kotzalas 2007, eqs. 7.3-7.4).
    """
    c = sum(hertz.elliptical(_PROBE_LOAD_N, bearing.rx_for(race), bearing.ry_for(race),
                             e_star).approach for race in ("inner", "outer"))
    return c ** -1.5


def contact_law(scene) -> tuple[float, float]:
    """``(K, n)`` of the rolling elements of ``scene``: Palmgren's line contact with ``n = 10/9``
    (rollers, :func:`palmgren_stiffness`) or Hertz point contact with ``n = 3/2`` (balls,
    :func:`hertz_point_stiffness`)."""
    b = scene.bearing
    if getattr(b, "kind", "roller") == "ball":
        return hertz_point_stiffness(b, scene.material.e_star_pa), POINT_CONTACT_EXPONENT
    return palmgren_stiffness(1e-3 * b.roller_length_mm), LINE_CONTACT_EXPONENT


def row_load_distribution(scene) -> LoadDistribution:
    """Load distribution of the loaded row of ``scene`` in ``bearing`` mode.

    The radial load ``scene.load.value_N`` is shared equally by ``scene.bearing.rows`` rows;
    the law is :func:`contact_law` (line contact for rollers, point contact for balls).
    """
    b = scene.bearing
    k, n = contact_law(scene)
    return solve_row(scene.load.value_N / b.rows, b.rollers_per_row, b.contact_angle_deg,
                     1e-6 * b.radial_clearance_um, k, n)


def scene_load_distribution(scene) -> LoadDistribution:
    """The load distribution the time history uses, for either load mode.

    ``bearing``: :func:`row_load_distribution`. ``contact``: the row load is found (Brent) such
    that the roller at the load-zone centre carries exactly ``scene.load.value_N``; with zero
    clearance this is just a scaling of the same shape.
    """
    if scene.load.mode == "bearing":
        return row_load_distribution(scene)
    b = scene.bearing
    k, n = contact_law(scene)
    target = scene.load.value_N
    c = 1e-6 * b.radial_clearance_um

    def f(fr):
        return solve_row(fr, b.rollers_per_row, b.contact_angle_deg, c, k, n).q_max - target

    lo = target * 0.05
    hi = target * b.rollers_per_row
    fr = brentq(f, lo, hi, rtol=1e-13, xtol=1e-9)
    return solve_row(fr, b.rollers_per_row, b.contact_angle_deg, c, k, n)
