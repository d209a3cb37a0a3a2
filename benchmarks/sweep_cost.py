"""Per-rule CPU of a sweep from Snakemake's benchmark files (issue 25 part 7).

``python benchmarks/sweep_cost.py LOGS [LOGS_AFTER]`` reads ``LOGS/benchmarks/**.tsv`` (one file
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
    both = a[["jobs", "cpu_s", "cpu_per_job_s"]].join(
        b[["jobs", "cpu_s", "cpu_per_job_s"]], lsuffix="_before", rsuffix="_after", how="outer")
    both["change_s"] = both["cpu_s_after"] - both["cpu_s_before"]
    print(both.round(2).to_string())
    print(f"total: {a['cpu_s'].sum():.1f} -> {b['cpu_s'].sum():.1f} CPU s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
