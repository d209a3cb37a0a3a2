"""Grid convergence of the defect signals in the window spacing (issue 12 part 3), by hand.

    nice -n 5 python benchmarks/convergence.py --out results/convergence            # solve + report
    python benchmarks/convergence.py --out results/convergence --report-only        # tables only

For each case (load x depth) and defect-window spacing across rolling (``local_dx_um``, all other
knobs at ``standard`` without checks/snapshots), the contact table is built once and cached
(``tables/F{load}kN_h{depth}um_dx{dx}.pkl``, with its CPU time); results are written after each
table, so a partial run still reports what it has. The signals are synthesised from the cached
tables for ``--revolutions`` (the table cost does not depend on it) with

- ``antialiased``: one common internal rate for every spacing (``--oversample``, default the
  ``auto`` value of the finest spacing that has a table), so that only the grid changes between
  rows;
- ``point``: the study's point samples (for p_max, reported next to it).

Per signal (p_max, p_max_defect, removed_force, approach_change = delta) and metric (peak =
max, rms of the signal minus its mean, envelope 1 x BPFI in the four fixed bands of
``config.yaml``), from the three finest spacings h, 2h, 4h: observed order
``p = log2(|f4h - f2h| / |f2h - fh|)``, Richardson value ``f* = fh + (fh - f2h) / (2^p - 1)``
(only when the three values are monotone and 0.5 <= p <= 4; otherwise none, flagged), and the
error of the default spacing (2 um) against ``f*`` (when there is no ``f*``: its change against
the finest spacing, a lower bound of its error). Writes ``convergence.csv`` (all values),
``richardson.csv`` (ladder 8, 4, 2, 1 um), ``richardson_05.csv`` (2, 1, 0.5 um, for the cases
run at 0.5 um with ``--cases ... --spacings 0.5``), ``info.json`` and ``convergence.md`` (the
tables of ``docs/benchmarks.md``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.acquisition import auto_oversample
from bearing_envelope.physics.history import synthesize_case
from bearing_envelope.physics.solves import SolveStats
from bearing_envelope.physics.table import build_table
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene
from bearing_envelope.diagnosis import harmonic_amplitudes
from bearing_envelope.signal import envelope_spectrum

CASES = ((250.0, 15.0), (250.0, 100.0), (750.0, 15.0), (750.0, 100.0))
SPACINGS = (8.0, 4.0, 2.0, 1.0)
EXTRA_SPACINGS = (0.5,)     # run on some cases only (--cases ... --spacings 0.5)
DEFAULT_DX = 2.0
BASE = {"preset": "standard", "n_checks": 0, "n_snapshot_offsets": 0}
SIGNALS = ("p_max", "p_max_defect", "removed_force", "approach_change")


def bands(fs, bpfi):
    return {"fs4_3fs8": (0.25 * fs, 0.375 * fs), "bpfi_3_6": (3 * bpfi, 6 * bpfi),
            "bpfi_10_13": (10 * bpfi, 13 * bpfi), "fixed": (8125.0, 16250.0)}


def scene(load, depth, revolutions):
    return Scene.from_mapping({"operation": {"revolutions": revolutions}},
                              load_kN=load, depth_um=depth)


def table_path(out, load, depth, dx):
    return out / "tables" / f"F{load:g}kN_h{depth:g}um_dx{dx:g}.pkl"


def build(out, load, depth, dx):
    path = table_path(out, load, depth, dx)
    if path.exists():
        return pickle.loads(path.read_bytes())
    sc = scene(load, depth, 1.0)
    fid = fidelity_from({**BASE, "local_dx_um": dx})
    ld = scene_load_distribution(sc)
    stats = SolveStats()
    c0 = time.process_time()
    table, _, _ = build_table(sc, fid, q_max=ld.q_max, stats=stats, progress=None)
    rec = {"table": table, "ld": ld, "fidelity": fid, "cpu_s": time.process_time() - c0,
           "n_solves": stats.n_solves, "n_iterations": stats.n_iterations}
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_bytes(pickle.dumps(rec))
    os.replace(tmp, path)
    return rec


def metrics(sig, fs, bpfi):
    rows = {}
    for name in SIGNALS:
        x = np.asarray(sig[name], float)
        rows[(name, "peak")] = float(x.max())
        rows[(name, "rms")] = float(np.sqrt(np.mean((x - x.mean()) ** 2)))
        for b, band in bands(fs, bpfi).items():
            f, a = envelope_spectrum(x - x.mean(), fs, band)
            rows[(name, f"env1x_{b}")] = float(
                harmonic_amplitudes(f, a, bpfi, n_harmonics=1, n_sidebands=0)[0]["amplitude"])
    return rows


def evaluate(out, revolutions, oversample):
    rows = []
    for load, depth in CASES:
        sc = scene(load, depth, revolutions)
        fs, bpfi = sc.operation.fs_hz, sc.bpfi_hz
        for dx in SPACINGS + EXTRA_SPACINGS:
            if not table_path(out, load, depth, dx).exists():
                continue
            rec = pickle.loads(table_path(out, load, depth, dx).read_bytes())
            for mode in ("antialiased", "point"):
                acq = {"mode": mode, "oversample": oversample if mode == "antialiased" else 1}
                _, sig, _ = synthesize_case(sc, rec["table"], rec["ld"], rec["fidelity"],
                                            acquisition=acq)
                for (name, metric), v in metrics(sig, fs, bpfi).items():
                    rows.append({"load_kN": load, "depth_um": depth, "dx_um": dx,
                                 "acquisition": mode, "signal": name, "metric": metric,
                                 "value": v, "table_cpu_s": rec["cpu_s"]})
    return pd.DataFrame(rows)


def richardson(df, min_dx=None):
    """Observed order and Richardson value from the three finest spacings ``>= min_dx``."""
    out = []
    keys = ["load_kN", "depth_um", "acquisition", "signal", "metric"]
    for key, g in df.groupby(keys):
        v = g.set_index("dx_um")["value"]
        if min_dx is not None:
            v = v[v.index >= min_dx - 1e-12]
        fine = sorted(v.index)[:3]
        rec = dict(zip(keys, key))
        rec.update({f"v_{d:g}": float(v[d]) for d in v.index})
        rec["finest_dx"] = fine[0]
        if len(fine) < 3:
            out.append({**rec, "status": "fewer than 3 spacings"})
            continue
        h, h2, h4 = fine
        f1, f2, f4 = float(v[h]), float(v[h2]), float(v[h4])
        d21, d42 = f1 - f2, f2 - f4
        rec["finest_change"] = abs(d21) / abs(f1) if f1 else float("nan")
        if DEFAULT_DX in v.index and f1 and DEFAULT_DX != h:
            rec["default_vs_finest"] = abs(float(v[DEFAULT_DX]) - f1) / abs(f1)
        if d21 == 0 and d42 == 0:
            rec.update(order=float("inf"), extrapolated=f1, status="exact")
        elif d21 * d42 <= 0 or d21 == 0:
            rec.update(order=float("nan"), extrapolated=float("nan"), status="oscillatory")
        else:
            p = math.log(abs(d42) / abs(d21), h2 / h)
            if 0.5 <= p <= 4:
                rec.update(order=p, extrapolated=f1 + d21 / ((h2 / h) ** p - 1), status="ok")
            else:
                rec.update(order=p, extrapolated=float("nan"), status="order out of [0.5, 4]")
        ref = rec.get("extrapolated", float("nan"))
        if DEFAULT_DX in v.index and np.isfinite(ref) and ref != 0:
            rec["default_error"] = abs(float(v[DEFAULT_DX]) - ref) / abs(ref)
        out.append(rec)
    return pd.DataFrame(out)


METRICS = ("peak", "rms", "env1x_fs4_3fs8", "env1x_bpfi_3_6", "env1x_bpfi_10_13", "env1x_fixed")


def _cell(r):
    """``e % (p)`` against the Richardson value, else ``~e %*`` against the finest spacing."""
    if r["status"] == "ok" or r["status"] == "exact":
        return f"{100 * r['default_error']:.2g} ({r['order']:.2g})"
    if np.isfinite(r.get("default_vs_finest", np.nan)):
        return f"~{100 * r['default_vs_finest']:.2g}*"
    return "-"


def markdown(rr):
    """Error of the default spacing (2 um), %, per case x signal x metric."""
    lines = ["| case | signal (acquisition) | " + " | ".join(METRICS) + " | worst |",
             "|---|---|" + "---|" * (len(METRICS) + 1)]
    order = [("removed_force", "antialiased"), ("approach_change", "antialiased"),
             ("p_max", "antialiased"), ("p_max_defect", "antialiased"), ("p_max", "point")]
    for (load, depth), g in rr.groupby(["load_kN", "depth_um"]):
        for sig, acq in order:
            sub = g[(g.signal == sig) & (g.acquisition == acq)].set_index("metric")
            if sub.empty:
                continue
            worst = []
            for m in METRICS:
                r = sub.loc[m]
                e = r["default_error"] if r["status"] in ("ok", "exact") else r.get(
                    "default_vs_finest", np.nan)
                worst.append(e)
            lines.append(f"| {load:g} kN, {depth:g} um | {sig} ({acq}) | "
                         + " | ".join(_cell(sub.loc[m]) for m in METRICS)
                         + f" | {100 * np.nanmax(worst):.2g} |")
    return "\n".join(lines)


def values_markdown(rr, signals=("removed_force", "approach_change", "p_max"),
                    metric="env1x_bpfi_10_13"):
    """Values per spacing, order and Richardson value of one metric."""
    dxs = sorted({float(c[2:]) for c in rr.columns if c.startswith("v_")}, reverse=True)
    lines = ["| case | signal (acquisition) | " + " | ".join(f"{d:g} um" for d in dxs)
             + " | order p | Richardson f* | status |",
             "|---|---|" + "---|" * (len(dxs) + 3)]
    for _, r in rr[(rr.metric == metric) & rr.signal.isin(signals)].iterrows():
        if r.signal != "p_max" and r.acquisition == "point":
            continue
        vals = " | ".join("-" if not np.isfinite(r.get(f"v_{d:g}", np.nan))
                          else f"{r[f'v_{d:g}']:.5g}" for d in dxs)
        p = f"{r['order']:.3g}" if np.isfinite(r.get("order", np.nan)) else "-"
        fx = f"{r['extrapolated']:.5g}" if np.isfinite(r.get("extrapolated", np.nan)) else "-"
        lines.append(f"| {r.load_kN:g} kN, {r.depth_um:g} um | {r.signal} ({r.acquisition}) | "
                     f"{vals} | {p} | {fx} | {r.status} |")
    return "\n".join(lines)


def reference_markdown(df, signals=("removed_force", "approach_change", "p_max")):
    """Cases with a 0.5 um table: each spacing's change against it, %, per signal x metric."""
    lines = ["| case | signal (acquisition) | metric | 4 um | 2 um (default) | 1 um |",
             "|---|---|---|---|---|---|"]
    keys = ["load_kN", "depth_um", "acquisition", "signal", "metric"]
    for key, g in df.groupby(keys):
        rec = dict(zip(keys, key))
        v = g.set_index("dx_um")["value"]
        if min(v.index) >= min(SPACINGS) or rec["signal"] not in signals:
            continue
        if rec["acquisition"] == "point" and rec["signal"] != "p_max":
            continue
        ref = float(v[min(v.index)])
        cells = " | ".join(f"{100 * abs(float(v[d]) - ref) / abs(ref):.2g}" if d in v.index
                           else "-" for d in (4.0, 2.0, 1.0))
        lines.append(f"| {rec['load_kN']:g} kN, {rec['depth_um']:g} um | {rec['signal']} "
                     f"({rec['acquisition']}) | {rec['metric']} | {cells} |")
    return "\n".join(lines)


def costs_markdown(out):
    rows = []
    for path in sorted((out / "tables").glob("*.pkl")):
        rec = pickle.loads(path.read_bytes())
        rows.append((path.stem, rec["cpu_s"], rec["n_solves"]))
    return "\n".join(["| table | CPU s | solves |", "|---|---|---|"]
                     + [f"| {n} | {c:.1f} | {k} |" for n, c, k in rows])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--revolutions", type=float, default=10.0)
    ap.add_argument("--oversample", type=int, default=None,
                    help="common internal rate factor (default: auto at the finest spacing)")
    ap.add_argument("--report-only", action="store_true")
    ap.add_argument("--from-csv", action="store_true",
                    help="with --report-only: tables from the saved convergence.csv (no synthesis)")
    ap.add_argument("--cases", type=str, default=None, help="JSON list of [load, depth]")
    ap.add_argument("--spacings", type=float, nargs="+", default=None)
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    cases = [tuple(c) for c in json.loads(args.cases)] if args.cases else CASES
    spacings = args.spacings or SPACINGS
    if not args.report_only:
        for dx in sorted(spacings, reverse=True):        # coarse first: partial results early
            for load, depth in cases:
                t0 = time.time()
                rec = build(args.out, load, depth, dx)
                print(f"F{load:g}kN h{depth:g}um dx {dx:g} um: table {rec['cpu_s']:.1f} s CPU "
                      f"({rec['n_solves']} solves), wall {time.time() - t0:.1f} s", flush=True)
    finest = min(dx for dx in SPACINGS + EXTRA_SPACINGS
                 if any(table_path(args.out, *c, dx).exists() for c in CASES))
    n = args.oversample or auto_oversample(scene(*CASES[0], 1.0),
                                           fidelity_from({**BASE, "local_dx_um": finest}))
    if args.report_only and args.from_csv:
        df = pd.read_csv(args.out / "convergence.csv")
        info0 = json.loads((args.out / "info.json").read_text())
        n = info0["oversample"]
    else:
        df = evaluate(args.out, args.revolutions, n)
        df.to_csv(args.out / "convergence.csv", index=False)
    spec = richardson(df, min_dx=min(SPACINGS))          # 8, 4, 2, 1 um: the study's ladder
    spec.to_csv(args.out / "richardson.csv", index=False)
    fine = richardson(df)                                # with 0.5 um where it was run
    fine = fine[fine.finest_dx < min(SPACINGS)]
    fine.to_csv(args.out / "richardson_05.csv", index=False)
    cpu = "unknown"
    try:
        cpu = next(ln.split(":", 1)[1].strip() for ln in open("/proc/cpuinfo")
                   if ln.startswith("model name"))
    except (OSError, StopIteration):
        pass
    info = info0 if args.report_only and args.from_csv else {
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "machine": cpu,
            "cores": os.cpu_count(), "load_average": os.getloadavg(),
            "python": sys.version.split()[0], "revolutions": args.revolutions, "oversample": n,
            "base": BASE, "command": " ".join(sys.argv)}
    if not (args.report_only and args.from_csv):
        (args.out / "info.json").write_text(json.dumps(info, indent=1))
    report = ["## default spacing (2 um) against the Richardson value of 4, 2, 1 um",
              "% (observed order); ~x* = not in the asymptotic range: change 2 -> 1 um", "",
              markdown(spec), "", "## values, envelope 1 x BPFI in bpfi_10_13", "",
              values_markdown(spec), ""]
    if not fine.empty:
        report += ["## with 0.5 um: Richardson value of 2, 1, 0.5 um", "", markdown(fine), "",
                   values_markdown(fine), "", "## change against the 0.5 um value, %", "",
                   reference_markdown(df), ""]
    report += ["## table costs", "", costs_markdown(args.out), "", json.dumps(info)]
    (args.out / "convergence.md").write_text("\n".join(report))
    print("\n".join(report))


if __name__ == "__main__":
    main()
