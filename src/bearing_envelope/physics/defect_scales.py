"""The defect's characteristic scales: the numbers that decide whether a defect's contact needs
the dynamics (:class:`DefectScales`, :func:`defect_scales`; docs/dynamics.md), from the
element's closed-form contact law (Hertz point contact for balls, Hertz's line-contact
half-width and Palmgren's load-deflection law for rollers) and the rigid geometry, no contact
solve: the Hertz constant of one element's contact
(:func:`hertz_constant`), the rigid drop into the pit (:func:`rigid_drop`), the element's mass
(:func:`element_mass`) and the race whose contact with the pit is tabulated
(:func:`tabulated_race`). The defect contact law that reads them:
:mod:`bearing_envelope.physics.defect_contact`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..contact import hertz
from .geometry import axial_separation, defect_depth
from .loads import (ELEMENT_DENSITY_KG_M3, contact_law, contact_stiffness, race_compliances,
                    scene_load_distribution)
from .scene import Scene

__all__ = ["hertz_constant", "rigid_drop", "RIGID_DROP_POINTS", "tabulated_race", "element_mass",
           "DefectScales", "defect_scales"]


def hertz_constant(scene: Scene, race: str | None = None) -> float:
    """Closed-form Hertz constant ``K`` (N m^-1.5) of ``F = K delta^1.5`` for the contact of
    one element with ``race`` (default: the scene's modelled contact), from
    :func:`bearing_envelope.contact.hertz.elliptical` at 1 N (``delta ~ F^(2/3)`` exactly).

    Parameters
    ----------
    scene : Scene
        The scene (curvatures, materials).
    race : {"inner", "outer"}, optional
        The race; None = ``scene.bearing.contact_race``.

    Returns
    -------
    float
        ``K`` (N m^-1.5).
    """
    b = scene.bearing
    r = race or b.contact_race
    c = hertz.elliptical(1.0, b.rx_for(r), b.ry_for(r), scene.material.e_star_pa).approach
    return c ** -1.5


def rigid_drop(scene: Scene, *, spacing_m: float = 0.25e-6) -> float:
    """Approach (m) at which a rigid element centred over the pit first touches the race: the
    smallest initial gap ``x^2/(2 R_x) + s(y) + depth(x, y)`` (the pit's point depth, not cell
    averaged) over a grid of ``spacing_m`` covering the pit's footprint and a margin. For a
    long slot of width ``w`` deeper than the drop this is ``w^2/(8 R_x)`` (at the slot's rims,
    lowered by their radius); for a round pit the element rests on the pit's rim where the
    axial curvature is weakest.

    Parameters
    ----------
    scene : Scene
        The scene with its pit (0 for a healthy race).
    spacing_m : float
        Least sampling step (m); coarser along an axis where the pit spans more than
        :data:`RIGID_DROP_POINTS` steps.

    Returns
    -------
    float
        The drop (m); 0 when the pit leaves the contact's centre on the race.
    """
    d = scene.defect
    if not d.active:
        return 0.0
    b = scene.bearing
    yd = 1e-3 * d.axial_position_mm
    pts = []
    for ext in (d.extent_x_m, d.extent_y_m):      # at most RIGID_DROP_POINTS per axis
        step = max(spacing_m, ext / RIGID_DROP_POINTS)
        half = 0.5 * ext + 4 * step
        pts.append(np.arange(-half, half + 0.5 * step, step))
    x, y = pts[0], yd + pts[1]
    g = (x * x / (2.0 * b.rx_m))[:, None] + axial_separation(b, y)[None, :] \
        + defect_depth(d, x[:, None], (y - yd)[None, :])
    # the contact's centre (a pit off the element's track leaves it on the race)
    g0 = float(axial_separation(b, np.zeros(1))[0] + defect_depth(d, 0.0, -yd))
    return min(float(np.min(g)), g0)


#: Largest number of sample points per axis of :func:`rigid_drop` (its spacing grows beyond it).
RIGID_DROP_POINTS = 2000


def tabulated_race(scene: Scene) -> str:
    """The race whose contact with the pit is tabulated: the last race the location's defect
    passes (inner race: the inner; outer race and rolling element: the outer).

    Parameters
    ----------
    scene : Scene
        The scene (its defect's location).

    Returns
    -------
    str
        ``"inner"`` or ``"outer"``.
    """
    return scene.defect.fault_location.races[-1]


def element_mass(bearing, density_kg_m3: float = ELEMENT_DENSITY_KG_M3) -> float:
    """Mass (kg) of one rolling element: ``rho pi d^3 / 6`` (ball) or ``rho pi d^2 L / 4``
    (roller of length ``roller_length_mm``).

    Parameters
    ----------
    bearing : Bearing
        Its ``kind``, ``roller_diameter_mm``, ``roller_length_mm``.
    density_kg_m3 : float
        Element density (default 52100 steel,
        :data:`~bearing_envelope.physics.loads.ELEMENT_DENSITY_KG_M3`).

    Returns
    -------
    float
        The mass (kg).
    """
    d = 1e-3 * bearing.roller_diameter_mm
    vol = math.pi * d ** 3 / 6.0 if bearing.kind == "ball" else \
        0.25 * math.pi * d * d * 1e-3 * bearing.roller_length_mm
    return density_kg_m3 * vol


@dataclass(frozen=True)
class DefectScales:
    """The scales that decide whether a defect's contact needs the dynamics (SI).

    Attributes
    ----------
    element_load_n : float
        Load of the element's contact with the pitted race where it meets the pit (N): an
        outer-race pit at its ``position_deg``, an inner-race or rolling-element pit at the
        load zone's centre (where its largest event is).
    other_load_n : float
        The same element's load on the other race (N).
    contact_half_width_m, contact_half_length_m : float
        Semi-axes of the pitted contact along rolling and along the axis at ``element_load_n``
        (m): the Hertz ellipse's (balls); the line contact's half-width
        ``sqrt(4 Q R_x / (pi l E*))`` and half the roller length (rollers).
    pit_length_m : float
        Pit extent along rolling ``w_x`` (m).
    pit_over_contact : float
        ``w_x / (2 a_x)``: > 1, the pit is longer than the contact (the element can drop).
    rigid_drop_m : float
        :func:`rigid_drop` (m).
    static_approach_m : float
        Approach of the pitted contact at ``element_load_n`` (m): Hertz's (balls), Palmgren's
        ``c Q^(9/10)`` per contact (rollers, :func:`~.loads.race_compliances`).
    drop_over_approach : float
        ``rigid_drop / static_approach``: > 1, centred over the pit the element loses contact
        with the pitted race unless it moves.
    surface_speed_m_s : float
        Speed of the contact over the pitted surface (:attr:`Scene.defect_speed_m_s`).
    event_duration_s : float
        ``w_x / v``: time the contact centre takes to cross the pit (s).
    element_mass_kg : float
        :func:`element_mass`.
    stiffness_n_m, other_stiffness_n_m : float
        Linearised contact stiffness ``n K^(1/n) Q^((n-1)/n)`` of the pitted and the other
        contact (N/m, :func:`~.loads.contact_stiffness`; ``K`` of one contact,
        :func:`~.loads.race_compliances`): ``1.5 K^(2/3) Q^(1/3)`` (balls, Hertz) or
        ``(10/9) K^(9/10) Q^(1/10)`` (rollers, Palmgren's line contact).
    natural_frequency_hz : float
        ``sqrt((k + k_other)/m) / (2 pi)``: the element between its two contacts (both resist
        its radial motion; rings held fixed).
    natural_period_s : float
        ``1 / natural_frequency_hz`` (inf for an unloaded element).
    event_over_period : float
        ``event_duration_s / natural_period_s``: below ~1 the event is shorter than the
        contact's natural period (quasi-static reasoning fails).
    fall_time_s : float
        ``sqrt(2 m drop / Q)``: time to fall the rigid drop under the constant force
        ``element_load_n`` (inf at zero load); above ``event_duration_s`` the element cannot
        reach the bottom of its drop before the exit edge.
    """

    element_load_n: float
    other_load_n: float
    contact_half_width_m: float
    contact_half_length_m: float
    pit_length_m: float
    pit_over_contact: float
    rigid_drop_m: float
    static_approach_m: float
    drop_over_approach: float
    surface_speed_m_s: float
    event_duration_s: float
    element_mass_kg: float
    stiffness_n_m: float
    other_stiffness_n_m: float
    natural_frequency_hz: float
    natural_period_s: float
    event_over_period: float
    fall_time_s: float


def _element_loads(scene: Scene) -> tuple[float, float, str]:
    """``(Q on the pitted race, Q on the other, pitted race)`` where the pit meets its event."""
    ld = scene_load_distribution(scene)
    d = scene.defect
    race = tabulated_race(scene)
    psi = math.radians(d.position_deg) if d.fault_location.positioned else 0.0
    q = {r: float(ld.load_at(psi, r)) for r in ("inner", "outer")}
    return q[race], q["outer" if race == "inner" else "inner"], race


def _semi_axes(scene: Scene, race: str, q: float) -> tuple[float, float, float]:
    """``(a_x, a_y, approach)`` (m) of the element's contact with ``race`` at load ``q`` (N):
    the Hertz ellipse (balls), or the line contact's half-width, half the roller length and
    Palmgren's approach ``c q^(1/n)`` (rollers); zeros at zero load."""
    if not q > 0:
        return 0.0, 0.0, 0.0
    b, e = scene.bearing, scene.material.e_star_pa
    if b.kind == "ball":
        h = hertz.elliptical(q, b.rx_for(race), b.ry_for(race), e)
        return h.a, h.b, h.approach
    c = race_compliances(scene)[0 if race == "inner" else 1]
    length = 2.0 * b.half_length_m
    return (hertz.line_half_width(q, length, b.rx_for(race), e), b.half_length_m,
            c * q ** (1.0 / contact_law(scene)[1]))


def defect_scales(scene: Scene) -> DefectScales:
    """The defect's characteristic scales (:class:`DefectScales`) for ``scene``.

    Parameters
    ----------
    scene : Scene
        The scene with its pit (bearing, load, operation, defect).

    Returns
    -------
    DefectScales
        Contact size against pit length, element load, event duration against the contact's
        natural period, drop against static approach.
    """
    q, q_other, race = _element_loads(scene)
    sc = scene.for_race(race)
    other = "outer" if race == "inner" else "inner"
    n = contact_law(sc)[1]
    comp = dict(zip(("inner", "outer"), race_compliances(sc)))
    k, k_o = (contact_stiffness(comp[r] ** -n, qq, n) for r, qq in ((race, q), (other, q_other)))
    a_x, a_y, delta = _semi_axes(sc, race, q)
    w, v = sc.defect.extent_x_m, sc.defect_speed_m_s
    m = element_mass(sc.bearing)
    drop = rigid_drop(sc)
    fn = math.sqrt((k + k_o) / m) / (2.0 * math.pi)
    period = 1.0 / fn if fn > 0 else math.inf
    return DefectScales(
        element_load_n=q, other_load_n=q_other, contact_half_width_m=a_x,
        contact_half_length_m=a_y, pit_length_m=w,
        pit_over_contact=w / (2.0 * a_x) if a_x > 0 else math.inf, rigid_drop_m=drop,
        static_approach_m=delta, drop_over_approach=drop / delta if delta > 0 else math.inf,
        surface_speed_m_s=v, event_duration_s=w / v, element_mass_kg=m,
        stiffness_n_m=k, other_stiffness_n_m=k_o,
        natural_frequency_hz=fn, natural_period_s=period,
        event_over_period=(w / v) / period, fall_time_s=math.sqrt(2.0 * m * drop / q)
        if q > 0 else math.inf)
