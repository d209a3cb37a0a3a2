"""Speed-accuracy study of the fidelity knobs, by hand (issue 6). Results: docs/benchmarks.md.

    python benchmarks/tradeoff.py --loads 250 --out results/tradeoff/bench_250   # one process
    python benchmarks/tradeoff.py --loads 750 --out results/tradeoff/bench_750   # the other core
    python benchmarks/tradeoff.py --merge results/tradeoff/bench_250 results/tradeoff/bench_750 \
        --out results/tradeoff/bench

Each process runs its loads x DEPTHS with every knob of KNOBS varied around BASE (standard
without the interpolation checks and snapshot solves, which do not change the history),
against the common reference REFERENCE (the paper preset, same exclusions), plus the
presets as they are (with their checks), all at the full 100 revolutions so that the preset
rows are full-case times. Writes tradeoff.csv, pareto.csv, tradeoff.png and the reference
runs (refs.pkl, reused by --presets-only to evaluate further presets without rerunning them).
"""

from __future__ import annotations

import argparse
import json
import pickle
import platform
import sys
import time
from pathlib import Path

import pandas as pd

from bearing_envelope.study.tradeoff import pareto_points, plot_tradeoff, tradeoff_study

DEPTHS = (0.0, 15.0, 100.0)
NO_CHECKS = {"n_checks": 0, "n_snapshot_offsets": 0}
BASE = {"preset": "standard", **NO_CHECKS}
REFERENCE = {"preset": "paper", **NO_CHECKS}
KNOBS = {
    "global_dx_um": [20.0, 10.0, 5.0],
    "global_dy_um": [300.0, 150.0, 80.0],
    "local_dx_um": [8.0, 4.0, 2.0],
    "local_dy_um": [40.0, 20.0, 10.0],
    "tol": [1e-4, 1e-6, 1e-8],
    "n_loads": [4, 7, 10],
    "offset_density": [0.5, 1.0, 2.0],
    "element": ["uniform", "linear"],
    "edge_radius_um": [40.0, 20.0, 10.0],
}
PRESETS = {"draft": "draft", "standard": "standard"}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--loads", type=float, nargs="+", default=[250.0, 750.0])
    ap.add_argument("--depths", type=float, nargs="+", default=list(DEPTHS))
    ap.add_argument("--revolutions", type=float, default=100.0)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--merge", type=Path, nargs="*", help="merge the CSVs of these output dirs")
    ap.add_argument("--presets-only", type=str, default=None,
                    help="JSON mapping name -> fidelity: evaluate only these presets against the "
                         "reference runs of --out (refs are recomputed if missing)")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.merge:
        df = pd.concat([pd.read_csv(d / "tradeoff.csv", keep_default_na=False,
                                    na_values=["", "nan", "NaN"]) for d in args.merge],
                       ignore_index=True)
        df["band"] = df["band"].fillna("")
        return finish(df, args.out)
    cases = [(f, h) for f in args.loads for h in args.depths]
    t0 = time.time()
    meta = {"started_utc": time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime()),
            "python": sys.version.split()[0], "machine": platform.processor() or platform.machine(),
            "cases": cases, "revolutions": args.revolutions, "base": BASE, "reference": REFERENCE}
    if args.presets_only:
        presets = json.loads(args.presets_only)
        refs = args.out / "refs.pkl"
        cache = pickle.loads(refs.read_bytes()) if refs.exists() else {}
        df = tradeoff_study(cases, knobs={}, base=BASE, reference=REFERENCE, element_series=(),
                            presets=presets, revolutions=args.revolutions, progress=log,
                            cache=cache)
        df.to_csv(args.out / "presets.csv", index=False)
        # keep the reference runs, so that further presets are evaluated without rerunning them
        refs.write_bytes(pickle.dumps({c: {k: cache[c][k]}
                                       for c, k in df.attrs["reference_keys"].items()}))
        return df
    cache: dict = {}
    df = tradeoff_study(cases, knobs=KNOBS, base=BASE, reference=REFERENCE,
                        element_series=("local_dx_um",), presets=PRESETS,
                        revolutions=args.revolutions, progress=log, cache=cache)
    refs = {c: {k: cache[c][k]} for c, k in df.attrs["reference_keys"].items()}
    (args.out / "refs.pkl").write_bytes(pickle.dumps(refs))
    meta["seconds"] = time.time() - t0
    (args.out / "meta.json").write_text(json.dumps(meta, indent=1))
    return finish(df, args.out)


def log(msg):
    print(time.strftime("%H:%M:%S"), msg, flush=True)


def finish(df, out: Path):
    df["band"] = df["band"].fillna("")
    df.to_csv(out / "tradeoff.csv", index=False)
    pts = pareto_points(df)
    pts.to_csv(out / "pareto.csv", index=False)
    plot_tradeoff(df, out / "tradeoff.png")
    (out / "summary.md").write_text(markdown(df, pts) + "\n" + markdown(df, pts, "error_knob"))
    return df


FIXED_BANDS = ("fs4_3fs8", "bpfi_3_6", "bpfi_10_13", "fixed")


def _pct(x):
    return "-" if pd.isna(x) else (f"{100 * x:.2g}" if x < 0.1 else f"{100 * x:.0f}")


def markdown(df, pts, error: str = "error") -> str:
    """The trade table (worst ``error`` over the cases, %) and the Pareto points as markdown."""
    cols = [("peak_pressure", None), ("p_max_rms", None), ("raw_bpfi_1", None),
            ("envelope_bpfi_1", FIXED_BANDS), ("envelope_bpfi_1", ("kurtogram",)),
            ("envelope_bpfi_2", FIXED_BANDS), ("envelope_bpfi_2", ("kurtogram",))]
    names = ["peak p", "rms p_max(t)", "raw 1xBPFI", "env 1x (4 fixed bands)", "env 1x (kurtogram)",
             "env 2x (4 fixed bands)", "env 2x (kurtogram)"]
    keys = df[["knob", "value"]].drop_duplicates().itertuples(index=False)
    lines = ["| knob | value | CPU s/case (mean) | CPU s, 750 kN 100 um | solves/case | "
             + " | ".join(names) + " |", "|" + "---|" * (5 + len(names))]
    seen_base = False
    for knob, value in keys:
        d = df[(df["knob"] == knob) & (df["value"] == value)]
        if d["is_base"].any() and error == "error":
            if seen_base:
                continue
            seen_base, knob, value = True, "base", "standard (no checks)"
        one = d.drop_duplicates("case")
        big = one[one["case"] == "F750kN_h100um"]["cpu_s"]
        row = [knob, value, f"{one['cpu_s'].mean():.1f}", f"{big.iloc[0]:.1f}" if len(big) else "-",
               f"{one['n_solves'].mean():.0f}"]
        for m, bands in cols:
            e = d[(d["metric"] == m) & (d["band"].isin(bands) if bands else True)][error]
            row.append(_pct(e.max()))
        lines.append("| " + " | ".join(row) + " |")
    out = [f"Column {error}, in % (worst over the cases; BPFI metrics over the defect cases).",
           ""] + lines
    if error != "error":
        return "\n".join(out) + "\n"
    out += ["", "Pareto points (mean CPU s per case, worst error %):", ""]
    for (m, b), g in pts.groupby(["metric", "band"], sort=False):
        f = g[g["pareto"]].sort_values("time_s")
        pp = ", ".join(f"{k}={v} ({t:.1f} s, {_pct(e)} %)" for k, v, t, e in
                       zip(f["knob"], f["value"], f["time_s"], f["error"]))
        out.append(f"- {m}{' [' + b + ']' if b else ''}: {pp}")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    main()
