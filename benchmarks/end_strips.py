"""Axial end strips against the window's axial ladder (issue 25, third session), by hand.

    C='[[500,50],[250,40],[750,20]]'
    nice -n 5 python benchmarks/reference.py run --out results_bench/ends --cases "$C" \\
        --runs accurate ldy20 ldy10 ldy5                      # the ladder (one process)
    nice -n 5 python benchmarks/reference.py run --out results_bench/ends --cases "$C" \\
        --runs end20 end10 end5 end10s20 end10s80 end5s80     # the strips (another process)
    python benchmarks/end_strips.py --out results_bench/ends [results_bench/more ...]

(Two processes must not write the same ``--out`` at once: give each its own and name them all
here; their values files are merged.) Every run is the base of ``benchmarks/reference.py``
(the ``standard`` preset spelled out, run name ``accurate``) with one change: the window's axial
spacing ``local_dy_um`` 20, 10, 5 um (``ldy*``) or the axial end strips ``end_dy_um`` (``end*``,
``s*``: ``end_strip_um``, default 40 um).

**Reference.** Per metric, the converged value of the local_dy ladder 40, 20, 10, 5 um: the
Richardson value of its finest three levels when they are monotone with an order in [0.5, 4],
else the finest (``reference.py``'s rule for one knob). Every other knob is the same in every
run, so the errors here are the window's axial discretisation error only (the reference study's
other knobs add their own; ``docs/benchmarks.md``, "Reference and converged default").

With ``--study-ref results_bench/reference/reference.csv`` (written by ``reference.py report``)
the errors are against the reference study's reference (every knob refined: the rim strips',
the global grid's, the tolerance's ... corrections) with its local_dy correction replaced by
this ladder's (the study built local_dy 5 um on 500 kN / 50 um only).

With ``--ref-run ldy5`` the errors are against the uniform 5 um window itself (the finest
level: what the strips should reproduce, without the ladder's extrapolation).

Prints, per run, the CPU per case of the table (``time.process_time``; the synthesis, ~1.3 s
per 100 revolutions, is the same for every run) and the worst relative error (%) over the
cases per signal and line group: envelope lines 1-3 x BPFI in the fixed bands (``env``), their
fr sidebands (``sb``), the lines in the kurtogram band (``kg``), raw DC and 1-3 x BPFI terms,
peak and rms.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))
import accuracy as acc  # noqa: E402
import reference as ref  # noqa: E402

LADDER = [(40.0, "accurate"), (20.0, "ldy20"), (10.0, "ldy10"), (5.0, "ldy5")]
ORDER = ["accurate", "ldy20", "ldy10", "ldy5", "end20", "end10", "end10s20", "end10s80", "end5",
         "end5s80"]
GROUPS = ("envelope_line", "envelope_sideband", "kurtogram_line", "raw_dc", "raw_bpfi", "peak",
          "rms")
SHORT = ("env", "sb", "kg", "dc", "bpfi", "peak", "rms")


def load(outs) -> pd.DataFrame:
    df = pd.concat([pd.read_csv(p) for o in outs for p in sorted((Path(o) / "values").glob("*.csv"))])
    return df.drop_duplicates(["run"] + acc.KEYS)


def converged(df: pd.DataFrame) -> pd.DataFrame:
    out = []
    for key, g in df.groupby(acc.KEYS, dropna=False):
        kv = ref._knob_value(g.set_index("run")["value"], LADDER)
        if kv is not None:
            out.append({**dict(zip(acc.KEYS, key)), "ref": kv[0], "status": kv[3]})
    return pd.DataFrame(out)


def table(df: pd.DataFrame, study_ref: Path | None = None, ref_run: str | None = None) -> str:
    r = converged(df)
    if ref_run is not None:
        r = df[df.run == ref_run][acc.KEYS + ["value"]].rename(columns={"value": "ref"}).assign(
            status=f"run {ref_run}")
    if study_ref is not None:
        # the study's reference with its local_dy correction replaced by this ladder's
        s = pd.read_csv(study_ref)[acc.KEYS + ["ref", "local_dy_um_delta"]]
        base = df[df.run == "accurate"][acc.KEYS + ["value"]]
        r = s.merge(r, on=acc.KEYS, suffixes=("_study", "")).merge(base, on=acc.KEYS)
        r["ref"] = r["ref_study"] - r["local_dy_um_delta"].fillna(0.0) + (r["ref"] - r["value"])
        r = r[acc.KEYS + ["ref", "status"]]
    e = df.merge(r, on=acc.KEYS)
    e["error"] = (e["value"] - e["ref"]).abs() / e["ref"].abs()
    e["group"] = [ref.line_group(q, s, b) for q, s, b in
                  zip(e["quantity"], e["sideband"], e["band_strategy"])]
    e = e[e.group.notna() & np.isfinite(e.error)]
    cpu = e.groupby(["run", "load_kN", "depth_um"])["table_cpu_s"].first().groupby("run").agg(
        ["mean", "max"])
    w = e.groupby(["run", "signal", "group"])["error"].max()
    runs = [x for x in ORDER if x in cpu.index] + sorted(set(cpu.index) - set(ORDER))
    cases = sorted({(a, b) for a, b in zip(e.load_kN, e.depth_um)})
    lines = [f"cases {cases}; reference status: " + ", ".join(
        f"{k} {v}" for k, v in r["status"].value_counts().items()), "",
        "| run | table CPU s per case: mean / max | " + " | ".join(
            f"{s}: " + " / ".join(SHORT) for s in acc.SIGNALS) + " |",
        "|---|---|" + "---|" * len(acc.SIGNALS)]
    for run in runs:
        cells = [" / ".join(f"{100 * w.get((run, s, g), np.nan):.2g}" for g in GROUPS)
                 for s in acc.SIGNALS]
        lines.append(f"| {ref.label(run)} | {cpu.loc[run, 'mean']:.1f} / {cpu.loc[run, 'max']:.1f}"
                     f" | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, nargs="+", required=True)
    ap.add_argument("--study-ref", type=Path, default=None,
                    help="reference.csv of `reference.py report` (every knob refined) instead "
                         "of the local_dy ladder")
    ap.add_argument("--ref-run", default=None,
                    help="a run as the reference instead (e.g. ldy5: the uniform 5 um window)")
    a = ap.parse_args(argv)
    print(table(load(a.out), a.study_ref, a.ref_run))


if __name__ == "__main__":
    main()
