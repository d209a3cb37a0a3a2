"""Each workflow job runs on the threads its rule declares, with the allocator settings of
``workflow/rules/jobenv.smk`` (issue 25 part 7).

A two-rule workflow that includes the real ``workflow/rules/jobenv.smk`` runs a script job with
``threads: 1`` and one with ``threads: 2``; each writes the thread variables of its environment
and the pool sizes numba and scipy.fft see.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RULES = ROOT / "workflow" / "rules"
BLAS_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")

DUMP = """
import json, os
import numba
from scipy import fft
env = {k: os.environ.get(k) for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                      "MKL_NUM_THREADS", "NUMBA_NUM_THREADS",
                                      "MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_")}
json.dump({"declared": snakemake.threads, "env": env,
           "numba_threads": numba.config.NUMBA_NUM_THREADS,
           "fft_workers": fft.get_workers()}, open(snakemake.output[0], "w"))
"""


def test_a_job_environment_carries_its_declared_threads(tmp_path):
    (tmp_path / "dump.py").write_text(DUMP)
    (tmp_path / "Snakefile").write_text(f"""
include: "{RULES / 'jobenv.smk'}"

rule all:
    input: "one.json", "two.json"

rule one:
    output: "one.json"
    threads: 1
    script: "dump.py"

rule two:
    output: "two.json"
    threads: 2
    script: "dump.py"
""")
    proc = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", "--workflow-profile",
                           "none", "--quiet"], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr[-3000:]
    for name, threads in (("one", 1), ("two", 2)):
        job = json.loads((tmp_path / f"{name}.json").read_text())
        assert job["declared"] == threads
        for var in BLAS_VARIABLES:
            assert job["env"][var] == str(threads), (name, var, job["env"])
        # numba's kernels are serial: one pool thread whatever the rule declares
        assert job["env"]["NUMBA_NUM_THREADS"] == "1"
        assert job["numba_threads"] == 1
        assert job["fft_workers"] == 1
        # glibc keeps the record-sized arrays in the heap (fewer page faults, same numbers)
        assert int(job["env"]["MALLOC_MMAP_THRESHOLD_"]) == 32 * 1024 * 1024
        assert int(job["env"]["MALLOC_TRIM_THRESHOLD_"]) >= 32 * 1024 * 1024


def test_every_rule_declares_one_thread():
    """jobenv.smk holds numba to 1: a rule that declares more must revisit it."""
    for smk in sorted(RULES.glob("*.smk")):
        text = smk.read_text()
        blocks = re.split(r"^rule (\w+):", text, flags=re.M)[1:]
        for name, body in zip(blocks[::2], blocks[1::2]):
            if "script:" not in body:
                continue
            m = re.search(r"^\s+threads:\s*(\S+)", body, flags=re.M)
            assert m is not None and m.group(1) == "1", f"{smk.name}: rule {name}"


def test_the_workflow_includes_the_job_environment_first():
    text = (ROOT / "Snakefile").read_text()
    assert text.index('"workflow/rules/jobenv.smk"') < text.index('"workflow/rules/common.smk"')
