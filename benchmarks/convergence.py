"""Grid convergence of the defect signals in the window spacing (issue 12 part 3), by hand.

    nice -n 5 python benchmarks/convergence.py --out results/convergence            # solve + report
    python benchmarks/convergence.py --out results/convergence --report-only        # tables only

For each case (load x depth) and defect-window spacing across rolling (``local_dx_um``, all other
knobs at ``standard`` without checks/snapshots), the contact table is built once and cached
(``tables/F{load}kN_h{depth}um_dx{dx}.pkl``, with its CPU time); results are written after each
table, so a partial run still reports what it has. The signals are synthesised from the cached
tables for ``--revolutions`` (the table cost does not depend on it) with

- ``antialiased``: one common internal rate for every spacing (``--oversample``, default the
  ``auto`` value of the finest spacing), so that only the grid changes between rows;
- ``point``: the study's point samples (for p_max, reported next to it).

Per signal (p_max, p_max_defect, removed_force, approach_change = delta) and metric (peak =
max, rms of the signal minus its mean, envelope 1 x BPFI in the four fixed bands of
``config.yaml``), from the three finest spacings h, 2h, 4h: observed order
``p = log2(|f4h - f2h| / |f2h - fh|)``, Richardson value ``f* = fh + (fh - f2h) / (2^p - 1)``
(only when the three values are monotone and 0.5 <= p <= 4; otherwise none, flagged), and the
error of the default spacing (2 um) against ``f*``. Writes ``convergence.csv`` (all values),
``richardson.csv`` and prints a markdown summary.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import pickle
import platform
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from bearing_envelope.fidelity import fidelity_from
from bearing_envelope.history import (SolveStats, acquisition_settings, auto_oversample,
                                      build_table, synthesize_case)
from bearing_envelope.loads import scene_load_distribution
from bearing_envelope.scene import Scene
from bearing_envelope.signal import envelope_spectrum, harmonic_amplitudes

CASES = ((250.0, 15.0), (250.0, 100.0), (750.0, 15.0), (750.0, 100.0))
SPACINGS = (8.0, 4.0, 2.0, 1.0)
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
        for dx in SPACINGS:
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


def richardson(df):
    out = []
    keys = ["load_kN", "depth_um", "acquisition", "signal", "metric"]
    for key, g in df.groupby(keys):
        v = g.set_index("dx_um")["value"]
        fine = sorted(v.index)[:3]
        rec = dict(zip(keys, key))
        rec.update({f"v_{d:g}": float(v[d]) for d in v.index})
        if len(fine) < 3:
            out.append({**rec, "status": "fewer than 3 spacings"})
            continue
        h, h2, h4 = fine
        f1, f2, f4 = float(v[h]), float(v[h2]), float(v[h4])
        d21, d42 = f1 - f2, f2 - f4
        rec["finest_change"] = abs(d21) / abs(f1) if f1 else float("nan")
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


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--revolutions", type=float, default=10.0)
    ap.add_argument("--oversample", type=int, default=None,
                    help="common internal rate factor (default: auto at the finest spacing)")
    ap.add_argument("--report-only", action="store_true")
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
    finest = min(SPACINGS)
    n = args.oversample or auto_oversample(scene(*CASES[0], 1.0),
                                           fidelity_from({**BASE, "local_dx_um": finest}))
    df = evaluate(args.out, args.revolutions, n)
    df.to_csv(args.out / "convergence.csv", index=False)
    rr = richardson(df)
    rr.to_csv(args.out / "richardson.csv", index=False)
    info = {"date": time.strftime("%Y-%m-%d"), "machine": platform.processor() or platform.machine(),
            "python": sys.version.split()[0], "revolutions": args.revolutions, "oversample": n,
            "base": BASE}
    (args.out / "info.json").write_text(json.dumps(info, indent=1))
    pd.set_option("display.width", 250)
    pd.set_option("display.max_rows", 500)
    cols = ["load_kN", "depth_um", "acquisition", "signal", "metric", "order", "default_error",
            "finest_change", "status"]
    print(rr[[c for c in cols if c in rr]].to_string(index=False))


if __name__ == "__main__":
    main()
