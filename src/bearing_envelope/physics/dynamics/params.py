"""Parameters of the lumped-parameter bearing model, the defect law's arrays, the geometric slot
law, and the step-size rule (``docs/dynamics.md``).

Every default of the model lives in :data:`STRUCTURE_DEFAULTS` (assumed values, to be identified
for a rig) or comes from the scene through :func:`params_from_scene`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import partial
from typing import Callable

import numpy as np

from ..defect_contact import tabulated_race
from ..geometry import hertz_estimate
from ..kinematics import bearing_rates
from ..loads import (CAGE_PHASE_RAD, ELEMENT_DENSITY_KG_M3, LoadDistribution, centrifugal_force,
                     contact_stiffness, race_compliances, scene_load_distribution, solve_row)
from ..dynamics_option import STRUCTURE_DEFAULTS   # the assumed structure's one home
from .layout import P_NAMES

__all__ = ["DefectLaw", "ElementPit", "DynamicParams", "element_pit_from_scene", "STRUCTURE_DEFAULTS", "slot_drop", "slot_law",
           "params_from_scene", "contact_stiffness", "highest_frequency_hz", "step_size",
           "quasi_static", "contact_damping", "STEPS_PER_PERIOD", "STEPS_PER_PERIOD_LOADED", "rule_steps", "PEAK_LOAD_FACTOR", "MODEL_NAME"]

#: Name of the model a result says made it.
MODEL_NAME = "lumped_dynamic"

#: Step rule: RK4 steps per period of the highest linearised frequency, the smallest count whose
#: envelope lines change <= 1 % when the step halves on every scene of ``python -m benchmarks
#: dynamics_cost --parts rule ball`` (docs/dynamics.md, 2026-12-06): worst 0.64 % from 30 to 60
#: (an element bouncing at the load zone's edge; 1.07 % from 20 to 40; the rig's scenes and the
#: ball pit < 0.01 %).
STEPS_PER_PERIOD = 30.0
#: Step rule of a scene whose every element carries load in its quasi-static solution (no element
#: leaves a race and strikes it again at the load zone's edge, the case that sets
#: :data:`STEPS_PER_PERIOD`): RK4 steps per period, the smallest measured whose envelope lines
#: change <= 1 % when the step halves on every rig scene kind (OR 6:00 and 3:00, IR, ball pit;
#: 12 and 48 kHz; ``python -m benchmarks dynamics_cost --parts rule``, docs/dynamics.md,
#: 2026-12-06: worst 0.056 % from 15 to 30, the ball pit at 48 kHz).
STEPS_PER_PERIOD_LOADED = 15.0
#: The contact load of the step rule, as a multiple of the quasi-static largest element load
#: (impacts load a contact above its static value).
PEAK_LOAD_FACTOR = 2.0


@dataclass(frozen=True)
class DefectLaw:
    """Force of the defective contact ``force_n[i, j] = F(x_m[i], delta_m[j])``.

    ``x_m``: position of the element's contact relative to the pit centre, along the element's
    motion relative to the race (entry edge at negative ``x``), ascending, m. ``delta_m``: the
    contact's approach relative to the undamaged surfaces (the ``delta`` of ``Q = K delta^n``),
    ascending, m. ``force_n`` (N, >= 0): read bilinearly; 0 for ``delta <= 0``, linear beyond
    the ``delta`` nodes (clipped at 0); Hertz outside ``[x_m[0], x_m[-1]]``.

    Raises
    ------
    ValueError
        Nodes not finite, not 1-D ascending with >= 2 of them, a force table of another shape
        than ``(len(x_m), len(delta_m))``, or a negative force.
    """

    x_m: np.ndarray
    delta_m: np.ndarray
    force_n: np.ndarray

    def __post_init__(self):
        for name in ("x_m", "delta_m", "force_n"):
            a = np.ascontiguousarray(getattr(self, name), dtype=float)
            if not np.all(np.isfinite(a)):
                raise ValueError(f"DefectLaw.{name}: got non-finite values; allowed: finite")
            object.__setattr__(self, name, a)
        for name in ("x_m", "delta_m"):
            a = getattr(self, name)
            if a.ndim != 1 or a.size < 2 or np.any(np.diff(a) <= 0):
                raise ValueError(f"DefectLaw.{name}: got shape {a.shape}; allowed: 1-D, >= 2 "
                                 "nodes, strictly ascending")
        if self.force_n.shape != (self.x_m.size, self.delta_m.size):
            raise ValueError(f"DefectLaw.force_n: got shape {self.force_n.shape}; allowed: "
                             f"(len(x_m), len(delta_m)) = {(self.x_m.size, self.delta_m.size)}")
        if np.any(self.force_n < 0):
            raise ValueError("DefectLaw.force_n: got negative forces; allowed: >= 0")

    @classmethod
    def from_table(cls, table) -> "DefectLaw":
        """The law of any object with ``x_m``, ``delta_m`` and ``force_n`` arrays (the
        non-Hertzian table of ``physics/defect_contact.py``).

        Parameters
        ----------
        table : object
            With attributes ``x_m``, ``delta_m``, ``force_n`` (SI).

        Returns
        -------
        DefectLaw
            A validated copy of the arrays.
        """
        return cls(np.array(table.x_m, dtype=float), np.array(table.delta_m, dtype=float),
                   np.array(table.force_n, dtype=float))


def slot_drop(x_m, radius_m: float, width_m: float, depth_m: float) -> np.ndarray:
    """Depth (m) the element's contact can sink at ``x`` over a long slot of width ``w``.

    The element, a circle of radius ``R`` in the rolling plane, rests on the nearer edge
    (``R - sqrt(R^2 - (x - e)^2)`` for the edges ``e = -w/2, +w/2``, the smaller) or on the
    bottom (``depth``): ``R - sqrt(R^2 - w^2/4)`` at the centre (Moazen-Ahmadi & Howard 2016).

    Parameters
    ----------
    x_m : array_like
        Position relative to the slot's centre, m.
    radius_m, width_m, depth_m : float
        Element radius, slot width, slot depth, m (> 0; ``w < 2 R``).

    Returns
    -------
    numpy.ndarray
        Drop, m, 0 outside the slot.

    Raises
    ------
    ValueError
        ``width_m`` outside ``(0, 2 radius_m)`` or ``depth_m`` not > 0.
    """
    if not (0 < width_m < 2 * radius_m) or not depth_m > 0:
        raise ValueError(f"slot_drop: width_m {width_m!r} must be in (0, 2 R = {2 * radius_m}) "
                         f"and depth_m {depth_m!r} > 0")
    x = np.asarray(x_m, dtype=float)
    e = 0.5 * width_m
    d = np.minimum(radius_m - np.sqrt(np.clip(radius_m ** 2 - (x + e) ** 2, 0, None)),
                   radius_m - np.sqrt(np.clip(radius_m ** 2 - (x - e) ** 2, 0, None)))
    return np.where(np.abs(x) < e, np.minimum(d, depth_m), 0.0)


def slot_law(radius_m: float, width_m: float, depth_m: float, k: float, n: float,
             delta_max_m: float, *, nx: int = 401, nd: int = 2001) -> DefectLaw:
    """The geometric defect law of a long slot: ``F = K <delta - h(x)>^n`` with ``h`` the drop of
    :func:`slot_drop`, on ``nx`` x ``nd`` uniform nodes over ``|x| <= w/2``, ``0 <= delta <=
    delta_max_m``.

    Parameters
    ----------
    radius_m, width_m, depth_m : float
        Element radius, slot width and depth, m.
    k, n : float
        Hertz law of the defective contact, ``Q = K delta^n``.
    delta_max_m : float
        Largest approach of the nodes, m.
    nx, nd : int
        Nodes along ``x`` and ``delta``.

    Returns
    -------
    DefectLaw
        The arrays.
    """
    x = np.linspace(-0.5 * width_m, 0.5 * width_m, nx)
    d = np.linspace(0.0, delta_max_m, nd)
    h = slot_drop(x, radius_m, width_m, depth_m)
    f = k * np.clip(d[None, :] - h[:, None], 0.0, None) ** n
    return DefectLaw(x, d, f)


@dataclass(frozen=True)
class ElementPit:
    """A pit on the surface of element 0 (``DynamicParams.defect_race == "element"``): its
    motion with the element's spin and which contact it meets (``docs/dynamics.md``, "A pit on a
    rolling element").

    The element turns relative to the cage by ``beta = spin_per_cage theta_c + lon`` (rolling
    without slip on the fixed outer race); the pit meets the outer contact at ``beta = 0`` and
    the inner at ``beta = pi`` (mod ``2 pi``), where the outer law (``DynamicParams.defect``)
    or :attr:`inner` replaces Hertz. ``lon`` and the pit's axial offset from the rolling track
    are :attr:`phase_rad` and 0 (a spin axis held fixed), or per cage turn from
    :attr:`orientation` (a wandering axis); an off-track pit strikes a contact only within its
    Hertz axial semi-axis ``b = b_1 Q^(1/3)`` (``Q`` the contact's Hertz force at its approach).

    Attributes
    ----------
    inner : DefectLaw or None
        The law of the element's inner contact over the pit (None: ``DynamicParams.defect``).
    spin_per_cage : float or None
        Element spin relative to the cage per radian of cage, ``BSF / FTF``; None: ``R_o / r``.
    phase_rad : float
        ``beta`` at ``theta_c = 0`` when :attr:`orientation` is None, rad.
    orientation : callable or None
        ``turns (int ndarray) -> (track_offset_m, lon_rad)`` for cage turn ``k`` (``theta_c``
        from ``(2k - 1) pi`` to ``(2k + 1) pi``); None: on the track, ``lon = phase_rad``.
    semi_axis_inner_m, semi_axis_outer_m : float
        Hertz axial semi-axis of each contact at 1 N, m (``b_1``; read with an orientation).

    Raises
    ------
    ValueError
        A ``spin_per_cage`` not finite and > 0, a non-finite ``phase_rad``, a semi-axis not
        finite and >= 0 (the message names the field).
    """

    inner: DefectLaw | None = None
    spin_per_cage: float | None = None
    phase_rad: float = 0.0
    orientation: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]] | None = field(
        default=None, compare=False)
    semi_axis_inner_m: float = 0.0
    semi_axis_outer_m: float = 0.0

    def __post_init__(self):
        if self.spin_per_cage is not None and not (math.isfinite(self.spin_per_cage)
                                                   and self.spin_per_cage > 0):
            raise ValueError(f"ElementPit.spin_per_cage: got {self.spin_per_cage!r}; allowed: "
                             "finite > 0 or None")
        if not math.isfinite(self.phase_rad):
            raise ValueError(f"ElementPit.phase_rad: got {self.phase_rad!r}; allowed: finite")
        for name in ("semi_axis_inner_m", "semi_axis_outer_m"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise ValueError(f"ElementPit.{name}: got {v!r}; allowed: finite >= 0")

    def table(self, turn_lo: int, turn_hi: int) -> np.ndarray:
        """The kernels' orientation rows of cage turns ``turn_lo .. turn_hi``.

        Parameters
        ----------
        turn_lo, turn_hi : int
            First and last cage turn.

        Returns
        -------
        numpy.ndarray
            ``(turn_hi - turn_lo + 1, 2)``: track offset (m), longitude (rad); one row
            ``(0, phase_rad)`` without an orientation.
        """
        if self.orientation is None:
            return np.array([[0.0, self.phase_rad]])
        off, lon = self.orientation(np.arange(turn_lo, turn_hi + 1))
        return np.ascontiguousarray(np.stack([off, lon], axis=1), dtype=float)


@dataclass(frozen=True)
class DynamicParams:
    """Everything the model needs, SI (``docs/dynamics.md`` names each symbol).

    Attributes
    ----------
    z : int
        Elements ``Z``.
    element_mass_kg, element_radius_m : float
        Element mass and radius.
    k_inner, k_outer, exponent : float
        ``Q = K delta^n`` of the inner and outer contact.
    contact_damping_ns_m : float
        Viscous damping of each contact while closed.
    clearance_m : float
        Diametral clearance ``P_d`` (negative: preload).
    contact_angle_rad : float
    force_n : float
        Radial load on the shaft, along ``load_angle_rad`` from ``x``.
    centrifugal_n : float
        Centrifugal force of an element (radial), ``m omega_c^2 D/2``.
    inner_race_radius_m, outer_race_radius_m : float
        Raceway contact radii.
    cage_rate_hz, shaft_rate_hz : float
    shaft_*, housing_*, resonator_*, sensor_angle_rad
        Structure (:data:`STRUCTURE_DEFAULTS`).
    defect : DefectLaw or None
        The pitted race's law, or a pitted element's outer contact law.
    defect_race : {"outer", "inner", "element"}
        ``element``: the pit is on element 0 (:class:`ElementPit`).
    defect_angle_rad : float
        Pit centre from ``x`` (outer race), or at ``t = 0`` (inner race, turning with the shaft).
    element_pit : ElementPit or None
        A pit on element 0 (``defect_race == "element"``; None there: ``ElementPit()``).
    cage_angle : callable or None
        ``t -> angle`` (rad) of element 0 (slip); None: ``2 pi f_c t``.

    Raises
    ------
    ValueError
        ``z`` not an integer >= 1; a mass, radius, contact stiffness, exponent or the
        resonator's frequency not finite and > 0; a damping, structure stiffness, force or rate
        not finite and >= 0; a non-finite clearance; a ``defect_race`` other than ``outer``,
        ``inner`` or ``element``; a wandering element pit on a line contact (the message names
        the field).
    """

    z: int
    element_mass_kg: float
    element_radius_m: float
    k_inner: float
    k_outer: float
    exponent: float
    contact_damping_ns_m: float
    clearance_m: float
    contact_angle_rad: float
    force_n: float
    centrifugal_n: float
    inner_race_radius_m: float
    outer_race_radius_m: float
    cage_rate_hz: float
    shaft_rate_hz: float
    shaft_mass_kg: float = STRUCTURE_DEFAULTS["shaft_mass_kg"]
    shaft_stiffness_n_m: float = STRUCTURE_DEFAULTS["shaft_stiffness_n_m"]
    shaft_damping_ns_m: float = STRUCTURE_DEFAULTS["shaft_damping_ns_m"]
    housing_mass_kg: float = STRUCTURE_DEFAULTS["housing_mass_kg"]
    housing_stiffness_n_m: float = STRUCTURE_DEFAULTS["housing_stiffness_n_m"]
    housing_damping_ns_m: float = 2 * STRUCTURE_DEFAULTS["housing_zeta"] * math.sqrt(
        STRUCTURE_DEFAULTS["housing_stiffness_n_m"] * STRUCTURE_DEFAULTS["housing_mass_kg"])
    resonator_hz: float = STRUCTURE_DEFAULTS["resonator_hz"]
    resonator_zeta: float = STRUCTURE_DEFAULTS["resonator_zeta"]
    resonator_mass_kg: float = STRUCTURE_DEFAULTS["resonator_mass_kg"]
    sensor_angle_rad: float = math.radians(STRUCTURE_DEFAULTS["sensor_angle_deg"])
    load_angle_rad: float = 0.0
    defect: DefectLaw | None = None
    defect_race: str = "outer"
    defect_angle_rad: float = 0.0
    cage_angle: Callable[[np.ndarray], np.ndarray] | None = field(default=None, compare=False)
    element_pit: ElementPit | None = None

    def __post_init__(self):
        if int(self.z) != self.z or self.z < 1:
            raise ValueError(f"DynamicParams.z: got {self.z!r}; allowed: an integer >= 1")
        for name in ("element_mass_kg", "element_radius_m", "k_inner", "k_outer", "exponent",
                     "shaft_mass_kg", "housing_mass_kg", "resonator_mass_kg", "resonator_hz",
                     "inner_race_radius_m", "outer_race_radius_m"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"DynamicParams.{name}: got {v!r}; allowed: finite > 0")
        for name in ("contact_damping_ns_m", "shaft_stiffness_n_m", "shaft_damping_ns_m",
                     "housing_stiffness_n_m", "housing_damping_ns_m", "resonator_zeta",
                     "force_n", "centrifugal_n", "cage_rate_hz", "shaft_rate_hz"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise ValueError(f"DynamicParams.{name}: got {v!r}; allowed: finite >= 0")
        if not math.isfinite(self.clearance_m):
            raise ValueError(f"DynamicParams.clearance_m: got {self.clearance_m!r}; allowed: finite")
        if self.defect_race not in ("outer", "inner", "element"):
            raise ValueError(f"DynamicParams.defect_race: got {self.defect_race!r}; allowed: "
                             "outer | inner | element")
        if self.element_pit is not None and self.element_pit.orientation is not None \
                and self.exponent != 1.5:
            raise ValueError(f"DynamicParams.element_pit: a wandering orientation needs a point "
                             f"contact (exponent 1.5), got exponent {self.exponent!r}")

    def with_(self, **changes) -> "DynamicParams":
        """A copy with ``changes`` (validated again).

        Parameters
        ----------
        **changes
            Field -> new value.

        Returns
        -------
        DynamicParams
            The copy.
        """
        return replace(self, **changes)

    @property
    def pit(self) -> ElementPit:
        """The element pit's description (:attr:`element_pit`, or :class:`ElementPit`'s
        defaults)."""
        return self.element_pit if self.element_pit is not None else ElementPit()

    def vector(self, cage_t0: float, cage_dt: float, turn0: int = 0,
               pit_sizes: tuple[int, int, int] = (2, 2, 1)) -> np.ndarray:
        """The scalar vector ``P`` of the kernels (:data:`~.layout.P_NAMES`).

        Parameters
        ----------
        cage_t0, cage_dt : float
            First time and spacing of the cage-angle nodes, s.
        turn0 : int
            Cage turn of the element pit's first orientation row.
        pit_sizes : tuple of int
            Nodes of the element pit's inner law along ``x`` and ``delta``, orientation rows (the
            arrays :func:`~.model.arrays` packs after these scalars).

        Returns
        -------
        numpy.ndarray
            ``P``, float64.
        """
        ca = math.cos(self.contact_angle_rad)
        wr = 2 * math.pi * self.resonator_hz
        pit = self.pit
        drace = {"outer": 1.0, "inner": 2.0, "element": 3.0}[self.defect_race]
        v = {"ms": self.shaft_mass_kg, "ks": self.shaft_stiffness_n_m, "cs": self.shaft_damping_ns_m,
             "mh": self.housing_mass_kg, "kh": self.housing_stiffness_n_m,
             "ch": self.housing_damping_ns_m, "mr": self.resonator_mass_kg,
             "kr": self.resonator_mass_kg * wr ** 2,
             "cr": 2 * self.resonator_zeta * self.resonator_mass_kg * wr,
             "sens_c": math.cos(self.sensor_angle_rad), "sens_s": math.sin(self.sensor_angle_rad),
             "me": self.element_mass_kg, "ki": self.k_inner, "ko": self.k_outer,
             "n": self.exponent, "cc": self.contact_damping_ns_m, "gap": 0.25 * self.clearance_m,
             "ca": ca, "fx": self.force_n * math.cos(self.load_angle_rad),
             "fy": self.force_n * math.sin(self.load_angle_rad), "fc": self.centrifugal_n * ca,
             "ri": self.inner_race_radius_m, "ro": self.outer_race_radius_m,
             "drace": 0.0 if self.defect is None else drace,
             "dang": self.defect_angle_rad, "ws": 2 * math.pi * self.shaft_rate_hz,
             "ct0": cage_t0, "cdt": cage_dt, "n15": 1.0 if self.exponent == 1.5 else 0.0,
             "re": self.element_radius_m,
             "spr": (self.outer_race_radius_m / self.element_radius_m
                     if pit.spin_per_cage is None else pit.spin_per_cage),
             "bi2": pit.semi_axis_inner_m ** 2 * self.k_inner ** (2.0 / 3.0),
             "bo2": pit.semi_axis_outer_m ** 2 * self.k_outer ** (2.0 / 3.0), "turn0": turn0,
             "nx2": pit_sizes[0], "nd2": pit_sizes[1], "nor": pit_sizes[2]}
        return np.array([v[k] for k in P_NAMES], dtype=float)

    @property
    def series_constant(self) -> float:
        """``K`` of the element's two contacts in series, ``(K_i^(-1/n) + K_o^(-1/n))^(-n)``."""
        m = 1.0 / self.exponent
        return (self.k_inner ** -m + self.k_outer ** -m) ** -self.exponent


def quasi_static(params: DynamicParams, phase: float = CAGE_PHASE_RAD) -> LoadDistribution:
    """The quasi-static (Harris/Stribeck) load distribution of the same bearing
    (:func:`bearing_envelope.physics.loads.solve_row`, centrifugal force included).

    Parameters
    ----------
    params : DynamicParams
        The model (its elements, load, stiffnesses, clearance and contact angle).
    phase : float
        Angle of element 0 from the load direction, rad.

    Returns
    -------
    LoadDistribution
        Its ``q`` are the inner contacts' loads.
    """
    m = 1.0 / params.exponent
    fc = params.centrifugal_n * math.cos(params.contact_angle_rad)
    kw = {"centrifugal": fc, "compliances": (params.k_inner ** -m, params.k_outer ** -m)} if fc > 0 else {}
    return solve_row(params.force_n, params.z, math.degrees(params.contact_angle_rad),
                     params.clearance_m, params.series_constant, params.exponent, phase, **kw)


def highest_frequency_hz(params: DynamicParams, peak_factor: float = PEAK_LOAD_FACTOR) -> float:
    """Highest linearised natural frequency (Hz) bounding the model's: an element between its
    two contacts at ``peak_factor`` x the quasi-static largest load (with the centrifugal force
    on the outer contact), ``sqrt((k_i + k_o)/m)/(2 pi)``, or the resonator, the larger.

    Parameters
    ----------
    params : DynamicParams
        The model (its masses and contact stiffnesses).
    peak_factor : float
        Contact load as a multiple of the quasi-static largest (``PEAK_LOAD_FACTOR``).

    Returns
    -------
    float
        Frequency, Hz.
    """
    q = peak_factor * max(float(np.max(quasi_static(params).q)) if params.force_n > 0 else 0.0,
                          params.centrifugal_n, 1.0)
    k = (contact_stiffness(params.k_inner, q, params.exponent)
         + contact_stiffness(params.k_outer, q + params.centrifugal_n, params.exponent))
    return max(math.sqrt(k / params.element_mass_kg) / (2 * math.pi), params.resonator_hz)


def rule_steps(params: DynamicParams) -> float:
    """The step rule's steps per period of ``params``: :data:`STEPS_PER_PERIOD_LOADED` when every
    element carries load in the quasi-static solution, else :data:`STEPS_PER_PERIOD`.

    Parameters
    ----------
    params : DynamicParams
        The model (its load, clearance and contact stiffnesses).

    Returns
    -------
    float
        Steps per period of :func:`highest_frequency_hz`.
    """
    loaded = params.force_n > 0 and float(np.min(quasi_static(params).q)) > 0.0
    return STEPS_PER_PERIOD_LOADED if loaded else STEPS_PER_PERIOD


def step_size(params: DynamicParams, steps_per_period: float | None = None,
              peak_factor: float = PEAK_LOAD_FACTOR) -> float:
    """The step rule: ``dt = 1 / (steps_per_period x f_max)`` with ``f_max`` from
    :func:`highest_frequency_hz`.

    Parameters
    ----------
    params : DynamicParams
        The model (its masses and contact stiffnesses).
    steps_per_period : float, optional
        RK4 steps per period of ``f_max`` (None: the scene's, :func:`rule_steps`).
    peak_factor : float
        As :func:`highest_frequency_hz`.

    Returns
    -------
    float
        Step, s.

    Raises
    ------
    ValueError
        ``steps_per_period`` < 4 (RK4 is unstable near 2.2 steps per period).
    """
    if steps_per_period is None:
        steps_per_period = rule_steps(params)
    if not steps_per_period >= 4:
        raise ValueError(f"steps_per_period: got {steps_per_period!r}; allowed: >= 4 (RK4 is "
                         "unstable near 2.2)")
    return 1.0 / (steps_per_period * highest_frequency_hz(params, peak_factor))


def _element_mass(bearing) -> float:
    d = 1e-3 * bearing.roller_diameter_mm
    vol = math.pi * d ** 3 / 6.0 if bearing.kind == "ball" else \
        0.25 * math.pi * d ** 2 * 1e-3 * bearing.roller_length_mm
    return ELEMENT_DENSITY_KG_M3 * vol


def element_pit_from_scene(scene, inner: DefectLaw | None = None) -> ElementPit:
    """The element pit of ``scene``'s rolling-element defect: the spin ``BSF / FTF``
    (:func:`~bearing_envelope.physics.kinematics.bearing_rates`), and with ``defect.spin_axis:
    wandering`` the location's own orientation rule (:mod:`~bearing_envelope.physics.locations.
    rolling_element`: redrawn once per cage turn where the ball is least loaded, seeded by
    ``defect.spin_seed``, only when :func:`~bearing_envelope.physics.locations.rolling_element.
    spin_is_free` under the scene's quasi-static load law; else turn 0's throughout) and each
    contact's Hertz axial semi-axis at 1 N.

    Parameters
    ----------
    scene : Scene
        A rolling-element defect (its bearing, speed, load and ``defect.spin_axis``,
        ``spin_seed``).
    inner : DefectLaw, optional
        The inner contact's law (None: the outer law for both).

    Returns
    -------
    ElementPit
        Its kinematics.
    """
    from ..locations.rolling_element import spin_is_free   # locations import much; read here

    b = scene.bearing
    r = bearing_rates(scene.operation.shaft_rate_hz, b.rollers_per_row, b.roller_diameter_mm,
                      b.pitch_diameter_mm, b.contact_angle_deg, bpfi=scene.bpfi_hz)
    orient, b1 = None, (0.0, 0.0)
    if scene.defect.spin_axis == "wandering":
        free = spin_is_free(scene_load_distribution(scene))
        orient = partial(_turn_orientations, scene, free)
        b1 = tuple(hertz_estimate(scene.for_race(race), 1.0).b for race in ("inner", "outer"))
    return ElementPit(inner=inner, spin_per_cage=r["bsf"] / r["ftf"], orientation=orient,
                      semi_axis_inner_m=b1[0], semi_axis_outer_m=b1[1])


def _turn_orientations(scene, free: bool, turns: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(track offset m, longitude rad)`` of cage turns ``turns`` from the location's own rule
    (:func:`~bearing_envelope.physics.locations.rolling_element.rolling_element_kinematics` at
    each turn's centre ``theta_c = 2 pi k``: its offset in the outer contact is ``r wrap(beta +
    lon)``, ``beta`` the rolling turn there)."""
    from ..locations.rolling_element import rolling_element_kinematics

    b = scene.bearing
    theta = 2.0 * math.pi * np.asarray(turns, dtype=float)
    kin = rolling_element_kinematics(scene, theta, redraw=free)
    beta = theta * b.outer_race_radius_m / b.roller_radius_m
    lon = np.mod(kin["offset_outer"] / b.roller_radius_m - beta, 2.0 * math.pi)
    return kin["track_offset"], lon


def params_from_scene(scene, *, defect: DefectLaw | None = None,
                      defect_inner: DefectLaw | None = None, centrifugal: bool = True,
                      slip: bool = True, **overrides) -> DynamicParams:
    """Model parameters of ``scene``'s bearing (one row, its share of the load).

    Contacts from :func:`~bearing_envelope.physics.loads.race_compliances` (Hertz point contact
    for balls, Palmgren line contact for rollers), ``K_j = c_j^(-n)``; element mass from
    :data:`~bearing_envelope.physics.loads.ELEMENT_DENSITY_KG_M3`; the cage angle from
    :func:`bearing_envelope.physics.history.cage_angle` (the scene's slip); the structure from
    :data:`STRUCTURE_DEFAULTS`; the pit at ``defect.position_deg`` of the scene's race, or on
    element 0 (a rolling-element defect: :func:`element_pit_from_scene`).

    Parameters
    ----------
    scene : Scene
        The case's scene: bearing geometry, material, load, shaft rate, cage slip and the
        defect's race and position.
    defect : DefectLaw, optional
        The defect law (None: healthy); a rolling-element pit's outer contact law.
    defect_inner : DefectLaw, optional
        A rolling-element pit's inner contact law (None: ``defect`` for both contacts).
    centrifugal : bool
        Include the elements' centrifugal force.
    slip : bool
        The scene's cage slip (else ``2 pi f_c t``).
    **overrides
        Any :class:`DynamicParams` field.

    Returns
    -------
    DynamicParams
        The model in SI units, the structure at :data:`STRUCTURE_DEFAULTS` unless
        ``overrides`` set it.
    """
    from ..history import cage_angle   # history imports much; read it only here

    b = scene.bearing
    n = 1.5 if b.kind == "ball" else 10.0 / 9.0
    ci, co = race_compliances(scene)
    me = _element_mass(b)
    ld = scene_load_distribution(scene)
    spins = scene.defect.fault_location.spins
    kw = dict(z=b.rollers_per_row, element_mass_kg=me, element_radius_m=b.roller_radius_m,
              k_inner=ci ** -n, k_outer=co ** -n, exponent=n, contact_damping_ns_m=0.0,
              clearance_m=1e-6 * b.radial_clearance_um, contact_angle_rad=b.contact_angle_rad,
              force_n=ld.force_row,
              centrifugal_n=centrifugal_force(b, scene.cage_rate_hz) if centrifugal else 0.0,
              inner_race_radius_m=b.inner_race_radius_m, outer_race_radius_m=b.outer_race_radius_m,
              cage_rate_hz=scene.cage_rate_hz, shaft_rate_hz=scene.operation.shaft_rate_hz,
              defect=defect, defect_race="element" if spins else tabulated_race(scene),
              element_pit=element_pit_from_scene(scene, defect_inner) if spins else None,
              defect_angle_rad=math.radians(scene.defect.position_deg),
              cage_angle=partial(cage_angle, scene)
              if slip and scene.operation.cage_slip_percent > 0 else None)
    kw.update(overrides)
    p = DynamicParams(**kw)
    if "contact_damping_ns_m" not in overrides:
        p = p.with_(contact_damping_ns_m=contact_damping(p, STRUCTURE_DEFAULTS["contact_zeta"]))
    return p


def contact_damping(params: DynamicParams, zeta: float) -> float:
    """Contact damping (N s/m) giving the element's mode between its two contacts the damping
    ratio ``zeta`` at the quasi-static largest load: ``c = zeta sqrt((k_i + k_o) m)`` (each of
    the two contacts carries ``c``, so the mode sees ``2c``).

    Parameters
    ----------
    params : DynamicParams
        The model (its element mass and contact stiffnesses).
    zeta : float
        Damping ratio, >= 0.

    Returns
    -------
    float
        ``c``, N s/m.
    """
    q = max(float(np.max(quasi_static(params).q)) if params.force_n > 0 else 0.0, 1.0)
    k = (contact_stiffness(params.k_inner, q, params.exponent)
         + contact_stiffness(params.k_outer, q + params.centrifugal_n, params.exponent))
    return zeta * math.sqrt(k * params.element_mass_kg)
