"""Speed-accuracy trade of the fidelity knobs (issue 6).

For a few representative load x depth cases, :func:`tradeoff_study` varies **one knob at a
time** around a base fidelity (the ``standard`` preset by default), simulates each variant
(:func:`bearing_envelope.physics.history.simulate`), runs the signal chain on it
(:func:`bearing_envelope.study.pipeline.case_bands` and :func:`~bearing_envelope.study.pipeline.case_harmonics`
on in-memory data) and compares every metric with a converged reference:

========================  ===========================================================================
metric                    estimate (error: ``|estimate - reference| / |reference|`` unless stated)
========================  ===========================================================================
``peak_pressure``         ``max_t p_max(t)`` (Pa)
``p_max_rms``             ``rms(p_max)`` (Pa); error ``rms(p_max - p_max_ref) / rms(p_max_ref)``
``raw_bpfi_1``            raw amplitude spectrum at 1 x BPFI (Pa)
``envelope_bpfi_1``       envelope spectrum at 1 x BPFI, one row per band strategy (Pa)
``envelope_bpfi_2``       envelope spectrum at 2 x BPFI, one row per band strategy (Pa)
========================  ===========================================================================

The BPFI metrics of a healthy case (depth 0) carry no defect signature (the reference value is
numerical leakage): their error is NaN there. Every band keeps its strategy per variant (the
kurtogram band is chosen again on each variant's signal), so the kurtogram rows include the
effect of a different band choice.

**Reference.** ``reference="finest"`` (default): one *common* fine reference per case, every
numeric knob at its finest listed value at once (grid spacings, tolerance, table densities),
``reference_element`` and the scene's nominal edge radius. Rows carry ``error`` (against it) and
``error_knob`` (against the finest value of the same knob, everything else at the base: the
knob's own contribution). ``reference="per_knob"`` uses the latter as ``error`` and skips the
common reference run. A :class:`~bearing_envelope.physics.fidelity.Fidelity` or mapping gives an
explicit common reference.

**Knobs** (``knobs`` argument, name -> values listed from coarse to fine): any numeric field of
:class:`~bearing_envelope.physics.fidelity.Fidelity` (``global_dx_um``, ``global_dy_um``,
``local_dx_um``, ``local_dy_um``, ``tol``, ``n_loads``, ...), ``offset_density`` (a factor ``f`` on
``n_offsets``, ``offsets_per_width``, ``max_offsets`` and ``1/offset_step_um`` together: the
table density in offset),
``element`` (``uniform`` / ``linear``) and ``edge_radius_um`` (a *scene* parameter: its rows
measure how much the metrics depend on the unknown rim radius, at the base fidelity, and what a
sharper rim costs; its ``error_knob`` is against the nominal radius). ``element_series`` repeats
the listed grid knobs with ``element="linear"`` (knob name ``local_dx_um[linear]``), so the two
element types can be compared at equal error.

**Cost.** ``cpu_s`` (process CPU time of the simulation: single-threaded, less sensitive to
other users of a shared machine than ``wall_s``), ``wall_s``, ``n_solves`` and ``n_iterations``
of the contact solves. Every run starts from an empty kernel cache (a case runs in a fresh
process in the workflow). Identical runs (the base point of every knob) are computed once.

:func:`pareto_front` reduces the tidy table to one point per (knob, value) per metric (CPU time
per case averaged, error the worst over the cases) and marks the non-dominated points;
:func:`plot_tradeoff` draws error against time with the front.
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from ..contact.halfspace import clear_kernel_cache
from ..diagnosis import AnalysisOptions
from ..physics.fidelity import Fidelity
from ..physics.history import simulate
from ..physics.locations import scene_event_frequencies
from ..physics.scene import DEFAULT_SCENE, Scene
from ..signal.bands import DEFAULT_BANDS as SIGNAL_DEFAULT_BANDS
from .pipeline import case_bands, case_harmonics, history_case
from .case_id import CaseId
from .sections import AnalysisSettings
from .tradeoff_settings import (_SCENE_KNOBS, DEFAULT_CASES, DEFAULT_KNOBS, TRADEOFF_DEFAULTS,
                                TradeoffSettings, _replace, apply_knob)

#: The columns :func:`pareto_table` and :func:`plot_tradeoff` read when not named: the error and
#: the CPU time of each point.
ERROR_COLUMN = "error"
TIME_COLUMN = "cpu_s"

__all__ = ["DEFAULT_CASES", "DEFAULT_KNOBS", "DEFAULT_BANDS", "COLUMNS", "tradeoff_study",
           "study_from_config", "TRADEOFF_DEFAULTS", "pareto_front", "pareto_table",
           "pareto_points", "plot_tradeoff", "metric_labels", "run_variant", "apply_knob",
           "analysis_used", "TradeoffSettings"]

#: The keys of an ``analysis:`` mapping :func:`tradeoff_study` reads (the others do not change
#: its metrics).
ANALYSIS_KEYS_USED = ("signal", "nlevel", "max_level", "min_bandwidth_hz", "bands", "filter_order",
                      "squared_envelope")

#: The band strategies of the workflow's default ``analysis.bands``: the library's
#: (:data:`bearing_envelope.signal.bands.DEFAULT_BANDS`) and a fixed fs/8 - fs/4 band.
DEFAULT_BANDS: list[dict[str, Any]] = [
    *(dict(b) for b in SIGNAL_DEFAULT_BANDS),
    {"name": "fixed", "strategy": "fixed", "low_hz": 8125.0, "high_hz": 16250.0},
]

COLUMNS = ["case", "load_kN", "depth_um", "knob", "value", "is_base", "is_reference",
           "element", "edge_radius_um", "fidelity", "cpu_s", "wall_s", "n_solves", "n_iterations",
           "metric", "band", "estimate", "reference_value", "error", "error_knob"]

def _base_value(base: Fidelity, scene_map: Mapping, knob: str):
    k = knob[:-len("[linear]")] if knob.endswith("[linear]") else knob
    if k in _SCENE_KNOBS:
        return float((scene_map.get("defect", {}) or {}).get(k, DEFAULT_SCENE["defect"][k]))
    if k == "offset_density":
        return 1.0
    return getattr(base, k)


def _merge(a: Mapping, b: Mapping) -> dict:
    out = json.loads(json.dumps(dict(a)))
    for k, v in b.items():
        if isinstance(v, Mapping) and isinstance(out.get(k), Mapping):
            out[k] = _merge(out[k], v)
        else:
            out[k] = v
    return out


# ---------------------------------------------------------------------------------------------
# one run


def _clear_kernel_cache() -> None:
    clear_kernel_cache()


def run_variant(scene, fidelity: Fidelity, analysis) -> dict[str, Any]:
    """Simulate one variant and evaluate the metrics.

    Parameters
    ----------
    scene : bearing_envelope.physics.scene.Scene
        The variant's validated scene.
    fidelity : Fidelity
        The variant's fidelity.
    analysis : AnalysisSettings or mapping
        The analysis section, typed; a mapping is built into one against ``scene`` (no
        sensor).

    Returns
    -------
    dict
        ``cpu_s`` (process CPU s) and ``wall_s`` (s) of the simulation alone, ``n_solves``,
        ``n_iterations``, ``p_max`` (the analysed signal's history, in its unit, Pa for the
        pressures), ``metrics``: ``{(metric, band): estimate}`` (band ``""`` for the
        band-free metrics) and ``bands``: the chosen band limits (``BandLimits.to_dict``).
    """
    _clear_kernel_cache()
    c0, w0 = time.process_time(), time.perf_counter()
    hist = simulate(scene, fidelity)
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    case = history_case(hist)
    if not isinstance(analysis, AnalysisSettings):
        analysis = AnalysisSettings.from_mapping(analysis, fs=float(scene.operation.fs_hz),
                                                 freqs=scene_event_frequencies(scene), has_sensor=False)
    sig = analysis.signal
    x = np.asarray(case.signals[sig], float)
    metrics: dict[tuple[str, str], float] = {("peak_pressure", ""): float(x.max()),
                                             ("p_max_rms", ""): float(np.sqrt(np.mean(x ** 2)))}
    doc, _ = case_bands(case, analysis)
    h = case_harmonics(case, analysis, doc)
    raw = h[(h["quantity"] == "raw_bpfi") & (h["order"] == 1)]
    metrics[("raw_bpfi_1", "")] = float(raw["amplitude"].iloc[0]) if len(raw) else math.nan
    env = h[(h["quantity"] == "envelope_bpfi") & (h["sideband"] == 0)]
    for _, r in env.iterrows():
        if int(r["order"]) in (1, 2):
            metrics[(f"envelope_bpfi_{int(r['order'])}", str(r["band"]))] = float(r["amplitude"])
    return {"cpu_s": cpu, "wall_s": wall, "n_solves": int(hist.stats["n_solves"]),
            "n_iterations": int(hist.stats["n_iterations"]), "p_max": x, "metrics": metrics,
            "bands": [b.to_dict() for b in doc.bands]}


def _error(metric: str, est: float, ref: float, x=None, xref=None, depth: float = 1.0) -> float:
    if metric == "p_max_rms":
        if x is None or xref is None or x.size != xref.size:
            return math.nan
        return float(np.sqrt(np.mean((x - xref) ** 2)) / np.sqrt(np.mean(xref ** 2)))
    if metric != "peak_pressure" and depth <= 0:
        return math.nan   # no defect signature in a healthy case
    if not (math.isfinite(est) and math.isfinite(ref)) or ref == 0:
        return math.nan
    return abs(est - ref) / abs(ref)


# ---------------------------------------------------------------------------------------------
# the study


def tradeoff_study(
    cases: Sequence[Sequence[float]] = DEFAULT_CASES,
    *,
    knobs: Mapping[str, Sequence] | None = None,
    base: str | Mapping | Fidelity = TRADEOFF_DEFAULTS["base"],
    reference: str | Mapping | Fidelity = TRADEOFF_DEFAULTS["reference"],
    reference_element: str = TRADEOFF_DEFAULTS["reference_element"],
    element_series: Sequence[str] = TRADEOFF_DEFAULTS["element_series"],
    presets: Mapping[str, Any] | None = None,
    revolutions: float = TRADEOFF_DEFAULTS["revolutions"],
    scene: Mapping[str, Any] | None = None,
    analysis: Mapping[str, Any] | None = None,
    progress=None,
    cache: dict | None = None,
) -> pd.DataFrame:
    """Cost and error of one-knob-at-a-time fidelity variants against a converged reference.

    Parameters
    ----------
    cases : sequence of (load_kN, depth_um)
        Representative cases (default :data:`DEFAULT_CASES`: 0, 15, 100 um at 250 and 750 kN).
    knobs : mapping, optional
        Knob name -> values from coarse to fine (default :data:`DEFAULT_KNOBS`). The base value
        of each knob is added when missing.
    base : preset name, mapping or Fidelity
        The point the knobs vary around (``standard``).
    reference : ``"finest"``, ``"per_knob"``, mapping or Fidelity
        The converged reference (module docstring).
    reference_element : {"uniform", "linear"}
        Element of the ``finest`` reference.
    element_series : sequence of str
        Grid knobs repeated with linear elements (empty: none).
    presets : mapping, optional
        Extra fidelities evaluated against the same reference: name -> preset name / mapping /
        Fidelity; their rows have ``knob = "preset"`` and ``value`` = the name.
    revolutions : float
        Shaft revolutions of each history (> 0). The contact table, i.e. almost all of the
        cost, does not depend on it; a few revolutions cover many BPFI events.
    scene : mapping, optional
        The ``scene:`` mapping (default scene if None); ``operation.revolutions`` is replaced.
    analysis : mapping, optional
        The ``analysis:`` mapping; only the keys of :data:`ANALYSIS_KEYS_USED` are read
        (``signal``, ``nlevel``, ``max_level``, ``min_bandwidth_hz``, ``bands``,
        ``filter_order``, ``squared_envelope``); default: :data:`DEFAULT_BANDS`, p_max, and
        the analysis defaults of :class:`~bearing_envelope.diagnosis.AnalysisOptions`.
        ``harmonics``, ``sidebands`` and ``raw_orders_fr`` are not read: the study's metrics
        are fixed (module docstring: envelope 1 x and 2 x BPFI, raw 1 x BPFI) and do not
        depend on them, so the analysis runs with AnalysisOptions' (the sweep's).
    progress : callable, optional
        Called with a one-line message after every run (e.g. ``print``).
    cache : dict, optional
        Run results by case name and run key (fidelity and scene overrides), filled by the
        study and read before running: pass the same dict to a second call (e.g. with other
        presets) to reuse the reference runs. Entries hold the ``p_max`` history.

    Returns
    -------
    pandas.DataFrame
        Tidy, columns :data:`COLUMNS`: one row per case x (knob, value) x metric x band.
        ``value`` is stored as text (``"4"``, ``"1e-06"``, ``"linear"``); ``is_base`` marks the
        base point of each knob (repeated under every knob), ``knob = "reference"`` the
        reference run (error 0).
    """
    settings = TradeoffSettings.from_mapping({
        "cases": cases, "knobs": knobs if knobs is not None else DEFAULT_KNOBS, "base": base,
        "reference": reference, "reference_element": reference_element,
        "element_series": element_series, "presets": presets or {}, "revolutions": revolutions})
    return _study(settings, scene=scene, analysis=analysis, progress=progress, cache=cache)


def _study(ts: TradeoffSettings, *, scene, analysis, progress, cache) -> pd.DataFrame:
    """:func:`tradeoff_study` of checked settings (nothing is checked again)."""
    base_f = ts.base
    scene_map = _merge(scene or {}, {"operation": {"revolutions": ts.revolutions}})
    an = analysis_used(analysis)
    all_knobs = _expand_knobs(ts.knobs, ts.element_series, base_f, scene_map)
    ref_f = _reference_fidelity(ts.reference, base_f, all_knobs, ts.reference_element)
    preset_f = ts.presets

    rows: list[dict] = []
    ref_keys: dict[str, str] = {}
    for load_kN, depth_um in ts.cases:
        runs = _CaseRuns(load_kN, depth_um, an, scene_map, cache, progress)
        ref = runs.run(ref_f, {}) if ref_f is not None else None
        if ref is not None:
            ref_keys[runs.name] = runs.last_key
        results = [(k, vs, fid, sc, v, runs.run(fid, sc))
                   for k, vs, fid, sc, v in _variants(all_knobs, base_f, preset_f)]
        finest = _knob_references(all_knobs, base_f, scene_map, results)
        out = _RowWriter(rows, load_kN, depth_um, ref, scene_map, base_f)
        if ref is not None:
            out.emit("reference", "reference", ref_f, {}, ref, False, True, None)
        for k, vs, fid, sc, v, res in results:
            is_base = k != "preset" and _same(v, _base_value(base_f, scene_map, k)) and \
                not k.endswith("[linear]")
            kref = finest.get(k) if k != "preset" else None
            out.emit(k, vs, fid, sc, res, bool(is_base), False, kref)
    df = pd.DataFrame(rows, columns=COLUMNS)
    if ref_f is None:
        df["error"] = df["error_knob"]
    df.attrs["reference_keys"] = ref_keys   # case -> key of the reference run in ``cache``
    return df


def analysis_used(analysis: Mapping[str, Any] | None) -> dict[str, Any]:
    """The analysis settings of the study: the analysis defaults of
    :class:`~bearing_envelope.diagnosis.AnalysisOptions` (the sweep's), and the keys of
    :data:`ANALYSIS_KEYS_USED` from ``analysis``.

    Parameters
    ----------
    analysis : Mapping or None
        The config's ``analysis:`` section.

    Returns
    -------
    dict
        ``signal``, ``nlevel``, ``filter_order``, ``squared_envelope``, ``harmonics``,
        ``sidebands``, ``raw_orders_fr``, ``bands``.
    """
    d = AnalysisOptions().config_values()   # the options as the config writes them
    an = {"signal": "p_max", **{k: d[k] for k in ("nlevel", "filter_order", "squared_envelope",
                                                  "harmonics", "sidebands", "raw_orders_fr")},
          "bands": DEFAULT_BANDS}
    if analysis:
        an.update({k: v for k, v in analysis.items()
                   if k in ANALYSIS_KEYS_USED})
    return an


def _expand_knobs(knobs: Mapping[str, Sequence], element_series: Sequence[str], base_f: Fidelity,
                  scene_map: Mapping) -> dict[str, list]:
    """Every knob's values (checked by :class:`TradeoffSettings`), the base value inserted in
    order, and the ``[linear]`` repeats of ``element_series``."""
    all_knobs: dict[str, list] = {}
    for k, vals in knobs.items():
        vals = list(vals)
        bv = _base_value(base_f, scene_map, k)
        if not any(_same(v, bv) for v in vals):
            vals = _insert_sorted(vals, bv)
        all_knobs[k] = vals
    for k in element_series:
        if base_f.element != "linear":
            all_knobs[f"{k}[linear]"] = list(all_knobs[k])
    return all_knobs


def _reference_fidelity(reference, base_f: Fidelity, all_knobs: Mapping[str, list],
                        reference_element: str) -> Fidelity | None:
    """The common reference (None for ``"per_knob"``; an explicit one as checked by
    :class:`TradeoffSettings`): see the module docstring."""
    if isinstance(reference, Fidelity):
        return reference
    if reference == "per_knob":
        return None
    ref_f = _replace(base_f, name="reference", element=reference_element)
    for k, vals in all_knobs.items():
        if k in ("element",) or k in _SCENE_KNOBS or k.endswith("[linear]"):
            continue
        ref_f, _ = apply_knob(ref_f, k, vals[-1])
    return dataclasses.replace(ref_f, name="reference")


def _variants(all_knobs: Mapping[str, list], base_f: Fidelity, preset_f: Mapping[str, Fidelity]):
    """``(knob, value text, fidelity, scene overrides, value)`` of every run but the reference."""
    variants: list[tuple[str, str, Fidelity, dict, Any]] = []
    for k, vals in all_knobs.items():
        for v in vals:
            fid, sc_over = apply_knob(base_f, k, v)
            fid = dataclasses.replace(fid, name=f"{k}={v}")
            variants.append((k, _fmt(v), fid, sc_over, v))
    for n, f in preset_f.items():
        variants.append(("preset", n, f, {}, n))
    return variants


def _knob_references(all_knobs: Mapping[str, list], base_f: Fidelity, scene_map: Mapping,
                     results: list) -> dict[str, dict]:
    """The run of each knob's own reference: its finest value (scene knobs and ``element``:
    the base value; ``[linear]`` repeats: their finest)."""
    finest = {}
    for k, vals in all_knobs.items():
        kk = k[:-len("[linear]")] if k.endswith("[linear]") else k
        fv = _base_value(base_f, scene_map, kk) if (kk in _SCENE_KNOBS or kk == "element") \
            else vals[-1]
        if k.endswith("[linear]"):
            fv = vals[-1]
        finest[k] = next(r for kk2, vs, fid, sc, v, r in results if kk2 == k and _same(v, fv))
    return finest


class _CaseRuns:
    """The runs of one case, by key (fidelity, scene overrides, analysis, scene), through
    ``cache`` when given."""

    def __init__(self, load_kN: float, depth_um: float, an: Mapping, scene_map: Mapping,
                 cache: dict | None, progress):
        self.load_kN, self.depth_um, self.an, self.scene_map = load_kN, depth_um, an, scene_map
        self.name = CaseId(load_kN, depth_um).name
        self.cache: dict[str, dict] = cache.setdefault(self.name, {}) if cache is not None else {}
        self.progress = progress
        self.last_key = ""

    def run(self, fid: Fidelity, sc_over: dict) -> dict:
        key = json.dumps([{k: v for k, v in fid.to_dict().items() if k != "name"}, sc_over],
                         sort_keys=True, default=str)
        key = json.dumps([key, self.an, self.scene_map], sort_keys=True, default=str)
        if key not in self.cache:
            sc = Scene.from_mapping(_merge(self.scene_map, sc_over), load_kN=self.load_kN,
                                    depth_um=self.depth_um)
            self.cache[key] = run_variant(sc, fid, self.an)
            if self.progress:
                r = self.cache[key]
                self.progress(f"{self.name} {fid.name} {sc_over or ''}: "
                              f"{r['cpu_s']:.1f} s cpu, {r['wall_s']:.1f} s wall, {r['n_solves']} solves")
        self.last_key = key
        return self.cache[key]


class _RowWriter:
    """Appends the tidy rows of one run of one case to ``rows``."""

    def __init__(self, rows: list, load_kN: float, depth_um: float, ref: dict | None,
                 scene_map: Mapping, base_f: Fidelity):
        self.rows, self.load_kN, self.depth_um, self.ref = rows, load_kN, depth_um, ref
        self.scene_map, self.base_f = scene_map, base_f

    def emit(self, knob, vstr, fid, sc_over, res, is_base, is_ref, kref) -> None:
        depth_um, common = self.depth_um, self.ref if self.ref is not None else kref
        edge = float(_merge(self.scene_map, sc_over).get("defect", {}).get(
            "edge_radius_um", _base_value(self.base_f, self.scene_map, "edge_radius_um")))
        for (metric, band), est in res["metrics"].items():
            rv = common["metrics"].get((metric, band), math.nan) if common is not None else math.nan
            e = _error(metric, est, rv, res["p_max"], common["p_max"] if common else None, depth_um)
            if kref is not None:
                rk = kref["metrics"].get((metric, band), math.nan)
                ek = _error(metric, est, rk, res["p_max"], kref["p_max"], depth_um)
            else:
                ek = math.nan
            if is_ref:
                e = 0.0 if not math.isnan(e) else e
            self.rows.append({
                "case": CaseId(self.load_kN, depth_um).name, "load_kN": self.load_kN,
                "depth_um": depth_um, "knob": knob, "value": vstr, "is_base": is_base,
                "is_reference": is_ref, "element": fid.element, "edge_radius_um": edge,
                "fidelity": json.dumps({k: v for k, v in fid.to_dict().items() if k != "name"},
                                       sort_keys=True),
                "cpu_s": res["cpu_s"], "wall_s": res["wall_s"], "n_solves": res["n_solves"],
                "n_iterations": res["n_iterations"], "metric": metric, "band": band,
                "estimate": est, "reference_value": rv, "error": e, "error_knob": ek,
            })


def _same(a, b) -> bool:
    if isinstance(a, str) or isinstance(b, str):
        return a == b
    return math.isclose(float(a), float(b), rel_tol=1e-9, abs_tol=0.0)


def _insert_sorted(vals: list, v) -> list:
    """Insert the base value keeping the coarse-to-fine order (numbers: by monotone order)."""
    if isinstance(v, str):
        return [v] + vals
    nums = [float(x) for x in vals]
    dec = len(nums) < 2 or nums[0] > nums[-1]   # grid spacings, tol: decreasing = finer
    out = list(vals)
    for i, x in enumerate(nums):
        if (dec and float(v) > x) or (not dec and float(v) < x):
            out.insert(i, v)
            return out
    out.append(v)
    return out


def _fmt(v) -> str:
    if isinstance(v, str):
        return v
    return f"{float(v):g}"


# ---------------------------------------------------------------------------------------------
# Pareto front


def metric_labels(df: pd.DataFrame) -> list[tuple[str, str]]:
    """The (metric, band) pairs of a tradeoff table, in a stable order.

    Parameters
    ----------
    df : pandas.DataFrame
        A tradeoff table (:func:`tradeoff_study`; ``metric`` and ``band`` are read).

    Returns
    -------
    list of (str, str)
        Distinct pairs, by metric in the order of the module's table (unknown metrics last),
        then by band name.
    """
    order = {"peak_pressure": 0, "p_max_rms": 1, "raw_bpfi_1": 2, "envelope_bpfi_1": 3,
             "envelope_bpfi_2": 4}
    pairs = df[["metric", "band"]].drop_duplicates().itertuples(index=False)
    return sorted(((m, b) for m, b in pairs), key=lambda p: (order.get(p[0], 9), p[1]))


def pareto_table(df: pd.DataFrame, metric: str, band: str = "", *, error: str = ERROR_COLUMN,
                 time: str = TIME_COLUMN) -> pd.DataFrame:
    """One point per (knob, value) for one metric: mean time per case, worst error over cases.

    Cases where the error is undefined (NaN: BPFI metrics of a healthy case) are left out of
    the worst error but not of the time. Columns: ``knob, value, time_s, error, n_cases,
    is_base, is_reference, pareto``.

    Parameters
    ----------
    df : pandas.DataFrame
        A tradeoff table (:func:`tradeoff_study`).
    metric : str
        The metric (``peak_pressure``, ``p_max_rms``, ``raw_bpfi_1``, ``envelope_bpfi_1``,
        ``envelope_bpfi_2``).
    band : str, default ""
        The band name of an envelope metric (``""`` for the others).
    error : str, keyword-only, default "error"
        The error column (``error`` or ``error_knob``).
    time : str, keyword-only, default "cpu_s"
        The time column (``cpu_s`` or ``wall_s``), seconds.

    Returns
    -------
    pandas.DataFrame
        One row per (knob, value) in first-appearance order; the base point, repeated under
        every knob, kept once as knob ``"base"`` (last); ``pareto`` from :func:`pareto_front`.

    Raises
    ------
    ValueError
        No row of ``metric`` and ``band``.
    """
    d = df[(df["metric"] == metric) & (df["band"] == band)]
    if d.empty:
        raise ValueError(f"no rows for metric {metric!r} band {band!r}")
    g = d.groupby(["knob", "value"], sort=False)
    out = pd.DataFrame({
        "time_s": g[time].mean(),
        "error": g[error].max(),   # NaN-skipping
        "n_cases": g[error].count(),
        "is_base": g["is_base"].any(),
        "is_reference": g["is_reference"].any(),
    }).reset_index()
    # the base point appears under every knob: keep it once
    base = out[out["is_base"]]
    if len(base) > 1:
        out = pd.concat([out[~out["is_base"]], base.iloc[[0]].assign(knob="base")],
                        ignore_index=True)
    out["pareto"] = pareto_front(out["time_s"].to_numpy(), out["error"].to_numpy())
    return out


def pareto_front(time_s, error) -> np.ndarray:
    """Boolean mask of the non-dominated points (minimise both time and error).

    A point is dominated when another point is no slower and no less accurate, and strictly
    better in one of the two. NaN errors are never on the front.

    Parameters
    ----------
    time_s : array_like
        Cost of each point (seconds).
    error : array_like
        Error of each point (same length).

    Returns
    -------
    ndarray of bool
        True for the points on the front.
    """
    t = np.asarray(time_s, float)
    e = np.asarray(error, float)
    ok = np.isfinite(t) & np.isfinite(e)
    mask = np.zeros(t.size, bool)
    for i in np.flatnonzero(ok):
        dom = ok & (t <= t[i]) & (e <= e[i]) & ((t < t[i]) | (e < e[i]))
        mask[i] = not dom.any()
    return mask


# ---------------------------------------------------------------------------------------------
# plot


def plot_tradeoff(df: pd.DataFrame, path=None, *, metrics: Sequence[tuple[str, str]] | None = None,
                  error: str = ERROR_COLUMN, time: str = TIME_COLUMN, ncols: int = 4):
    """Error against CPU time per case, one panel per metric, Pareto front marked.

    Each knob is a line through its values (coarse to fine), the base point a black square, the
    reference (zero error, drawn at the bottom edge) a black star, presets labelled diamonds;
    uniform and linear elements along ``local_dx_um`` are drawn solid and dashed in the same
    colour, so the element that reaches a given error sooner is the curve further left. The
    front is the grey step line through the circled points.

    Parameters
    ----------
    df : pandas.DataFrame
        A tradeoff table (:func:`tradeoff_study`).
    path : str or os.PathLike, optional
        Where the figure is saved (110 dpi, format from the suffix); None: not saved.
    metrics : sequence of (metric, band), optional, keyword-only
        The panels; default every pair of :func:`metric_labels`.
    error, time : str, keyword-only
        The error and time columns, as in :func:`pareto_table`.
    ncols : int, keyword-only, default 4
        Panels per row (at most the number of panels).

    Returns
    -------
    matplotlib.figure.Figure
        The figure (not attached to pyplot).
    """
    # lazy: matplotlib adds ~1.5 s to importing this module (the study runs need no plots)
    from matplotlib.figure import Figure

    metrics = list(metrics) if metrics is not None else metric_labels(df)
    n = len(metrics)
    ncols = min(ncols, n)
    nrows = int(math.ceil(n / ncols))
    fig = Figure(figsize=(4.2 * ncols, 3.4 * nrows), layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False).ravel()
    knobs = [k for k in dict.fromkeys(df["knob"]) if k not in ("reference", "preset")]
    base_knobs = [k for k in knobs if not k.endswith("[linear]")]
    import matplotlib  # lazy, as Figure above

    cmap = matplotlib.colormaps["tab10"]
    colour = {k: cmap(i % 10) for i, k in enumerate(base_knobs)}
    for k in knobs:
        if k.endswith("[linear]"):
            colour[k] = colour.get(k[:-len("[linear]")], "k")
    for ax, (metric, band) in zip(axes, metrics):
        pt = pareto_table(df, metric, band, error=error, time=time)
        pos = pt["error"][pt["error"] > 0]
        floor = float(pos.min()) / 3 if len(pos) else 1e-6
        for k in knobs:
            d = pt[pt["knob"] == k]
            if not len(d):
                continue
            # add the base point to each knob's line
            b = pt[pt["knob"] == "base"]
            kb = df[(df["knob"] == k) & df["is_base"]]["value"]
            if len(kb) and len(b) and not (d["value"] == kb.iloc[0]).any():
                vals = df[(df["knob"] == k)]["value"].drop_duplicates().tolist()
                d = pd.concat([d, b.assign(knob=k, value=kb.iloc[0])]).set_index("value").reindex(
                    [v for v in vals if v in set(d["value"]) | {kb.iloc[0]}]).reset_index()
            ax.plot(d["time_s"], d["error"].clip(lower=floor), "-" if not k.endswith("]") else "--",
                    marker="o" if not k.endswith("]") else "^", ms=4, color=colour[k], label=k)
        b = pt[pt["knob"] == "base"]
        ax.plot(b["time_s"], b["error"].clip(lower=floor), "s", color="k", ms=6, label="base")
        r = pt[pt["is_reference"]]
        ax.plot(r["time_s"], np.full(len(r), floor), "*", color="k", ms=10, label="reference (error 0)")
        p = pt[pt["knob"] == "preset"]
        for _, row in p.iterrows():
            ax.plot(row["time_s"], max(row["error"], floor), "D", color="m", ms=6)
            ax.annotate(row["value"], (row["time_s"], max(row["error"], floor)), fontsize=7,
                        xytext=(3, 3), textcoords="offset points", color="m")
        front = pt[pt["pareto"]].sort_values("time_s")
        if len(front):
            ax.step(front["time_s"], front["error"].clip(lower=floor), where="post", color="0.5",
                    lw=3, alpha=0.4, zorder=0)
            ax.plot(front["time_s"], front["error"].clip(lower=floor), "o", mfc="none", mec="k",
                    ms=9, label="Pareto front")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{metric}" + (f" [{band}]" if band else ""), fontsize=9)
        ax.set_xlabel(f"{'CPU' if time == 'cpu_s' else 'wall'} time per case (s)")
        ax.set_ylabel("relative error (worst case)")
        ax.grid(True, which="both", alpha=0.3)
    for ax in axes[n:]:
        ax.set_visible(False)
    h, lab = axes[0].get_legend_handles_labels()
    fig.legend(h, lab, loc="outside lower center", ncols=min(6, len(lab)), fontsize=8)
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig


def pareto_points(df: pd.DataFrame, *, error: str = ERROR_COLUMN,
                  time: str = TIME_COLUMN) -> pd.DataFrame:
    """:func:`pareto_table` of every metric of a tradeoff table, stacked (columns ``metric``,
    ``band`` first).

    Parameters
    ----------
    df : pandas.DataFrame
        A tradeoff table (:func:`tradeoff_study`).
    error, time : str, keyword-only
        The error and time columns, as in :func:`pareto_table`.

    Returns
    -------
    pandas.DataFrame
        The points of every pair of :func:`metric_labels`, in that order.
    """
    parts = []
    for metric, band in metric_labels(df):
        pt = pareto_table(df, metric, band, error=error, time=time)
        pt.insert(0, "band", band)
        pt.insert(0, "metric", metric)
        parts.append(pt)
    return pd.concat(parts, ignore_index=True)


def study_from_config(section: "TradeoffSettings | Mapping[str, Any] | None", *,
                      scene: Mapping[str, Any] | None = None,
                      analysis: Mapping[str, Any] | None = None, progress=None) -> pd.DataFrame:
    """:func:`tradeoff_study` configured by the workflow's ``tradeoff:`` section.

    Keys (all optional): ``cases`` (list of ``[load_kN, depth_um]``), ``revolutions``, ``base``,
    ``reference``, ``reference_element``, ``element_series``, ``knobs`` (name -> values, coarse
    to fine; replaces the default set), ``presets`` (list of preset names or mapping name ->
    fidelity mapping). See ``src/bearing_envelope/data/config.schema.yaml``.

    Parameters
    ----------
    section : TradeoffSettings, mapping or None
        The section as the loader typed it (``Settings.tradeoff``: not checked again), or a
        mapping (checked here, once).
    scene : mapping, optional
        The ``scene:`` mapping.
    analysis : mapping, optional
        The ``analysis:`` mapping (:func:`analysis_used`).
    progress : callable, optional
        Called with a one-line message after every run.

    Returns
    -------
    pandas.DataFrame
        As :func:`tradeoff_study`.
    """
    ts = section if isinstance(section, TradeoffSettings) else \
        TradeoffSettings.from_mapping(section)
    return _study(ts, scene=scene, analysis=analysis, progress=progress, cache=None)
