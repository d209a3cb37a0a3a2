"""Content-addressed store of the no-defect global contact solves (issue 25 part B).

Every depth case of one load solves the same no-defect contacts over the whole roller (the
table's load nodes, the roller-end maxima on a denser load grid, the interpolation checks'
random loads): 63 of a ``standard`` case's 238 solves, more than half its CPU. They depend on
the scene without its defect, the roller load, the global grid and the solver; this store keeps
each result under the sha256 of exactly that (:func:`global_key`): the gap field of the initial
global grid (bytes; it holds the whole geometry and the roller-end relief), the grid, the roller
load, the material's plane-strain modulus and hardness bound, the fidelity fields the global
solve reads, the grid-growth rule, and the solver's code version (:func:`solver_code_version`:
the sources of :mod:`bearing_envelope.contact` and of the zoom solves, numpy and scipy
versions). A case read from the store is bit-identical to one solved alone (the arrays are
stored as float64 ``.npz`` without pickle).

Entries are ``{directory}/{sha256}.npz``, written to a temporary file in the same folder and
renamed (atomic: a reader never sees half an entry; two jobs that solve the same entry at once
both write the same bytes). An entry that does not read (truncated, corrupt), whose stored key
differs from the one asked for, or whose payload checksum does not match, is reported in one
line on stderr and solved and stored again; a missing one is solved and stored (one line too).
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import tempfile
import zipfile
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
import scipy

__all__ = ["NoDefectCache", "GlobalSolution", "global_key", "solver_code_version",
           "CACHE_FORMAT"]

#: Layout version of an entry (bump when the stored fields change).
CACHE_FORMAT = 1

#: Modules whose source is part of the solver's code version.
_SOLVER_SOURCES = ("../contact/__init__.py", "../contact/solver.py", "../contact/halfspace.py",
                   "../contact/_kernels.py", "solves/__init__.py", "solves/stats.py",
                   "solves/global_solve.py", "solves/windows.py", "solves/load_node.py",
                   "solves/defect.py", "solves/rims.py", "geometry.py")


@dataclass(frozen=True)
class GlobalSolution:
    """What the zoom route reads of a global no-defect solve: pressure (Pa), approach (m),
    contact area (m^2), CG iterations and final residual."""

    pressure: np.ndarray
    approach: float
    contact_area: float
    iterations: int
    residual: float


@lru_cache(maxsize=1)
def solver_code_version() -> str:
    """sha256 of the solver's sources (:data:`_SOLVER_SOURCES`) and the numpy/scipy versions.

    Returns
    -------
    str
        The digest (hex).
    """
    h = hashlib.sha256()
    here = Path(__file__).resolve().parent
    for rel in _SOLVER_SOURCES:
        h.update(rel.encode())
        h.update((here / rel).resolve().read_bytes())
    h.update(f"numpy {np.__version__} scipy {scipy.__version__}".encode())
    return h.hexdigest()


def global_key(gap: np.ndarray, grid_x: np.ndarray, grid_y: np.ndarray, fields: dict[str, Any]
               ) -> tuple[str, str]:
    """``(sha256, key text)`` of a global solve: the gap's bytes (float64), the grid's
    coordinates, the scalar ``fields`` (JSON, sorted, floats as ``float.hex``) and
    :func:`solver_code_version`.

    Parameters
    ----------
    gap : numpy.ndarray
        The no-defect gap of the solve (m).
    grid_x, grid_y : numpy.ndarray
        The grid's coordinates (m).
    fields : dict
        The solve's scalar settings (load, tolerance, ...).

    Returns
    -------
    tuple of (str, str)
        The entry's sha256 and the key text it hashes.
    """
    def enc(v):
        if isinstance(v, float):
            return float(v).hex()
        return v

    meta = {k: enc(v) for k, v in sorted(fields.items())}
    meta["format"] = CACHE_FORMAT
    meta["code"] = solver_code_version()
    arrays = hashlib.sha256()
    for a in (gap, grid_x, grid_y):
        a = np.ascontiguousarray(a, dtype=np.float64)
        arrays.update(str(a.shape).encode())
        arrays.update(a.tobytes())
    meta["arrays_sha256"] = arrays.hexdigest()
    text = json.dumps(meta, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest(), text


def _payload_sha(grid_x, grid_y, sol: GlobalSolution) -> str:
    h = hashlib.sha256()
    for a in (grid_x, grid_y, sol.pressure):
        h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
    h.update(json.dumps([float(sol.approach).hex(), float(sol.contact_area).hex(),
                         int(sol.iterations), float(sol.residual).hex()]).encode())
    return h.hexdigest()


class NoDefectCache:
    """The store in ``directory`` (created on first write); counts ``hits`` and ``misses``.

    Parameters
    ----------
    directory : str or os.PathLike
        Folder of the entries, one ``{sha}.npz`` each; created on the first :meth:`save`.
    """

    def __init__(self, directory: str | os.PathLike):
        self.directory = Path(directory)
        self.hits = 0
        self.misses = 0

    def path(self, sha: str) -> Path:
        """The file of an entry.

        Parameters
        ----------
        sha : str
            The entry's key digest (:func:`global_key`).

        Returns
        -------
        pathlib.Path
            ``{directory}/{sha}.npz``.
        """
        return self.directory / f"{sha}.npz"

    def load(self, sha: str, key: str):
        """``(grid_x, grid_y, dx, dy, GlobalSolution)`` of an entry, or None when it is missing
        or invalid (one line on stderr says which and why).

        Parameters
        ----------
        sha : str
            The entry's key digest.
        key : str
            The key text, compared with the one stored.

        Returns
        -------
        tuple or None
            ``(grid_x, grid_y, dx, dy, GlobalSolution)``, or None.
        """
        p = self.path(sha)
        if not p.exists():
            self._note(sha, "missing")
            return None
        try:
            with np.load(p, allow_pickle=False) as z:
                stored_key = str(z["key"][()])
                gx, gy = z["grid_x"].copy(), z["grid_y"].copy()
                sol = GlobalSolution(z["pressure"].copy(), float(z["approach"][()]),
                                     float(z["contact_area"][()]), int(z["iterations"][()]),
                                     float(z["residual"][()]))
                dx, dy = float(z["dx"][()]), float(z["dy"][()])
                payload = str(z["payload_sha256"][()])
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as exc:
            self._note(sha, f"unreadable ({type(exc).__name__}: {exc})")
            return None
        if stored_key != key:
            self._note(sha, "key mismatch (stored for other inputs)")
            return None
        if payload != _payload_sha(gx, gy, sol):
            self._note(sha, "payload checksum mismatch")
            return None
        self.hits += 1
        return gx, gy, dx, dy, sol

    def store(self, sha: str, key: str, grid_x, grid_y, dx: float, dy: float,
              sol: GlobalSolution) -> None:
        """Write an entry atomically (temporary file in the same folder, then renamed).

        Parameters
        ----------
        sha : str
            The entry's key digest.
        key : str
            The key text (stored with the entry).
        grid_x, grid_y : numpy.ndarray
            The grid's coordinates (m).
        dx, dy : float
            Cell sizes (m).
        sol : GlobalSolution
            The solve to store.
        """
        self.directory.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".tmp-{sha[:12]}-", suffix=".npz", dir=self.directory)
        try:
            with os.fdopen(fd, "wb") as fh:
                np.savez(fh, key=np.array(key), grid_x=np.asarray(grid_x, np.float64),
                         grid_y=np.asarray(grid_y, np.float64), dx=np.float64(dx),
                         dy=np.float64(dy), pressure=np.asarray(sol.pressure, np.float64),
                         approach=np.float64(sol.approach),
                         contact_area=np.float64(sol.contact_area),
                         iterations=np.int64(sol.iterations), residual=np.float64(sol.residual),
                         payload_sha256=np.array(_payload_sha(grid_x, grid_y, sol)))
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(tmp, self.path(sha))
        except BaseException:
            if os.path.exists(tmp):
                os.unlink(tmp)
            raise

    def _note(self, sha: str, why: str) -> None:
        self.misses += 1
        print(f"bearing_envelope: no-defect cache entry {sha[:16]} {why}: solving and storing it",
              file=sys.stderr)
