"""Per-rule CPU of a sweep from Snakemake's benchmark files.

``python -m benchmarks sweep_cost LOGS [LOGS_AFTER]`` reads ``LOGS/benchmarks/**.tsv`` (one file
per job: ``cpu_time`` = user + system CPU seconds of the job's process tree, ``s`` = wall,
``max_rss`` in MB) and prints, per rule, the jobs, their CPU (sum, mean per job), wall and the
largest resident set; with two folders, side by side with the difference. The CPU of the
Snakemake process itself and of rules without a benchmark file is the total of
``/usr/bin/time -v`` minus the sum printed here.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pandas as pd


def rule_costs(logs: Path) -> pd.DataFrame:
    """One row per rule: ``jobs, cpu_s, cpu_per_job_s, wall_s, max_rss_mb``."""
    rows = []
    for tsv in sorted((logs / "benchmarks").rglob("*.tsv")):
        rel = tsv.relative_to(logs / "benchmarks")
        rule = rel.parts[0] if len(rel.parts) > 1 else rel.stem
        b = pd.read_csv(tsv, sep="\t")
        rows.append({"rule": rule, "cpu_s": float(b["cpu_time"].sum()), "wall_s": float(b["s"].sum()),
                     "max_rss_mb": pd.to_numeric(b["max_rss"], errors="coerce").max()})
    df = pd.DataFrame(rows)
    out = df.groupby("rule").agg(jobs=("cpu_s", "size"), cpu_s=("cpu_s", "sum"),
                                 wall_s=("wall_s", "sum"), max_rss_mb=("max_rss_mb", "max"))
    out["cpu_per_job_s"] = out["cpu_s"] / out["jobs"]
    return out.sort_values("cpu_s", ascending=False)


def main(argv: list[str]) -> int:
    tables = [rule_costs(Path(a)) for a in argv]
    if len(tables) == 1:
        t = tables[0]
        print(t.round(2).to_string())
        print(f"total of the benchmarked jobs: {t['cpu_s'].sum():.1f} CPU s, {int(t['jobs'].sum())} jobs")
        return 0
    a, b = tables
    cols = ["jobs", "cpu_s", "cpu_per_job_s"]
    both = a[cols].merge(b[cols], left_index=True, right_index=True, how="outer",
                         suffixes=("_before", "_after"))
    both["change_s"] = both["cpu_s_after"] - both["cpu_s_before"]
    print(both.round(2).to_string())
    print(f"total: {a['cpu_s'].sum():.1f} -> {b['cpu_s'].sum():.1f} CPU s")
    return 0


def smoke() -> None:
    """Two tiny log folders of two rules each, alone and side by side."""
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        for run, cpu in (("before", 1.0), ("after", 0.5)):
            for rule, case in (("simulate", "F1kN_h0um"), ("simulate", "F1kN_h5um"),
                               ("aggregate", None)):
                path = Path(d, run, "benchmarks", rule, f"{case}.tsv") if case else \
                    Path(d, run, "benchmarks", f"{rule}.tsv")
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_text("s\th:m:s\tmax_rss\tcpu_time\n"
                                f"{2 * cpu}\t0:00:02\t100.0\t{cpu}\n")
        assert main([str(Path(d, "before"))]) == 0
        assert main([str(Path(d, "before")), str(Path(d, "after"))]) == 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
