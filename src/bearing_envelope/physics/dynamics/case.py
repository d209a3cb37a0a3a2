"""A case simulated by the model its scene needs (``docs/dynamics.md``, "Model only what the scene
needs"): :func:`simulate_case` runs the quasi-static history
(:func:`bearing_envelope.physics.history.simulate`) or the dynamic model, by
:func:`~.criterion.model_choice`; :func:`simulate_dynamic` is the dynamic path: the scene's
parameters (:func:`~.params.params_from_scene` with the scene's structure overrides), the
defect's non-Hertzian law (:func:`bearing_envelope.physics.defect_contact.defect_table` at the
case's fidelity, joined to the model's healthy contact by :func:`joined_law`), :func:`~.model.simulate_dynamics` at the scene's acquisition ``fs`` and record
length. Its :class:`DynamicHistory` is what :func:`bearing_envelope.io.write_case` stores.
"""

from __future__ import annotations

import dataclasses
import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from ..acquisition import add_noise
from ..defect_contact import defect_table
from ..fidelity import Fidelity, fidelity_from
from ..loads import LoadDistribution, scene_load_distribution
from .criterion import DYNAMIC, ModelChoice, model_choice
from .model import modal_oversample, simulate_dynamics
from .params import (STRUCTURE_DEFAULTS, DefectLaw, DynamicParams, contact_damping,
                     params_from_scene, step_size)

__all__ = ["DynamicHistory", "DYNAMIC_SIGNAL_UNITS", "DYNAMIC_SIGNAL_DESCRIPTIONS",
           "NOISY_SIGNALS", "scene_params", "case_params", "joined_law", "JOINED_DELTA_NODES", "simulate_dynamic", "simulate_case", "dynamic_cost",
           "CPU_S_PER_ELEMENT_STEP"]

#: CPU seconds per RK4 step and element, measured (``python -m benchmarks dynamics_cost
#: --parts cost --full``, docs/dynamics.md, 2026-12-06 05:05 UTC, load 4-8, the fused loop with
#: the pit read near it only): the 6205's 10 s record at 12 kHz with the 0.007 in pit,
#: 18,083,835 steps of 0.556 us for its 9 balls in 19.67 CPU s (2.0 CPU s per record second).
CPU_S_PER_ELEMENT_STEP = 19.67 / 18083835 / 9

#: The 1-D signals of a dynamic case (``/signals``) and their units.
DYNAMIC_SIGNAL_UNITS = {
    "housing_force_x": "N", "housing_force_y": "N",
    "housing_displacement_x": "m", "housing_displacement_y": "m",
    "housing_acceleration_x": "m/s^2", "housing_acceleration_y": "m/s^2",
    "sensor_acceleration": "m/s^2", "sensor_displacement": "m", "defect_force": "N"}

DYNAMIC_SIGNAL_DESCRIPTIONS = {
    "housing_force_x": "force the elements pass to the outer ring with the housing, along the load",
    "housing_force_y": "force the elements pass to the outer ring with the housing, across the load",
    "housing_displacement_x": "outer ring with housing, displacement along the load",
    "housing_displacement_y": "outer ring with housing, displacement across the load",
    "housing_acceleration_x": "outer ring with housing, acceleration along the load",
    "housing_acceleration_y": "outer ring with housing, acceleration across the load",
    "sensor_acceleration": "the resonator (sensor structure), absolute acceleration along the "
                           "sensor axis",
    "sensor_displacement": "the resonator (sensor structure), absolute displacement along the "
                           "sensor axis",
    "defect_force": "force of the element contact over the pit (0 when none is on it)"}

#: Signals that carry the scene's noise (``operation.noise_snr_db``; the clean ones beside them).
NOISY_SIGNALS = ("sensor_acceleration", "housing_force_x", "housing_force_y")


@dataclass
class DynamicHistory:
    """A case simulated by the dynamic model (what :func:`bearing_envelope.io.write_case` stores).

    Attributes
    ----------
    scene : Scene
    fidelity : Fidelity
        The fidelity of the defect contact law.
    time : ndarray
        ``arange(n) / fs``, s.
    signals : dict of str to ndarray
        :data:`DYNAMIC_SIGNAL_UNITS`, each ``(n,)`` at ``fs`` (with noise: the noisy ones of
        :data:`NOISY_SIGNALS`, the clean ones under ``<name>_clean``).
    element_load_n : ndarray
        ``(n, Z)``: each element's outer contact load, N.
    model : dict
        The model that made them: ``model`` (``lumped_dynamic``), ``step_s``, ``steps``,
        ``oversample``, ``cpu_s``, ``defect_force_peak_n``, ``structure`` (the assumed
        structure, SI), ``choice`` (the criterion's line), ``defect_law`` (the table's metadata).
    load_distribution : LoadDistribution
        The quasi-static load zone (the initial state's).
    stats : dict
        ``wall_seconds``, ``cpu_seconds``, ``table_cpu_seconds``.
    acquisition : dict
        ``mode`` and ``oversample`` of the record.
    """

    scene: object
    fidelity: Fidelity
    time: np.ndarray
    signals: dict
    element_load_n: np.ndarray
    model: dict
    load_distribution: LoadDistribution
    stats: dict = field(default_factory=dict)
    acquisition: dict = field(default_factory=dict)


def _structure(scene) -> dict:
    """The assumed structure with the scene's overrides (``scene.dynamics.structure``)."""
    return {**STRUCTURE_DEFAULTS, **dict(scene.dynamics.structure)}


def scene_params(scene, defect: DefectLaw | None = None) -> DynamicParams:
    """:func:`~.params.params_from_scene` with the structure of ``scene.dynamics.structure``
    (keys of :data:`~.params.STRUCTURE_DEFAULTS`; damping ratios turned into dampings).

    Parameters
    ----------
    scene : Scene
        The case's scene.
    defect : DefectLaw, optional
        The defect law (None: healthy).

    Returns
    -------
    DynamicParams
        The model, SI.
    """
    s = _structure(scene)
    p = params_from_scene(scene, defect=defect,
                          shaft_mass_kg=s["shaft_mass_kg"], shaft_stiffness_n_m=s["shaft_stiffness_n_m"],
                          shaft_damping_ns_m=s["shaft_damping_ns_m"], housing_mass_kg=s["housing_mass_kg"],
                          housing_stiffness_n_m=s["housing_stiffness_n_m"],
                          housing_damping_ns_m=2 * s["housing_zeta"] * math.sqrt(
                              s["housing_stiffness_n_m"] * s["housing_mass_kg"]),
                          resonator_hz=s["resonator_hz"], resonator_zeta=s["resonator_zeta"],
                          resonator_mass_kg=s["resonator_mass_kg"],
                          sensor_angle_rad=math.radians(s["sensor_angle_deg"]))
    return p.with_(contact_damping_ns_m=contact_damping(p, s["contact_zeta"]))


#: Approach nodes of the joined law (uniform from 0 to the table's largest approach): the
#: kernel reads bilinearly, and a power law read linearly between the table's 10-16 approach
#: nodes is off by up to ``n (n - 1)/8 (d delta/delta)^2`` (0.2 % of the default roller's load
#: at its static approach, 50 N where the pit changes 3 N; 1.1 % measured for the 6205's ball at
#: draft); on 2001 nodes by under 1e-7.
JOINED_DELTA_NODES = 2001


def joined_law(table, params: DynamicParams, n_approach: int = JOINED_DELTA_NODES) -> DefectLaw:
    """The defect law of ``table`` joined to the model's healthy contact:
    ``F(x, delta) = r(x, delta_t) K delta^n`` on ``n_approach`` uniform approach nodes, with ``K, n``
    the model's law of the pitted race, ``r = F_table / F_healthy`` the pit's ratio (read linearly
    between the table's approach nodes: ``r`` is smooth where ``F`` is a power law) and
    ``delta_t = F_healthy^-1(K delta^n)`` the table's approach at which its healthy contact
    carries the model's force (``F_healthy^(1/n)`` read linearly between the nodes). The reading
    is then the model's law outside the ``x`` range and at its ends (no step where an element
    enters the table) and inside it the pit removes the
    share of the element's load that the table gives at that load (what the quasi-static model
    reads, ``P(Q, x)`` at the load ``Q``).

    Measured (docs/dynamics.md, "Model only what the scene needs"): for a ball the table's
    healthy solve is within 5e-4 of Hertz, but its reading between the draft table's approach
    nodes is off Hertz by 1.1 % at the 6205's static approach at 6:00 (1.9 % between half and
    twice it): a 0.6 N step where an element enters the table, against the 3 N the 0.007 in
    pit removes; for the default sweep's crowned
    roller the healthy solve carries 15-72 % of Palmgren's line-contact law at the same approach
    (draft, 250 kN): read as it is, the force would step by up to 85 % of the roller's load
    where a roller enters the table, a spurious impulse at every passage; and its ratio read at
    the model's approach (22.2 um at 250 kN against the solved contact's 36.6 um for the same
    26.9 kN) removed 2.3 times the share the table gives at that load at the pit centre (1.5
    times at 750 kN; 9.3 / 4.8 dB on the housing force's BPFI line in fs/4-3fs/8).

    Parameters
    ----------
    table : DefectContactTable
        ``x_m``, ``delta_m``, ``force_n``, ``healthy_force_n`` (ascending where positive),
        ``race``.
    params : DynamicParams
        The model (its ``k_inner``/``k_outer`` and ``exponent``).
    n_approach : int
        Approach nodes of the joined law (>= 2).

    Returns
    -------
    DefectLaw
        The joined arrays (``x_m`` the table's).

    Raises
    ------
    ValueError
        ``healthy_force_n`` not ascending where it carries force.
    """
    k = params.k_inner if table.race == "inner" else params.k_outer
    d = np.asarray(table.delta_m, dtype=float)
    healthy = np.asarray(table.healthy_force_n, dtype=float)
    f = np.asarray(table.force_n, dtype=float)
    ok = healthy > 0
    bad = np.flatnonzero(np.diff(healthy[ok]) <= 0)
    if bad.size:
        lo, hi = float(healthy[ok][bad[0]]), float(healthy[ok][bad[0] + 1])
        raise ValueError(f"joined_law: table.healthy_force_n got {hi:g} N after {lo:g} N; "
                         "allowed: ascending where positive")
    ratio = np.ones_like(f)
    ratio[:, ok] = f[:, ok] / healthy[ok]
    first = int(np.argmax(ok))            # below the first loaded node: its ratio
    ratio[:, :first] = ratio[:, first:first + 1]
    fine = np.linspace(0.0, float(d[-1]), int(n_approach))
    force = k * fine ** params.exponent
    # the table's approach carrying the model's force (clamped to the last node beyond it),
    # read linearly in F^(1/n): exact for a healthy force that is a power law of exponent n
    root = 1.0 / params.exponent
    f_nodes = np.concatenate(([0.0], healthy[ok] ** root))
    d_nodes = np.concatenate(([d[first - 1] if first else 0.0], d[ok]))
    at = np.interp(force ** root, f_nodes, d_nodes)
    r = np.array([np.interp(at, d, row) for row in ratio])
    return DefectLaw(np.array(table.x_m, dtype=float), fine, r * force[None, :])


def case_params(scene, fidelity: Fidelity | str | None = None):
    """The dynamic model of a case: :func:`scene_params` with the pit's joined law
    (:func:`joined_law` of :func:`~bearing_envelope.physics.defect_contact.defect_table`); a pit
    on a rolling element meets both races, each with its own table (the outer as ``defect``,
    the inner as ``element_pit.inner``).

    Parameters
    ----------
    scene : Scene
        The case.
    fidelity : Fidelity, preset name or None (``standard``)
        The defect tables' fidelity.

    Returns
    -------
    (DynamicParams, DefectContactTable or None)
        The model and the pitted race's table (None without a defect).
    """
    fid = fidelity_from(fidelity)
    table = defect_table(scene, fid) if scene.defect.active else None
    p = scene_params(scene)
    if table is not None:
        p = p.with_(defect=joined_law(table, p))
        if p.defect_race == "element":
            inner = defect_table(scene, fid, race="inner")
            p = p.with_(element_pit=dataclasses.replace(p.element_pit,
                                                        inner=joined_law(inner, p)))
    return p, table


def simulate_dynamic(scene, fidelity: Fidelity | str | None = None, *,
                     choice: ModelChoice | None = None) -> DynamicHistory:
    """Simulate one case with the dynamic model at the scene's ``fs`` and record length.

    Parameters
    ----------
    scene : Scene
        The case (bearing, load, operation: ``fs_hz``, ``revolutions``, acquisition, noise;
        defect; ``dynamics.structure``).
    fidelity : Fidelity, preset name or None (``standard``)
        The defect contact law's fidelity (:func:`~bearing_envelope.physics.defect_contact.
        defect_table`).
    choice : ModelChoice, optional
        The criterion's line to store (default: :func:`~.criterion.model_choice` of ``scene``).

    Returns
    -------
    DynamicHistory
        The sensor's signals, element loads, defect force, and the model that made them.
    """
    fid = fidelity_from(fidelity)
    t0, c0 = _time.perf_counter(), _time.process_time()
    choice = choice or model_choice(scene)
    p, table = case_params(scene, fid)
    c_table = _time.process_time() - c0
    op = scene.operation
    n = scene.n_samples
    acq = op.acquisition
    over = None if acq.oversample == "auto" else int(acq.oversample)
    r = simulate_dynamics(p, n / op.fs_hz, op.fs_hz, acquisition_mode=acq.mode, oversample=over)
    sig = {"housing_force_x": r.housing_force_n[:, 0], "housing_force_y": r.housing_force_n[:, 1],
           "housing_displacement_x": r.housing_displacement_m[:, 0],
           "housing_displacement_y": r.housing_displacement_m[:, 1],
           "housing_acceleration_x": r.housing_acceleration_m_s2[:, 0],
           "housing_acceleration_y": r.housing_acceleration_m_s2[:, 1],
           "sensor_acceleration": r.resonator_acceleration_m_s2,
           "sensor_displacement": r.resonator_displacement_m, "defect_force": r.defect_force_n}
    if op.noise_snr_db is not None:
        for i, name in enumerate(NOISY_SIGNALS):
            sig[f"{name}_clean"] = sig[name]
            sig[name] = add_noise(sig[name], op.noise_snr_db, op.noise_seed + i)
    model = {"model": r.model, "step_s": r.step_s, "steps": r.steps, "oversample": r.oversample,
             "cpu_s": r.cpu_s, "defect_force_peak_n": r.defect_force_peak_n,
             "structure": _structure(scene), "choice": choice.reason,
             "contact_damping_ns_m": p.contact_damping_ns_m,
             "defect_law": table.metadata() if table is not None else None}
    stats = {"wall_seconds": _time.perf_counter() - t0, "cpu_seconds": _time.process_time() - c0,
             "table_cpu_seconds": c_table}
    return DynamicHistory(scene, fid, r.t_s, sig, r.element_load_n, model,
                          scene_load_distribution(scene), stats,
                          {"mode": acq.mode, "oversample": r.oversample})


def dynamic_cost(scene) -> dict:
    """The dynamic model's cost for ``scene``, before running it: the step rule
    (:func:`~.params.step_size` of the scene's parameters, healthy: the rule does not read the
    defect law) over the record, at :data:`CPU_S_PER_ELEMENT_STEP`. The defect law's table is
    not included (0.4-9 CPU s for the 6205's pits, docs/dynamics.md).

    Parameters
    ----------
    scene : Scene
        The case (bearing, load, ``fs_hz``, record length, ``dynamics.structure``).

    Returns
    -------
    dict
        ``steps``, ``step_s`` (s), ``oversample``, ``cpu_s`` (CPU s), ``memory_bytes`` (the
        record's signals, element loads and velocities at ``fs``, three copies).
    """
    p = scene_params(scene)
    op = scene.operation
    dt = step_size(p)
    steps = int(math.ceil(scene.n_samples / op.fs_hz / dt))
    over = 1 if op.acquisition.mode == "point" else modal_oversample(p, op.fs_hz)
    return {"steps": steps, "step_s": dt, "oversample": over,
            "cpu_s": steps * p.z * CPU_S_PER_ELEMENT_STEP,
            "memory_bytes": 3 * 8.0 * scene.n_samples * (len(DYNAMIC_SIGNAL_UNITS) + 2 * p.z)}


def simulate_case(scene, fidelity: Fidelity | str | None = None, **quasi_static_options):
    """One case by the model its scene needs (:func:`~.criterion.model_choice`).

    Parameters
    ----------
    scene : Scene
        The case.
    fidelity : Fidelity, preset name or None
        As :func:`bearing_envelope.physics.history.simulate`.
    **quasi_static_options
        Passed to :func:`bearing_envelope.physics.history.simulate` (``progress``,
        ``nodefect_cache``, ``use_numba``); unused by the dynamic model.

    Returns
    -------
    History or DynamicHistory
        The quasi-static history (unchanged) or the dynamic one.
    """
    from ..history import simulate   # history imports much; read it only here

    choice = model_choice(scene)
    if choice.model == DYNAMIC:
        return simulate_dynamic(scene, fidelity, choice=choice)
    return simulate(scene, fidelity, **quasi_static_options)
