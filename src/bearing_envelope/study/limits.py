"""Limits before allocation: what passes the pre-run check runs, and fits the machine.

:func:`precheck` is the second half of the workflow's pre-run check (``common.smk`` calls it
after :func:`bearing_envelope.study.settings.workflow_settings`; ``bearing-envelope
check-config`` too). It refuses, with one line naming the field, the value and what is
allowed:

- a case whose name would be too long for a file name, or does not read back exactly;
- a hardness below :data:`MIN_HARDNESS_GPA`, a record shorter than the analysis' longest
  kurtogram window (:func:`min_revolutions`);
- a missing ``scene.bearing.profile_file``;
- a case ``simulate`` would refuse before its first solve: a contact too small for the solver
  even on refined grids (:func:`~bearing_envelope.physics.history.plan_tables`, the same
  call; a case whose defect never meets a loaded contact is reported, as ``simulate`` reports
  it, in :attr:`ResourceEstimate.note`, and refused only when the run builds the detection map);
- global grid cells longer than :data:`MAX_GLOBAL_CELL_ASPECT` times their width (the contact
  solver does not converge on them);
- a case whose estimated memory or CPU time (:func:`estimate_case`) exceeds the machine's
  available memory or the stated limits (``limits.max_case_memory_GB``,
  ``limits.max_case_cpu_s``; :data:`DEFAULT_LIMITS`);
- a job of a case whose estimated CPU time exceeds ``limits.max_case_cpu_s``: every expensive
  axis is estimated (:func:`estimate_jobs`: the simulation's grid cells and solves, the record's
  samples, the kurtogram's levels, the bands, the SNR levels of the detection map and its
  false-alarm trials), and the refusal names the field behind the largest factor;
- a ``paper_run`` that is not the folder of a finished paper-conventions run.
"""

from __future__ import annotations

import math
import os

import numpy as np
from collections.abc import Mapping
from dataclasses import dataclass

from ..diagnosis.detection import EXCLUDED_SIDEBANDS
from ..physics.acquisition import auto_oversample
from ..physics.dynamics.case import dynamic_cost
from ..physics.dynamics.criterion import DYNAMIC, model_choice
from ..physics.history import plan_tables
from ..physics.loads import scene_load_distribution
from ..physics.solves import window_spec
from ..physics.table import offset_count
from ..signal.kurtogram import max_kurtogram_level
from .config_read import ConfigError, config_files
from .settings import DEFAULT_MAX_CASES, workflow_settings

__all__ = ["DEFAULT_LIMITS", "MIN_HARDNESS_GPA", "MAX_CASE_NAME_CHARS", "MAX_GLOBAL_CELL_ASPECT",
           "ResourceEstimate",
           "JobEstimate", "estimate_case", "estimate_jobs", "check_case", "PAPER_RUN_TABLES",
           "paper_run_tables", "checked_settings", "EMPTY_CONFIG_NOTE", "min_revolutions", "available_memory_bytes", "precheck",
           "profile_files"]

#: Stated limits when the config has no ``limits:`` section: estimated CPU seconds of any one
#: job of a case (10 CPU minutes; the default sweep's heaviest job needs about 30 s, a
#: paper-fidelity simulation about 1,300 s: raise it for those), memory (None: the machine's
#: available memory) and the number of cases (checked by the loader before any case is built,
#: so its default lives there: :data:`bearing_envelope.study.settings.DEFAULT_MAX_CASES`).
DEFAULT_LIMITS = {"max_case_cpu_s": 600.0, "max_case_memory_GB": None,
                  "max_cases": DEFAULT_MAX_CASES}

#: Lowest hardness accepted, GPa: below it the hardness bound flattens every contact (pure
#: lead is 0.04 GPa; bearing steel about 7.4 GPa).
MIN_HARDNESS_GPA = 0.1

#: Samples the fast kurtogram needs for its first level (``max_kurtogram_level(n) >= 1``).
MIN_KURTOGRAM_SAMPLES = 2 ** 8

#: Longest case name accepted (characters, without ``.h5``): file systems allow 255 bytes per
#: name, and the workflow adds suffixes such as ``_kurtogram.npz`` and ``.unreadable-{time}``.
MAX_CASE_NAME_CHARS = 120

#: Float64 signals kept per output sample by a simulation (contact, integral, kinematic
#: signals, clean copies, time) and the working copies while writing them.
_SIGNALS_PER_SAMPLE = 24

#: Bytes per grid cell of one contact solve: DC-FFT on the doubled grid (4 cells, complex128)
#: for the kernel and two work arrays, plus the CG vectors (measured peak: 0.3-0.5 GB for the
#: standard window grids).
_BYTES_PER_CELL = 4 * 16 * 4 + 8 * 10

#: Bytes of the anti-alias filter design per unit of oversampling (about 54 taps per unit,
#: float64, and the design's temporaries: measured 4 GiB for oversample 1e7).
_FILTER_BYTES_PER_OVERSAMPLE = 54 * 8 * 3

#: Memory of the interpreter and libraries, bytes (measured: 150-200 MB before any array).
_BASE_BYTES = 250e6

#: CPU seconds per grid cell and CG iteration of a solve, per fine (oversampled) sample of the
#: history synthesis, and of imports and setup; calibrated so that the default sweep's cases come out at their
#: measured 5-10 s (``docs/benchmarks.md``).
_CPU_S_PER_CELL_ITERATION = 4.0e-9
_BASE_CPU_S = 1.5
_CPU_S_PER_FINE_SAMPLE = 2.0e-6
_CG_ITERATIONS = 60

#: The global solves: CPU seconds per cell x log2(4 cells) and iteration, and the iterations
#: per solve, about 2 sqrt(cells) up to the fidelity's ``max_iter``: an upper bound. Measured
#: at draft (750 kN / 50 um, ``global_dx_um`` refined, 2026-12-05): 65,269 cells (1.5625 x 400
#: um) cost 14.9 CPU s, 8 of the table's global solves past the solver's stall guard (175-838
#: iterations), the others 23-30; the iterations follow the cells' aspect ratio rather than
#: their number (16-200:1: 13-33 iterations up to 1.7 million cells, 9.4 CPU s for one solve
#: at 0.5 x 50 um; beyond 256:1, :data:`MAX_GLOBAL_CELL_ASPECT`, refused). The constant is the
#: measured 6.3-8.3e-9 with a margin.
_CPU_S_PER_GLOBAL_CELL_ITERATION = 8.2e-9

#: The window solves' iterations grow with the window grid too (each starts from the previous
#: offset's solution, so far fewer than the global ones): :data:`_CG_ITERATIONS` up to the
#: standard window (27,219 cells: 13.4 CPU s per default case measured, under its
#: estimate), then 0.5 sqrt(cells): the paper window (248,221 cells) measured 1,328 CPU s for
#: the heaviest default case (docs/cluster.md), which 60 iterations estimated at 426 s (now
#: 1,430 s).
_WINDOW_ITERATIONS_PER_SQRT_CELL = 0.5
_GLOBAL_ITERATIONS_PER_SQRT_CELL = 2.0

#: Load nodes above which the table's solve count, not its grid, is named as the cause.
_MANY_LOADS = 50

#: Window solves per load node besides the offsets: the no-defect window and the checks.
_EXTRA_WINDOW_SOLVES = 2

_GB = 1e9


@dataclass(frozen=True)
class ResourceEstimate:
    """Estimated resources of one simulation job."""

    case: str
    n_samples: int
    oversample: int
    global_cells: int
    window_cells: int
    n_solves: int
    memory_bytes: float
    cpu_seconds: float
    #: Field(s) of the config -> bytes / CPU seconds they account for (the largest names the
    #: field to change when the estimate is refused).
    memory_parts: tuple = ()
    cpu_parts: tuple = ()
    #: What ``simulate`` will say about the case in one line (``TablePlan.note``: the defect
    #: never meets a loaded contact, pits beyond the bridging limit), or None.
    note: str | None = None

    def culprit(self, kind: str) -> str:
        """The config field behind the largest part of the ``memory`` or ``cpu`` estimate.

        Parameters
        ----------
        kind : {"memory", "cpu"}
            Which estimate (any other value reads the CPU parts).

        Returns
        -------
        str
            The dotted config field(s) of the largest part (``"scene"`` when there are none).
        """
        parts = dict(self.memory_parts if kind == "memory" else self.cpu_parts)
        return max(parts, key=parts.get) if parts else "scene"

    def describe(self) -> str:
        """The estimate in one phrase, for the refusal messages.

        Returns
        -------
        str
            Samples x oversampling, global and window cells x solves, then the memory (GB) and
            CPU seconds; counts of 10^12 and more in 3 significant digits.
        """
        def count(v: int) -> str:      # 1e300 samples in 3 significant digits, not 300
            return f"{v:,}" if v < 10 ** 12 else f"{float(v):.3g}"

        return (f"{count(self.n_samples)} samples x {count(self.oversample)} oversample, "
                f"{count(self.global_cells)} global + {count(self.window_cells)} window cells "
                f"x {self.n_solves} solves: about {self.memory_bytes / _GB:.3g} GB and "
                f"{self.cpu_seconds:.3g} CPU s")


def _cells(extent_m: float, step_m: float) -> float:
    return max(1.0, 2.0 * extent_m / step_m)


def _oversample(scene, fidelity) -> int:
    """The acquisition's internal oversampling factor (without designing its filter)."""
    acq = scene.operation.acquisition
    if acq.mode == "point":
        return 1
    return auto_oversample(scene, fidelity) if acq.oversample == "auto" else int(acq.oversample)


def _table_cost(scene, fid, q_max: float) -> tuple[float, float, int, float, float]:
    """Global cells, window cells, solves, global and window CPU seconds of one contact table
    up to ``q_max`` (N) at its fidelity ``fid`` (refined or not: :func:`table_fidelity`)."""
    a, _s, dx, dy, xh, _yd, _hy_read, hy = window_spec(scene, fid, q_max, 1.0)
    g_cells = _cells(fid.global_extent * a, fid.global_dx_um * 1e-6) * \
        _cells(scene.bearing.half_length_m, fid.global_dy_um * 1e-6)
    w_cells = _cells(xh, dx) * _cells(hy, dy)
    offsets = offset_count(scene, fid, q_max) + fid.n_checks + _EXTRA_WINDOW_SOLVES
    iterations = min(fid.max_iter, _GLOBAL_ITERATIONS_PER_SQRT_CELL * math.sqrt(g_cells))
    global_cpu = _CPU_S_PER_GLOBAL_CELL_ITERATION * iterations * fid.n_loads * \
        g_cells * math.log2(4 * g_cells)
    w_iterations = min(fid.max_iter, max(_CG_ITERATIONS,
                                         _WINDOW_ITERATIONS_PER_SQRT_CELL * math.sqrt(w_cells)))
    window_cpu = _CPU_S_PER_CELL_ITERATION * w_iterations * fid.n_loads * \
        offsets * w_cells * math.log2(4 * w_cells)
    return g_cells, w_cells, fid.n_loads * (1 + offsets), global_cpu, window_cpu


def estimate_case(name: str, scene, fidelity, plan=None) -> ResourceEstimate:
    """Memory and CPU time of one case's simulation, from its scene and fidelity alone.

    Samples x signals for the history (the acquisition works block-wise at the fine rate),
    grid cells x solves for each contact table the case solves (:func:`plan_tables`, the
    check :func:`~bearing_envelope.physics.history.simulate` makes: none when the defect never
    meets a loaded contact; a light contact's table on its refined grids,
    :func:`~bearing_envelope.physics.history.table_fidelity`): ``n_loads`` global solves, and
    per load node the window solves at the table's offsets
    (:func:`~bearing_envelope.physics.table.offset_count`). An order-of-magnitude estimate:
    within a factor of 3 of the measured cases, enough to refuse what cannot fit.

    Parameters
    ----------
    name : str
        The case's name (carried into the estimate and the messages).
    scene : bearing_envelope.physics.scene.Scene
        The case's validated scene (record length, sampling, acquisition, bearing, load).
    fidelity : bearing_envelope.physics.fidelity.Fidelity
        The grids and table densities.
    plan : bearing_envelope.physics.history.TablePlan, optional
        The case's :func:`plan_tables` (computed when not given).

    Returns
    -------
    ResourceEstimate
        Samples, oversampling, cells, solves, ``memory_bytes`` (bytes) and ``cpu_seconds``
        (CPU s), with the config fields each part comes from, and the plan's note.

    Raises
    ------
    ValueError
        A table's contact too small for the solver (:func:`plan_tables`).
    """
    if model_choice(scene).model == DYNAMIC:   # issue 42: the dynamic model's step rule
        d, field = dynamic_cost(scene), "scene.operation.revolutions x fs_hz"
        return ResourceEstimate(name, scene.n_samples, d["oversample"], 0, 0, 0,
                                _BASE_BYTES + d["memory_bytes"], _BASE_CPU_S + d["cpu_s"],
                                ((field, d["memory_bytes"]),), ((field, d["cpu_s"]),))
    op = scene.operation
    n = int(math.ceil(op.revolutions / op.shaft_rate_hz * op.fs_hz))
    over = _oversample(scene, fidelity)
    plan = plan_tables(scene, fidelity) if plan is None else plan
    g_cells = w_cells = global_solves = window_solves = 0.0
    solves, refined = 0, False
    for race, (q_max, fid_t) in plan.tables.items():
        g, w, k, gs, ws = _table_cost(scene.for_race(race), fid_t, q_max)
        g_cells, w_cells = max(g_cells, g), max(w_cells, w)
        solves, global_solves, window_solves = solves + k, global_solves + gs, window_solves + ws
        refined = refined or fid_t is not fidelity
    fine = _CPU_S_PER_FINE_SAMPLE * n * over
    solve = global_solves + window_solves
    grid_field = ("fidelity.n_loads" if fidelity.n_loads > _MANY_LOADS else
                  "fidelity.local_dx_um / local_dy_um" if window_solves >= global_solves else
                  "fidelity.global_dx_um / global_dy_um")
    if refined:     # the light contact's refinement is what costs: the load decides it
        grid_field += " (a light contact's refined grids: sweep.loads_kN, scene.load)"
    samples_field = "scene.operation.revolutions x fs_hz"
    over_field = "scene.operation.acquisition.oversample"
    memory_parts = ((samples_field, 8.0 * _SIGNALS_PER_SAMPLE * n),
                    (grid_field, _BYTES_PER_CELL * max(g_cells, w_cells)),
                    (over_field, _FILTER_BYTES_PER_OVERSAMPLE * over))
    cpu_parts = ((samples_field if over <= _MANY_LOADS else over_field, fine), (grid_field, solve))
    return ResourceEstimate(name, n, over, int(g_cells), int(w_cells), solves,
                            _BASE_BYTES + sum(v for _, v in memory_parts),
                            _BASE_CPU_S + fine + solve, memory_parts, cpu_parts, plan.note)


def available_memory_bytes() -> float:
    """Memory available to new processes (``MemAvailable`` of /proc/meminfo; else physical).

    Returns
    -------
    float
        Bytes.
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))


def min_revolutions(scene) -> float:
    """Shortest record (shaft revolutions) the bands job can analyse: the fast kurtogram needs
    :data:`MIN_KURTOGRAM_SAMPLES` samples for its first level
    (:func:`bearing_envelope.signal.max_kurtogram_level` >= 1); shorter records fail in the job
    with ``nlevel must be an integer >= 1``.

    Parameters
    ----------
    scene : bearing_envelope.physics.scene.Scene
        Its ``operation.fs_hz`` and ``operation.shaft_rate_hz`` are read.

    Returns
    -------
    float
        Shaft revolutions.
    """
    return MIN_KURTOGRAM_SAMPLES / scene.operation.fs_hz * scene.operation.shaft_rate_hz


def _limits(config: Mapping) -> dict:
    out = dict(DEFAULT_LIMITS)
    given = config.get("limits") or {}
    if not isinstance(given, Mapping):
        raise ConfigError(f"limits: got {given!r}; allowed: a mapping with max_case_cpu_s, "
                          f"max_case_memory_GB")
    for key, value in given.items():
        if key not in DEFAULT_LIMITS:
            raise ConfigError(f"limits.{key}: unknown key; allowed: {', '.join(DEFAULT_LIMITS)}")
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))
                                  or not math.isfinite(value) or value <= 0):
            raise ConfigError(f"limits.{key}: got {value!r}; allowed: a number > 0 or null")
        out[key] = value
    return out


def _check_case(case, scene, analysis, limits: dict, memory_cap: float,
                fidelity, detection_map: bool = False) -> ResourceEstimate:
    """The per-case checks of :func:`precheck` (name, lower bounds, simulate's own check of the
    case, resource estimate); returns the estimate. With the detection map
    (``detection_map``), a defect that never meets a loaded contact is refused: the map's SNR
    is that of the defect's part of the record, and there is none (its diagnose job found a
    constant record, issue 43's retest)."""
    if len(case.name) > MAX_CASE_NAME_CHARS:
        raise ConfigError(f"sweep: case name {case.name[:40]}... has {len(case.name)} "
                          f"characters; allowed: at most {MAX_CASE_NAME_CHARS}")
    hard = scene.material.hardness_pa
    if hard is not None and hard < MIN_HARDNESS_GPA * 1e9:
        raise ConfigError(f"scene.material.hardness_GPa: got {hard / 1e9:g}; allowed: null or "
                          f">= {MIN_HARDNESS_GPA:g} GPa")
    n = int(math.ceil(scene.operation.revolutions / scene.operation.shaft_rate_hz
                      * scene.operation.fs_hz))
    if analysis is not None and max_kurtogram_level(n) < 1:
        raise ConfigError(f"scene.operation.revolutions: got {scene.operation.revolutions:g} "
                          f"({n} samples); allowed: >= {min_revolutions(scene):.3g} (the "
                          f"kurtogram needs {MIN_KURTOGRAM_SAMPLES} samples)")
    _check_grid(fidelity)
    try:
        plan = plan_tables(scene, fidelity)    # simulate's own check of the case, no solve
    except ValueError as exc:
        field = ("scene.defect.position_deg" if scene.defect.fault_location.positioned
                 else "sweep.loads_kN")
        raise ConfigError(f"{field}: case {case.name}: {exc}") from None
    if detection_map and scene.defect.active and not plan.exposure["loaded"]:
        field = ("scene.defect.position_deg" if scene.defect.fault_location.positioned
                 else "sweep.loads_kN")
        raise ConfigError(f"{field}: case {case.name}: {plan.note}; allowed with the detection "
                          f"map (sensor: and diagnosability.enabled): a defect that meets a "
                          f"loaded contact (the map's SNR is that of the defect's part of the "
                          f"record, none here), or diagnosability.enabled: false")
    est = estimate_case(case.name, scene, fidelity, plan)
    _check_estimate(est, limits, memory_cap)
    return est


#: Longest global grid cell accepted, as the ratio of its sides (``global_dy_um /
#: global_dx_um`` or the inverse): the contact solver's Fourier preconditioner stalls on
#: longer cells (the stall guard drops it, and plain CG needs thousands of iterations).
#: Measured on the draft test config at 750 kN (2026-12-05, ``docs/validation.md``): at 16-200
#: every isolated global solve converged in 13-33 iterations; at 256 (``global_dx_um``
#: 1.5625 x 400) the case's table converged, 8 of its global solves past the stall guard
#: (175-838 iterations); at 300 one solve needed 793, at 400 1,689, at 500 2,095 and at 400
#: (0.75 x 300 um) one did not converge in 4,000; ``global_dx_um: 0.1`` (4,000) failed
#: inside its job at ``max_iter`` (issue 43).
MAX_GLOBAL_CELL_ASPECT = 256.0


def _check_grid(fidelity) -> None:
    """Refuse global cells longer than :data:`MAX_GLOBAL_CELL_ASPECT` times their width, on
    which the contact solver does not converge (a refined table halves both sides)."""
    dx, dy = fidelity.global_dx_um, fidelity.global_dy_um
    if dy / dx > MAX_GLOBAL_CELL_ASPECT:
        field, got, other, bound = "global_dx_um", dx, f"global_dy_um {dy:g}", dy / MAX_GLOBAL_CELL_ASPECT
    elif dx / dy > MAX_GLOBAL_CELL_ASPECT:
        field, got, other, bound = "global_dy_um", dy, f"global_dx_um {dx:g}", dx / MAX_GLOBAL_CELL_ASPECT
    else:
        return
    raise ConfigError(f"fidelity.{field}: got {got:g} um ({max(dx, dy) / min(dx, dy):.4g}:1 "
                      f"global cells with fidelity.{other} um); allowed: >= {bound:.4g} um "
                      f"(cells at most {MAX_GLOBAL_CELL_ASPECT:g}:1: on longer ones the contact "
                      f"solver's preconditioner stalls and a solve needs thousands of "
                      f"iterations, past fidelity.max_iter {fidelity.max_iter}); refine both "
                      f"global_dx_um and global_dy_um")


def _check_estimate(est: ResourceEstimate, limits: dict, memory_cap: float) -> None:
    """Refuse an estimate over the available memory or ``limits.max_case_cpu_s``."""
    if est.memory_bytes > memory_cap:
        raise ConfigError(f"{est.culprit('memory')}: case {est.case} would need about "
                          f"{est.memory_bytes / _GB:.3g} GB ({est.describe()}); allowed: "
                          f"<= {memory_cap / _GB:.3g} GB (the available memory or "
                          f"limits.max_case_memory_GB)")
    if limits["max_case_cpu_s"] is not None and est.cpu_seconds > limits["max_case_cpu_s"]:
        raise ConfigError(f"{est.culprit('cpu')}: case {est.case} would need about "
                          f"{est.cpu_seconds:.3g} CPU s ({est.describe()}); allowed: "
                          f"<= {limits['max_case_cpu_s']:g} CPU s (limits.max_case_cpu_s)")


#: CPU seconds of the analysis jobs, calibrated on this machine (2-core Xeon, 2026-12-05) on
#: the draft record (16,456 samples) and the default sweep's logged jobs (411,393 samples;
#: ``logs/benchmarks``) and rounded up: every job's start (imports, reading the case), the
#: fast kurtogram per sample and level, one band's envelope analysis, one synthetic record
#: (sensor model and noise) and one detection test of a band on a record (fixed part and per
#: sample). Measured: a diagnose test 5 ms + 6e-8 s per sample, an envelope band 70 ms at 16k
#: samples and 0.2 s at 411k, a false-alarm trial at 5 SNRs x 5 bands 0.12 s at 411k.
_JOB_BASE_CPU_S = 2.0
_CPU_S_PER_KURTOGRAM_SAMPLE_LEVEL = 3.0e-7
_CPU_S_PER_BAND, _CPU_S_PER_BAND_SAMPLE = 0.07, 5.0e-7
_CPU_S_PER_RECORD, _CPU_S_PER_RECORD_SAMPLE = 0.01, 2.0e-7
_CPU_S_PER_TEST, _CPU_S_PER_TEST_SAMPLE = 0.005, 1.5e-7

#: The default sweep's size on each axis: the refusal names the field whose value is the
#: largest multiple of its default (the axis that made the job expensive).
_AXIS_DEFAULTS = {"scene.operation.revolutions x fs_hz": 411_393, "analysis.bands": 5,
                  "analysis.nlevel": 8, "diagnosability.snr_db": 5,
                  "diagnosability.false_alarm_trials": 10}

_AXIS_UNITS = {"scene.operation.revolutions x fs_hz": "samples", "analysis.bands": "bands",
               "analysis.nlevel": "kurtogram levels", "diagnosability.snr_db": "SNR levels",
               "diagnosability.false_alarm_trials": "trials"}


@dataclass(frozen=True)
class JobEstimate:
    """Estimated CPU time of one analysis job of a case, and the axes it grows with."""

    rule: str
    case: str
    cpu_seconds: float
    #: Config field -> its size (samples, bands, levels, SNR levels, trials) in this job.
    axes: tuple = ()

    def culprit(self) -> str:
        """The field whose size is the largest multiple of its default (:data:`_AXIS_DEFAULTS`).

        Returns
        -------
        str
            A dotted config field.
        """
        return max(self.axes, key=lambda a: a[1] / _AXIS_DEFAULTS[a[0]])[0]

    def describe(self) -> str:
        """The axes in one phrase (``411,393 samples x 5 bands x ...``).

        Returns
        -------
        str
            Each expensive axis as ``count unit``, joined by `` x ``.
        """
        return " x ".join(f"{v:,} {_AXIS_UNITS[k]}" for k, v in self.axes)


def estimate_jobs(case_name: str, scene, analysis, sensor=None, diagnosability=None, *,
                  healthy: bool = True) -> list:
    """CPU time of every analysis job of one case (rules ``bands``, ``envelope``, and with a
    sensor ``sensor``, ``diagnose`` and, for a healthy case, ``false_alarms``).

    Parameters
    ----------
    case_name : str
        The case (named in the estimates).
    scene : bearing_envelope.physics.scene.Scene
        Its record length and sampling are read.
    analysis : AnalysisSettings or None
        The ``analysis:`` section (None: no analysis job).
    sensor : TransferModel, optional
        The ``sensor:`` section (None: no sensor or detection-map job).
    diagnosability : DiagnosabilitySettings, optional
        SNR levels, false-alarm trials and where the kurtogram comes from.
    healthy : bool
        A healthy case (depth 0): it also has a ``false_alarms`` job.

    Returns
    -------
    list of JobEstimate
        One per job of the case.
    """
    if analysis is None:
        return []
    op = scene.operation
    n = int(math.ceil(op.revolutions / op.shaft_rate_hz * op.fs_hz))
    nlevel = analysis.options.nlevel           # None: the deepest the record allows
    nb, levels = len(analysis.bands), int(nlevel or max(1, max_kurtogram_level(n)))
    samples = ("scene.operation.revolutions x fs_hz", n)
    kurt = _CPU_S_PER_KURTOGRAM_SAMPLE_LEVEL * n * levels if analysis.needs_kurtogram else 0.0
    band = _CPU_S_PER_BAND + _CPU_S_PER_BAND_SAMPLE * n
    out = [JobEstimate("bands", case_name, _JOB_BASE_CPU_S + kurt + _CPU_S_PER_BAND * nb,
                       (samples, ("analysis.nlevel", levels), ("analysis.bands", nb))),
           JobEstimate("envelope", case_name, _JOB_BASE_CPU_S + nb * band,
                       (samples, ("analysis.bands", nb)))]
    if sensor is None or diagnosability is None:
        return out
    record = _CPU_S_PER_RECORD + _CPU_S_PER_RECORD_SAMPLE * n + nb * (
        _CPU_S_PER_TEST + _CPU_S_PER_TEST_SAMPLE * n) + (
        kurt if diagnosability.kurtogram_from == "record" else 0.0)
    snrs, trials = len(diagnosability.snr_db), int(diagnosability.false_alarm_trials)
    axes = (samples, ("analysis.bands", nb), ("diagnosability.snr_db", snrs))
    out += [JobEstimate("sensor", case_name, _JOB_BASE_CPU_S + _CPU_S_PER_RECORD
                        + _CPU_S_PER_RECORD_SAMPLE * n, (samples,)),
            JobEstimate("diagnose", case_name, _JOB_BASE_CPU_S + kurt + snrs * record, axes)]
    if healthy:
        out.append(JobEstimate("false_alarms", case_name,
                               _JOB_BASE_CPU_S + kurt + float(trials) * snrs * record,
                               axes + (("diagnosability.false_alarm_trials", trials),)))
    return out


def _check_jobs(jobs: list, limits: dict) -> None:
    """Refuse an analysis job whose estimate exceeds ``limits.max_case_cpu_s``."""
    cap = limits["max_case_cpu_s"]
    for job in jobs:
        if cap is not None and job.cpu_seconds > cap:
            raise ConfigError(f"{job.culprit()}: the {job.rule} job of case {job.case} would "
                              f"need about {job.cpu_seconds:.3g} CPU s ({job.describe()}); "
                              f"allowed: <= {cap:g} CPU s per job (limits.max_case_cpu_s)")


#: The tables of a paper-conventions run the "study vs this model" page reads.
PAPER_RUN_TABLES = ("cases", "harmonics", "bands")


def paper_run_tables(run) -> dict:
    """The tables of a finished paper-conventions run (config key ``paper_run``).

    Parameters
    ----------
    run : str or None
        The run's working folder (``snakemake --configfile config_paper.yaml --directory
        DIR``); None or empty: none.

    Returns
    -------
    dict
        ``{name: path}`` of :data:`PAPER_RUN_TABLES` (``results/tables/{name}.csv``); ``{}``
        without a run.

    Raises
    ------
    ConfigError
        ``paper_run`` given but not a folder, or a table missing from it.
    """
    if not run:
        return {}
    paths = {n: os.path.join(run, "results", "tables", f"{n}.csv") for n in PAPER_RUN_TABLES}
    if not os.path.isdir(run):
        raise ConfigError(f"paper_run: {run!r} is not a folder; allowed: null or the working "
                          f"folder of a finished paper-conventions run (snakemake --configfile "
                          f"config_paper.yaml --directory DIR)")
    missing = [p for p in paths.values() if not os.path.isfile(p)]
    if missing:
        raise ConfigError(f"paper_run: {run!r} has no {missing[0]}; allowed: null or the "
                          f"working folder of a finished paper-conventions run (its "
                          f"results/tables/{{cases,harmonics,bands}}.csv)")
    return paths


def precheck(settings) -> list[ResourceEstimate]:
    """The checks of this module on validated settings; returns each case's estimate.

    Parameters
    ----------
    settings : bearing_envelope.study.settings.Settings
        The loader's settings (:func:`~bearing_envelope.study.settings.workflow_settings`).

    Returns
    -------
    list of ResourceEstimate
        One per sweep case, in sweep order; empty without a ``sweep:`` section.

    Raises
    ------
    ConfigError
        One line naming the field, the value and what is allowed.
    """
    cfg = settings.config
    limits = _limits(cfg)
    cap = available_memory_bytes()
    if limits["max_case_memory_GB"] is not None:
        cap = min(cap, limits["max_case_memory_GB"] * _GB)
    profile = ((settings.scene_mapping.get("bearing") or {}).get("profile_file"))
    if profile and not os.path.isfile(profile):
        raise ConfigError(f"scene.bearing.profile_file: {profile!r} not found; allowed: an "
                          f"existing CSV file (position_mm, deviation_um)")
    paper_run_tables(cfg.get("paper_run"))
    out = []
    if settings.sweep is None:
        return out
    setup = settings.simulation
    for case in settings.sweep.cases():
        scene = settings.scene(case)   # built once, by the loader
        out.append(_check_case(case, scene, settings.analysis, limits, cap, setup.fidelity,
                               settings.sensor is not None and settings.diagnosability.enabled))
        _check_jobs(estimate_jobs(case.name, scene, settings.analysis, settings.sensor,
                                  settings.diagnosability, healthy=case.depth_um == 0), limits)
    _check_physics(settings)   # after the estimates: they bound the record length first
    return out


#: Fewest resolution bins (1 / record length) a demodulation band may span: a narrower band
#: (``0.007 .. 0.014 Hz``) passes no line at all, yet its envelope spectrum gives amplitudes.
MIN_BAND_BINS = 2

#: Sidebands of the fault line excluded from the detection map's background (the default of
#: :func:`bearing_envelope.diagnosis.detection.detection_statistic`, which the map uses).
_MAP_SIDEBANDS = EXCLUDED_SIDEBANDS


def _location_scenes(settings) -> dict:
    """One case per swept location at its highest load and deepest defect (first in sweep
    order), with its scene: the cases whose record, lines and contact the checks below read."""
    out = {}
    top = max(settings.sweep.loads_kN)
    for case in settings.sweep.cases():
        if case.load_kN == top and case.location not in out:
            out[case.location] = (case, settings.scene(case))
    return out


def _check_physics(settings) -> None:
    """Checks a job would otherwise make on its inputs, once per swept location: the contact
    not plastic everywhere at the highest load (:func:`_check_contact`), every band wider than
    the record's resolution (:func:`_check_band_widths`), and, when the run builds the
    detection map (a ``sensor:`` section and ``diagnosability.enabled``, the condition of the
    default target in ``workflow/rules/common.smk``), a background around the fault line for
    it (:func:`_check_map_background`)."""
    for case, scene in _location_scenes(settings).values():
        _check_contact(settings, case, scene)
        if settings.analysis is not None:
            _check_band_widths(settings.analysis, scene)
        if settings.sensor is not None and settings.diagnosability.enabled:
            _check_map_background(scene, case)


def _check_contact(settings, case, scene) -> None:
    """Refuse a load whose Hertz mean pressure at the most loaded element exceeds the hardness
    (the scene's, else bearing steel's): the whole contact would sit at the plastic bound."""
    from ..physics.geometry import hertz_estimate
    from ..physics.scene import BEARING_STEEL_HARDNESS_GPA

    q = scene_load_distribution(scene).q_max
    if not (math.isfinite(q) and q > 0):
        raise ConfigError(f"scene.bearing: case {case.name}: the load distribution puts "
                          f"{q:g} N on the most loaded element; allowed: a bearing and load "
                          f"that load at least one element")
    mean = 2.0 / 3.0 * hertz_estimate(scene, q).p0
    hard = scene.material.hardness_pa or BEARING_STEEL_HARDNESS_GPA * 1e9
    if mean > hard:
        i = list(settings.sweep.loads_kN).index(case.load_kN)
        f_max = case.load_kN * (hard / mean) ** 3     # p ~ Q^(1/3), Q ~ F
        raise ConfigError(f"sweep.loads_kN[{i}]: got {case.load_kN:g}; allowed: a load whose "
                          f"contact is not plastic everywhere: the most loaded element's Hertz "
                          f"mean pressure is {mean / 1e9:.3g} GPa > hardness {hard / 1e9:.3g} GPa "
                          f"(about {f_max:.3g} kN at most for this bearing)")


def _record(scene) -> tuple[int, float]:
    """Samples of a case's record and its frequency resolution (Hz)."""
    op = scene.operation
    n = int(math.ceil(op.revolutions / op.shaft_rate_hz * op.fs_hz))
    return n, op.fs_hz / n


def _check_band_widths(analysis, scene) -> None:
    """Every fixed, fraction or order band at least :data:`MIN_BAND_BINS` resolution bins wide."""
    from ..physics.locations import scene_event_frequencies
    from ..signal.bands import resolve_band

    _n, df = _record(scene)
    fs = scene.operation.fs_hz
    for b in analysis.bands:
        lo, hi = resolve_band(b.to_mapping(), fs, frequencies=scene_event_frequencies(scene),
                              static=True)[0]
        if lo is not None and 0 < lo < df:
            raise ConfigError(f"analysis.bands[{b.name}]: low edge {lo:.3g} Hz; allowed: 0 or "
                              f"at least one resolution bin ({df:.3g} Hz at "
                              f"scene.operation.revolutions = {scene.operation.revolutions:g}): "
                              f"a band-pass edge below it has no stable filter")
        if lo is not None and hi - lo < MIN_BAND_BINS * df:
            raise ConfigError(f"analysis.bands[{b.name}]: {lo:g} .. {hi:g} Hz is "
                              f"{hi - lo:.3g} Hz wide; allowed: at least {MIN_BAND_BINS} "
                              f"resolution bins ({MIN_BAND_BINS * df:.3g} Hz at "
                              f"scene.operation.revolutions = {scene.operation.revolutions:g})")


def _map_background_problem(scene, revolutions: float) -> str | None:
    """Why the detection map could not test this scene's fault line at ``revolutions``."""
    from ..diagnosis.detection import background_mask, background_problem
    from ..physics.locations import scene_event_frequencies
    from .pipeline import MAP_BACKGROUND, MAP_FMAX

    op = scene.operation
    n = int(math.ceil(revolutions / op.shaft_rate_hz * op.fs_hz))
    df = op.fs_hz / n
    line = scene.defect.fault_location.event_rate(scene_event_frequencies(scene))
    f = np.arange(int(MAP_FMAX * line / df) + 2) * df
    bg = background_mask(f, line, max(0.01 * line, 0.5 * df), MAP_BACKGROUND,
                         fr=op.shaft_rate_hz, sidebands=_MAP_SIDEBANDS)
    return background_problem(f, bg, line, "two_sided")


def _check_map_background(scene, case) -> None:
    """The detection map (rules diagnose, false_alarms) tests the fault line against the
    spectrum around it (:data:`bearing_envelope.study.pipeline.MAP_BACKGROUND`): the record
    must resolve enough bins there besides the shaft harmonics and sidebands it excludes."""
    rev = scene.operation.revolutions
    problem = _map_background_problem(scene, rev)
    if problem is None:
        return
    need = rev
    while need < 1e6 and _map_background_problem(scene, need) is not None:
        need *= 1.25
    raise ConfigError(f"scene.operation.revolutions: got {rev:g}; allowed: a record long enough "
                      f"for the detection map's background (case {case.name}: {problem}; about "
                      f">= {need:.3g} revolutions)")


def profile_files(settings) -> list[str]:
    """Files the cases depend on besides the config (``scene.bearing.profile_file``): inputs of
    the simulate rule, so that editing one reruns the simulations (its SHA-256 is stored in
    each case as ``profile_file_sha256``).

    Parameters
    ----------
    settings : bearing_envelope.study.settings.Settings
        Its ``scene_mapping`` is read.

    Returns
    -------
    list of str
        ``[profile_file]`` as the config gives it, or ``[]``.
    """
    profile = (settings.scene_mapping.get("bearing") or {}).get("profile_file")
    return [os.fspath(profile)] if profile else []


def check_case(case, scene, fidelity, config: Mapping | None = None, analysis=None) -> ResourceEstimate:
    """The per-case checks of :func:`precheck` for one case outside the workflow
    (``bearing-envelope simulate``): lower bounds and the resource estimate against the
    available memory and the ``limits:`` of ``config`` (defaults :data:`DEFAULT_LIMITS`).

    Parameters
    ----------
    case : bearing_envelope.study.case_id.CaseId
        The case (its name's length is checked).
    scene : bearing_envelope.physics.scene.Scene
        The case's validated scene.
    fidelity : bearing_envelope.physics.fidelity.Fidelity
        The fidelity it will run at.
    config : mapping, optional
        A config mapping; only its ``limits:`` section is read.
    analysis : bearing_envelope.study.sections.AnalysisSettings, optional
        When given, the record must be long enough for the kurtogram
        (:func:`min_revolutions`).

    Returns
    -------
    ResourceEstimate
        The case's estimate (:func:`estimate_case`), within the limits.

    Raises
    ------
    ConfigError
        One line naming the field, the estimate and what is allowed.
    """
    limits = _limits(config or {})
    cap = available_memory_bytes()
    if limits["max_case_memory_GB"] is not None:
        cap = min(cap, limits["max_case_memory_GB"] * _GB)
    return _check_case(case, scene, analysis, limits, cap, fidelity)


#: What Snakemake answers for a ``--configfile`` whose YAML document is empty (or only
#: comments), before any workflow code runs: the project answers the same (refused).
EMPTY_CONFIG_NOTE = ("Snakemake refuses such a --configfile itself ('Config file must be given "
                     "as JSON or YAML with keys at top level')")


def _is_null_document(path) -> bool:
    """Whether a config file holds no YAML value: only blank lines, comments, document markers
    or a lone null (``~``, ``null``); read as text, not parsed again."""
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            text = fh.read(1 << 16)
    except OSError:
        return False
    lines = [ln.strip() for ln in text.splitlines()]
    body = [ln for ln in lines if ln and not ln.startswith("#") and ln not in ("---", "...")]
    return len(text) < (1 << 16) and body in ([], ["~"], ["null"], ["Null"], ["NULL"])


def checked_settings(files=(), overrides: Mapping | None = None):
    """The pre-run check of a run, the one path of ``check-config``, the workflow's main
    process and ``benchmarks/hostile_configs.py``: ``./config.yaml`` and ``files`` merged
    (:func:`~bearing_envelope.study.settings.workflow_settings`), then :func:`precheck`.

    Parameters
    ----------
    files : sequence of path
        The ``--configfile`` files (overlays over ``./config.yaml``), in merge order.
    overrides : mapping, optional
        Snakemake's ``--config`` values.

    Returns
    -------
    (Settings, list of ResourceEstimate)
        The validated settings and each case's estimate.

    Raises
    ------
    ConfigError
        One line naming the file or field: also a file that holds no settings (empty, only
        comments), which Snakemake refuses itself before any workflow code runs.
    """
    settings = workflow_settings(files, overrides)
    for f in config_files(files):
        if _is_null_document(f):
            raise ConfigError(f"{os.fspath(f)}: holds no settings (an empty YAML document); "
                              f"allowed: a mapping of sections (sweep:, scene:, ...); "
                              f"{EMPTY_CONFIG_NOTE}")
    return settings, precheck(settings)
