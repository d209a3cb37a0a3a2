"""Load distribution over the rollers of a radially loaded bearing, and the load zone.

Deflection-based equilibrium of one row (Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed.,
2007, vol. 1 ch. 7; Stribeck 1901). The inner ring is displaced by ``delta_r`` towards the
load direction (``psi = 0``) and by ``delta_y`` across it. The roller at angle ``psi`` is
compressed along its contact normal (contact angle ``alpha``) by

.. math::

    \\delta(\\psi) = \\left(\\delta_r\\cos\\psi + \\delta_y\\sin\\psi - \\tfrac{P_d}{2}\\right)\\cos\\alpha ,

with ``P_d`` the radial (diametral) internal clearance, and carries

.. math::

    Q(\\psi) = K\\,\\langle\\delta(\\psi)\\rangle_+^{\\,n},\\qquad n = 10/9\\ \\text{(line contact)},

with ``K`` the roller's load-deflection constant (both raceway contacts in series). Equilibrium of
the row in both directions, solved numerically for ``(delta_r, delta_y)`` (nested Brent solves,
:func:`solve_row`):

.. math::

    \\sum_j Q(\\psi_j)\\cos\\psi_j\\cos\\alpha = F_{row} ,\\qquad
    \\sum_j Q(\\psi_j)\\sin\\psi_j\\cos\\alpha = 0 .

Where the rollers sit symmetric about the load (cage phase a multiple of ``pi/Z``, the phase 0
the scenes use) the second holds with ``delta_y = 0``. At any other phase the elements on one
side of the load carry more than their mirror images and the ring moves across the load too
(the 6205 at 1 kN, 10 um clearance: ``delta_y = -0.52 um`` at 5.7 deg; an x-only balance
leaves up to 2.9 % of the largest load wrong).

This is equivalent to the load-zone law
``Q(psi) = Q_max [1 - (1 - cos psi)/(2 eps)]^n`` with
``eps = (1 - P_d/(2 delta))/2``, ``delta = hypot(delta_r, delta_y)``, about the zone's centre
``atan2(delta_y, delta_r)``. With zero clearance ``eps = 1/2`` and, for many rollers,
``Q_max = F_row / (Z J_r(1/2) cos(alpha))`` with ``1/J_r(1/2) = 4.08`` for line contact (4.37 for
point contact, n = 3/2) -- Harris & Kotzalas (2007) table 7.1 / Stribeck's constant. Stribeck's
design rule ``Q_max ~ 4.6 F/(Z cos alpha)`` (rollers) or 5 (balls) allows for some clearance.

``K`` from Palmgren's line-contact deflection (Harris & Kotzalas 2007, eq. 6.40):
``delta = 3.84e-5 Q^0.9 / l^0.8`` (mm, N, mm) per raceway contact, two contacts in series:
``Q = K delta^(10/9)``. It only matters with clearance (the shape of the load zone).

**Negative clearance (preload).** ``P_d < 0`` is an interference between the elements and the
races (operating clearance after interference fits and a warmer inner ring, :func:`operating_clearance`):
every element is compressed by ``-P_d/2`` before any load and the load zone spans more than
180 deg (``eps > 1``).

**Centrifugal force** (``load.centrifugal``; Harris & Kotzalas 2007, vol. 2 ch. 3): each
element, of mass ``m``, orbiting with the cage at ``omega_c`` on the pitch radius, presses on the
outer race with ``F_c = m omega_c^2 D/2`` (:func:`centrifugal_force`). Then the outer contact
carries ``Q_o = Q_i + F_c cos(alpha)`` and the compatibility of the element's two deflections,

.. math::

    c_i Q_i^{1/n} + c_o (Q_i + F_c\\cos\\alpha)^{1/n} = \\delta(\\psi),

gives the inner contact's load ``Q_i(psi)``; where ``delta(psi) <= c_o (F_c cos alpha)^(1/n)`` the
inner contact opens (``Q_i = 0``) and the element rests on the outer race with ``F_c`` alone: an
element outside the radial load zone still loads the outer race. The inner ring's equilibrium
``sum Q_i cos(psi) cos(alpha) = F_row`` (and its ``sin`` partner) is solved as before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from ..contact import hertz
from .kinematics import RADIAL_CONTACT_ANGLE_DEG

#: The centrifugal force along the contact normal of a load law without it (N): off.
CENTRIFUGAL_OFF_N = 0.0
#: Cage phase of a load distribution when none is given: element 0 on the load line, rad.
CAGE_PHASE_RAD = 0.0

__all__ = ["LoadDistribution", "LOAD_ROUNDING_ULPS",
           "palmgren_stiffness", "centrifugal_force", "race_compliances",
           "operating_clearance", "ELEMENT_DENSITY_KG_M3", "STEEL_EXPANSION_PER_K", "solve_row", "row_load_distribution",
           "load_zone_integral", "scene_load_distribution", "hertz_point_stiffness", "contact_law",
           "LINE_CONTACT_EXPONENT", "POINT_CONTACT_EXPONENT", "contact_stiffness"]


def palmgren_stiffness(length_m: float, contacts: int = 2) -> float:
    """Roller load-deflection constant ``K`` (N m^-10/9) of ``Q = K delta^(10/9)``.

    Palmgren's line contact ``delta = 3.84e-5 Q^0.9 / l^0.8`` (delta, l in mm; Q in N) per contact,
    ``contacts`` contacts (inner + outer raceway) in series.

    Parameters
    ----------
    length_m : float
        Effective roller length, m.
    contacts : int, default 2
        Contacts in series.

    Returns
    -------
    float
        ``K``, N m^-10/9.
    """
    lmm = length_m * 1e3
    c = contacts * 3.84e-5 / lmm ** 0.8          # delta_mm = c * Q^0.9
    # Q = (delta_mm / c)^(1/0.9) = (1e3 delta_m / c)^(10/9)
    return (1e3 / c) ** (10.0 / 9.0)


def load_zone_integral(eps: float, n: float = 10.0 / 9.0) -> float:
    """Sjovall's radial integral ``J_r(eps) = 1/(2 pi) int (1 - (1-cos psi)/(2 eps))^n cos psi dpsi``.

    ``Q_max = F / (Z J_r cos(alpha))`` for many rollers. ``1/J_r(0.5) = 4.08`` (n = 10/9),
    ``4.37`` (n = 3/2).

    Parameters
    ----------
    eps : float
        Load-zone parameter (0.5: half the bearing loaded; >= 1: all of it).
    n : float, default 10/9
        Load-deflection exponent.

    Returns
    -------
    float
        ``J_r(eps)``.
    """
    lim = math.pi if eps >= 1 else math.acos(max(-1.0, 1.0 - 2.0 * eps))

    def f(p):
        return max(0.0, 1.0 - (1.0 - math.cos(p)) / (2.0 * eps)) ** n * math.cos(p)

    return quad(f, -lim, lim, limit=200)[0] / (2.0 * math.pi)


#: Rounding of an element's compression, in machine epsilons of its terms' magnitude
#: (:attr:`LoadDistribution.rounding_load`): a subtraction of two terms of size ``delta_r`` and
#: a cosine rounded to an epsilon each stay well inside 8.
LOAD_ROUNDING_ULPS = 8.0


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
        Displacement of the inner ring along the load (m).
    psi : ndarray
        Roller angles used in the equilibrium (rad), roller 0 at the solve's ``phase``.
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
    #: Centrifugal force of an element along the contact normal, ``F_c cos(alpha)`` (N); 0 = off.
    centrifugal: float = CENTRIFUGAL_OFF_N
    #: ``(delta, Q_i)`` nodes of the inner contact's load against the element's compression
    #: (with the centrifugal force only; :func:`_inner_load` solved exactly at each node).
    law_nodes: tuple | None = None
    #: Displacement of the inner ring across the load (m): 0 where the elements sit symmetric
    #: about the load (:func:`solve_row`).
    delta_y: float = 0.0

    @property
    def displacement(self) -> float:
        """Magnitude of the inner ring's displacement ``hypot(delta_r, delta_y)`` (m)."""
        return math.hypot(self.delta_r, self.delta_y)

    @property
    def zone_centre(self) -> float:
        """Angle of the load zone's centre from the load direction, ``atan2(delta_y, delta_r)``
        (rad): 0 where the elements sit symmetric about the load."""
        return math.atan2(self.delta_y, self.delta_r)

    @property
    def q_max(self) -> float:
        """Load at the load zone's centre (N): the inner contact's, the largest of the law
        (at ``psi = 0`` where the elements sit symmetric about the load)."""
        return float(self.load_at(self.zone_centre))

    @property
    def q_max_outer(self) -> float:
        """Outer contact's load at ``psi = 0`` (N): ``q_max`` plus the centrifugal force."""
        return self.q_max + self.centrifugal

    @property
    def epsilon(self) -> float:
        """Load-zone parameter ``eps = (1 - P_d/(2 delta))/2``, ``delta`` = :attr:`displacement`."""
        return 0.5 * (1.0 - self.clearance / (2.0 * self.displacement))

    @property
    def half_angle(self) -> float:
        """Half extent of the radial load zone about its centre, ``psi_l = arccos(P_d / (2 delta))``
        (rad), ``delta`` = :attr:`displacement`; pi when a preload loads every element."""
        return math.acos(min(1.0, max(-1.0, self.clearance / (2.0 * self.displacement))))

    def load_at(self, psi, race: str = "inner"):
        """Element load ``Q(psi)`` (N) at angle(s) ``psi`` (rad) from the load direction.

        ``race``: the contact whose load is returned: ``inner`` (``Q_i``) or ``outer``
        (``Q_i + F_c cos(alpha)``); the two are equal without the centrifugal force.

        Parameters
        ----------
        psi : float or ndarray
            Angle(s) from the load direction, rad.
        race : {"inner", "outer"}, default "inner"
            The contact.

        Returns
        -------
        float or ndarray
            Element load, N, shape of ``psi`` (0 outside the load zone, plus the centrifugal
            force for ``outer``).
        """
        d = (self.delta_r * np.cos(psi) + self.delta_y * np.sin(psi)
             - 0.5 * self.clearance) * math.cos(self.contact_angle_rad)
        if self.law_nodes is None:
            q = self.stiffness * np.clip(d, 0.0, None) ** self.exponent
        else:
            q = np.interp(d, self.law_nodes[0], self.law_nodes[1], left=0.0)
        return q + self.centrifugal if race == "outer" else q

    @property
    def rounding_load(self) -> float:
        """The element load (N) of a compression within the rounding of its computation.

        The compression ``(delta_r cos psi + delta_y sin psi - P_d/2) cos alpha`` is computed from
        terms of size ``delta_r`` and ``P_d/2``; within :data:`LOAD_ROUNDING_ULPS` machine epsilons of them
        it is zero computed badly (``delta_r cos(pi/2) = 6e-17 delta_r``: 2.3e-22 N at the
        edge of a zero-clearance zone), not a load (issue 43).

        Returns
        -------
        float
            ``Q`` of that compression, N (the inner contact's; the centrifugal force is a real
            load and is not part of it).
        """
        d = LOAD_ROUNDING_ULPS * np.finfo(float).eps * (self.displacement + 0.5 * abs(
            self.clearance)) * math.cos(self.contact_angle_rad)
        if self.law_nodes is None:
            return float(self.stiffness * d ** self.exponent)
        return float(np.interp(d, self.law_nodes[0], self.law_nodes[1], left=0.0))

    def loaded(self, q):
        """Whether element loads ``q`` (N) are loads: above :attr:`rounding_load`.

        Parameters
        ----------
        q : float or ndarray
            Element loads, N (either contact's).

        Returns
        -------
        bool or ndarray of bool
            ``q > rounding_load``, shape of ``q``.
        """
        return np.asarray(q) > self.rounding_load

    def shape(self, psi):
        """``Q(psi) / Q_max``.

        Parameters
        ----------
        psi : float or ndarray
            Angle(s) from the load direction, rad.

        Returns
        -------
        float or ndarray
            Inner-contact load over ``q_max``, shape of ``psi``.
        """
        return self.load_at(psi) / self.q_max


#: Nodes of the ``(delta, Q_i)`` law with the centrifugal force (uniform in ``delta``): the
#: linear reading is within 1e-6 Q_max of the exact solve (tests/test_loads_outside_zone.py).
LAW_NODES = 4097


def _inner_load(delta, c_i: float, c_o: float, fc: float, n: float) -> np.ndarray:
    """Inner contact load ``Q_i`` (N) of an element compressed by ``delta`` (m) along its
    normal, with the outer contact carrying ``Q_i + fc``: the root of
    ``c_i Q^(1/n) + c_o (Q + fc)^(1/n) = delta`` (bisection, 80 halvings: exact to rounding), 0
    where ``delta <= c_o fc^(1/n)`` (the inner contact open)."""
    d = np.atleast_1d(np.asarray(delta, dtype=float))
    lo = np.zeros_like(d)
    hi = (np.clip(d, 0.0, None) / c_i) ** n
    m = 1.0 / n
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        over = c_i * mid ** m + c_o * (mid + fc) ** m > d
        hi = np.where(over, mid, hi)
        lo = np.where(over, lo, mid)
    return 0.5 * (lo + hi)


def _root(f, x0: float, step: float, xtol: float) -> float:
    """Root of the nondecreasing ``f`` (Brent's method) bracketed from ``x0`` by steps doubling
    from ``step`` towards the sign change; ``x0`` itself when ``f(x0) == 0``."""
    f0 = f(x0)
    if f0 == 0.0:
        return x0
    sign = -1.0 if f0 > 0 else 1.0
    far = x0 + sign * step
    while (f(far) > 0) == (f0 > 0):
        step *= 2.0
        if step > 1.0:
            raise ValueError("over 1 m")
        far = x0 + sign * step
    lo, hi = sorted((x0, far))
    return brentq(f, lo, hi, xtol=xtol, rtol=1e-14, maxiter=500)


#: The transverse force (fraction of the row load) below which the x-only solution is taken as
#: balanced: rounding of ``sum Q sin psi`` at a phase where the elements sit symmetric about the
#: load (about 1e-16; the 2-D solve balances to ~1e-14).
SYMMETRIC_Y_RESIDUAL = 1e-12


def solve_row(force_row: float, n_rollers: int,
              contact_angle_deg: float = RADIAL_CONTACT_ANGLE_DEG,
              clearance: float = 0.0, stiffness: float = 1e10, exponent: float = 10.0 / 9.0,
              phase: float = CAGE_PHASE_RAD, *, centrifugal: float = CENTRIFUGAL_OFF_N,
              compliances: tuple[float, float] | None = None) -> LoadDistribution:
    """Solve the radial equilibrium of one row for the ring's displacement ``(delta_r, delta_y)``.

    Both force balances hold (Harris & Kotzalas 2007, vol. 1 ch. 7): along the load,
    ``sum Q_j cos(psi_j) cos(alpha) = F_row``, and across it, ``sum Q_j sin(psi_j) cos(alpha) = 0``,
    with ``Q_j`` of the compression ``(delta_r cos psi_j + delta_y sin psi_j - P_d/2) cos alpha``.
    The equilibrium minimises a convex energy, so nested Brent solves find it: ``delta_y`` for
    each ``delta_r`` (the transverse force grows with ``delta_y``), then ``delta_r`` (the
    longitudinal force, at the balanced ``delta_y``, grows with ``delta_r``). Where the elements
    sit symmetric about the load (``phase`` a multiple of ``pi/Z``) ``delta_y = 0`` and the
    along-the-load solve alone is the answer.

    Parameters
    ----------
    force_row : float
        Radial load on the row (N), > 0.
    n_rollers : int
        Rollers in the row ``Z``.
    contact_angle_deg : float
        Contact angle (deg).
    clearance : float
        Radial internal (operating) clearance ``P_d`` (m); negative = preload.
    stiffness : float
        ``K`` of ``Q = K delta^n`` (N m^-n); with zero clearance it does not change ``Q``.
    exponent : float
        ``n`` (10/9 line contact, 3/2 point contact).
    phase : float
        Angle of roller 0 from the load direction (rad).
    centrifugal : float
        Centrifugal force of an element along the contact normal, ``F_c cos(alpha)`` (N), >= 0
        (module docstring); 0 = off (the closed-form law, unchanged).
    compliances : (float, float) or None
        ``(c_i, c_o)`` of each contact's deflection ``delta_j = c_j Q^(1/n)`` (m N^(-1/n),
        :func:`race_compliances`); required with ``centrifugal > 0``.

    Returns
    -------
    LoadDistribution
        ``delta_r``, ``delta_y`` (m) and the roller loads ``q`` (N) at the angles ``psi`` (rad)
        of the solved equilibrium, with the law's constants.

    Raises
    ------
    ValueError
        A load, roller count, clearance or centrifugal force out of range, fewer than three
        rollers at a phase where they are not symmetric about the load, or no equilibrium
        below 1 m of ring displacement.

    Examples
    --------
    Zero clearance, rollers (``n = 10/9``): the most loaded roller carries Stribeck's
    ``4.08 F / Z`` and the load zone spans half the ring (``epsilon = 0.5``):

    >>> from bearing_envelope.physics.loads import solve_row
    >>> ld = solve_row(1000.0, 40)
    >>> round(ld.q_max * 40 / 1000.0, 2), round(ld.epsilon, 2)
    (4.08, 0.5)
    """
    if not (force_row > 0):
        raise ValueError(f"force_row must be > 0, got {force_row!r}")
    if int(n_rollers) != n_rollers or n_rollers < 1:
        raise ValueError(f"n_rollers must be an integer >= 1, got {n_rollers!r}")
    if not math.isfinite(clearance):
        raise ValueError(f"clearance must be finite, got {clearance!r}")
    if not (centrifugal >= 0) or (centrifugal > 0 and compliances is None):
        raise ValueError(f"centrifugal must be >= 0 (with compliances), got {centrifugal!r}")
    ca = math.radians(contact_angle_deg)
    psi = phase + 2.0 * math.pi * np.arange(n_rollers) / n_rollers
    cos_psi, sin_psi = np.cos(psi), np.sin(psi)

    def loads(dr, dy=0.0):
        d = (dr * cos_psi + dy * sin_psi - 0.5 * clearance) * math.cos(ca)
        if centrifugal > 0:
            return _inner_load(d, compliances[0], compliances[1], centrifugal, exponent)
        return stiffness * np.clip(d, 0.0, None) ** exponent

    def no_equilibrium():
        return ValueError(
            f"load distribution: no equilibrium found: the radial load {force_row:g} N per "
            f"row needs a ring displacement over 1 m (contact_angle_deg {contact_angle_deg:g}, "
            f"allowed: a radial bearing, <= 45 deg; clearance {clearance:g} m; stiffness "
            f"{stiffness:g} N m^-n)")

    def x_force(dr, dy=0.0):
        return float(np.sum(loads(dr, dy) * cos_psi) * math.cos(ca) - force_row)

    def y_force(dr, dy):
        return float(np.sum(loads(dr, dy) * sin_psi) * math.cos(ca))

    lo = max(0.0, 0.5 * clearance / max(np.max(cos_psi), 1e-12))
    hi = max(lo, 1e-9) * 2 + 1e-9
    while x_force(hi) < 0:
        hi *= 2.0
        if hi > 1.0:
            raise no_equilibrium()
    dr = brentq(x_force, lo, hi, xtol=1e-18, rtol=1e-14, maxiter=500)
    dy = 0.0
    if abs(y_force(dr, 0.0)) > SYMMETRIC_Y_RESIDUAL * force_row:
        dr, dy = _balance_y(x_force, y_force, dr, clearance, n_rollers, phase, no_equilibrium)
    nodes = None
    if centrifugal > 0:
        d_top = (math.hypot(dr, dy) - 0.5 * clearance) * math.cos(ca)
        d_open = compliances[1] * centrifugal ** (1.0 / exponent)
        dn = np.linspace(min(d_open, d_top), d_top, LAW_NODES)
        nodes = (dn, _inner_load(dn, compliances[0], compliances[1], centrifugal, exponent))
    return LoadDistribution(float(force_row), int(n_rollers), ca, float(clearance), float(stiffness),
                            float(exponent), float(dr), psi, loads(dr, dy), float(centrifugal), nodes,
                            float(dy))


def _balance_y(x_force, y_force, dr0: float, clearance: float, n_rollers: int, phase: float,
               no_equilibrium) -> tuple[float, float]:
    """``(delta_r, delta_y)`` with both forces balanced (:func:`solve_row`), from the
    along-the-load solution ``dr0``: ``delta_y`` balanced for each ``delta_r`` inside the
    Brent solve of ``delta_r``."""
    if n_rollers < 3:
        raise ValueError(
            f"load distribution: n_rollers {n_rollers} at phase {phase:g} rad cannot balance "
            f"the load across its line; allowed: >= 3 rollers, or a phase that is a multiple "
            f"of pi/{n_rollers}")
    scale = max(abs(dr0), 0.5 * abs(clearance), 1e-12)
    tol = 1e-15 * scale

    def dy_of(dr):
        return _root(lambda dy: y_force(dr, dy), 0.0, 1e-3 * scale, tol)

    try:
        dr = _root(lambda d: x_force(d, dy_of(d)), dr0, 1e-2 * scale, tol)
    except ValueError:
        raise no_equilibrium() from None
    return dr, dy_of(dr)


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

    Parameters
    ----------
    bearing : Bearing
        A ball bearing (``rx_for``, ``ry_for``).
    e_star : float
        Composite modulus, Pa.

    Returns
    -------
    float
        ``K``, N m^-3/2.
    """
    c = sum(hertz.elliptical(_PROBE_LOAD_N, bearing.rx_for(race), bearing.ry_for(race),
                             e_star).approach for race in ("inner", "outer"))
    return c ** -1.5


def contact_law(scene) -> tuple[float, float]:
    """``(K, n)`` of the rolling elements of ``scene``: Palmgren's line contact with ``n = 10/9``
    (rollers, :func:`palmgren_stiffness`) or Hertz point contact with ``n = 3/2`` (balls,
    :func:`hertz_point_stiffness`).

    Parameters
    ----------
    scene : Scene
        The scene (its bearing and material).

    Returns
    -------
    K : float
        Load-deflection constant, N m^-n.
    n : float
        Exponent of ``Q = K delta^n``.
    """
    b = scene.bearing
    if getattr(b, "kind", "roller") == "ball":
        return hertz_point_stiffness(b, scene.material.e_star_pa), POINT_CONTACT_EXPONENT
    return palmgren_stiffness(1e-3 * b.roller_length_mm), LINE_CONTACT_EXPONENT


def contact_stiffness(k: float, q: float, n: float) -> float:
    """Linearised stiffness ``dQ/d delta = n K^(1/n) Q^((n-1)/n)`` of ``Q = K delta^n`` at load
    ``q``: ``1.5 K^(2/3) Q^(1/3)`` for a point contact, ``(10/9) K^(9/10) Q^(1/10)`` for
    Palmgren's line contact (:func:`contact_law`).

    Parameters
    ----------
    k, q, n : float
        ``K`` (N m^-n), load (N, >= 0), ``n``.

    Returns
    -------
    float
        Stiffness, N/m.
    """
    return n * k ** (1.0 / n) * max(q, 0.0) ** ((n - 1.0) / n)


#: Density of the rolling elements (kg/m^3): through-hardened AISI 52100 / 100Cr6, 7.81e3
#: (ASTM A295 data sheets; Harris & Kotzalas use 7.8e3) -- assumed for every catalogue bearing.
ELEMENT_DENSITY_KG_M3 = 7810.0
#: Linear thermal expansion of bearing steel (1/K): 52100, 11.9e-6 near 20-100 C (assumed).
STEEL_EXPANSION_PER_K = 11.9e-6


def centrifugal_force(bearing, cage_rate_hz: float,
                      density_kg_m3: float = ELEMENT_DENSITY_KG_M3) -> float:
    """Centrifugal force (N) of one rolling element orbiting with the cage, ``m omega_c^2 D/2``.

    Harris & Kotzalas (2007), vol. 2 ch. 3: ``F_c = m omega_c^2 d_m / 2``; ``m = rho pi d^3/6``
    (ball) or ``rho pi d^2 L/4`` (roller of length ``roller_length_mm``).

    Parameters
    ----------
    bearing : Bearing
        Its element diameter, roller length (rollers) and pitch diameter (mm in the
        catalogue, m inside).
    cage_rate_hz : float
        Orbit rate of the element (Hz): the cage rate.
    density_kg_m3 : float
        Element density (kg/m^3).

    Returns
    -------
    float
        ``F_c`` (N), radial, outwards.
    """
    d = 1e-3 * bearing.roller_diameter_mm
    vol = math.pi * d ** 3 / 6.0 if bearing.kind == "ball" else \
        0.25 * math.pi * d ** 2 * 1e-3 * bearing.roller_length_mm
    return density_kg_m3 * vol * (2.0 * math.pi * cage_rate_hz) ** 2 * 0.5 * bearing.pitch_diameter_m


def race_compliances(scene) -> tuple[float, float]:
    """``(c_i, c_o)`` of each raceway contact's deflection ``delta_j = c_j Q^(1/n)`` (m N^(-1/n)):
    Hertz approaches at 1 N (balls, as :func:`hertz_point_stiffness`) or Palmgren's
    ``3.84e-5 / l^0.8`` mm per contact (rollers, as :func:`palmgren_stiffness`); in series they
    give :func:`contact_law`'s ``K = (c_i + c_o)^(-n)``.

    Parameters
    ----------
    scene : Scene
        The scene (its bearing and material).

    Returns
    -------
    tuple of float
        ``(c_i, c_o)``; equal for rollers.
    """
    b = scene.bearing
    if getattr(b, "kind", "roller") == "ball":
        e = scene.material.e_star_pa
        return tuple(hertz.elliptical(_PROBE_LOAD_N, b.rx_for(r), b.ry_for(r), e).approach
                     for r in ("inner", "outer"))
    c = 1e-3 * 3.84e-5 / b.roller_length_mm ** 0.8
    return c, c


def operating_clearance(bearing, *, shaft_interference_um: float = 0.0,
                        housing_interference_um: float = 0.0,
                        inner_warmer_by_K: float = 0.0) -> float:
    """Operating radial clearance (um) from the mounted-free clearance ``radial_clearance_um``.

    Same-material thick-cylinder (Lame) fits: an inner ring on a solid shaft widens its raceway
    by ``I_s d_bore / D_i`` (``D_i = D - d``, the groove bottom), an outer ring in a housing of
    large section narrows its raceway by ``I_h D_o / OD`` (``D_o = D + d``); an inner ring
    warmer than the outer by ``dT`` widens by ``a dT D_i`` against the outer
    (``a`` = :data:`STEEL_EXPANSION_PER_K`). Harris & Kotzalas (2007), vol. 1 ch. 8 (fits and
    clearance); the fractions (0.804 and 0.903 for the 6205: 25/31.10 and 46.98/52) lie near the
    70-90 % that bearing makers quote for the clearance taken up by a fit.

    Parameters
    ----------
    bearing : Bearing
        Its ``radial_clearance_um``, ``pitch_diameter_mm``, ``roller_diameter_mm``, ``bore_mm``
        and ``outside_diameter_mm``.
    shaft_interference_um : float, default 0
        Diametral interference of the inner ring on the shaft, um.
    housing_interference_um : float, default 0
        Diametral interference of the outer ring in the housing, um.
    inner_warmer_by_K : float, default 0
        Temperature of the inner ring above the outer, K.

    Returns
    -------
    float
        ``P_d`` (um): negative = preload.
    """
    pd, d = bearing.pitch_diameter_mm, bearing.roller_diameter_mm
    d_i, d_o = pd - d, pd + d
    return (bearing.radial_clearance_um - shaft_interference_um * bearing.bore_mm / d_i
            - housing_interference_um * d_o / bearing.outside_diameter_mm
            - 1e3 * STEEL_EXPANSION_PER_K * inner_warmer_by_K * d_i)


def _row_kwargs(scene) -> dict:
    """The centrifugal keywords of :func:`solve_row` for ``scene`` (``load.centrifugal``)."""
    if not getattr(scene.load, "centrifugal", False):
        return {}
    fc = centrifugal_force(scene.bearing, scene.cage_rate_hz) * math.cos(scene.bearing.contact_angle_rad)
    return {"centrifugal": fc, "compliances": race_compliances(scene)}


def row_load_distribution(scene) -> LoadDistribution:
    """Load distribution of the loaded row of ``scene`` in ``bearing`` mode.

    The radial load ``scene.load.value_N`` is shared equally by ``scene.bearing.rows`` rows;
    the law is :func:`contact_law` (line contact for rollers, point contact for balls), with
    the centrifugal force when ``load.centrifugal`` is on.

    Parameters
    ----------
    scene : Scene
        The scene (``load.value_N``, N: the radial load of the bearing).

    Returns
    -------
    LoadDistribution
        The loaded row's distribution.
    """
    b = scene.bearing
    k, n = contact_law(scene)
    return solve_row(scene.load.value_N / b.rows, b.rollers_per_row, b.contact_angle_deg,
                     1e-6 * b.radial_clearance_um, k, n, **_row_kwargs(scene))


def scene_load_distribution(scene) -> LoadDistribution:
    """The load distribution the time history uses, for either load mode.

    ``bearing``: :func:`row_load_distribution`. ``contact``: the row load is found (Brent) such
    that the roller at the load-zone centre carries exactly ``scene.load.value_N``; with zero
    clearance this is just a scaling of the same shape.

    Parameters
    ----------
    scene : Scene
        The scene (``load.mode``, ``load.value_N`` in N).

    Returns
    -------
    LoadDistribution
        The loaded row's distribution.
    """
    if scene.load.mode == "bearing":
        return row_load_distribution(scene)
    b = scene.bearing
    k, n = contact_law(scene)
    target = scene.load.value_N
    c = 1e-6 * b.radial_clearance_um

    kw = _row_kwargs(scene)

    def f(fr):
        return solve_row(fr, b.rollers_per_row, b.contact_angle_deg, c, k, n, **kw).q_max - target

    lo = target * 0.05
    hi = target * b.rollers_per_row
    fr = brentq(f, lo, hi, rtol=1e-13, xtol=1e-9)
    return solve_row(fr, b.rollers_per_row, b.contact_angle_deg, c, k, n, **kw)
