"""Shared fixtures: one draft sweep per test session (tests/test_workflow.py, tests/test_report.py),
and how the suite is split over pytest-xdist's workers (pyproject.toml: ``-n 2 --dist loadgroup``).

Under xdist:

- a test that uses a module-scoped fixture runs on the same worker as the rest of its module
  (``xdist_group`` named after the module), so no module fixture is built twice (the SLURM
  cluster, the runtime venv, the reliability tests' tiny sweep, ...); every other test is its own
  unit of work and goes to whichever worker is free;
- the draft sweep is built once for the whole run, by the first worker that needs it, under a
  file lock in the run's shared temporary directory; each worker then works on its own copy
  (some tests rebuild files in it);
- the slow files (end-to-end Snakemake runs, ``SLOW_FIRST``) are handed out first, so that the
  last minutes do not leave one worker idle.

Without xdist (``-n 0`` or ``-p no:xdist``) nothing of this applies: the tests run in file
order and the draft sweep is built in the session's temporary directory, as before.
"""

from __future__ import annotations

import fcntl
import json
import os
import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DRAFT = ROOT / "tests" / "data" / "config_draft.yaml"

#: Slow files, in the order their tests are handed out under xdist, before every other test
#: (docs/benchmarks.md, test-suite time).
SLOW_FIRST = ("test_slurm.py", "test_reliability.py", "test_report.py", "test_workflow.py")


def _xdist_worker(config) -> bool:
    """True in an xdist worker: the workers collect, and the controller schedules the tests in
    the order of their collection (xdist sets the workers' own ``numprocesses`` to None)."""
    return hasattr(config, "workerinput")


def _module_scoped(item) -> bool:
    info = getattr(item, "_fixtureinfo", None)
    if info is None:
        return False
    return any(d.scope in ("module", "class", "package")
               for defs in info.name2fixturedefs.values() for d in defs)


def _groups_file(basetemp: Path) -> Path:
    return basetemp / "xdist-groups.json"


@pytest.hookimpl(tryfirst=True)  # before xdist's own hook, which reads the xdist_group marks
def pytest_collection_modifyitems(config, items):
    if not _xdist_worker(config):
        return
    groups = {}
    for item in items:
        if _module_scoped(item):
            groups[item.nodeid] = item.nodeid.split("::")[0]
            item.add_marker(pytest.mark.xdist_group(groups[item.nodeid]))
    # xdist 3.8 tells the controller a test's group by appending "@group" to its node id, which
    # pytest >= 9.2 no longer lets it do (pytest-xdist issue 1386: the groups are silently
    # ignored); so the groups also go to the controller's scheduler (below) through a file in
    # the run's temporary directory, written before the worker reports its collection.
    shared = config._tmp_path_factory.getbasetemp().parent
    tmp = shared / f"xdist-groups.{os.getpid()}.tmp"
    tmp.write_text(json.dumps(groups))
    os.replace(tmp, _groups_file(shared))

    def rank(item):
        name = Path(item.nodeid.split("::")[0]).name
        return SLOW_FIRST.index(name) if name in SLOW_FIRST else len(SLOW_FIRST)

    items.sort(key=rank)  # stable: file order within each rank


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``--dist loadgroup`` with the groups of ``pytest_collection_modifyitems`` above."""
    if config.getvalue("dist") != "loadgroup":
        return None
    from xdist.scheduler import LoadGroupScheduling

    class FileGroupScheduling(LoadGroupScheduling):
        _groups: dict | None = None

        def _split_scope(self, nodeid: str) -> str:
            if self._groups is None:
                path = _groups_file(config._tmp_path_factory.getbasetemp())
                self._groups = json.loads(path.read_text()) if path.exists() else {}
            return self._groups.get(nodeid) or super()._split_scope(nodeid)

    return FileGroupScheduling(config, log)


def _build_draft(wd: Path) -> None:
    sys.path.insert(0, str(Path(__file__).parent))
    from test_workflow import smk

    smk(wd)


@pytest.fixture(scope="session")
def draft_run(tmp_path_factory):
    """A workdir holding the full draft sweep (2 loads x 2 depths, 4 revolutions)."""
    wd = tmp_path_factory.mktemp("sweep")
    if os.environ.get("PYTEST_XDIST_WORKER") is None:
        _build_draft(wd)
        return wd
    # one build for all workers: the first to take the lock builds, the others wait and copy
    shared = tmp_path_factory.getbasetemp().parent
    built = shared / "draft-sweep"
    with open(shared / "draft-sweep.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (shared / "draft-sweep.done").exists():
            shutil.rmtree(built, ignore_errors=True)  # a failed earlier attempt
            built.mkdir()
            _build_draft(built)
            (shared / "draft-sweep.done").touch()
    shutil.rmtree(wd)
    shutil.copytree(built, wd, symlinks=True)
    shutil.rmtree(wd / ".snakemake" / "locks", ignore_errors=True)
    return wd
