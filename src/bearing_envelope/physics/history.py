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

Points 1, 2 and 4 describe the inner-race defect (the study's). Every location, the inner race
included, is one object of :mod:`bearing_envelope.physics.locations` (issue 44): its kinematics
and signals (:meth:`~bearing_envelope.physics.locations.FaultLocation.signals`), the loads its
tables cover (:meth:`~bearing_envelope.physics.locations.FaultLocation.table_loads`) and its
exposure; :func:`simulate` and :func:`evaluate_signals` ask it and never branch on its name.
The inner race's kinematics and synthesis (:func:`kinematics`, :func:`synthesize`) live in
:mod:`bearing_envelope.physics.locations.inner_race` and are re-exported here.
"""

from __future__ import annotations

import dataclasses
import math
import os
import time as _time
from dataclasses import dataclass, field

import numpy as np

from .acquisition import (acquire, acquisition_settings, add_noise, antialias_undershoot,
                          signal_bounds)
from .exposure import exposure, exposure_line
from .fidelity import Fidelity, fidelity_from
from .geometry import hertz_estimate
from .loads import LoadDistribution, scene_load_distribution
from .locations import cage_angle
from .locations.inner_race import kinematics, synthesize, synthesize_numpy
from .nodefect_cache import NoDefectCache
from .scene import Scene
from .solves import SolveStats
from .table import PressureTable, build_table, unloaded_table

__all__ = ["History", "simulate", "synthesize", "synthesize_numpy", "kinematics", "cage_angle",
           "defect_angle", "location_tables", "resolved_load", "check_resolved", "plan_tables",
           "TablePlan", "MIN_CONTACT_CELLS",
           "MAX_GRID_HALVINGS", "table_fidelity",
           "evaluate_signals", "synthesize_case", "CONTACT_SIGNALS", "STATE_SIGNALS",
           "SIGNAL_UNITS"]

def defect_angle(scene: Scene, t: np.ndarray, *, t_end: float | None = None) -> np.ndarray:
    """Angle (rad, from the load direction) of the contact where the defect is met, at ``t``.

    The direction of the force the defect removes from the contact: the location's
    :meth:`~bearing_envelope.physics.locations.FaultLocation.angle` (the inner-race defect's
    own angle, the outer-race defect's fixed position, a rolling element's centre).

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
    return scene.defect.fault_location.angle(scene, t, t_end=t_end)


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
    :meth:`PressureTable.evaluate_integrals`, by the location's
    :meth:`~bearing_envelope.physics.locations.FaultLocation.signals`.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    table : dict of str to PressureTable, or PressureTable
        The location's tables by race (``History.tables``); one table: that of the scene's
        contact (``bearing.contact_race``).
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
    tables = {scene.bearing.contact_race: table} if isinstance(table, PressureTable) else table
    return scene.defect.fault_location.signals(scene, tables, ld, t, t_end=t_end,
                                               use_numba=use_numba)


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


#: Fewest global cells across rolling (``2 a_H`` over ``fidelity.global_dx_um``) of the smallest
#: contact a table solves: the inner race's smallest node at ``draft`` on the 6205 at 1 kN
#: (``Q_MIN_FRACTION`` x 534 N = 27 N, 2a = 4.2 cells) is the smallest the tables solve
#: routinely; a 0.03 N contact (0.4 cells) gave a 3,440 % interpolation error and 2.8e-4 N a
#: GlobalGridError (issue 43).
MIN_CONTACT_CELLS = 4.0
#: Most halvings of the fidelity's contact grids (:func:`table_fidelity`) for a table whose
#: largest contact is narrower than :data:`MIN_CONTACT_CELLS` global cells: 3 (1/8) solves the
#: CWRU outer race's centrifugal 0.224 N (2a = 21 um) at ``draft`` (25 -> 3.1 um) and, at
#: ``standard``, contacts down to 0.003 N (issue 43, docs/scene.md "Elements loaded outside
#: the load zone", measured cost there); a lighter contact is refused.
MAX_GRID_HALVINGS = 3


def _halvings(scene: Scene, fid: Fidelity, q: float) -> int:
    """Halvings of ``global_dx_um`` for the contact at ``q`` (N) to span
    :data:`MIN_CONTACT_CELLS` cells (0: it does; large for ``q <= 0``)."""
    if q <= 0:
        return 1 << 30
    ratio = MIN_CONTACT_CELLS * fid.global_dx_m / (2.0 * hertz_estimate(scene, q).a)
    return max(0, math.ceil(math.log2(ratio) - 1e-12))


def table_fidelity(scene: Scene, fid: Fidelity, q_max: float) -> Fidelity:
    """The fidelity a table whose largest load is ``q_max`` is solved at: ``fid`` itself when
    that contact spans :data:`MIN_CONTACT_CELLS` global cells across rolling, else ``fid`` with
    its contact grids (``global_dx_um``, ``global_dy_um``, ``local_dx_um``, ``rim_dx_um``)
    halved the fewest times (at most :data:`MAX_GRID_HALVINGS`) that make it span them, and its
    offset nodes as fine as the refined window (``offset_step_um``; ``max_offsets`` x 4): at a
    pit wider than the contact the pressure changes on the scale of the window's cells.
    Measured on the CWRU 0.224 N contact at ``standard`` (one halving; docs/scene.md, "Elements
    loaded outside the load zone"): the table's on-grid interpolation error 0.1 % of the
    no-defect pressure (47 % on 262b56a's grid, 27 % with the grids alone refined), 10 % at
    off-grid offsets; another halving moves the peak ``p_max`` 10 % and the removed force 2 %.

    Parameters
    ----------
    scene : Scene
        The scene with its modelled contact (``for_race``).
    fid : Fidelity
        The case's fidelity.
    q_max : float
        The table's largest load, N (> 0; resolved after at most
        :data:`MAX_GRID_HALVINGS`: :func:`_check_resolved`).

    Returns
    -------
    Fidelity
        The table's fidelity (``fid`` itself, or a refined copy).
    """
    k = _halvings(scene, fid, q_max)
    if k == 0:
        return fid
    f = 2.0 ** -k
    return dataclasses.replace(
        fid, global_dx_um=f * fid.global_dx_um, global_dy_um=f * fid.global_dy_um,
        local_dx_um=f * fid.local_dx_um, max_offsets=4 * fid.max_offsets,
        offset_step_um=min(fid.offset_step_um, f * fid.local_dx_um),
        rim_dx_um=None if fid.rim_dx_um is None else f * fid.rim_dx_um)


def resolved_load(scene: Scene, fid: Fidelity, q_lo: float, q_hi: float) -> float:
    """The smallest load in ``[q_lo, q_hi]`` (N) whose Hertz contact spans
    :data:`MIN_CONTACT_CELLS` global cells across rolling (``q_lo`` when it does already;
    bisection in ``log Q``: ``a_H`` grows with ``Q``).

    Parameters
    ----------
    scene : Scene
        The scene with its modelled contact (``for_race``).
    fid : Fidelity
        The fidelity (``global_dx_m``).
    q_lo, q_hi : float
        The load range, N (``0 < q_lo <= q_hi``; ``q_hi`` resolved).

    Returns
    -------
    float
        The load, N.
    """
    def resolved(q):
        return 2.0 * hertz_estimate(scene, q).a >= MIN_CONTACT_CELLS * fid.global_dx_m

    if resolved(q_lo):
        return q_lo
    lo, hi = math.log(q_lo), math.log(q_hi)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if resolved(math.exp(mid)) else (mid, hi)
    return math.exp(hi)


def _check_resolved(scene: Scene, fid: Fidelity, ld: LoadDistribution, q_max: float) -> None:
    """Refuse, in one line, a table whose largest load is too small a contact for the solver
    even on grids refined :data:`MAX_GRID_HALVINGS` times (:func:`table_fidelity`)."""
    if _halvings(scene, fid, q_max) <= MAX_GRID_HALVINGS:
        return
    site = scene.defect.fault_location
    where = (f"defect.position_deg further inside the load zone (its edge at "
             f"{math.degrees(ld.half_angle):.4g} deg), " if site.positioned else "")
    finest = fid.global_dx_um / 2 ** MAX_GRID_HALVINGS
    raise ValueError(
        f"{site.where(scene)}: the largest element load the defect meets on the "
        f"{scene.bearing.contact_race} race, {q_max:.3g} N (load {scene.load.load_kN:g} kN, "
        f"bearing.radial_clearance_um {scene.bearing.radial_clearance_um:g}), is a contact "
        f"narrower than {MIN_CONTACT_CELLS:g} global cells even refined to {finest:g} um "
        f"(fidelity.global_dx_um {fid.global_dx_um:g} / {2 ** MAX_GRID_HALVINGS}), too small "
        f"for the contact solver; allowed: {where}a larger load or a smaller "
        f"bearing.radial_clearance_um, or a finer fidelity.global_dx_um")


@dataclass(frozen=True)
class TablePlan:
    """What :func:`simulate` will solve for a case, known before any solve
    (:func:`plan_tables`)."""

    #: The case's load law (:func:`~.loads.scene_load_distribution`).
    load_distribution: LoadDistribution
    #: :func:`~.exposure.exposure` of the case.
    exposure: dict
    #: The one line :func:`simulate` records as ``stats["exposure_note"]`` and the commands
    #: print (:func:`~.exposure.exposure_line`: never loaded, or pits beyond the bridging
    #: limit), or None.
    note: str | None
    #: Race -> ``(q_max, fidelity)``: the largest load of each contact table to solve and the
    #: fidelity it is solved at (:func:`table_fidelity`); empty when the defect never meets a
    #: loaded contact (no solve).
    tables: dict


def plan_tables(scene: Scene, fidelity: Fidelity | str | None = None) -> TablePlan:
    """The contact tables of a case before any solve: the check :func:`simulate` makes (the
    load law and the exposure only, cheap), for the pre-run check and the cost estimate of
    every case (:mod:`bearing_envelope.study.limits`).

    Parameters
    ----------
    scene : Scene
        The case's scene.
    fidelity : Fidelity, preset name or None
        The fidelity of the solves.

    Returns
    -------
    TablePlan
        The load law, the exposure, the note :func:`simulate` records, and per race the
        table's largest load and (refined) fidelity.

    Raises
    ------
    ValueError
        One line naming ``defect.position_deg`` / ``bearing.radial_clearance_um``
        (:func:`_check_resolved`) when a table's largest load is too small a contact for the
        solver; none for a case that never meets a loaded contact.
    """
    fid = fidelity_from(fidelity)
    ld = scene_load_distribution(scene)
    exp = exposure(scene, ld)
    tables = {}
    if exp["loaded"] or not scene.defect.active:
        for race, (q_max, _) in scene.defect.fault_location.table_loads(scene, ld, exp).items():
            sc = scene.for_race(race)
            _check_resolved(sc, fid, ld, q_max)
            tables[race] = (q_max, table_fidelity(sc, fid, q_max))
    return TablePlan(ld, exp, exposure_line(scene, exp), tables)


def check_resolved(scene: Scene, fidelity: Fidelity | str | None = None) -> str | None:
    """Refuse, before any solve, a case whose contact tables would be too small a contact for
    the solver (:func:`plan_tables`, the check :func:`simulate` makes), and return the line
    :func:`simulate` records about the case.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    fidelity : Fidelity, preset name or None
        The fidelity of the solves (``global_dx_um``).

    Returns
    -------
    str or None
        The case's :attr:`TablePlan.note` (e.g. the defect never meets a loaded contact).

    Raises
    ------
    ValueError
        One line naming ``defect.position_deg`` / ``bearing.radial_clearance_um``
        (:func:`_check_resolved`); none for a case that never meets a loaded contact.
    """
    return plan_tables(scene, fidelity).note


def location_tables(scene: Scene, fid: Fidelity, ld: LoadDistribution, exposure: dict,
                    stats: SolveStats, progress: bool = False) -> tuple[dict, dict]:
    """The contact tables of the scene's location: one per race it asks for, over the loads
    it asks (:meth:`~bearing_envelope.physics.locations.FaultLocation.table_loads`); a
    smallest load too small a contact for the grid is raised to the smallest resolved
    (:func:`resolved_load`; readings below the first node are scaled), a largest one refused.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    fid : Fidelity
        The fidelity of the solves.
    ld : LoadDistribution
        The load law.
    exposure : dict
        :func:`~.exposure.exposure` of the scene.
    stats : SolveStats
        Accumulates the solve statistics.
    progress : bool, default False
        Show progress.

    Returns
    -------
    tables : dict of str to PressureTable
        Race -> table.
    snapshots : dict
        The first table's pressure fields at a few offsets per load.

    Raises
    ------
    ValueError
        One line naming ``defect.position_deg`` / ``bearing.radial_clearance_um`` when the
        largest load is too small a contact for the solver (:func:`_check_resolved`).
    """
    tables, snaps = {}, None
    for race, (q_max, q_min) in scene.defect.fault_location.table_loads(scene, ld,
                                                                        exposure).items():
        sc = scene.for_race(race)
        _check_resolved(sc, fid, ld, q_max)
        fid_t = table_fidelity(sc, fid, q_max)
        if q_min is not None:
            q_min = resolved_load(sc, fid_t, q_min, q_max)
        tab, _, sn = build_table(sc, fid_t, q_max=q_max, stats=stats, progress=progress,
                                 q_min=q_min)
        if fid_t is not fid:              # stored only when refined: other tables unchanged
            tab.info["grid_halvings"] = _halvings(sc, fid, q_max)
        tables[race] = tab
        snaps = sn if snaps is None else snaps
    return tables, snaps


def simulate(scene: Scene, fidelity: Fidelity | str | None = None, *, progress: bool = False,
             use_numba: bool = True, nodefect_cache: str | os.PathLike | None = None) -> History:
    """Simulate one case: load distribution, contact table, acquisition of every signal, noise.

    Parameters
    ----------
    scene : Scene
        The case: bearing, material, operation (shaft rate in Hz, sampling rate in Hz,
        revolutions), load (kN) and defect (depth in um, location).
    fidelity : Fidelity, preset name or None (``standard``)
        Numerical settings (grids in m, table nodes, tolerances) or the name of a preset
        (``draft``, ``fast``, ``standard``, ``accurate``, ``paper``).
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
    plan = plan_tables(scene, fid)     # the pre-run check's refusal and note, before any solve
    ld, exp = plan.load_distribution, plan.exposure
    stats = SolveStats(cache=None if nodefect_cache is None else NoDefectCache(nodefect_cache))
    if not exp["loaded"] and scene.defect.active:
        # recognised before any solve: the contact at the defect never carries load
        tables = {r: unloaded_table(scene.for_race(r)) for r in exp["races"]}
        snaps = {}
        # the history of an unloaded contact: its load is 0, not the law's rounding (2e-22 N at
        # a zero-clearance zone's edge) nor a neighbour's load the pit never meets (discrete)
        ld_sig = dataclasses.replace(ld, stiffness=0.0, law_nodes=None, centrifugal=0.0)
    else:
        tables, snaps = location_tables(scene, fid, ld, exp, stats, progress)
        ld_sig = ld
    table = next(iter(tables.values()))
    t_table = _time.perf_counter() - t_start
    op = scene.operation
    t1 = _time.perf_counter()
    t, sig, acq = synthesize_case(scene, tables, ld_sig, fid, use_numba=use_numba)
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
        "exposure": exp, "exposure_note": plan.note,
    }
    if not scene.defect.fault_location.solves_every_row:
        # defect solves on the contact's rows that were solved again on the whole window
        # (physics/solves/windows.py, window_solve); the inner race solves every row
        stats_d["n_rows_fallback"] = stats.n_rows_fallback
    return History(scene, fid, t, signals["p_max"], signals["p_max_defect"], Q, X, table, snaps,
                   ld, signals, stats_d, acq, tables)
