"""What code made an artefact: the package modules a script depends on, and run logs.

- :func:`code_dependencies`: the source files of this package that a script or module imports,
  directly or through other package modules (imports inside functions included), found by
  reading the sources (nothing is imported). A workflow rule lists them as inputs, so editing a
  module reruns exactly the stages whose code imports it; no list is kept by hand.
- :class:`log_to`: send stderr and logging of a job to its log file.
"""

from __future__ import annotations

import ast
import errno
import os
from pathlib import Path

__all__ = ["PACKAGE_DIR", "code_dependencies", "module_imports", "log_to"]

#: Folder of this package's sources.
PACKAGE_DIR = Path(__file__).resolve().parent.parent
_PACKAGE = PACKAGE_DIR.name


def _module_file(dotted: str) -> Path | None:
    """Source file of a package module given as ``bearing_envelope.a.b`` (None if absent)."""
    parts = dotted.split(".")
    if parts[0] != _PACKAGE:
        return None
    base = PACKAGE_DIR.joinpath(*parts[1:])
    for cand in (base.with_suffix(".py"), base / "__init__.py"):
        if cand.is_file():
            return cand
    return None


def _dotted(path: Path) -> str:
    rel = path.resolve().relative_to(PACKAGE_DIR).with_suffix("")
    parts = [_PACKAGE, *rel.parts]
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def module_imports(path: str | os.PathLike) -> set[Path]:
    """Source files of this package imported by one file (any nesting level, not recursive).

    ``import bearing_envelope.x``, ``from bearing_envelope.x import y`` (``y`` a submodule or a
    name of ``x``) and relative imports inside the package are followed; the parent packages'
    ``__init__.py`` files, which Python runs on such an import, are included.

    Parameters
    ----------
    path : str or os.PathLike
        A Python source file, inside the package or not (relative imports are followed only
        inside it).

    Returns
    -------
    set of pathlib.Path
        Resolved source files of this package (``path`` itself excluded); imports of other
        packages are ignored.
    """
    path = Path(path).resolve()
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    inside = PACKAGE_DIR in path.parents
    here = _dotted(path) if inside else None
    is_pkg = path.name == "__init__.py"
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                if here is None:
                    continue
                parts = here.split(".")
                keep = len(parts) - node.level + (1 if is_pkg else 0)
                base = ".".join(parts[:keep] + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            names.add(base)
            names.update(f"{base}.{a.name}" for a in node.names)
    found: set[Path] = set()
    for name in names:
        parts = name.split(".")
        for i in range(1, len(parts) + 1):  # the module and every parent package it runs
            f = _module_file(".".join(parts[:i]))
            if f is not None:
                found.add(f)
    found.discard(path)
    return found


def code_dependencies(*paths: str | os.PathLike) -> list[str]:
    """Sorted source files of this package that ``paths`` (scripts or modules) depend on.

    The closure of :func:`module_imports`: every package module reachable through imports
    (including imports inside functions, so the list errs on the side of rerunning). Package
    modules given in ``paths`` are included themselves.

    Parameters
    ----------
    *paths : str or os.PathLike
        Scripts or modules (files that must exist).

    Returns
    -------
    list of str
        Absolute paths of the package's source files, sorted.

    Raises
    ------
    FileNotFoundError
        A path that is not a file.

    Examples
    --------
    >>> deps = code_dependencies(PACKAGE_DIR / "physics" / "history.py")
    >>> any(p.endswith("contact/solver.py") for p in deps)
    True
    """
    todo = [Path(p).resolve() for p in paths]
    for p in todo:
        if not p.is_file():
            raise FileNotFoundError(f"code_dependencies: no such file {p}")
    seen: set[Path] = {p for p in todo if PACKAGE_DIR in p.parents}
    while todo:
        for dep in module_imports(todo.pop()):
            if dep not in seen:
                seen.add(dep)
                todo.append(dep)
    return sorted(str(p) for p in seen)


class log_to:
    """Context manager sending stderr (warnings, tracebacks) and logging to a log file.

    Used by the workflow scripts: ``with log_to(snakemake.log[0]): ...``. An exception is
    written to the log and re-raised so that the job fails; a full disk (ENOSPC, EDQUOT,
    :class:`bearing_envelope.io.integrity.DiskFullError`) ends the job with one line on stderr
    instead (``SystemExit``), wherever it was raised (an HDF5 case, a figure's PNG), and so does
    a damaged input (an edited per-case table; the pre-run recovery normally rebuilds it first).

    Parameters
    ----------
    path : str or os.PathLike
        The log file, created (or truncated) on entering the block; its parent must exist.
    """

    def __init__(self, path):
        self.path = path

    def __enter__(self):
        import logging
        import sys

        self._fh = open(self.path, "w", encoding="utf-8")
        self._old = sys.stderr
        sys.stderr = self._fh
        logging.basicConfig(stream=self._fh, level=logging.INFO, force=True)
        return self._fh

    def __exit__(self, exc_type, exc, tb):
        import sys
        import traceback

        full = isinstance(exc, OSError) and exc.errno in (errno.ENOSPC, errno.EDQUOT)
        try:
            if full:
                print(f"error: {exc}", file=self._fh)  # a full disk: one line, no traceback
            elif exc_type is not None:
                traceback.print_exception(exc_type, exc, tb, file=self._fh)
            self._fh.close()
        except OSError:   # the log is on the full disk too
            pass
        sys.stderr = self._old
        if full:
            raise SystemExit(f"bearing_envelope: disk full: {exc}") from None
        if exc is not None and _is_damaged_artefact(exc):  # traceback in the log, one line
            raise SystemExit(f"bearing_envelope: damaged input: {exc}") from None
        return False


def _is_damaged_artefact(exc) -> bool:
    """An input the job refuses as damaged (an edited per-case table, a broken case file)."""
    from ..io.artefacts import ArtefactFormatError
    from ..io.case import CaseFormatError

    return isinstance(exc, (ArtefactFormatError, CaseFormatError))
