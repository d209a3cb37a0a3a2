"""The main process's validated settings, handed to the jobs it starts (validated once per run).

On a cluster every job starts a fresh Snakemake that parses the workflow again; without a
hand-off each job would run the loader and the pre-run check again (one per job and per job
step). Instead the workflow's main process, after its loader and pre-run check, writes the
settings once (:func:`hand_off`) and passes their address in the environment variable
:data:`ENV_VAR` (exported to the job by the executor); a job takes them back
(:func:`take_over`) without reading, validating or checking the config again.

The address names the file, the SHA-256 of its bytes and a digest of the run's config inputs
(:func:`inputs_digest`: the bytes of every config file and the ``--config`` values). A job takes
the settings only when both match: the file is the one its main process wrote (it is a pickle,
unpickled only when its digest is the one the main process put in the job's environment) and the
config the job was given is the one the main process validated. Anything else is one line
(:class:`HandOffError`).

The folder is the caller's (the workflow passes ``.snakemake/bearing_envelope``); this module
names none.
"""

from __future__ import annotations

import hashlib
import json
import os
import pickle
from collections.abc import Mapping, Sequence
from pathlib import Path

__all__ = ["ENV_VAR", "HandOffError", "inputs_digest", "hand_off", "take_over"]

#: Environment variable carrying the address of the handed-off settings to a job.
ENV_VAR = "BEARING_ENVELOPE_SETTINGS"


class HandOffError(ValueError):
    """A job cannot take the main process's settings (one line saying why)."""


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def inputs_digest(files: Sequence[str | os.PathLike],
                  overrides: Mapping | None = None) -> str:
    """SHA-256 over the bytes of each config file (in merge order) and the ``--config`` values.

    Parameters
    ----------
    files : sequence of path
        The config files of the run, in merge order
        (:func:`bearing_envelope.study.settings.config_files`).
    overrides : mapping, optional
        Snakemake's ``--config`` values.

    Returns
    -------
    str
        Hex digest; equal for two runs given the same files' contents and values.
    """
    h = hashlib.sha256()
    for f in files:
        data = Path(f).read_bytes()
        h.update(f"{len(data)}\n".encode())
        h.update(data)
    h.update(json.dumps(dict(overrides or {}), sort_keys=True, default=repr).encode())
    return h.hexdigest()


def hand_off(settings, directory: str | os.PathLike, files: Sequence[str | os.PathLike],
             overrides: Mapping | None = None) -> str:
    """Write ``settings`` for the jobs of this run and return the address to export.

    Parameters
    ----------
    settings : bearing_envelope.study.settings.Settings
        The loader's validated settings (after the pre-run check).
    directory : str or os.PathLike
        Folder for the file (created; the caller's, e.g. ``.snakemake/bearing_envelope``).
    files, overrides
        The run's config inputs, as given to :func:`inputs_digest`.

    Returns
    -------
    str
        The value of :data:`ENV_VAR` for the jobs: JSON with ``path``, ``sha256`` (of the
        file's bytes) and ``inputs`` (:func:`inputs_digest`).
    """
    data = pickle.dumps(settings, protocol=pickle.HIGHEST_PROTOCOL)
    digest = _sha256(data)
    folder = Path(directory)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"settings-{digest[:32]}.pickle"
    if not (path.is_file() and _sha256(path.read_bytes()) == digest):
        tmp = folder / f".{path.name}.{os.getpid()}.tmp"
        tmp.write_bytes(data)
        os.replace(tmp, path)
    return json.dumps({"path": os.path.abspath(path), "sha256": digest,
                       "inputs": inputs_digest(files, overrides)}, sort_keys=True)


def take_over(address: str, files: Sequence[str | os.PathLike],
              overrides: Mapping | None = None):
    """The settings the main process handed off, for a job given ``files`` and ``overrides``.

    Parameters
    ----------
    address : str
        The value of :data:`ENV_VAR` (:func:`hand_off`).
    files, overrides
        The job's config inputs (as its main process passed them).

    Returns
    -------
    bearing_envelope.study.settings.Settings
        As the main process's loader built and checked them; nothing is validated again.

    Raises
    ------
    HandOffError
        One line: the address is not the hand-off's, the file is missing or its bytes are not
        the ones the main process wrote, or the job's config inputs differ from the run's.
    """
    try:
        spec = json.loads(address)
        path, digest, inputs = spec["path"], spec["sha256"], spec["inputs"]
    except (ValueError, TypeError, KeyError):
        raise HandOffError(f"{ENV_VAR}: {address[:80]!r} is not a settings hand-off; allowed: "
                           f"the value the workflow's main process exports") from None
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise HandOffError(f"{ENV_VAR}: {path}: {exc.strerror or exc}; the jobs need the "
                           f"folder of the main process (a shared filesystem)") from None
    if _sha256(data) != digest:
        raise HandOffError(f"{ENV_VAR}: {path}: its bytes are not the ones the main process "
                           f"wrote (SHA-256 differs); rerun the workflow")
    if inputs_digest(files, overrides) != inputs:
        raise HandOffError(f"{ENV_VAR}: the config files or --config values of this job differ "
                           f"from the ones its main process validated; rerun the workflow")
    return pickle.loads(data)  # noqa: S301 -- the bytes its main process wrote (digest checked)
