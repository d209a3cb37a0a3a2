"""HDF5 case format: one file per load x depth case (layout in ``docs/file-format.md``).

:func:`write_case` stores a :class:`bearing_envelope.history.History` atomically (temporary file
in the same directory, then :func:`os.replace`); :func:`read_case` returns a typed :class:`Case`.
A file of another format version, or one missing a required dataset, raises :class:`CaseFormatError`
(a ``ValueError``) naming the problem.
"""

from __future__ import annotations

import datetime as _dt
import json
import os
import socket
import subprocess
import tempfile
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["FORMAT_VERSION", "Case", "CaseFormatError", "write_case", "read_case", "git_commit",
           "case_file_problem", "set_aside_unreadable", "clean_stale_temps", "temp_path_for"]

#: Version of the layout written by :func:`write_case`; :func:`read_case` accepts only this one.
FORMAT_VERSION = 1

_REQUIRED = ("time", "signals/p_max", "signals/p_max_defect", "signals/roller_load",
             "signals/defect_offset")
_COMPRESSION = dict(compression="gzip", compression_opts=4, shuffle=True)


class CaseFormatError(ValueError):
    """The file is not a case file of the supported format version."""


@dataclass
class Case:
    """A case file's content (SI units).

    Attributes
    ----------
    fs, fr : float
        Sampling rate and shaft rate (Hz).
    bpfi : float
        BPFI used by the history (the override if any), Hz.
    bpfi_geometry, bpfo, ftf, bsf : float
        Geometric fault frequencies (Hz).
    time : ndarray
        Sample times (s).
    p_max, p_max_defect : ndarray
        Maximum pressure over the whole contact / in the defect neighbourhood (Pa); with noise on,
        the noisy signals (the clean ones are in ``signals``).
    roller_load : ndarray
        Load of the roller at the defect (N).
    defect_offset : ndarray
        Arc-length offset of the defect from that roller's contact centre (m).
    load_kN, depth_um : float
        The case's sweep values.
    scene : dict
        Scene mapping (:meth:`bearing_envelope.scene.Scene.to_mapping`).
    attrs : dict
        All root attributes (versions, commit, fidelity, solver settings, diagnostics).
    signals : dict
        Name -> 1-D array: ``p_max``, ``p_max_defect``, ``roller_load``, ``defect_offset`` and,
        with noise, ``p_max_clean``, ``p_max_defect_clean``.
    snapshots : dict
        ``load_<i>`` -> dict of pressure fields and coordinates.
    table : dict
        The ``P(Q, x)`` table and its diagnostics.
    """

    fs: float
    fr: float
    bpfi: float
    bpfi_geometry: float
    bpfo: float
    ftf: float
    bsf: float
    time: np.ndarray
    p_max: np.ndarray
    p_max_defect: np.ndarray
    roller_load: np.ndarray
    defect_offset: np.ndarray
    load_kN: float
    depth_um: float
    scene: dict
    attrs: dict
    signals: dict = field(default_factory=dict)
    snapshots: dict = field(default_factory=dict)
    table: dict = field(default_factory=dict)


def git_commit(path: str | None = None) -> str:
    """Commit hash of the repository holding ``path`` (this package by default), ``+dirty`` if
    the tree has changes; ``"unknown"`` without git."""
    cwd = path or os.path.dirname(os.path.abspath(__file__))
    try:
        out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=cwd, capture_output=True, text=True,
                             timeout=10)
        if out.returncode != 0:
            return "unknown"
        commit = out.stdout.strip()
        st = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=cwd,
                            capture_output=True, text=True, timeout=10)
        return commit + ("+dirty" if st.returncode == 0 and st.stdout.strip() else "")
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (np.floating, np.integer, np.bool_)):
        return obj.item()
    return obj


def _dset(group, name, data, units: str, description: str = "", chunk: bool = True):
    data = np.asarray(data)
    kw = dict(_COMPRESSION) if (chunk and data.size > 16) else {}
    if kw and data.ndim == 1:
        kw["chunks"] = (min(data.size, 65536),)
    ds = group.create_dataset(name, data=data, **kw)
    ds.attrs["units"] = units
    if description:
        ds.attrs["description"] = description
    return ds


def write_case(path: str | os.PathLike, history, *, extra_attrs: dict | None = None) -> str:
    """Write a simulated case atomically to ``path`` (HDF5; layout ``docs/file-format.md``).

    Parameters
    ----------
    path : path-like
        Output file; its directory is created if needed.
    history : bearing_envelope.history.History
    extra_attrs : dict, optional
        More root attributes (e.g. the config file name).

    Returns
    -------
    str
        The path written.
    """
    import h5py

    from . import __version__

    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    sc = history.scene
    ff = sc.frequencies()
    clean_stale_temps(directory, path)
    tmp = temp_path_for(path)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    try:
        with h5py.File(tmp, "w") as f:
            a = f.attrs
            a["format"] = "bearing_envelope.case"
            a["format_version"] = FORMAT_VERSION
            a["package_version"] = __version__
            a["git_commit"] = git_commit()
            a["created_utc"] = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
            a["load_kN"] = sc.load.load_kN
            a["depth_um"] = sc.defect.depth_um
            a["load_mode"] = sc.load.mode
            a["fs"] = sc.operation.fs_hz
            a["fr"] = sc.operation.shaft_rate_hz
            a["bpfi"] = sc.bpfi_hz
            a["bpfi_geometry"] = ff.bpfi
            a["bpfo"] = ff.bpfo
            a["ftf"] = ff.ftf
            a["bsf"] = ff.bsf
            a["cage_rate_used"] = sc.cage_rate_hz
            a["scene_json"] = json.dumps(_jsonable(sc.to_mapping()), sort_keys=True)
            a["fidelity_json"] = json.dumps(_jsonable(history.fidelity.to_dict()), sort_keys=True)
            a["solver_json"] = json.dumps({
                "solver": "bearing_envelope.contact.solve_contact (Polonsky-Keer CG, DC-FFT)",
                "tol": history.fidelity.tol, "max_iter": history.fidelity.max_iter,
                "route": "zoom: global no-defect solve per roller load + local window under "
                         "displacement control with far-field displacement and approach",
            }, sort_keys=True)
            a["stats_json"] = json.dumps(_jsonable(history.stats), sort_keys=True)
            ld = history.load_distribution
            a["load_distribution_json"] = json.dumps({
                "force_row_N": ld.force_row, "q_max_N": ld.q_max, "delta_r_m": ld.delta_r,
                "epsilon": ld.epsilon, "half_angle_rad": ld.half_angle,
                "clearance_m": ld.clearance, "stiffness_N_per_m_n": ld.stiffness,
                "exponent": ld.exponent}, sort_keys=True)
            for k, v in (extra_attrs or {}).items():
                a[k] = v
            _dset(f, "time", history.time, "s", "sample times")
            sg = f.create_group("signals")
            units = {"p_max": "Pa", "p_max_defect": "Pa", "p_max_clean": "Pa",
                     "p_max_defect_clean": "Pa"}
            for name, arr in history.signals.items():
                _dset(sg, name, arr, units.get(name, ""), "")
            sg["p_max"].attrs["description"] = "maximum contact pressure over the whole contact"
            sg["p_max_defect"].attrs["description"] = "maximum pressure in the defect neighbourhood"
            _dset(sg, "roller_load", history.roller_load, "N", "load of the roller at the defect")
            _dset(sg, "defect_offset", history.defect_offset, "m",
                  "arc-length offset of the defect from the nearest roller's contact centre")
            tg = f.create_group("table")
            tb = history.table
            _dset(tg, "roller_load", tb.q_nodes, "N", "roller-load nodes")
            _dset(tg, "xi", tb.xi_nodes, "1", "normalised offset nodes |x|/s(Q)")
            _dset(tg, "offset", tb.offsets(), "m", "offset nodes x = xi s(Q), (load, xi)")
            _dset(tg, "p0", tb.p0, "Pa", "no-defect maximum pressure P0(Q)")
            _dset(tg, "w0", tb.w0, "Pa", "no-defect maximum in the window's read strip W0(Q)")
            _dset(tg, "q_out", tb.q_out, "N", "dense roller loads of p_out")
            _dset(tg, "p_out", tb.p_out, "Pa", "no-defect maximum outside the read strip (ends)")
            _dset(tg, "p_max", np.maximum(tb.w0[:, None] * tb.ratio, tb.p_out[::3][:, None]), "Pa",
                  "P(Q, x), whole contact")
            _dset(tg, "p_max_defect", tb.w0[:, None] * tb.ratio_defect, "Pa",
                  "P_d(Q, x), defect neighbourhood")
            tg.attrs["a_coef"] = tb.a_coef
            tg.attrs["kappa"] = tb.kappa
            tg.attrs["s_const"] = tb.s_const
            tg.attrs["s_max"] = tb.s_max
            for k, v in tb.info.items():
                if isinstance(v, np.ndarray):
                    _dset(tg, k, v, "", "")
                else:
                    tg.attrs[k] = v
            if "interp_checks" in tg:
                tg["interp_checks"].attrs["columns"] = "Q_N, x_m, P_direct, Pd_direct, P_interp, Pd_interp, P0"
            sn = f.create_group("snapshots")
            for key, snap in history.snapshots.items():
                g = sn.create_group(key)
                for k, v in snap.items():
                    if np.ndim(v) == 0:
                        g.attrs[k] = v
                    else:
                        unit = "Pa" if "pressure" in k else "m"
                        _dset(g, k, v, unit)
                g.attrs["roller_load_units"] = "N"
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    return path


_TMP_PREFIX = ".tmp-"


def _host() -> str:
    return socket.gethostname().replace(".", "_").replace("~", "_") or "host"


def temp_path_for(path: str | os.PathLike) -> str:
    """A new, empty temporary file next to ``path`` (mode as a plain ``open`` would give).

    Named ``.tmp-{host}~{pid}~{target name}~{random}.h5`` so that :func:`clean_stale_temps` can tell
    a temporary file of a dead writer (or an earlier attempt at the same target) from one another
    job is writing right now.
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


def case_file_problem(path: str | os.PathLike) -> str | None:
    """Why an existing case file cannot be used (``None`` when it reads).

    Opens the file, checks the format attributes and the required datasets, and reads the last
    element of each (a truncated file fails there). Cheap: no full read.
    """
    import h5py

    path = os.fspath(path)
    try:
        with h5py.File(path, "r") as f:
            fmt = _attr(f.attrs.get("format"))
            if fmt != "bearing_envelope.case":
                return f"not a bearing_envelope case file (format attribute {fmt!r})"
            ver = _attr(f.attrs.get("format_version"))
            if ver != FORMAT_VERSION:
                return f"format_version {ver!r} is not supported (this reader: {FORMAT_VERSION})"
            for name in _REQUIRED:
                if name not in f:
                    return f"required dataset '/{name}' is missing"
                d = f[name]
                if d.shape and d.shape[0]:
                    d[-1]
    except (OSError, KeyError, ValueError, RuntimeError) as exc:
        return f"unreadable HDF5 ({' '.join(str(exc).split())[:160]})"
    return None


def set_aside_unreadable(path: str | os.PathLike, *, warn=None) -> str | None:
    """Move an unreadable case file aside so that the workflow rebuilds it.

    If ``path`` exists and :func:`case_file_problem` finds a problem, the file is renamed to
    ``{path}.unreadable-{UTC time}`` (kept for inspection, never deleted) and a one-line warning
    naming both paths and the problem goes to ``warn`` (default: stderr). Returns the new path, or
    ``None`` when the file is missing or fine.
    """
    import sys

    path = os.fspath(path)
    if not os.path.isfile(path):
        return None
    problem = case_file_problem(path)
    if problem is None:
        return None
    stamp = _dt.datetime.now(_dt.timezone.utc).strftime("%Y%m%dT%H%M%SZ")
    aside = f"{path}.unreadable-{stamp}"
    os.replace(path, aside)
    msg = (f"warning: {path}: {problem}; moved aside to {aside}; it will be rebuilt as a "
           f"missing file")
    (warn or (lambda m: print(m, file=sys.stderr)))(msg)
    return aside


def _read_group(g) -> dict:
    import h5py

    out: dict[str, Any] = {k: _attr(v) for k, v in g.attrs.items()}
    for k, v in g.items():
        out[k] = _read_group(v) if isinstance(v, h5py.Group) else v[()]
    return out


def _attr(v):
    if isinstance(v, bytes):
        return v.decode()
    if isinstance(v, np.generic):
        return v.item()
    return v


def read_case(path: str | os.PathLike) -> Case:
    """Read a case file written by :func:`write_case`.

    Raises
    ------
    FileNotFoundError
        No such file.
    CaseFormatError
        Not a case file, another format version, a required dataset is missing, or the file is
        unreadable (truncated, corrupt); the message says how to rebuild it.
    """
    path = os.fspath(path)
    rebuild = (f"; rebuild it with `snakemake -j1 -f {path}` (or delete it: the next run of the "
               f"workflow moves an unreadable case file aside and rebuilds it)")
    try:
        return _read_case(path)
    except CaseFormatError as exc:
        raise CaseFormatError(f"{exc}{rebuild}") from exc
    except (OSError, RuntimeError, KeyError) as exc:
        if isinstance(exc, FileNotFoundError):
            raise
        raise CaseFormatError(f"{path}: unreadable ({' '.join(str(exc).split())[:160]}){rebuild}") \
            from exc


def _read_case(path: str | os.PathLike) -> Case:
    """Read a case file written by :func:`write_case` (errors not yet given the rebuild hint).

    Raises
    ------
    FileNotFoundError
        No such file.
    CaseFormatError
        Not a case file, another format version, or a required dataset is missing.
    """
    import h5py

    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(f"case file not found: {path}")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise CaseFormatError(f"{path}: not an HDF5 file ({exc})") from exc
    with f:
        attrs = {k: _attr(v) for k, v in f.attrs.items()}
        if attrs.get("format") != "bearing_envelope.case":
            raise CaseFormatError(f"{path}: not a bearing_envelope case file (format attribute "
                                  f"{attrs.get('format')!r})")
        ver = attrs.get("format_version")
        if ver != FORMAT_VERSION:
            raise CaseFormatError(f"{path}: format_version {ver!r} is not supported (this reader: "
                                  f"{FORMAT_VERSION})")
        for name in _REQUIRED:
            if name not in f:
                raise CaseFormatError(f"{path}: required dataset '/{name}' is missing")
        signals = {k: v[()] for k, v in f["signals"].items()}
        table = _read_group(f["table"]) if "table" in f else {}
        snaps = _read_group(f["snapshots"]) if "snapshots" in f else {}
        time = f["time"][()]
    for k in ("scene_json", "fidelity_json", "solver_json", "stats_json", "load_distribution_json"):
        if k in attrs:
            attrs[k[:-5]] = json.loads(attrs[k])
    return Case(
        fs=float(attrs["fs"]), fr=float(attrs["fr"]), bpfi=float(attrs["bpfi"]),
        bpfi_geometry=float(attrs["bpfi_geometry"]), bpfo=float(attrs["bpfo"]),
        ftf=float(attrs["ftf"]), bsf=float(attrs["bsf"]), time=time,
        p_max=signals["p_max"], p_max_defect=signals["p_max_defect"],
        roller_load=signals["roller_load"], defect_offset=signals["defect_offset"],
        load_kN=float(attrs["load_kN"]), depth_um=float(attrs["depth_um"]),
        scene=attrs.get("scene", {}), attrs=attrs, signals=signals, snapshots=snaps, table=table,
    )
