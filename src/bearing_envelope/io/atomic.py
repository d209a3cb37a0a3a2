"""Atomic writes: a reader never sees a half-written file or folder.

Files are written to a temporary name in the target directory and renamed (:func:`os.replace`);
folders are built in a writer-owned temporary folder and swapped in whole. Temporary files of
writers that died are found (:func:`clean_stale_temps`) by the host and pid in their name.
"""

from __future__ import annotations

import datetime as _dt
import os
import shutil as _shutil
import socket
import tempfile
from contextlib import contextmanager as _contextmanager
from pathlib import Path as _Path

__all__ = ["temp_path_for", "clean_stale_temps", "public_mode", "atomic_path", "atomic_dir",
           "write_csv_atomic"]


_TMP_PREFIX = ".tmp-"


def _host() -> str:
    return socket.gethostname().replace(".", "_").replace("~", "_") or "host"


def temp_path_for(path: str | os.PathLike) -> str:
    """A new, empty temporary file next to ``path`` (mode as a plain ``open`` would give).

    Named ``.tmp-{host}~{pid}~{target name}~{random}.h5`` so that :func:`clean_stale_temps` can tell
    a temporary file of a dead writer (or an earlier attempt at the same target) from one another
    job is writing right now.

    Parameters
    ----------
    path : str or os.PathLike
        The file the temporary one will become.

    Returns
    -------
    str
        The temporary file's path (created, empty).
    """
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=f"{_TMP_PREFIX}{_host()}~{os.getpid()}~{os.path.basename(path)}~",
                               suffix=".h5", dir=directory)
    os.close(fd)
    return tmp


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def clean_stale_temps(directory: str | os.PathLike, target: str | os.PathLike | None = None) -> list[str]:
    """Remove temporary case files left by killed writers; returns the paths removed.

    A ``.tmp-*.h5`` file in ``directory`` is stale when it belongs to ``target`` (only one job
    writes a given file at a time, and it has not created its own yet), or when it was made on this
    host by a process that no longer runs. Files of other live writers (another job of the same
    sweep, another host of a cluster) are left alone. Called at the start of every
    :func:`write_case`, so a SIGKILL during a write leaves nothing behind after the next write.

    Parameters
    ----------
    directory : str or os.PathLike
        The folder to clean.
    target : str or os.PathLike, optional
        The file about to be written: its own earlier temporary files are stale too.

    Returns
    -------
    list of str
        The paths removed.
    """
    directory = os.fspath(directory)
    name = None if target is None else os.path.basename(os.fspath(target))
    host = _host()
    removed = []
    try:
        entries = os.listdir(directory)
    except OSError:
        return removed
    for entry in entries:
        if not (entry.startswith(_TMP_PREFIX) and entry.endswith(".h5")):
            continue
        parts = entry[len(_TMP_PREFIX):].split("~")
        stale = False
        if len(parts) == 4:
            e_host, e_pid, e_name, _ = parts
            if name is not None and e_name == name:
                stale = True
            elif e_host == host and e_pid.isdigit() and int(e_pid) != os.getpid():
                stale = not _pid_alive(int(e_pid))
        elif name is not None:
            # the former naming (.tmp-{random}.h5) says nothing about its writer: remove it once it
            # has not been touched for an hour (no write of a case takes that long)
            try:
                stale = _dt.datetime.now().timestamp() - os.path.getmtime(
                    os.path.join(directory, entry)) > 3600
            except OSError:
                stale = False
        if stale:
            try:
                os.unlink(os.path.join(directory, entry))
                removed.append(os.path.join(directory, entry))
            except OSError:
                pass
    return removed


def public_mode(path) -> None:
    """Give a file made by ``mkstemp`` (mode 0600) the mode a plain ``open`` would give.

    Parameters
    ----------
    path : str or os.PathLike
        The file whose mode is set (0666 minus the umask).
    """
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(path, 0o666 & ~umask)


@_contextmanager
def atomic_path(path: str | os.PathLike, suffix: str = ""):
    """Yield a temporary file name next to ``path``; on success rename it to ``path``.

    The temporary file (``.tmp-<name>.*<suffix>`` in the target directory, created if needed)
    is removed if the body raises, so a reader never sees a half-written file.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write.
    suffix : str
        Suffix of the temporary file (some writers choose the format by it).

    Yields
    ------
    str
        The temporary file's path, to write to.
    """
    path = _Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".tmp-{path.name}.", suffix=suffix, dir=path.parent)
    os.close(fd)
    try:
        yield tmp
        public_mode(tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


@_contextmanager
def atomic_dir(path: str | os.PathLike):
    """Yield a new, empty folder next to ``path`` (``.tmp-<name>.*``, this writer's own); on
    success put it in place of ``path`` whole: an existing ``path`` is moved aside first and
    removed after, so ``path`` is always either the old or the new complete set, and two
    writers of the same folder never share a temporary one. Removed if the body raises.

    Parameters
    ----------
    path : str or os.PathLike
        The folder to (re)place.

    Yields
    ------
    str
        The temporary folder's path, to fill.
    """
    path = _Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = _Path(tempfile.mkdtemp(prefix=f".tmp-{path.name}.", dir=path.parent))
    aside = None
    try:
        yield tmp
        os.chmod(tmp, 0o777 & ~_umask())
        aside = _Path(tempfile.mkdtemp(prefix=f".tmp-{path.name}.old.", dir=path.parent))
        if path.exists():
            os.replace(path, aside / path.name)
        os.replace(tmp, path)
    finally:
        _shutil.rmtree(tmp, ignore_errors=True)
        if aside is not None:
            _shutil.rmtree(aside, ignore_errors=True)


def _umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


def write_csv_atomic(df, path: str | os.PathLike, **kwargs) -> str:
    """Write a DataFrame as CSV (no index unless ``index=True``) atomically; returns the path.

    Parameters
    ----------
    df : pandas.DataFrame
        The table.
    path : str or os.PathLike
        The CSV file to write.
    **kwargs
        Passed to :meth:`pandas.DataFrame.to_csv`.

    Returns
    -------
    str
        ``path``.
    """
    index = kwargs.pop("index", False)
    with atomic_path(path, ".csv") as tmp:
        df.to_csv(tmp, index=index, **kwargs)
    return os.fspath(path)
