"""Recovery before the DAG: a corrupt or deleted case file is rebuilt with everything after it.

Snakemake (>= 8) does not rerun the job of a missing intermediate file while the files made
from it are present and up to date (it treats it like a ``temp()`` file): deleting a case file,
or moving a corrupt one aside, then gives "Nothing to be done". So, before the DAG is built,
:func:`recover_case_files` verifies every case file in full
(:func:`bearing_envelope.io.case_file_problem`: every chunk against its checksum, the attribute
digest), moves a bad one aside, and for a missing one whose consumers' outputs exist touches a
*rebuild marker* (:func:`rebuild_marker`, ``results/.rebuild/{stage}/{case}``). The marker is
an input of the case's first consumer (rules ``bands`` and ``sensor``) while it exists: newer
than that consumer's outputs, it makes the consumer rerun, the consumer needs the missing case,
and Snakemake reruns the case and everything downstream -- in the same run.

Nothing is moved or touched on a dry run or any other command that runs no job
(:func:`is_dry_run`): then the warning says what a real run would do.
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from pathlib import Path

from ..io import case_file_problem, set_aside_unreadable

__all__ = ["NON_EXECUTING_FLAGS", "NON_EXECUTING_ARGS", "is_dry_run", "rebuild_marker", "marker_if_present",
           "Recovery", "recover_case_files"]

#: Long command-line options of Snakemake after which no job runs (dry run, summaries, reports,
#: lint, unlock, cleanup, graph output): the pre-run recovery then changes nothing.
NON_EXECUTING_FLAGS = frozenset({
    "--dry-run", "--dryrun", "--touch", "--report", "--lint", "--unlock", "--list-rules",
    "--list", "--list-target-rules", "--lt", "--summary", "--detailed-summary", "--dag",
    "--rulegraph", "--filegraph", "--d3dag", "--cleanup-metadata", "--cm", "--list-changes",
    "--lc", "--list-input-changes", "--li", "--list-params-changes", "--lp",
    "--list-code-changes", "--list-untracked", "--lu", "--delete-all-output",
    "--delete-temp-output", "--print-compilation", "--containerize", "--archive",
    "--generate-unit-tests", "--export-cwl", "--conda-create-envs-only", "--conda-cleanup-envs",
    "--cleanup-shadow", "--version", "--help", "--show-failed-logs-only", "--list-conda-envs",
    "--container-cleanup-images", "--edit-notebook", "--dry-run",
})

#: Short options of Snakemake that run no job: -n (dry run), -t (touch), -S (summary),
#: -D (detailed summary), -l (list rules), -h (help), -v (version).
_NON_EXECUTING_SHORT = frozenset("ntSDlhv")

#: Short options that take a value (the rest of a cluster is that value, not more flags).
_SHORT_WITH_VALUE = frozenset("jcsdRTPCUO")

MARKER_DIR = "results/.rebuild"


def _short_flags(arg: str) -> set[str]:
    """The flags of a short-option cluster (``-np`` -> {n, p}; ``-j2`` -> {j})."""
    flags = set()
    for ch in arg[1:]:
        flags.add(ch)
        if ch in _SHORT_WITH_VALUE:
            break
    return flags


#: Attributes of Snakemake's parsed command line (``snakemake.cli.parse_args``) that make it
#: run no job: each selects a branch of ``snakemake.cli.args_to_api`` other than executing
#: the workflow (dry run, touch, listings, summaries, reports, graphs, cleanups ...).
NON_EXECUTING_ARGS = (
    "dryrun", "touch", "report", "lint", "list_target_rules", "list_rules",
    "print_compilation", "containerize", "generate_unit_tests", "dag", "rulegraph",
    "filegraph", "d3dag", "unlock", "cleanup_metadata", "conda_cleanup_envs",
    "conda_create_envs_only", "list_conda_envs", "cleanup_shadow", "container_cleanup_images",
    "list_changes", "list_input_changes", "list_params_changes", "list_untracked", "summary",
    "detailed_summary", "archive", "delete_all_output", "delete_temp_output", "version",
    "edit_notebook",
)


def _snakemake_args(argv: list[str]):
    """Snakemake's own reading of ``argv`` (abbreviations, profiles and the workflow profile
    included), or None when it cannot be parsed here (not a snakemake command line)."""
    import contextlib
    import io

    try:
        from snakemake.cli import parse_args
    except ImportError:
        return None
    sink = io.StringIO()
    try:
        with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
            return parse_args(argv)[1]
    except (Exception, SystemExit):  # noqa: BLE001 -- any failure: fall back to the flags
        return None


def _flags_say_dry_run(argv: list[str]) -> bool:
    """The fallback: a long option that is :data:`NON_EXECUTING_FLAGS` or a prefix of one
    (argparse accepts unambiguous abbreviations: ``--dry-r``, ``--summ``), or a short-option
    cluster holding ``-n``, ``-t``, ``-S``, ``-D``, ``-l``, ``-h``, ``-v``."""
    # An option's value that looks like a flag (``-s -n``) counts as the flag: a false "dry
    # run" only skips the recovery, a missed one would change files on a dry run.
    for arg in argv:
        if arg.startswith("--"):
            name = arg.split("=", 1)[0]
            if len(name) > 3 and any(f.startswith(name) for f in NON_EXECUTING_FLAGS):
                return True
        elif arg.startswith("-") and len(arg) > 1 and not arg[1].isdigit():
            if _short_flags(arg) & _NON_EXECUTING_SHORT:
                return True
    return False


def is_dry_run(argv: list[str] | None = None, workflow=None) -> bool:
    """Whether this Snakemake invocation runs no job (so must change no file).

    ``workflow.dryrun`` is read when given, but Snakemake 8.x/9.x set it only after the
    Snakefile was parsed (it is False while the workflow's own code runs), so the command line
    decides, read by Snakemake's own parser (:func:`snakemake.cli.parse_args`: abbreviated
    options such as ``--dry-r``, a profile saying ``dry-run: true``): any attribute of
    :data:`NON_EXECUTING_ARGS` set means no job runs. When that parser cannot read ``argv``,
    the flags decide (:func:`_flags_say_dry_run`); either way a flag named on the command line
    counts.

    Parameters
    ----------
    argv : list of str, optional
        The command line, program name first (default :data:`sys.argv`).
    workflow : snakemake.workflow.Workflow, optional
        The running workflow; its ``dryrun`` attribute counts when set.

    Returns
    -------
    bool
        True when no job runs (dry run, touch, listings, summaries, ...).
    """
    if workflow is not None and getattr(workflow, "dryrun", False):
        return True
    args = list(sys.argv if argv is None else argv)[1:]
    if _flags_say_dry_run(args):
        return True
    parsed = _snakemake_args(args)
    return parsed is not None and any(getattr(parsed, a, None) for a in NON_EXECUTING_ARGS)


def rebuild_marker(stage: str, case: str) -> str:
    """Path of the rebuild marker of ``results/{stage}/{case}.h5``.

    Parameters
    ----------
    stage : str
        The case file's stage folder (``cases``, ``sensor``).
    case : str
        Case name.

    Returns
    -------
    str
        ``results/.rebuild/{stage}/{case}``, relative to the working folder.
    """
    return f"{MARKER_DIR}/{stage}/{case}"


def marker_if_present(stage: str, case: str) -> list[str]:
    """``[marker]`` when the case's rebuild marker exists, else ``[]`` (a rule input).

    Parameters
    ----------
    stage, case : str
        As in :func:`rebuild_marker`.

    Returns
    -------
    list of str
        ``[rebuild_marker(stage, case)]`` or ``[]``.
    """
    path = rebuild_marker(stage, case)
    return [path] if os.path.exists(path) else []


@dataclass
class Recovery:
    """What :func:`recover_case_files` found and did (paths relative to the working folder)."""

    set_aside: list[str]
    rebuilt_missing: list[str]
    dry_run: bool


def _touch(path: str) -> None:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).touch()


def recover_case_files(stages: dict[str, list[str]], consumers, *, dry_run: bool,
                       warn=None) -> Recovery:
    """Verify every case file; move bad ones aside and mark missing ones for rebuilding.

    Parameters
    ----------
    stages : dict
        Stage (``cases``, ``sensor``) -> case names; the files are ``results/{stage}/{case}.h5``.
    consumers : callable
        ``consumers(stage, case)`` -> paths made from that file; when one exists, a missing
        file gets its rebuild marker touched (otherwise nothing was built from it yet and
        Snakemake builds it anyway).
    dry_run : bool
        Change nothing; the warnings say what a real run would do.
    warn : callable, optional
        Receives each one-line warning (default: stderr).

    Returns
    -------
    Recovery
        ``set_aside``: the corrupt files moved aside (on a dry run: that would be);
        ``rebuilt_missing``: the missing files whose consumers exist; ``dry_run`` as given.
        Each file of either list gets its rebuild marker touched (not on a dry run).
    """
    say = warn or (lambda m: print(m, file=sys.stderr))
    found = Recovery([], [], dry_run)
    for stage, cases in stages.items():
        for case in cases:
            path = f"results/{stage}/{case}.h5"
            if os.path.isfile(path):
                problem = case_file_problem(path)
                if problem is None:
                    continue
                if dry_run:
                    say(f"warning: {path}: {problem}; a real run moves it aside and rebuilds it")
                    found.set_aside.append(path)
                    continue
                set_aside_unreadable(path, warn=say)
                found.set_aside.append(path)
            elif not any(os.path.exists(p) for p in consumers(stage, case)):
                continue
            else:
                found.rebuilt_missing.append(path)
                if dry_run:
                    say(f"warning: {path} is missing; a real run rebuilds it and what is made "
                        f"from it")
                    continue
            if not dry_run:
                _touch(rebuild_marker(stage, case))
    return found
