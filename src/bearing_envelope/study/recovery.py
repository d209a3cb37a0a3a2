"""Recovery before the DAG: a damaged or deleted artefact is rebuilt with everything after it.

Snakemake (>= 8) does not rerun the job of a missing intermediate file while the files made
from it are present and up to date (it treats it like a ``temp()`` file): deleting a case file,
or moving a corrupt one aside, then gives "Nothing to be done". So, before the DAG is built,
:func:`recover_artefacts` verifies every artefact it is given in full (a case file: every chunk
against its checksum, the attribute digest; a sealed per-case table: its content against its
``# content_sha256=`` line, so an edit that keeps the file's mtime is found too), moves a bad
one aside, and for it or a missing one whose consumers' outputs exist touches a *rebuild
marker*. The marker is an input of the artefact's first consumer while it exists: newer than
that consumer's outputs, it makes the consumer rerun, the consumer needs the missing file, and
Snakemake rebuilds it and everything downstream -- in the same run. The paths (artefacts,
markers, consumers) are the caller's: this module names no folder of the workflow.

Nothing is moved or touched on a dry run or any other command that runs no job
(:func:`is_dry_run`): then the warning says what a real run would do.
"""

from __future__ import annotations

import datetime as _dt
import os
import sys
from dataclasses import dataclass
from pathlib import Path

from ..io import case_file_problem
from ..io.integrity import sealed_text_problem

__all__ = ["NON_EXECUTING_FLAGS", "NON_EXECUTING_ARGS", "is_dry_run", "marker_if_present",
           "ARTEFACT_KINDS", "Artefact", "Recovery", "recover_artefacts"]

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


def marker_if_present(marker: str | os.PathLike) -> list[str]:
    """``[marker]`` when the rebuild marker exists, else ``[]`` (a rule input).

    Parameters
    ----------
    marker : str or os.PathLike
        A rebuild marker (:attr:`Artefact.marker`; the workflow names its folder).

    Returns
    -------
    list of str
        ``[marker]`` or ``[]``.
    """
    return [os.fspath(marker)] if os.path.exists(marker) else []


#: What :func:`recover_artefacts` verifies, by kind: an HDF5 case file (every chunk against its
#: checksum, the attribute digest: :func:`bearing_envelope.io.case_file_problem`) or a sealed
#: text table (its ``# content_sha256=`` line against its content, whatever its mtime:
#: :func:`bearing_envelope.io.integrity.sealed_text_problem`).
ARTEFACT_KINDS = ("case", "sealed table")


@dataclass(frozen=True)
class Artefact:
    """A file verified before the DAG: its path, its rebuild marker (an input of its first
    consumer while the marker exists) and the files made from it (all paths the caller's)."""

    path: str
    marker: str
    consumers: tuple = ()
    kind: str = "case"


@dataclass
class Recovery:
    """What :func:`recover_artefacts` found and did (paths as the caller gave them)."""

    set_aside: list[str]
    rebuilt_missing: list[str]
    dry_run: bool


def _touch(path: str) -> None:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).touch()


def _problem(art: Artefact) -> str | None:
    if art.kind == "sealed table":
        return sealed_text_problem(art.path)
    return case_file_problem(art.path)


def _set_aside(path: str, problem: str, say) -> None:
    stamp = _dt.datetime.now(_dt.timezone.utc).strftime("%Y%m%dT%H%M%SZ")
    aside = f"{path}.unreadable-{stamp}"
    os.replace(path, aside)
    say(f"warning: {path}: {problem}; moved aside to {aside}; it will be rebuilt as a missing "
        f"file")


def recover_artefacts(artefacts, *, dry_run: bool, warn=None) -> Recovery:
    """Verify every artefact; move bad ones aside and mark them and missing ones for rebuilding.

    Parameters
    ----------
    artefacts : iterable of Artefact
        The files to verify, each with its rebuild marker and consumers.
    dry_run : bool
        Change nothing; the warnings (one line each) say what a real run would do.
    warn : callable, optional
        Receives each one-line warning (default: stderr).

    Returns
    -------
    Recovery
        ``set_aside``: the damaged files moved aside (on a dry run: that would be);
        ``rebuilt_missing``: the missing files whose consumers exist. Each file of either list
        gets its rebuild marker touched (not on a dry run): it then reruns its first consumer,
        which needs the file, so Snakemake rebuilds it and everything after it in this run.
    """
    say = warn or (lambda m: print(m, file=sys.stderr))
    found = Recovery([], [], dry_run)
    for art in artefacts:
        if os.path.isfile(art.path):
            problem = _problem(art)
            if problem is None:
                continue
            found.set_aside.append(art.path)
            if dry_run:
                say(f"warning: {art.path}: {problem}; a real run moves it aside and rebuilds it")
                continue
            _set_aside(art.path, problem, say)
        elif not any(os.path.exists(p) for p in art.consumers):
            continue
        else:
            found.rebuilt_missing.append(art.path)
            if dry_run:
                say(f"warning: {art.path} is missing; a real run rebuilds it and what is made "
                    f"from it")
                continue
        _touch(art.marker)
    return found
