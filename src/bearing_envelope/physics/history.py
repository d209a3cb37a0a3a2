"""Time history of the maximum contact pressure of one load x depth case.

Model only what the scene requires (issue 3, design.md section 2):

1. **Kinematics.** The inner ring (and the defect on it) turns at the shaft rate ``f_r``; the
   defect's angle from the load direction is ``theta_d = 2 pi f_r t``. The cage turns at ``f_c``;
   roller ``j`` sits at ``theta_c + 2 pi j / Z``. The defect meets a roller whenever the relative
   angle ``theta_d - theta_c`` crosses a multiple of ``2 pi / Z``, i.e. at ``Z (f_r - f_c) = BPFI``.
   The **BPFI override** (the study's 231.9 Hz against the geometric 194.2 Hz) is realised through
   the implied cage rate ``f_c = f_r - BPFI / Z`` (5.259 Hz instead of FTF = 6.973 Hz): event
   spacing is exactly ``1/BPFI`` and the load-zone modulation of the defect stays at ``f_r``.
   Both BPFI values are recorded. Arc-length offset of the defect from the nearest roller's
   contact centre: ``x = R_i wrap(theta_d - theta_c)`` with ``wrap`` into ``[-pi/Z, pi/Z)`` and
   ``R_i`` the raceway radius at the contact. With cage slip the cage rate is reduced by a seeded
   random fraction, piecewise constant over each BPFI period, uniform in ``[0, 2 s]`` (mean ``s``):
   roller passage times jitter.
2. **Roller load** at the defect: the load-zone law ``Q(psi)`` of :mod:`bearing_envelope.physics.loads`
   evaluated at the defect's angle ``psi = theta_d``. (The roller centred on the defect has this
   load at the event; using the law at the defect angle, not at the nearest roller's, keeps the
   no-defect signal free of a spurious BPFI-rate step.)
3. **Table P(Q, x)** instead of a solve per sample (zoom route, design.md section 4): for each
   roller-load node a global no-defect solve over the whole roller length (coarse grid), then a
   fine local window around the defect spanning the whole contact width and a short axial
   stretch. The window's axial edges coincide with global cell edges; the displacement of the
   global pressure outside the window is computed exactly at the window's axial spacing (each
   coarse cell split into sub-cells of the same pressure) and interpolated linearly across
   rolling only. The window's no-defect solve carries the force the global solve put on the same
   cells; its approach then drives the defect solves under displacement control (the force the
   defect removes, ~0.1-1 % of Q, is recorded). Results are read only ``window_margin_um`` inside
   the window's axial edges. The far field outside the window responds (``fidelity.far_field:
   responds``, issue 25): it takes up part of the load the defect sheds at fixed approach, by
   reciprocity with a flat-punch solve of the far contact and a shape from the centred defect
   (:func:`~bearing_envelope.physics.solves.far_response`); with it frozen at its no-defect
   pressure (``frozen``, before issue 25) the removed force was 2.2x too large at a 400 um
   margin. The global grid covers the contact only (its extent does not depend on the defect),
   so the global no-defect solves of a load are the same for every depth and can be shared
   (:mod:`~bearing_envelope.physics.nodefect_cache`). Symmetry ``P(Q, -x) = P(Q, x)``; each offset is warm-started from
   its neighbour (a stalled warm start is retried from the no-defect window solution, then cold).
   Offset nodes are multiples of the window spacing (every node sees the defect at the same
   sub-cell position). Interpolation (:class:`PressureTable`): ratios ``P/P0(Q)``, rows read at
   the offset scaled to each row's contact size ``s(Q) = kappa a_H(Q) + w_x/2 + r_n``, blended
   linearly in ``q = Q^(1/3)``; ``P0`` linear in ``q``. Beyond the last node the defect cannot
   touch the contact: ``P = P0(Q)`` and the neighbourhood carries no pressure. The interpolation
   error is measured against direct solves at random ``(Q, x)`` (x on the window grid: pure table
   error; x anywhere: plus the sub-cell discretisation jitter of an under-resolved rim) and stored.
4. **Signals** per sample: ``p_max`` (maximum over the whole contact) and ``p_max_defect``
   (maximum in the defect's neighbourhood: footprint grown by ``neighbourhood_um``), roller load
   and offset. Synthesis over all samples by a numba kernel (:func:`synthesize`) or numpy
   (:func:`synthesize_numpy`).

This is the inner-race defect (the study's). An outer-race or rolling-element defect
(``defect.location``, issue 23) takes its kinematics, loads and contact tables from
:mod:`bearing_envelope.physics.locations`; :func:`simulate` and :func:`evaluate_signals`
dispatch to it and leave the inner-race path untouched.
"""

from __future__ import annotations

import math
import os
import time as _time
from dataclasses import dataclass, field

import numpy as np

from .acquisition import (acquire, acquisition_settings, add_noise, antialias_undershoot,
                          signal_bounds)
from .exposure import exposure, exposure_line
from .fidelity import Fidelity, fidelity_from
from .kernels import HAVE_NUMBA, synth_kernel
from .loads import LoadDistribution, scene_load_distribution
from .locations import location_signals, location_tables
from .nodefect_cache import NoDefectCache
from .scene import Scene
from .solves import SolveStats
from .table import PressureTable, build_table, unloaded_table

__all__ = ["History", "simulate", "synthesize", "synthesize_numpy", "kinematics", "cage_angle",
           "defect_angle",
           "evaluate_signals", "synthesize_case", "CONTACT_SIGNALS", "STATE_SIGNALS",
           "SIGNAL_UNITS"]

def kinematics(scene: Scene, t: np.ndarray, *, t_end: float | None = None) -> dict[str, np.ndarray]:
    """Shaft and cage angles, defect offset and roller index at times ``t`` (s).

    Returns a dict with ``theta_shaft`` (rad, the defect's angle from the load direction),
    ``theta_cage`` (rad), ``offset`` (m), ``roller`` (index of the nearest roller) and
    ``theta_roller`` (rad, that roller's angle from the load direction). ``t_end`` (s): end of
    the whole record when ``t`` is one block of it (keeps the seeded slip process the same).

    Parameters
    ----------
    scene : Scene
        The case's scene.
    t : ndarray
        Times, s, shape ``(n,)``.
    t_end : float, optional
        End of the whole record, s, when ``t`` is one block of it.

    Returns
    -------
    dict of str to ndarray
        ``theta_shaft``, ``theta_cage``, ``offset``, ``roller`` (int64), ``theta_roller``; each
        of shape ``(n,)``.
    """
    b = scene.bearing
    z = b.rollers_per_row
    theta_d = 2.0 * np.pi * scene.operation.shaft_rate_hz * t
    theta_c = cage_angle(scene, t, t_end=t_end)
    pitch = 2.0 * np.pi / z
    rel = theta_d - theta_c
    k = np.floor((rel + 0.5 * pitch) / pitch)
    wrapped = rel - k * pitch
    return {"theta_shaft": theta_d, "theta_cage": theta_c,
            "offset": b.inner_race_radius_m * wrapped, "roller": np.mod(k, z).astype(np.int64),
            "theta_roller": theta_d - wrapped}


def cage_angle(scene: Scene, t: np.ndarray, *, t_end: float | None = None) -> np.ndarray:
    """Cage angle (rad) at times ``t``; with slip a seeded, piecewise-constant random slip.

    ``t_end`` (s): the record's end when ``t`` is a block of it (the slip draws depend only on
    the seed and ``t_end``, so blocks of one record agree). Times slightly before 0 (the
    anti-alias filter's lead-in) continue the first period's rate.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    t : ndarray
        Times, s.
    t_end : float, optional
        End of the whole record, s, when ``t`` is one block of it.

    Returns
    -------
    ndarray
        Cage angle, rad, shape of ``t``; ``2 pi f_c t`` without slip.
    """
    op = scene.operation
    fc = scene.cage_rate_hz
    if op.cage_slip_percent <= 0:
        return 2.0 * np.pi * fc * t
    rng = np.random.default_rng(op.slip_seed)
    period = 1.0 / scene.bpfi_hz
    last = max(float(t[-1]) if t.size else 0.0, 0.0 if t_end is None else float(t_end))
    n = int(np.ceil(last / period)) + 2
    s = rng.uniform(0.0, 2e-2 * op.cage_slip_percent, n)
    rate = 2.0 * np.pi * fc * (1.0 - s)
    edges = np.concatenate([[0.0], np.cumsum(rate * period)])   # angle at k * period
    k = np.clip((t / period).astype(np.int64), 0, n - 1)
    return edges[k] + rate[k] * (t - k * period)


def defect_angle(scene: Scene, t: np.ndarray, *, t_end: float | None = None) -> np.ndarray:
    """Angle (rad, from the load direction) of the contact where the defect is met, at ``t``.

    The direction of the force the defect removes from the contact: the inner-race defect's
    own angle (it turns with the shaft), the outer-race defect's fixed position, and for a
    rolling element its centre's angle (the cage angle: it meets both races on that radius).

    Parameters
    ----------
    scene : Scene
        The case's scene.
    t : ndarray
        Times, s.
    t_end : float, optional
        End of the whole record, s, when ``t`` is one block of it (the slip process).

    Returns
    -------
    ndarray
        Angle, rad, shape of ``t`` (not wrapped).
    """
    loc = scene.defect.location
    if loc == "inner_race":
        theta = kinematics(scene, np.atleast_1d(t), t_end=t_end)["theta_shaft"]
        return theta.reshape(np.shape(t))
    if loc == "outer_race":
        return np.full(np.shape(t), math.radians(scene.defect.position_deg))
    return cage_angle(scene, np.asarray(t, dtype=float), t_end=t_end)


def _law_params(ld: LoadDistribution):
    return (ld.stiffness, ld.delta_r, ld.clearance, math.cos(ld.contact_angle_rad), ld.exponent)


def synthesize_numpy(scene: Scene, table: PressureTable, ld: LoadDistribution, t: np.ndarray,
                     *, t_end: float | None = None):
    """Per-sample synthesis, numpy version: ``(p_max, p_max_defect, roller_load, offset)``.

    The roller load is the load-zone law at the defect's angle (``load.roller_load: smooth``)
    or at the angle of the roller over the defect (``discrete``).

    Parameters
    ----------
    scene : Scene
        The case's scene.
    table : PressureTable
        The inner-race contact table.
    ld : LoadDistribution
        The load-zone law.
    t : ndarray
        Times, s, shape ``(n,)``.
    t_end : float, optional
        End of the whole record, s, when ``t`` is one block of it.

    Returns
    -------
    tuple of ndarray
        ``p_max`` (Pa), ``p_max_defect`` (Pa), ``roller_load`` (N), ``offset`` (m); each of
        shape ``(n,)``.
    """
    kin = kinematics(scene, t, t_end=t_end)
    psi = kin["theta_roller"] if scene.load.roller_load == "discrete" else kin["theta_shaft"]
    Q = ld.load_at(psi)
    P, Pd = table.evaluate(Q, kin["offset"])
    return P, Pd, Q, kin["offset"]


def synthesize(scene: Scene, table: PressureTable, ld: LoadDistribution, t: np.ndarray,
               *, t_end: float | None = None):
    """Per-sample synthesis with the numba kernel (falls back to numpy without numba).

    Same outputs as :func:`synthesize_numpy`: ``(p_max, p_max_defect, roller_load, offset)``;
    the pressures are capped at ``table.p_cap`` when set.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    table : PressureTable
        The inner-race contact table.
    ld : LoadDistribution
        The load-zone law.
    t : ndarray
        Times, s, shape ``(n,)``.
    t_end : float, optional
        End of the whole record, s, when ``t`` is one block of it.

    Returns
    -------
    tuple of ndarray
        ``p_max`` (Pa), ``p_max_defect`` (Pa), ``roller_load`` (N), ``offset`` (m); each of
        shape ``(n,)``.
    """
    if not HAVE_NUMBA:  # pragma: no cover
        return synthesize_numpy(scene, table, ld, t, t_end=t_end)
    t = np.ascontiguousarray(t, dtype=float)
    theta_c = np.ascontiguousarray(cage_angle(scene, t, t_end=t_end))
    n = t.size
    P, Pd, Q, X = (np.empty(n) for _ in range(4))
    K, dr, c, ca, ex = _law_params(ld)
    synth_kernel(t, theta_c, scene.operation.shaft_rate_hz, scene.bearing.rollers_per_row,
                  scene.bearing.inner_race_radius_m, K, dr, c, ca, ex,
                  scene.load.roller_load == "discrete", *table.args(), P, Pd, Q, X)
    if table.p_cap is not None:
        np.minimum(P, table.p_cap, out=P)
        np.minimum(Pd, table.p_cap, out=Pd)
    return P, Pd, Q, X


#: Signals of a case that describe the contact (filtered by the anti-alias acquisition), and the
#: kinematic bookkeeping that is point-sampled in every mode (a sawtooth offset is not filtered).
CONTACT_SIGNALS = ("p_max", "p_max_defect", "removed_force", "contact_force", "approach",
                   "approach_change", "contact_area")
STATE_SIGNALS = ("roller_load", "defect_offset")

#: Units of every signal a case can hold.
SIGNAL_UNITS = {"p_max": "Pa", "p_max_defect": "Pa", "removed_force": "N", "contact_force": "N",
                "approach": "m", "approach_change": "m", "contact_area": "m^2",
                "roller_load": "N", "defect_offset": "m"}


def evaluate_signals(scene: Scene, table: PressureTable, ld: LoadDistribution, t: np.ndarray,
                     *, t_end: float | None = None, use_numba: bool = True) -> dict[str, np.ndarray]:
    """Every signal of :data:`CONTACT_SIGNALS` and :data:`STATE_SIGNALS` at the instants ``t``
    (s): pressures from :meth:`PressureTable.evaluate`, integrals from
    :meth:`PressureTable.evaluate_integrals`. An outer-race or rolling-element defect
    (``table`` then the dict of :func:`~.locations.location_tables`):
    :func:`~.locations.location_signals`.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    table : PressureTable or dict of str to PressureTable
        The contact table (inner race), or the location's tables.
    ld : LoadDistribution
        The load-zone law.
    t : ndarray
        Times, s, shape ``(n,)``.
    t_end : float, optional
        End of the whole record, s, when ``t`` is one block of it.
    use_numba : bool, default True
        Use the numba kernels (the numpy path for a centrifugal load law).

    Returns
    -------
    dict of str to ndarray
        Signal name -> values at ``t`` (SI units, :data:`SIGNAL_UNITS`), each of shape ``(n,)``.
    """
    if scene.defect.location != "inner_race":
        return location_signals(scene, table, ld, cage_angle(scene, t, t_end=t_end),
                                use_numba=use_numba)
    # the numba kernel has the closed-form load law; the centrifugal law is read by numpy
    fn = synthesize if use_numba and ld.centrifugal == 0 else synthesize_numpy
    P, Pd, Q, X = fn(scene, table, ld, t, t_end=t_end)
    out = {"p_max": P, "p_max_defect": Pd, "roller_load": Q, "defect_offset": X}
    out.update(table.evaluate_integrals(Q, X, use_numba=use_numba))
    return out




@dataclass
class History:
    """Result of :func:`simulate` (what :func:`bearing_envelope.io.write_case` stores)."""

    scene: Scene
    fidelity: Fidelity
    time: np.ndarray
    p_max: np.ndarray
    p_max_defect: np.ndarray
    roller_load: np.ndarray
    defect_offset: np.ndarray
    table: PressureTable
    snapshots: dict
    load_distribution: LoadDistribution
    signals: dict
    stats: dict
    acquisition: dict = field(default_factory=dict)
    #: Every contact table of the case by race (``inner``/``outer``): one for the inner or outer
    #: race, two for a rolling element (``table`` is the first).
    tables: dict = field(default_factory=dict)


def synthesize_case(scene: Scene, table: PressureTable, ld: LoadDistribution,
                    fidelity: Fidelity, *, use_numba: bool = True,
                    acquisition: dict | None = None) -> tuple[np.ndarray, dict, dict]:
    """All signals of a case at ``fs`` with the scene's acquisition (or ``acquisition``, a dict
    like :func:`acquisition_settings`). Returns ``(time, signals, acquisition)``.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    table : PressureTable or dict of str to PressureTable
        The contact table(s), as :func:`evaluate_signals`.
    ld : LoadDistribution
        The load-zone law.
    fidelity : Fidelity
        Resolves the acquisition when ``acquisition`` is not given.
    use_numba : bool, default True
        Use the numba kernels.
    acquisition : dict, optional
        The acquisition settings; default :func:`acquisition_settings` of the scene.

    Returns
    -------
    time : ndarray
        ``arange(n) / fs``, s, ``n = scene.n_samples``.
    signals : dict of str to ndarray
        Every signal at ``fs``, each of shape ``(n,)``.
    acquisition : dict
        The settings used; for ``antialiased`` also ``internal_range``, ``undershoot_bound``
        and ``clipped`` (the samples the filter rang past a physical bound, clipped back:
        :func:`~bearing_envelope.physics.acquisition.clip_to_bounds`).
    """
    op = scene.operation
    acq = acquisition or acquisition_settings(scene, fidelity)
    n = scene.n_samples
    t_end = (n + 1) / op.fs_hz + 1.0 / scene.bpfi_hz

    def ev(t):
        return evaluate_signals(scene, table, ld, t, t_end=t_end, use_numba=use_numba)

    ranges: dict[str, list[float]] = {}
    clipped: dict[str, dict] = {}
    sig = acquire(ev, n, op.fs_hz, mode=acq["mode"], oversample=acq["oversample"],
                  filtered=CONTACT_SIGNALS, ranges=ranges, bounds=signal_bounds(scene),
                  clipped=clipped)
    if acq["mode"] == "antialiased":
        acq = {**acq, "internal_range": ranges, "clipped": clipped,
               "undershoot_bound": antialias_undershoot(acq["oversample"])}
    return np.arange(n) / op.fs_hz, sig, acq


def simulate(scene: Scene, fidelity: Fidelity | str | None = None, *, progress: bool = False,
             use_numba: bool = True, nodefect_cache: str | os.PathLike | None = None) -> History:
    """Simulate one case: load distribution, contact table, acquisition of every signal, noise.

    Parameters
    ----------
    scene : Scene
    fidelity : Fidelity, preset name or None (``standard``)
    progress : bool
        Show a tqdm bar over the contact solves (only on a terminal).
    use_numba : bool
        Use the numba synthesis kernels (else numpy).
    nodefect_cache : path, optional
        Folder of the content-addressed store of the global no-defect solves
        (:mod:`~bearing_envelope.physics.nodefect_cache`): shared by every case of a load, the
        results bit-identical to solving them. None: solved every time.

    Returns
    -------
    History
        The sampled time, every signal (``p_max``, ``p_max_defect``, ``removed_force``,
        ``contact_force``, ``approach``, ``approach_change``, ``contact_area``), roller load and
        defect offset per sample, the contact table, snapshots and solve statistics.

    Examples
    --------
    One shaft revolution of the default scene at 250 kN with a 50 um deep defect, at ``draft``:

    >>> from bearing_envelope.physics.scene import Scene
    >>> from bearing_envelope.physics.history import simulate
    >>> scene = Scene.from_mapping({"operation": {"revolutions": 1}}, load_kN=250.0,
    ...                            depth_um=50.0)
    >>> hist = simulate(scene, "draft")
    >>> abs(hist.time.size - scene.operation.fs_hz / scene.operation.shaft_rate_hz) < 1
    True
    >>> bool(hist.signals["removed_force"].max() > 0)    # the defect sheds load
    True
    """
    fid = fidelity_from(fidelity)
    t_start = _time.perf_counter()
    ld = scene_load_distribution(scene)
    exp = exposure(scene, ld)
    stats = SolveStats(cache=None if nodefect_cache is None else NoDefectCache(nodefect_cache))
    if not exp["loaded"] and scene.defect.active:
        # recognised before any solve: the contact at the defect never carries load
        tables = {r: unloaded_table(scene.for_race(r)) for r in exp["races"]}
        table, snaps = next(iter(tables.values())), {}
    elif scene.defect.location == "inner_race":
        table, nodes, snaps = build_table(scene, fid, q_max=ld.q_max, stats=stats,
                                          progress=progress)
        tables = {"inner": table}
    else:
        tables, nodes, snaps = location_tables(scene, fid, exp, stats, progress)
        table = next(iter(tables.values()))
    t_table = _time.perf_counter() - t_start
    op = scene.operation
    t1 = _time.perf_counter()
    t, sig, acq = synthesize_case(scene, table if scene.defect.location == "inner_race" else tables,
                                  ld, fid, use_numba=use_numba)
    t_synth = _time.perf_counter() - t1
    P, Pd, Q, X = sig["p_max"], sig["p_max_defect"], sig["roller_load"], sig["defect_offset"]
    signals = {k: sig[k] for k in CONTACT_SIGNALS}
    if op.noise_snr_db is not None:
        signals.update({
            "p_max": add_noise(P, op.noise_snr_db, op.noise_seed),
            "p_max_defect": add_noise(Pd, op.noise_snr_db, op.noise_seed + 1),
            "p_max_clean": P, "p_max_defect_clean": Pd,
        })
    stats_d = {
        "n_solves": stats.n_solves, "n_iterations": stats.n_iterations,
        "n_failed_solves": stats.n_failed, "failed_solver_seconds": stats.failed_seconds,
        "n_stall_guard": stats.n_stall_guard,
        "nodefect_cache_hits": stats.cache.hits if stats.cache else 0,
        "nodefect_cache_misses": stats.cache.misses if stats.cache else 0,
        "solver_seconds": stats.solver_seconds, "table_seconds": t_table,
        "synthesis_seconds": t_synth, "wall_seconds": _time.perf_counter() - t_start,
        "exposure": exp, "exposure_note": exposure_line(scene, exp),
    }
    if scene.defect.location != "inner_race":
        # defect solves on the contact's rows that were solved again on the whole window
        # (physics/solves.py, window_solve); the inner race solves every row
        stats_d["n_rows_fallback"] = stats.n_rows_fallback
    return History(scene, fid, t, signals["p_max"], signals["p_max_defect"], Q, X, table, snaps,
                   ld, signals, stats_d, acq, tables)
