"""A reference that varies every knob, an error model per load, the converged default.

    nice -n 10 python -m benchmarks reference run --out results_bench/reference --worker 0/2
    nice -n 10 python -m benchmarks reference run --out results_bench/reference --worker 1/2
    (without --runs: MODEL_RUNS on the model's cases, HELDOUT_RUNS on the held-out ones;
    about 2 h of a 2-core machine; with ``--cases`` the held-out ones alone, about 40 min,
    whose report judges the error model the package ships)
    python -m benchmarks reference report --out results_bench/reference [--write-model]
    nice -n 10 python -m benchmarks reference cost --out results_bench/cost

It reuses ``benchmarks/accuracy.py`` (tables cached per case and run, the metrics of the analysis
chain, the Richardson step) with every fidelity at the far field ``responds`` and the amplitudes
read ``interpolated`` (the defaults since issue 25 parts 1-2).

**Reference.** Around ``accurate`` (the base), each knob is refined alone, one ladder per knob
(:data:`KNOBS`, coarse to fine): rim strips (``rim_dx_um`` 1, 0.5, 0.25 um), the global axial
grid (``global_dy_um`` 80, 40, 20, 10 um; since the 2026-11-26 fourth session at a 10 um window in
every level, :data:`KNOB_BASE`, since the window's axial spacing follows the global one), the
window's axial spacing (``local_dy_um`` 40, 20, 10 um,
5 um where built), the window margin (``window_margin_um`` 400, 1,600 um), the tolerance
(``tol`` 1e-5, 1e-6), the table's load nodes (``n_loads`` 5, 9, 17 where built) and offset
density (x1, x2, x4 where built). Per metric and knob, the converged value is the Richardson
value of the finest three levels when they are monotone with an order in [0.5, 4], else the
finest value; the knob's correction is that minus the base value; the reference is the base
value plus every knob's correction (to first order the errors of independent knobs add, as in
``benchmarks/accuracy.py``). Its uncertainty per metric (``ref_uncert``) is the sum over knobs
of |Richardson - finest| (a converged ladder) or of the last step |finest - next| (otherwise).

**Error model** (``--write-model``): per point, load, case kind (defect / healthy), signal and
quantity class, the worst relative error over the model's cases at that load (three depths), the
analysis bands and the orders; ``study/accuracy.py`` reads the worst over the loads (its
``load_rule="per_load"``, each case's own load). **Coverage**: on the
held-out cases (:data:`HELDOUT`, not used by the model) the fraction of amplitudes whose error
is within the estimate, per quantity class.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.study.accuracy import quantity_class, stored_error_model

from . import accuracy as acc  # tables, metrics, the Richardson step

#: the model's cases: three depths per load (two until 2026-11-26) and a healthy race per load
MODEL = ((500.0, 15.0), (500.0, 100.0), (250.0, 15.0), (250.0, 100.0), (750.0, 15.0),
         (750.0, 100.0), (250.0, 0.0), (500.0, 0.0), (750.0, 0.0),
         # three depths per load since the 2026-11-27 session (the held-out 20-50 um lie
         # between 15 and 60 um)
         (500.0, 60.0), (250.0, 60.0), (750.0, 60.0))
#: cases kept out of the model: their errors test its estimates
HELDOUT = ((500.0, 50.0), (250.0, 40.0), (750.0, 20.0))
#: the base: rim strips 0.5 um + a 40 um axial global grid over the former default (the 2026-11-24
#: ``accurate``; ``standard`` since issue 25 part 6), fields spelled out so the runs do not
#: depend on the preset names
BASE = {"preset": "fast", "rim_dx_um": 0.5, "global_dy_um": 40.0}
X2, X4 = acc.offsets_x(2.0), acc.offsets_x(4.0)

#: every run: name -> fidelity mapping (checks and snapshots off)
RUNS: dict[str, dict] = {
    "draft": {"preset": "draft"},            # run names are the 2026-11-24 preset names
    "standard": {"preset": "fast"},          # the default before issue 25 part 6
    "accurate": BASE,
    "rim1": {**BASE, "rim_dx_um": 1.0},
    "rim0.25": {**BASE, "rim_dx_um": 0.25},
    "gdy80": {**BASE, "global_dy_um": 80.0},
    "gdy20": {**BASE, "global_dy_um": 20.0},
    "gdy10": {**BASE, "global_dy_um": 10.0},
    # the global ladder at a fixed 10 um window (the window's axial spacing is
    # global_dy / ceil(global_dy / local_dy): the 80/40/20/10 ladder at local_dy 40 also refines
    # the window 40/40/20/10, which the local_dy ladder counts already; 2026-11-26 fourth session)
    "gdy80l10": {**BASE, "global_dy_um": 80.0, "local_dy_um": 10.0},
    "gdy20l10": {**BASE, "global_dy_um": 20.0, "local_dy_um": 10.0},
    "ldy20": {**BASE, "local_dy_um": 20.0},
    "ldy10": {**BASE, "local_dy_um": 10.0},
    "margin1600": {**BASE, "window_margin_um": 1600.0},
    "tol1e-6": {**BASE, "tol": 1e-6},
    "loads9": {**BASE, "n_loads": 9},
    "x2": {**BASE, **X2},
    # phase 2 (built where time allowed): further ladder levels and candidate defaults
    "ldy5": {**BASE, "local_dy_um": 5.0},
    "loads17": {**BASE, "n_loads": 17},
    "x4": {**BASE, **X4},
    "acc+loads9+x2": {**BASE, "n_loads": 9, **X2},
    "acc+loads9+x2+ldy20": {**BASE, "n_loads": 9, **X2, "local_dy_um": 20.0},
    "acc+loads9+x2+ldy10": {**BASE, "n_loads": 9, **X2, "local_dy_um": 10.0},
    "acc+ldy10": {**BASE, "local_dy_um": 10.0},
    # issue 25, third session: the axial end strips (fidelity.end_dy_um, end_strip_um) over the
    # base; ``benchmarks/end_strips.py`` compares them with the local_dy ladder
    "end20": {**BASE, "end_dy_um": 20.0},
    "end10": {**BASE, "end_dy_um": 10.0},
    "end5": {**BASE, "end_dy_um": 5.0},
    "end10s20": {**BASE, "end_dy_um": 10.0, "end_strip_um": 20.0},
    "end10s80": {**BASE, "end_dy_um": 10.0, "end_strip_um": 80.0},
    "end5s80": {**BASE, "end_dy_um": 5.0, "end_strip_um": 80.0},
    # 2026-11-27: candidates for a preset within 2 % on the integral signals (end strips over a
    # finer window; the global grid at 20 um for p_max's raw terms)
    "ldy10e5s80": {**BASE, "local_dy_um": 10.0, "end_dy_um": 5.0, "end_strip_um": 80.0},
    "ldy20e5s80": {**BASE, "local_dy_um": 20.0, "end_dy_um": 5.0, "end_strip_um": 80.0},
    "gdy20l10e5s80": {**BASE, "global_dy_um": 20.0, "local_dy_um": 10.0, "end_dy_um": 5.0,
                      "end_strip_um": 80.0},
}
#: a knob whose ladder is not built around the base: its correction is taken from this run
#: (the global ladder at the 10 um window: converged value minus its own 40 um level)
KNOB_BASE = {"global_dy_um": "ldy10"}
#: runs that are presets, by the preset's name since issue 25 part 6 (the model and the tables);
#: ``accurate`` since 2026-11-27 is run ``ldy10e5s80`` (until then run ``gdy20``)
PRESET_OF = {"standard": "fast", "accurate": "standard", "ldy10e5s80": "accurate",
             "draft": "draft"}


def label(run: str) -> str:
    return PRESET_OF.get(run, run) + (f" (run {run})" if run in PRESET_OF and run != PRESET_OF[run]
                                      else "")


#: the runs of a model case (2026-11-27: the finest three levels of every ladder of
#: :data:`KNOBS` the held-out cases have, but 17 load nodes; the presets): a reference with
#: fewer knobs than the held-out cases' understates the model's errors (with two levels of the
#: global grid only, p_max's raw DC bar at standard was 0.011 % against 0.81 % held out)
MODEL_RUNS = ("standard", "accurate", "ldy10e5s80", "draft", "rim1", "rim0.25", "ldy10",
              "gdy20l10", "gdy10", "ldy20", "ldy5", "margin1600", "tol1e-6", "loads9", "x2",
              "gdy20")
#: the runs of a held-out case: the model's, the coarsest global level (its table shows the
#: step), the third level of the load nodes, the candidates
HELDOUT_RUNS = MODEL_RUNS + ("gdy80l10", "loads17", "end10s80", "ldy20e5s80", "gdy20l10e5s80")
#: the runs every case of the report has (a case without them is left out)
REQUIRED = ("standard", "accurate", "gdy20", "ldy10", "margin1600", "loads9", "x2", "gdy20l10")
#: knob -> [(level, run)] from coarse to fine; the base (``accurate``) is one level of each
KNOBS: dict[str, list[tuple[float, str]]] = {
    "rim_dx_um": [(1.0, "rim1"), (0.5, "accurate"), (0.25, "rim0.25")],
    # at a 10 um window (every level; :data:`KNOB_BASE`): the global grid alone
    "global_dy_um": [(80.0, "gdy80l10"), (40.0, "ldy10"), (20.0, "gdy20l10"), (10.0, "gdy10")],
    "local_dy_um": [(40.0, "accurate"), (20.0, "ldy20"), (10.0, "ldy10"), (5.0, "ldy5")],
    "window_margin_um": [(400.0, "accurate"), (1600.0, "margin1600")],
    "tol": [(1e-5, "accurate"), (1e-6, "tol1e-6")],
    "n_loads": [(5, "accurate"), (9, "loads9"), (17, "loads17")],
    "offset_density": [(1, "accurate"), (2, "x2"), (4, "x4")],
}


def runs_spec(names) -> dict[str, dict]:
    return {n: {**RUNS[n], **acc.OFF} for n in names}


def values_path(out: Path, load: float, depth: float) -> Path:
    return out / "values" / f"F{load:g}kN_h{depth:g}um.csv"


def run_case(out: Path, load: float, depth: float, names, revolutions: float, analysis) -> None:
    """Build and evaluate ``names`` for one case; the values are appended run by run (a run
    already in the case's values file is skipped)."""
    vp = values_path(out, load, depth)
    vp.parent.mkdir(parents=True, exist_ok=True)
    done = set(pd.read_csv(vp, usecols=["run"])["run"]) if vp.exists() else set()
    warm = False
    for run, spec in runs_spec(names).items():
        if run in done:
            continue
        t0 = time.time()
        rec = acc.build(out, load, depth, run, spec)
        if not warm:                      # numba's JIT outside every timed synthesis
            acc._warm_up(out, [(load, depth)])
            warm = True
        rows = acc.evaluate_run(out, load, depth, run, spec, revolutions, 131, analysis)
        df = pd.DataFrame(rows)
        df.to_csv(vp, mode="a", header=not vp.exists(), index=False)
        print(f"F{load:g}kN h{depth:g}um {run}: table {rec['cpu_s']:.1f} s CPU "
              f"({rec['n_solves']} solves), synthesis {df['synth_cpu_s_100rev'].iloc[0]:.1f} s "
              f"CPU/100 rev, wall {time.time() - t0:.1f} s, load {os.getloadavg()[0]:.1f}",
              flush=True)


def cmd_run(args) -> None:
    i, n = (int(v) for v in args.worker.split("/"))
    cases = [tuple(c) for c in json.loads(args.cases)] if args.cases else \
        [HELDOUT[0], MODEL[1], MODEL[2], MODEL[3], MODEL[4], MODEL[5], MODEL[0], HELDOUT[2],
         HELDOUT[1], *MODEL[6:]]
    analysis = acc.analysis_config()
    for load, depth in cases[i::n]:
        names = args.runs or (HELDOUT_RUNS if (load, depth) in HELDOUT else MODEL_RUNS)
        run_case(args.out, load, depth, names, args.revolutions, analysis)


def _knob_value(v: pd.Series, ladder):
    """(converged value, finest, last step, status) of one knob's ladder at one metric."""
    have = [(lvl, float(v[r])) for lvl, r in ladder if r in v.index]
    if len(have) < 2:
        return None
    fine = [x for _, x in have[-3:]][::-1]                 # finest first
    if len(fine) == 3:
        conv, _, status = acc.richardson3(*fine)
    else:
        conv, status = fine[0], "two levels: finest"
    resid = abs(conv - fine[0]) if status == "richardson" else abs(fine[0] - fine[1])
    return conv, fine[0], resid, status


def reference(df: pd.DataFrame) -> pd.DataFrame:
    """Per metric: the base value plus each knob's correction (:data:`KNOBS`)."""
    out = []
    for key, g in df.groupby(acc.KEYS):
        v = g.drop_duplicates("run").set_index("run")["value"]
        if "accurate" not in v.index:
            continue
        base = float(v["accurate"])
        rec = dict(zip(acc.KEYS, key))
        ref, unc = base, 0.0
        for knob, ladder in KNOBS.items():
            kv = _knob_value(v, ladder)
            origin = KNOB_BASE.get(knob, "accurate")
            if kv is None or origin not in v.index:
                continue
            conv, _, resid, status = kv
            rec[f"{knob}_delta"] = conv - float(v[origin])
            rec[f"{knob}_status"] = status
            rec[f"{knob}_resid"] = resid
            ref += conv - float(v[origin])
            unc += resid
        rec["ref"], rec["ref_uncert"] = ref, unc
        out.append(rec)
    r = pd.DataFrame(out)
    r["ref_uncert_rel"] = r["ref_uncert"] / r["ref"].abs()
    return r


def errors(df: pd.DataFrame, ref: pd.DataFrame) -> pd.DataFrame:
    e = df.merge(ref[acc.KEYS + ["ref", "ref_uncert_rel"]], on=acc.KEYS, how="inner")
    e["error"] = (e["value"] - e["ref"]).abs() / e["ref"].abs()
    e["quantity_class"] = [quantity_class(q, s) for q, s in zip(e["quantity"], e["sideband"])]
    e["group"] = [line_group(q, s, b) for q, s, b in
                  zip(e["quantity"], e["sideband"], e["band_strategy"])]
    return e[np.isfinite(e["error"])]


def line_group(quantity: str, sideband: int, strategy: str = "") -> str | None:
    """The issue's classes: main envelope lines (1-3 x BPFI) and sidebands in the fixed bands,
    the same in the kurtogram band (chosen again on each point's signal, so it can jump to another
    band), raw terms (``raw_dc``, ``raw_fr``, ``raw_bpfi``), peak, rms (the band-passed peak is
    none of them)."""
    if quantity in ("peak", "rms"):
        return quantity
    if quantity == "envelope_bpfi":
        kg = "kurtogram_" if strategy == "kurtogram" else "envelope_"
        return kg + ("sideband" if sideband else "line")
    if quantity.startswith("raw_"):
        return quantity + ("_sideband" if sideband else "")
    return None


def _cases(e: pd.DataFrame, cases) -> pd.DataFrame:
    keep = np.zeros(len(e), bool)
    for load, depth in cases:
        keep |= (e.load_kN == load) & (e.depth_um == depth)
    return e[keep]


GROUPS = ("envelope_line", "envelope_sideband", "kurtogram_line", "kurtogram_sideband", "raw_dc",
          "raw_fr", "raw_bpfi", "peak", "rms")
SHORT = ("env", "sb", "kg", "kg sb", "dc", "fr", "bpfi", "peak", "rms")


def worst_table(e: pd.DataFrame, cases, title: str) -> str:
    """Worst error (%) over ``cases`` per point, signal and group, with CPU per case."""
    e = _cases(e, cases)
    e = e[e.group.notna() & (e.depth_um > 0)]
    cpu = e.groupby(["run", "load_kN", "depth_um"])["cpu_s"].first().groupby("run").agg(
        ["mean", "max"]).sort_values("mean")
    w = e.groupby(["run", "signal", "group"])["error"].max()
    sigs = list(acc.SIGNALS)
    lines = [f"\n{title} (envelope: fixed bands; kg: kurtogram band; raw: dc, 1-3 x fr, "
             f"1-3 x BPFI)\n", "| point | CPU s per case: mean / max | " + " | ".join(
                 f"{s}: " + " / ".join(SHORT) for s in sigs) + " |",
             "|---|---|" + "---|" * len(sigs)]
    for run in cpu.index:
        cells = []
        for s in sigs:
            cells.append(" / ".join(f"{100 * w.get((run, s, g), np.nan):.2g}" for g in GROUPS))
        lines.append(f"| {label(run)} | {cpu.loc[run, 'mean']:.1f} / {cpu.loc[run, 'max']:.1f} | "
                     + " | ".join(cells) + " |")
    return "\n".join(lines)


def model_table(e: pd.DataFrame) -> pd.DataFrame:
    """Per point, load, kind, signal and quantity class: the worst error over the model's cases
    at that load, the bands and the orders."""
    m = _cases(e, MODEL).copy()
    if m.empty:                                # a held-out-only run
        return pd.DataFrame(columns=["point", "load_kN", "kind", "signal", "quantity_class",
                                     "rel_error", "n_values"])
    m["kind"] = np.where(m.depth_um > 0, "defect", "healthy")
    keys = ["run", "load_kN", "kind", "signal", "quantity_class"]
    g = m.groupby(keys)
    t = g["error"].max().reset_index().rename(columns={"error": "rel_error", "run": "point"})
    t["n_values"] = g["error"].size().values
    t["point"] = t["point"].map(lambda r: PRESET_OF.get(r, r))
    # only the points run on every model case (a partial ladder level is not a model point)
    full = m.groupby("run").apply(lambda x: len(set(zip(x.load_kN, x.depth_um))))
    keep = {PRESET_OF.get(r, r) for r, n in full.items() if n == full.max()}
    return t[t.point.isin(keep)].reset_index(drop=True)


def coverage(e: pd.DataFrame, model: pd.DataFrame) -> pd.DataFrame:
    """Per preset and quantity class: the held-out amplitudes covered by the model's estimate
    (error <= estimate), read as the worst over the model's loads (``study/accuracy.py``'s rule
    since 2026-11-27) and, for comparison, at the case's load
    (:func:`~bearing_envelope.study.accuracy.lookup_rel_error`, ``load_rule="per_load"``)."""
    from bearing_envelope.study.accuracy import lookup_rel_error

    h = _cases(e, HELDOUT)
    h = h[(h.depth_um > 0) & h.run.isin([r for r in PRESET_OF])].copy()
    h["point"] = h["run"].map(PRESET_OF)
    for col, load in (("per_load", h.load_kN), ("pooled", [None] * len(h))):
        h[col] = [lookup_rel_error(model, p, ld, "defect", s, q) for p, ld, s, q in
                  zip(h.point, load, h.signal, h.quantity_class)]
    h = h[np.isfinite(h.per_load)]
    h["cov_load"] = h.error <= h.per_load
    h["cov_pooled"] = h.error <= h.pooled
    with np.errstate(divide="ignore"):
        h["ratio"] = h.error / h.per_load
        h["ratio_pooled"] = h.error / h.pooled
    g = h.groupby(["point", "quantity_class"])
    return pd.DataFrame({"n": g.size(),
                         "covered: worst over loads (the package)": g["cov_pooled"].mean(),
                         "covered: per load": g["cov_load"].mean(),
                         "worst error / estimate (worst over loads)": g["ratio_pooled"].max(),
                         "worst error / estimate (per load)": g["ratio"].max()})


def knob_table(ref: pd.DataFrame) -> str:
    """Per knob: the correction and the last step (relative, defect cases, per signal)."""
    r = ref[ref.depth_um > 0]
    lines = ["| knob | signal | correction: median / 95th pct / max % | last step or "
             "Richardson residual: median / 95th pct / max % | ladder status |",
             "|---|---|---|---|---|"]
    for knob in KNOBS:
        if f"{knob}_delta" not in r:
            continue
        for s in acc.SIGNALS:
            x = r[r.signal == s]
            d = (x[f"{knob}_delta"].abs() / x.ref.abs()).dropna()
            u = (x[f"{knob}_resid"].abs() / x.ref.abs()).dropna()
            if d.empty:
                continue
            st = x[f"{knob}_status"].value_counts().to_dict()
            lines.append(f"| {knob} | {s} | " + " / ".join(
                f"{100 * v:.2g}" for v in (d.median(), d.quantile(0.95), d.max())) + " | "
                + " / ".join(f"{100 * v:.2g}" for v in (u.median(), u.quantile(0.95), u.max()))
                + f" | {st} |")
    return "\n".join(lines)


#: single-knob runs a predicted combination may take (knob -> the runs of its levels)
COMBINE = {"global_dy_um": ("gdy80", "gdy20"), "local_dy_um": ("ldy20", "ldy10"),
           "window_margin_um": ("margin1600",), "n_loads": ("loads9",),
           "offset_density": ("x2",), "rim_dx_um": ("rim0.25",)}


def predicted(e: pd.DataFrame, cases) -> pd.DataFrame:
    """Every combination of the single-knob runs (:data:`COMBINE`) around ``accurate``: its
    values predicted to first order (base + the sum of its runs' changes), the worst predicted
    error per signal and group over ``cases``, and its CPU per case predicted as the base's times
    the product of its runs' CPU ratios. A guide for the choice; the chosen point is measured."""
    import itertools

    e = _cases(e, cases)
    e = e[e.group.notna() & (e.depth_um > 0)]
    v = e.pivot_table(index=acc.KEYS + ["group"], columns="run", values="value", aggfunc="first")
    ref = e.groupby(acc.KEYS)["ref"].first()
    cpu = e.groupby(["run", "load_kN", "depth_um"])["cpu_s"].first().groupby("run").mean()
    opts = [[None] + [r for r in runs if r in v.columns] for runs in COMBINE.values()]
    rows = []
    for combo in itertools.product(*opts):
        pick = [r for r in combo if r]
        pred = v["accurate"] + sum((v[r] - v["accurate"] for r in pick), 0.0)
        err = (pred - ref.reindex(pred.index.droplevel("group")).to_numpy()).abs() / \
            ref.reindex(pred.index.droplevel("group")).abs().to_numpy()
        w = err.groupby(["signal", "group"]).max()
        c = cpu["accurate"] * float(np.prod([cpu[r] / cpu["accurate"] for r in pick]))
        rows.append({"combo": "+".join(pick) or "accurate", "cpu_s": c,
                     **{f"{s}:{g}": float(w.get((s, g), np.nan)) for s, g in w.index}})
    return pd.DataFrame(rows).sort_values("cpu_s")


def meets(row: pd.Series, line: float, side: float) -> bool:
    """Every main group within ``line`` and every sideband group within ``side`` (the kurtogram
    band, chosen again per point, is reported apart)."""
    ok = True
    for c, v in row.items():
        if ":" not in c or "kurtogram" in c or not np.isfinite(v):
            continue
        ok &= v <= (side if "sideband" in c else line)
    return bool(ok)


def predicted_markdown(e: pd.DataFrame, cases) -> str:
    p = predicted(e, cases)
    p["2 %/5 %"] = [meets(r, 0.02, 0.05) for _, r in p.iterrows()]
    p["1 %/2 %"] = [meets(r, 0.01, 0.02) for _, r in p.iterrows()]
    cols = ["combo", "cpu_s", "2 %/5 %", "1 %/2 %"] + [c for c in p.columns if ":" in c]
    q = p[cols].copy()
    for c in cols[4:]:
        q[c] = 100 * q[c]
    return q.to_markdown(index=False, floatfmt=".3g")


def cmd_report(args) -> None:
    files = sorted((args.out / "values").glob("*.csv"))
    df = pd.concat([pd.read_csv(f, keep_default_na=False, na_values=[""]) for f in files])
    df["band"] = df["band"].fillna("")
    runs = df.groupby(["load_kN", "depth_um"])["run"].agg(set)
    partial = [k for k, v in runs.items() if not set(REQUIRED) <= v]
    for load, depth in partial:                     # a case whose ladders are not all built
        print(f"left out (not every knob built): {load:g} kN / {depth:g} um", file=sys.stderr)
        df = df[~((df.load_kN == load) & (df.depth_um == depth))]
    if df.empty:
        raise SystemExit(f"reference report: no case of {args.out} has every run of REQUIRED "
                         f"({', '.join(REQUIRED)})")
    ref = reference(df)
    ref.to_csv(args.out / "reference.csv", index=False)
    e = errors(df, ref)
    e.to_csv(args.out / "errors.csv", index=False)
    model = model_table(e)
    source = "this run's model cases"
    if model.empty:                   # a held-out-only run: judge the model the package ships
        model, source = stored_model(), "the package's stored model (no model case in this run)"
    cov = coverage(e, model)
    cov.to_csv(args.out / "coverage.csv")
    r = ref[ref.depth_um > 0]
    text = "\n\n".join([
        worst_table(e, HELDOUT, "Held-out cases (500/50, 250/40, 750/20): worst error %"),
        worst_table(e, MODEL, "Model cases: worst error %"),
        knob_table(ref),
        "Reference uncertainty (sum of the knobs' residuals, relative, defect cases) per "
        "signal and group: median / 95th pct / max %\n\n" + uncert_table(e[e.run == "accurate"]),
        f"Coverage on the held-out cases (error <= estimate) of {source}, per preset and "
        "quantity class:\n\n" + cov.to_markdown(floatfmt=".3g"),
        "Predicted (first order) over all cases, % (a guide; the chosen point is measured):\n\n"
        + predicted_markdown(e, MODEL + HELDOUT),
        json.dumps({"n_metrics": len(r), "files": len(files)})])
    (args.out / "reference.md").write_text(text)
    print(text)
    if args.write_model:
        have = {(float(a), float(b)) for a, b in zip(e.load_kN, e.depth_um)}
        write_model(model, args.out, [c for c in MODEL if c in have])


def stored_model() -> pd.DataFrame:
    """The error model the package ships (``data/discretisation_error.csv``, its JSON
    provenance line skipped): what a held-out-only run judges."""
    return stored_error_model()[1]


def uncert_table(e: pd.DataFrame) -> str:
    e = e[e.group.notna() & (e.depth_um > 0)]
    g = e.groupby(["signal", "group"])["ref_uncert_rel"]
    t = pd.DataFrame({"median %": 100 * g.median(), "95th %": 100 * g.quantile(0.95),
                      "max %": 100 * g.max()})
    return t.to_markdown(floatfmt=".2g")


def write_model(model: pd.DataFrame, out: Path, cases) -> None:
    """The package's error model (``data/discretisation_error.csv``): a JSON provenance line,
    then the table (every run that is a fidelity point)."""
    info = json.loads((out / "info.json").read_text()) if (out / "info.json").exists() else {}
    run_of = {p: r for r, p in PRESET_OF.items()}
    fids = {p: fidelity_from(acc._fid(runs_spec([run_of.get(p, p)])[run_of.get(p, p)])).to_dict()
            for p in sorted(set(model.point))}
    header = {"source": "benchmarks/reference.py",
              "date": f"{info.get('date')} to {time.strftime('%H:%M UTC', time.gmtime())}",
              "reference": "the base (fast + rim strips 0.5 um + global_dy 40 um, the preset "
                           "standard) + each knob's ladder (rim_dx 1/0.5/0.25 um, global_dy "
                           "80/40/20/10 um at a 10 um window, local_dy 40/20/10/5 um, window "
                           "margin 400/1600 um, tol 1e-5/1e-6, n_loads 5/9 (17 on the held-out "
                           "cases), offsets x1/x2): Richardson or finest per knob, corrections "
                           "added (benchmarks/reference.py)",
              "far_field": "responds", "amplitude": "interpolated",
              "cases": [list(c) for c in cases], "heldout": [list(c) for c in HELDOUT],
              "lookup": "the worst over the model's loads (study/accuracy.py error_model; "
                        "load_rule per_load: the row of the load, between two model loads the "
                        "larger of the two, outside the nearest)",
              "fidelities": fids}
    path = Path(__file__).resolve().parents[1] / "src" / "bearing_envelope" / "data" / \
        "discretisation_error.csv"
    tmp = path.with_suffix(".tmp")
    with open(tmp, "w") as fh:
        fh.write("# " + json.dumps(header) + "\n")
        model.to_csv(fh, index=False)
    os.replace(tmp, path)


def cmd_cost(args) -> None:
    """CPU per case as the sweep's ``simulate`` job spends it (checks and snapshots on, 100
    revolutions, the no-defect store): per fidelity, the load's cases in sweep order from an
    empty store, side by side in one process."""
    import tempfile

    from bearing_envelope.physics.history import simulate

    simulate(acc.scene(args.load, 50.0, 0.2), fidelity_from("draft"))      # numba's JIT
    rows = []
    for name in args.fidelity:
        with tempfile.TemporaryDirectory() as cache:
            for depth in args.depths:
                c0 = time.process_time()
                simulate(acc.scene(args.load, depth, 100.0), fidelity_from(name),
                         nodefect_cache=cache)
                rows.append({"fidelity": name, "load_kN": args.load, "depth_um": depth,
                             "cpu_s": time.process_time() - c0,
                             "load_average": os.getloadavg()[0]})
                print(rows[-1], flush=True)
    pd.DataFrame(rows).to_csv(args.out / f"cost_F{args.load:g}.csv", index=False)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--out", type=Path, required=True)
    r.add_argument("--worker", default="0/1")
    r.add_argument("--cases", default=None, help="JSON list of [load, depth]")
    r.add_argument("--runs", nargs="+", default=None)
    r.add_argument("--revolutions", type=float, default=10.0)
    p = sub.add_parser("report")
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--write-model", action="store_true")
    c = sub.add_parser("cost")
    c.add_argument("--out", type=Path, required=True)
    c.add_argument("--load", type=float, default=500.0)
    c.add_argument("--depths", type=float, nargs="+", default=[15.0, 50.0])
    c.add_argument("--fidelity", nargs="+", default=["fast", "accurate", "standard"])
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.cmd == "cost":
        cmd_cost(args)
    elif args.cmd == "run":
        info = args.out / "info.json"
        if not info.exists():
            info.write_text(json.dumps({"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
                                        "python": sys.version.split()[0],
                                        "load_average": os.getloadavg()}))
        cmd_run(args)
    else:
        cmd_report(args)
    return 0


def smoke() -> None:
    """One case, run ``draft``, one revolution; the report refuses the incomplete case."""
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        main(["run", "--out", d, "--cases", "[[250, 15]]", "--runs", "draft",
              "--revolutions", "1"])
        try:
            main(["report", "--out", d])
        except SystemExit as e:
            assert "REQUIRED" in str(e)
        else:
            raise AssertionError("report of an incomplete case")
    model = stored_model()                  # what a held-out-only report judges
    assert {"standard", "accurate", "draft"} <= set(model.point), set(model.point)
    assert (model.rel_error >= 0).all() and len(model.load_kN.unique()) == 3


if __name__ == "__main__":
    main()
