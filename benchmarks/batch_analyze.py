"""Throughput of ``bearing-envelope analyze`` on many records (issue 24 part 5).

Builds a manifest of the local CWRU drive-end records (the 28 of ``cwru_de12/`` and the 3 of
``real/``; shaft rate from the nominal rpm, bearing 6205), then times the batch at --jobs 1 and
2 (with the verdict table and the HTML page, figures included) and, for comparison, one process
per record on the first ``--baseline`` records. Wall time and CPU time (user + system of the
child processes) are printed as a markdown table; the verdict tables of the two batch runs are
compared byte for byte. ``--repeat 2`` lists every record twice (61-62 analyses of the same
31 files: a direct check of the 61-record target without other records).

Usage::

    python benchmarks/batch_analyze.py [--data ../shared/data/real] [--baseline 5]
"""

from __future__ import annotations

import argparse
import csv
import os
import resource
import subprocess
import sys
import tempfile
import time


def manifest(data: str, path: str, repeat: int = 1) -> int:
    """Write the manifest of the local records; returns the number of rows."""
    rows = []
    de12 = os.path.join(data, "cwru_de12")
    with open(os.path.join(de12, "index.csv"), encoding="utf-8") as fh:
        for r in csv.DictReader(fh):
            rows.append({"file": os.path.join(de12, r["file"]), "rpm": r["rpm_nominal"],
                         "bearing": "6205"})
    for f in sorted(os.listdir(data)):
        if f.endswith(".npz"):
            rows.append({"file": os.path.join(data, f), "rpm": "1797", "bearing": "6205"})
    rows = rows * repeat
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=["file", "rpm", "bearing"])
        w.writeheader()
        w.writerows(rows)
    return len(rows)


def timed(cmd: list[str]) -> tuple[float, float, int]:
    """(wall s, CPU s of the children, exit code) of a command."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    rc = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, rc


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", default=os.path.join(os.path.dirname(os.path.dirname(
        os.path.dirname(os.path.abspath(__file__)))), "shared", "data", "real"))
    ap.add_argument("--baseline", type=int, default=5,
                    help="records analysed one process each for comparison (0: none)")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--jobs", nargs="+", default=["1", "2"])
    a = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="batch_analyze_")
    m = os.path.join(tmp, "manifest.csv")
    n = manifest(a.data, m, a.repeat)
    print(f"{n} records; load average at the start {os.getloadavg()[0]:.2f}")
    print("| run | records | wall (s) | CPU (s) | wall per record (s) |\n|---|---|---|---|---|")
    tables = []
    for j in a.jobs:
        t = os.path.join(tmp, f"t{j}.csv")
        wall, cpu, rc = timed(["bearing-envelope", "analyze", "--manifest", m, "--jobs", j,
                               "--table", t, "--html", os.path.join(tmp, f"r{j}", "r.html"),
                               "--quiet"])
        tables.append(open(t, "rb").read())
        print(f"| batch --jobs {j} (exit {rc}) | {n} | {wall:.1f} | {cpu:.1f} | {wall / n:.2f} |")
    if a.baseline:
        with open(m, encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))[: a.baseline]
        wall = cpu = 0.0
        for r in rows:
            w, c, _ = timed(["bearing-envelope", "analyze", r["file"], "--fr",
                             str(float(r["rpm"]) / 60), "--bearing", "6205"])
            wall, cpu = wall + w, cpu + c
        print(f"| one process per record | {len(rows)} | {wall:.1f} | {cpu:.1f} | "
              f"{wall / len(rows):.2f} |")
    print(f"load average at the end {os.getloadavg()[0]:.2f}; verdict tables identical: "
          f"{len(set(tables)) == 1}")


if __name__ == "__main__":
    sys.exit(main())
