"""Validations of one value per run: how often the scene, fidelity, analysis, sensor and
trade-off values of a sweep are built and checked, by the workflow's loader and by its jobs.

A Snakemake dry run of the sweep runs in this process (the loader and the pre-run check of
``workflow/rules/common.smk``) with counters wrapped around the functions that build and check
each value; then every job of the DAG that runs a script receives its params as Snakemake hands
them (pickled) and runs the jobs' one loader, ``study.job_transport.job_settings``, counted the same
way. No job runs.

    python -m benchmarks job_validations [--configfile FILE ...] [--target T ...]

Defaults: the repository's ``config.yaml`` (the default sweep), targets ``all`` and ``tradeoff``.
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import functools
import pickle
import tempfile
from pathlib import Path
from types import SimpleNamespace

ROOT = Path(__file__).resolve().parents[1]


def _counted_targets():
    """``{value: [(owner, attribute), ...]}``: the functions that build and check each value."""
    from bearing_envelope.physics.fidelity import Fidelity
    from bearing_envelope.physics.scene import Scene
    from bearing_envelope.physics.transfer import TransferModel
    from bearing_envelope.study import tradeoff
    from bearing_envelope.study.sections import AnalysisSettings

    out = {
        "scene (Scene.from_mapping)": [(Scene, "from_mapping")],
        "fidelity (a Fidelity built and checked)": [(Fidelity, "__post_init__")],
        "analysis (AnalysisSettings.from_mapping / from_json)": [
            (AnalysisSettings, "from_mapping"), (AnalysisSettings, "from_json")],
        "sensor (TransferModel.from_mapping)": [(TransferModel, "from_mapping")],
    }
    typed = getattr(tradeoff, "TradeoffSettings", None)
    if typed is not None:
        out["tradeoff section (TradeoffSettings.from_mapping)"] = [(typed, "from_mapping")]
    return out


@contextlib.contextmanager
def _counting(counts: collections.Counter):
    """Wrap every counted function so that each call adds one to ``counts[value]``."""
    undo = []
    for value, targets in _counted_targets().items():
        for owner, name in targets:
            if name not in owner.__dict__:   # e.g. AnalysisSettings.from_json (removed)
                continue
            raw = owner.__dict__[name]
            is_cm = isinstance(raw, classmethod)
            func = raw.__func__ if is_cm else raw

            def wrapper(*a, _f=func, _v=value, **kw):
                counts[_v] += 1
                return _f(*a, **kw)

            functools.update_wrapper(wrapper, func)
            setattr(owner, name, classmethod(wrapper) if is_cm else wrapper)
            undo.append((owner, name, raw))
    try:
        yield counts
    finally:
        for owner, name, raw in reversed(undo):
            setattr(owner, name, raw)


def _dry_run_dag(configfiles: list[Path], targets: list[str], workdir: Path):
    """The DAG of a dry run of the workflow (its loader runs in this process)."""
    from snakemake.api import SnakemakeApi
    from snakemake.settings.enums import Quietness
    from snakemake.settings.types import (ConfigSettings, DAGSettings, OutputSettings,
                                          ResourceSettings)

    with SnakemakeApi(OutputSettings(quiet={Quietness.ALL})) as api:
        wapi = api.workflow(resource_settings=ResourceSettings(cores=1),
                            config_settings=ConfigSettings(configfiles=configfiles),
                            snakefile=ROOT / "Snakefile", workdir=workdir)
        dapi = wapi.dag(dag_settings=DAGSettings(targets=set(targets)))
        dapi.execute_workflow(executor="dryrun")
        return wapi._workflow.dag


def count(configfiles: list[Path], targets: list[str], job_loader=None) -> dict:
    """Calls per value in the loader (the dry run) and in the jobs' loader, and jobs per rule.

    Parameters
    ----------
    configfiles : list of Path
        The ``--configfile`` files (empty: ``config.yaml`` of the repository, copied into the
        temporary run directory).
    targets : list of str
        The dry run's targets.
    job_loader : callable, optional
        What a job runs on its ``snakemake`` object (default ``study.job_transport.job_settings``).

    Returns
    -------
    dict
        ``loader`` and ``jobs``: Counters of calls per value; ``rules``: jobs per rule.
    """
    if job_loader is None:
        from bearing_envelope.study.job_transport import job_settings as job_loader
    loader, jobs = collections.Counter(), collections.Counter()
    with tempfile.TemporaryDirectory() as tmp:
        if not configfiles:
            (Path(tmp) / "config.yaml").write_text((ROOT / "config.yaml").read_text())
        with _counting(loader):
            dag = _dry_run_dag([Path(c).resolve() for c in configfiles], targets, Path(tmp))
        scripted = [j for j in dag.jobs if j.rule.script]
        rules = collections.Counter(j.rule.name for j in scripted)
        with _counting(jobs):
            for j in scripted:
                # what Snakemake's script preamble does with a job's params
                job_loader(pickle.loads(pickle.dumps(SimpleNamespace(params=j.params))))
    return {"loader": loader, "jobs": jobs, "rules": rules}


def _table(res: dict) -> str:
    lines = ["| value | loader (dry run, pre-run check) | jobs | per run |", "|---|---|---|---|"]
    for value in _counted_targets():
        a, b = res["loader"][value], res["jobs"][value]
        lines.append(f"| {value} | {a} | {b} | {a + b} |")
    rules = ", ".join(f"{k} {v}" for k, v in sorted(res["rules"].items()))
    return "\n".join(lines) + f"\n\nscript jobs: {rules}"


def main(argv=None) -> int:
    """Print the counts of a sweep (markdown table)."""
    ap = argparse.ArgumentParser(prog="python -m benchmarks job_validations",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--configfile", action="append", default=[], type=Path)
    ap.add_argument("--target", action="append", default=[])
    args = ap.parse_args(argv)
    print(_table(count(args.configfile, args.target or ["all", "tradeoff"])))
    return 0


def smoke() -> None:
    """The draft config (4 cases): every script job's values arrive without a check."""
    res = count([ROOT / "tests" / "data" / "config_draft.yaml"], ["all"])
    assert res["rules"]["simulate"] == 4, res["rules"]
    assert sum(res["jobs"].values()) == 0, res["jobs"]
    assert res["loader"]["scene (Scene.from_mapping)"] >= 4, res["loader"]
