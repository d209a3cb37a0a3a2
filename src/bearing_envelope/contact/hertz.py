"""Closed-form Hertz solutions: test oracles and grid sizing for the contact solver.

Two smooth, frictionless, linearly elastic bodies whose initial separation near the first point
of contact is the quadratic

.. math::

    g(x, y) = \\frac{x^2}{2 R_x} + \\frac{y^2}{2 R_y},

pressed together by a normal force ``F``, touch over an ellipse with semi-axes ``a`` (along
``x``, the rolling direction) and ``b`` (along ``y``, the axial direction) and carry the
semi-ellipsoidal pressure

.. math::

    p(x, y) = p_0 \\sqrt{1 - (x/a)^2 - (y/b)^2},\\qquad F = \\tfrac{2}{3}\\pi a b\\, p_0 .

``e_star`` is the composite (plane-strain) modulus
:math:`1/E^* = (1-\\nu_1^2)/E_1 + (1-\\nu_2^2)/E_2`
(:func:`bearing_envelope.contact.composite_modulus`).
All quantities SI (N, m, Pa).

References
----------
K. L. Johnson, *Contact Mechanics*, Cambridge University Press, 1985, sections 4.1-4.2 (eqs. 4.22,
4.23 and 4.36-4.41).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy.optimize import brentq
from scipy.special import ellipe, ellipk, ellipkm1

from ..checks import check_positive

__all__ = ["HertzContact", "sphere", "elliptical", "elliptic_ratio", "curvature_difference",
           "harris_point_contact", "hamrock_brewe", "line_half_width"]


@dataclass(frozen=True)
class HertzContact:
    """Result of a Hertz contact.

    Attributes
    ----------
    a : float
        Semi-axis along ``x`` (rolling direction), m.
    b : float
        Semi-axis along ``y`` (axial direction), m. ``a == b`` for a circle.
    p0 : float
        Maximum (central) pressure, Pa.
    approach : float
        Rigid-body approach (mutual approach of distant points), m.
    mean_pressure : float
        ``F / (pi a b)`` = ``2 p0 / 3``, Pa.
    force : float
        Normal force, N.
    """

    a: float
    b: float
    p0: float
    approach: float
    mean_pressure: float
    force: float

    @property
    def area(self) -> float:
        """Contact area ``pi a b`` (m^2)."""
        return math.pi * self.a * self.b

    def pressure(self, x, y):
        """Pressure field ``p0 sqrt(1 - (x/a)^2 - (y/b)^2)`` (zero outside), Pa.

        Parameters
        ----------
        x, y : array_like
            Position from the contact centre along the ``a`` and ``b`` semi-axes (m), broadcast
            together.

        Returns
        -------
        numpy.ndarray
            Pressure (Pa) at each position.
        """
        import numpy as np

        s = 1.0 - (np.asarray(x) / self.a) ** 2 - (np.asarray(y) / self.b) ** 2
        return self.p0 * np.sqrt(np.clip(s, 0.0, None))


def sphere(force: float, radius: float, e_star: float) -> HertzContact:
    """Hertz contact of a sphere (equivalent radius ``R``) on a flat.

    Parameters
    ----------
    force : float
        Normal force ``F`` (N), > 0.
    radius : float
        Equivalent radius ``R`` (m): ``1/R = 1/R_1 + 1/R_2``, > 0.
    e_star : float
        Composite modulus ``E*`` (Pa), > 0.

    Returns
    -------
    HertzContact
        With ``a = b``.

    Notes
    -----
    .. math::

        a = \\left(\\frac{3 F R}{4 E^*}\\right)^{1/3},\\quad
        p_0 = \\frac{3F}{2\\pi a^2} = \\frac{2 E^* a}{\\pi R},\\quad
        \\delta = \\frac{a^2}{R},\\quad \\bar p = \\frac{F}{\\pi a^2}.

    Examples
    --------
    >>> c = sphere(100.0, 0.01, 1.15e11)
    >>> round(c.a * 1e3, 4), round(c.p0 / 1e9, 4)
    (0.1868, 1.3678)
    """
    force = check_positive(force, "force")
    radius = check_positive(radius, "radius")
    e_star = check_positive(e_star, "e_star")
    a = (3.0 * force * radius / (4.0 * e_star)) ** (1.0 / 3.0)
    p0 = 3.0 * force / (2.0 * math.pi * a * a)
    return HertzContact(a, a, p0, a * a / radius, force / (math.pi * a * a), force)


def _ratio_of_curvatures(k: float) -> float:
    """``A_minor / A_major`` as a function of the axis ratio ``k = minor/major`` (0 < k < 1).

    With ``m = e^2 = 1 - k^2`` (Johnson eq. 4.39):
    ``A_minor/A_major = (E(m)/k^2 - K(m)) / (K(m) - E(m))``; it decreases from +inf to 1
    as ``k`` goes from 0 to 1.
    """
    m1 = k * k
    kk = ellipkm1(m1)  # K(m) with m = 1 - m1, accurate for m -> 1
    ee = ellipe(1.0 - m1)
    return (ee / m1 - kk) / (kk - ee)


def elliptic_ratio(curvature_ratio: float) -> float:
    """Axis ratio ``k = minor/major`` of the Hertz ellipse for ``A_minor/A_major >= 1``.

    Solves ``(E(e)/k^2 - K(e)) / (K(e) - E(e)) = A_minor/A_major`` (``e^2 = 1 - k^2``) by
    Brent's method in ``log k``.

    Parameters
    ----------
    curvature_ratio : float
        ``A_minor / A_major >= 1``, the ratio of the relative curvatures.

    Returns
    -------
    float
        ``k = minor / major`` in (0, 1].

    Raises
    ------
    ValueError
        ``curvature_ratio`` is not finite or < 1.
    """
    r = float(curvature_ratio)
    if not math.isfinite(r) or r < 1.0:
        raise ValueError(f"curvature_ratio must be finite and >= 1, got {r!r}")
    if r - 1.0 < 1e-9:  # sphere to ~1e-9 relative
        return 1.0
    # k ~ r^(-2/3) for moderate ratios; bracket in log k.
    lo, hi = -40.0, math.log(1.0 - 1e-9)
    return math.exp(brentq(lambda lk: _ratio_of_curvatures(math.exp(lk)) - r, lo, hi, xtol=1e-15, rtol=1e-15))


def elliptical(force: float, rx: float, ry: float, e_star: float) -> HertzContact:
    """General (elliptical) Hertz contact.

    Parameters
    ----------
    force : float
        Normal force ``F`` (N), > 0.
    rx, ry : float
        Equivalent radii of relative curvature in the ``x`` (rolling) and ``y`` (axial)
        directions (m), > 0: the initial gap is ``x^2/(2 rx) + y^2/(2 ry)``.
        ``math.inf`` is not allowed (line contact has no finite Hertz ellipse).
    e_star : float
        Composite modulus ``E*`` (Pa), > 0.

    Returns
    -------
    HertzContact
        ``a`` along ``x``, ``b`` along ``y``.

    Notes
    -----
    Write the gap as ``A_maj s^2 + A_min t^2`` with ``A_maj = min(1/(2 rx), 1/(2 ry))`` the
    curvature along the major axis (semi-axis ``c``) and ``A_min`` along the minor axis
    (semi-axis ``d = k c``, ``k <= 1``), ``e^2 = 1 - k^2``. Johnson (eqs. 4.36-4.41):

    .. math::

        \\frac{A_{min}}{A_{maj}} = \\frac{E(e)/k^2 - K(e)}{K(e) - E(e)}

    (solved numerically for ``k``), then

    .. math::

        c^3 = \\frac{3 F\\,[K(e) - E(e)]}{2\\pi E^* e^2 A_{maj}},\\quad d = k c,\\quad
        p_0 = \\frac{3F}{2\\pi c d},\\quad \\delta = \\frac{p_0\\, d\\, K(e)}{E^*},

    with ``K`` and ``E`` the complete elliptic integrals of the first and second kind
    (:func:`scipy.special.ellipkm1`, :func:`scipy.special.ellipe`). For ``rx == ry`` this is
    :func:`sphere`.

    Examples
    --------
    Roller on inner race of the source study (design.md): ``rx = 7.68 mm``, ``ry = 4233 mm``,
    ``E* = 115.4 GPa``, ``F = 26.8 kN`` gives ``a ~ 0.33 mm``, ``b ~ 15.9 mm``, ``p0 ~ 2.5 GPa``:

    >>> c = elliptical(26.8e3, 7.68e-3, 4.233, 115.4e9)
    >>> round(c.a * 1e3, 2), round(c.b * 1e3, 1), round(c.p0 / 1e9, 2)
    (0.33, 15.9, 2.46)
    """
    force = check_positive(force, "force")
    rx = check_positive(rx, "rx")
    ry = check_positive(ry, "ry")
    e_star = check_positive(e_star, "e_star")
    ax, ay = 0.5 / rx, 0.5 / ry
    a_maj, a_min = min(ax, ay), max(ax, ay)
    k = elliptic_ratio(a_min / a_maj)
    if k == 1.0:
        return sphere(force, rx, e_star)
    m1 = k * k
    m = 1.0 - m1
    kk = float(ellipkm1(m1))
    ee = float(ellipe(m))
    c = (3.0 * force * (kk - ee) / (2.0 * math.pi * e_star * m * a_maj)) ** (1.0 / 3.0)
    d = k * c
    p0 = 3.0 * force / (2.0 * math.pi * c * d)
    approach = p0 * d * kk / e_star
    a, b = (d, c) if ax >= ay else (c, d)
    return HertzContact(a, b, p0, approach, force / (math.pi * a * b), force)


# ---------------------------------------------------------------------------------------------
# point contact: two further, independent routes to the same ellipse (issue 23)


def curvature_difference(rx: float, ry: float) -> tuple[float, float]:
    """Curvature sum and difference of a contact: ``(sum rho, F(rho))``.

    ``sum rho = 1/R_x + 1/R_y`` (1/m) and ``F(rho) = |1/R_x - 1/R_y| / sum rho`` in [0, 1)
    (Harris & Kotzalas 2007, vol. 1, eqs. 2.26-2.27: the curvature difference of two bodies; for
    a ball on a race ``1/R_x = 2/d +- 1/R_race``, ``1/R_y = 2/d - 1/(f d)``).

    Parameters
    ----------
    rx, ry : float
        Effective radii of curvature of the contact in the two principal planes (m).

    Returns
    -------
    tuple of (float, float)
        ``(sum rho, F(rho))``: curvature sum (1/m) and curvature difference.
    """
    rx = check_positive(rx, "rx")
    ry = check_positive(ry, "ry")
    s = 1.0 / rx + 1.0 / ry
    return s, abs(1.0 / rx - 1.0 / ry) / s


def _f_rho_of_kappa(kappa: float) -> float:
    """``F(rho)`` of the ellipticity ``kappa = major/minor >= 1`` (Harris & Kotzalas 2007, eq. 6.18):
    ``F(rho) = ((kappa^2 + 1) E(m) - 2 K(m)) / ((kappa^2 - 1) E(m))``, ``m = 1 - 1/kappa^2``."""
    m = 1.0 - 1.0 / (kappa * kappa)
    kk, ee = float(ellipk(m)), float(ellipe(m))
    return ((kappa * kappa + 1.0) * ee - 2.0 * kk) / ((kappa * kappa - 1.0) * ee)


#: Largest ellipticity ``major/minor`` :func:`harris_point_contact` solves for (F(rho) -> 1 is a
#: line contact): 1e4.
KAPPA_MAX = 1.0e4


def harris_point_contact(force: float, rx: float, ry: float, e_star: float) -> HertzContact:
    """Hertz ellipse from the curvature-difference equation (an independent route to
    :func:`elliptical`).

    Solves ``F(rho) = ((kappa^2+1) E - 2 K) / ((kappa^2-1) E)`` for ``kappa = major/minor``
    (Brent, ``scipy.special.ellipk``/``ellipe`` with ``m = 1 - 1/kappa^2``), then

    .. math::

        a^* = \\left(\\frac{2 \\kappa^2 E}{\\pi}\\right)^{1/3},\\quad
        b^* = \\left(\\frac{2 E}{\\pi \\kappa}\\right)^{1/3},\\quad
        (\\text{major}, \\text{minor}) = (a^*, b^*)
        \\left(\\frac{3 Q}{2 \\sum\\rho\\, E^*}\\right)^{1/3},\\quad
        p_0 = \\frac{3 Q}{2 \\pi\\, \\text{major}\\, \\text{minor}}

    (Harris & Kotzalas, *Rolling Bearing Analysis* 5th ed. 2007, vol. 1, eqs. 6.34-6.39, written
    with ``E*`` instead of steel's constants). The major axis lies along the direction of the
    larger radius. Parameters and return as :func:`elliptical` (``a`` along ``x``).

    Parameters
    ----------
    force : float
        Normal load ``Q`` (N).
    rx, ry : float
        Effective radii of curvature in the two principal planes (m).
    e_star : float
        Composite modulus ``E*`` (Pa).

    Returns
    -------
    HertzContact
        Semi-axes, peak pressure and approach of the contact.
    """
    force = check_positive(force, "force")
    e_star = check_positive(e_star, "e_star")
    srho, frho = curvature_difference(rx, ry)
    if frho < 1e-12:
        kappa = 1.0
        ee = kk = 0.5 * math.pi
    else:
        kappa = brentq(lambda k: _f_rho_of_kappa(k) - frho, 1.0 + 1e-9, KAPPA_MAX,
                       xtol=1e-14, rtol=1e-15)
        m = 1.0 - 1.0 / (kappa * kappa)
        ee, kk = float(ellipe(m)), float(ellipk(m))
    scale = (3.0 * force / (2.0 * srho * e_star)) ** (1.0 / 3.0)
    major = (2.0 * kappa * kappa * ee / math.pi) ** (1.0 / 3.0) * scale
    minor = (2.0 * ee / (math.pi * kappa)) ** (1.0 / 3.0) * scale
    p0 = 3.0 * force / (2.0 * math.pi * major * minor)
    a, b = (major, minor) if rx >= ry else (minor, major)
    return HertzContact(a, b, p0, p0 * minor * kk / e_star, force / (math.pi * a * b), force)


#: Hamrock & Brewe (1983) curve fits, ``alpha_r = R_major / R_minor >= 1``:
#: ellipticity ``k = HB_K_COEF alpha_r^HB_K_EXP``, second-kind integral
#: ``E = HB_E_CONST + HB_E_COEF / alpha_r``, first-kind ``K = HB_F_CONST + HB_F_COEF ln alpha_r``.
HB_K_COEF, HB_K_EXP = 1.0339, 0.6360
HB_E_CONST, HB_E_COEF = 1.0003, 0.5968
HB_F_CONST, HB_F_COEF = 1.5277, 0.6023


def hamrock_brewe(force: float, rx: float, ry: float, e_star: float) -> HertzContact:
    """Hertz ellipse from the Hamrock & Brewe (1983) closed-form approximations (a check of
    :func:`elliptical` that needs no elliptic integral).

    With ``alpha_r = R_major/R_minor`` (the larger radius over the smaller), ``R`` the curvature
    sum radius ``1/R = 1/R_x + 1/R_y`` and ``E' = 2 E*``:

    .. math::

        k = 1.0339\\,\\alpha_r^{0.6360},\\quad \\mathcal{E} = 1.0003 + 0.5968/\\alpha_r,\\quad
        \\mathcal{F} = 1.5277 + 0.6023 \\ln \\alpha_r ,

    .. math::

        D_{major} = 2\\left(\\frac{6 k^2 \\mathcal{E} Q R}{\\pi E'}\\right)^{1/3},\\quad
        D_{minor} = 2\\left(\\frac{6 \\mathcal{E} Q R}{\\pi k E'}\\right)^{1/3},\\quad
        p_0 = \\frac{6 Q}{\\pi D_{major} D_{minor}},\\quad
        \\delta = \\mathcal{F}\\left[\\frac{9}{2 \\mathcal{E} R}
        \\left(\\frac{Q}{\\pi k E'}\\right)^2\\right]^{1/3}.

    B. J. Hamrock, D. E. Brewe, "Simplified solution for stresses and deformations", J. Lubr.
    Technol. 105 (1983) 171-177; Hamrock, Schmid & Jacobson, *Fundamentals of Machine
    Elements*, ch. 8. Stated accuracy a few per cent (k within ~3 %).

    Parameters
    ----------
    force : float
        Normal load ``Q`` (N).
    rx, ry : float
        Effective radii of curvature in the two principal planes (m).
    e_star : float
        Composite modulus ``E*`` (Pa).

    Returns
    -------
    HertzContact
        Semi-axes, peak pressure and approach of the contact (the approximation's).
    """
    force = check_positive(force, "force")
    rx = check_positive(rx, "rx")
    ry = check_positive(ry, "ry")
    e_prime = 2.0 * check_positive(e_star, "e_star")
    alpha_r = max(rx, ry) / min(rx, ry)
    k = HB_K_COEF * alpha_r ** HB_K_EXP
    ee = HB_E_CONST + HB_E_COEF / alpha_r
    ff = HB_F_CONST + HB_F_COEF * math.log(alpha_r)
    r = 1.0 / (1.0 / rx + 1.0 / ry)
    major = (6.0 * k * k * ee * force * r / (math.pi * e_prime)) ** (1.0 / 3.0)
    minor = (6.0 * ee * force * r / (math.pi * k * e_prime)) ** (1.0 / 3.0)
    p0 = 3.0 * force / (2.0 * math.pi * major * minor)
    approach = ff * (4.5 / (ee * r) * (force / (math.pi * k * e_prime)) ** 2) ** (1.0 / 3.0)
    a, b = (major, minor) if rx >= ry else (minor, major)
    return HertzContact(a, b, p0, approach, force / (math.pi * a * b), force)


def line_half_width(force: float, length: float, rx: float, e_star: float) -> float:
    """Half-width ``b`` (m) of a Hertz line contact, ``b = sqrt(4 Q R_x / (pi l E*))``.

    Two parallel cylinders (a roller and its raceway) of effective radius ``R_x`` pressed
    together by ``Q`` spread evenly over the length ``l`` (``Q / l`` per unit length) touch over
    a strip ``2b`` wide with the elliptical pressure ``p0 sqrt(1 - (x/b)^2)``,
    ``p0 = 2 Q / (pi b l)`` (Johnson 1985, eqs. 4.43-4.45; Harris & Kotzalas 2007, eq. 6.39).

    Parameters
    ----------
    force : float
        Normal load ``Q`` (N), > 0.
    length : float
        Contact length ``l`` (m), > 0.
    rx : float
        Effective radius across the strip ``R_x`` (m), > 0.
    e_star : float
        Composite modulus ``E*`` (Pa), > 0.

    Returns
    -------
    float
        ``b``, m.
    """
    force = check_positive(force, "force")
    length = check_positive(length, "length")
    rx = check_positive(rx, "rx")
    e_star = check_positive(e_star, "e_star")
    return math.sqrt(4.0 * force * rx / (math.pi * length * e_star))
