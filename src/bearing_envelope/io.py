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
           "case_file_problem", "set_aside_unreadable", "clean_stale_temps", "temp_path_for",
           "read_error_model"]

#: Version of the layout written by :func:`write_case`; :func:`read_case` accepts only this one.
#: 2: integral signals (removed_force, contact_force, approach, approach_change, contact_area),
#: their tables, and the acquisition (root attribute ``acquisition_json``).
FORMAT_VERSION = 2

_REQUIRED = ("time", "signals/p_max", "signals/p_max_defect", "signals/roller_load",
             "signals/defect_offset")
_COMPRESSION = dict(compression="gzip", compression_opts=4, shuffle=True)


_SIGNAL_DESCRIPTIONS = {
    "p_max": "maximum contact pressure over the whole contact",
    "p_max_defect": "maximum pressure in the defect neighbourhood",
    "removed_force": "force the defect removes from the contact at the no-defect approach",
    "contact_force": "roller load minus removed force: the force through the contact at fixed "
                     "approach (blocked force)",
    "approach": "approach delta(t) at the roller load (no-defect curve at Q + removed force)",
    "approach_change": "approach minus the no-defect approach at the same roller load (>= 0)",
    "contact_area": "contact area at the roller load",
}


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
        Name -> 1-D array: ``p_max``, ``p_max_defect``, ``roller_load``, ``defect_offset``, the
        integral signals ``removed_force`` (N), ``contact_force`` (N), ``approach`` (m),
        ``approach_change`` (m), ``contact_area`` (m^2) and, with noise, ``p_max_clean``,
        ``p_max_defect_clean``.
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
    from .history import SIGNAL_UNITS

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
                "hardness_Pa": sc.material.hardness_pa,
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
            a["acquisition_json"] = json.dumps(_jsonable(getattr(history, "acquisition", {})),
                                               sort_keys=True)
            _dset(f, "time", history.time, "s", "sample times")
            sg = f.create_group("signals")
            for name, arr in history.signals.items():
                base = name[:-6] if name.endswith("_clean") else name
                _dset(sg, name, arr, SIGNAL_UNITS.get(base, ""), _SIGNAL_DESCRIPTIONS.get(base, ""))
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
            _dset(tg, "p_max", tb.p_max_nodes(), "Pa", "P(Q, x), whole contact")
            _dset(tg, "p_max_defect", tb.w0[:, None] * tb.ratio_defect, "Pa",
                  "P_d(Q, x), defect neighbourhood")
            tg.attrs["out_density"] = tb.out_density
            _dset(tg, "removed_force", tb.q_nodes[:, None] * tb.ratio_force, "N",
                  "force the defect removes at the no-defect approach, dF(Q, x)")
            _dset(tg, "area_change", tb.area0[:, None] * tb.ratio_area, "m^2",
                  "contact-area change with the defect at the no-defect approach, dA(Q, x)")
            _dset(tg, "approach0", tb.approach0, "m", "no-defect approach delta0(Q) (global solves)")
            _dset(tg, "area0", tb.area0, "m^2", "no-defect contact area A0(Q) (global solves)")
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
            _write_error_model(f, history)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    return path


def _write_error_model(f, history) -> None:
    """Group ``discretisation_error``: the estimated relative error of each amplitude at the
    case's fidelity (:func:`bearing_envelope.accuracy.error_model`)."""
    import h5py

    from .accuracy import error_model

    em = error_model(history.fidelity, history.scene.defect.depth_um, history.scene.to_mapping())
    g = f.create_group("discretisation_error")
    g.attrs["point"] = em.point or ""
    g.attrs["kind"] = em.kind
    g.attrs["basis"] = em.basis
    for col in em.table.columns:
        v = em.table[col].to_numpy()
        if v.dtype == object or v.dtype.kind in "OUT":
            g.create_dataset(col, data=np.asarray(v, dtype=object), dtype=h5py.string_dtype())
        else:
            g.create_dataset(col, data=v)


def read_error_model(path: str | os.PathLike) -> tuple[dict[str, str], "pd.DataFrame"]:
    """The ``discretisation_error`` group of a case file: its attributes (``point``, ``kind``,
    ``basis``) and the table (empty when the fidelity has no estimate)."""
    import h5py
    import pandas as pd

    with h5py.File(path, "r") as f:
        if "discretisation_error" not in f:
            return {"point": "", "kind": "", "basis": "not estimated: the case file predates "
                    "error estimates"}, pd.DataFrame()
        g = f["discretisation_error"]
        attrs = {k: _attr(v) for k, v in g.attrs.items()}
        cols = {k: [_attr(x) for x in g[k][()]] if g[k].dtype.kind == "O" else g[k][()]
                for k in g}
    return attrs, pd.DataFrame(cols)


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
    for k in ("scene_json", "fidelity_json", "solver_json", "stats_json", "load_distribution_json",
              "acquisition_json"):
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


# ============================================================================================
# Sweep artefacts other than the case file: bands + kurtogram, spectra, sensor case, tables.
# Every artefact has a write_*/read_* pair, a format version (ARTEFACT_FORMATS) and is written
# through a temporary file in the target directory, then renamed (os.replace). Layouts:
# docs/file-format.md. Nothing here knows where the workflow puts the files.
# ============================================================================================

import shutil as _shutil  # noqa: E402
from contextlib import contextmanager as _contextmanager  # noqa: E402
from pathlib import Path as _Path  # noqa: E402

from .vocabulary import BAND_TABLE_COLUMNS, CASE_TABLE_COLUMNS, TIDY_COLUMNS  # noqa: E402

__all__ += [
    "ARTEFACT_FORMATS", "ArtefactFormatError", "atomic_path", "atomic_dir", "write_csv_atomic",
    "BandLimits", "CaseBands", "write_bands", "read_bands",
    "KurtogramMap", "write_kurtogram", "read_kurtogram",
    "CaseSpectra", "write_spectra", "read_spectra",
    "SensorSignal", "SENSOR_SUFFIXES", "check_sensor_output", "write_sensor_case", "read_sensor",
    "write_tidy", "read_tidy", "write_case_table", "read_case_table",
    "write_band_table", "read_band_table", "write_pivots", "read_pivots",
]

#: Format version of each artefact layout; a reader accepts only its own version.
ARTEFACT_FORMATS = {
    "bands": 1,       # JSON: band limits of one case (+ best kurtogram cell)
    "kurtogram": 1,   # NPZ: kurtogram matrix of one case
    "spectra": 1,     # NPZ: raw and envelope spectra of one case
    "sensor": 1,      # HDF5 case file + signals/acceleration, or NPZ
    "tables": 1,      # CSV: tidy harmonics, cases, bands, pivots (version = the column set)
}


class ArtefactFormatError(ValueError):
    """A file is not the artefact its reader expects (format name, version or content)."""


def _public_mode(path) -> None:
    """Give a file made by ``mkstemp`` (mode 0600) the mode a plain ``open`` would give."""
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(path, 0o666 & ~umask)


@_contextmanager
def atomic_path(path: str | os.PathLike, suffix: str = ""):
    """Yield a temporary file name next to ``path``; on success rename it to ``path``.

    The temporary file (``.tmp-<name>.*<suffix>`` in the target directory, created if needed)
    is removed if the body raises, so a reader never sees a half-written file.
    """
    path = _Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".tmp-{path.name}.", suffix=suffix, dir=path.parent)
    os.close(fd)
    try:
        yield tmp
        _public_mode(tmp)
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
    writers of the same folder never share a temporary one. Removed if the body raises."""
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
    """Write a DataFrame as CSV (no index unless ``index=True``) atomically; returns the path."""
    index = kwargs.pop("index", False)
    with atomic_path(path, ".csv") as tmp:
        df.to_csv(tmp, index=index, **kwargs)
    return os.fspath(path)


def _check_format(path, doc_format, doc_version, artefact: str) -> None:
    want = f"bearing_envelope.{artefact}"
    if doc_format != want:
        raise ArtefactFormatError(f"{path}: not a {artefact} file (format {doc_format!r}, "
                                  f"expected {want!r})")
    if doc_version != ARTEFACT_FORMATS[artefact]:
        raise ArtefactFormatError(f"{path}: {artefact} format_version {doc_version!r} is not "
                                  f"supported (this reader: {ARTEFACT_FORMATS[artefact]})")


def _exists(path) -> str:
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(f"file not found: {path}")
    return path


# ------------------------------------------------------------------------------- bands (JSON)
@dataclass(frozen=True)
class BandLimits:
    """One demodulation band of one case.

    Attributes
    ----------
    name : str
        The band's name (``analysis.bands[].name``).
    strategy : str
        How it was chosen: ``kurtogram``, ``fraction``, ``orders`` or ``fixed``.
    low_hz, high_hz : float
        Band edges (Hz) after clamping.
    clamped : bool
        The upper edge was clamped below Nyquist.
    provenance : dict
        What :func:`bearing_envelope.signal.resolve_band` reported (JSON-able).
    """

    name: str
    strategy: str
    low_hz: float
    high_hz: float
    clamped: bool = False
    provenance: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {"name": self.name, "strategy": self.strategy, "low_hz": float(self.low_hz),
                "high_hz": float(self.high_hz), "clamped": bool(self.clamped),
                "provenance": _jsonable(self.provenance)}


@dataclass(frozen=True)
class CaseBands:
    """Band limits of one case (the ``bands`` artefact; :func:`bearing_envelope.pipeline.case_bands`).

    Attributes
    ----------
    case : str
        Case name.
    load_kN, depth_um : float
        The case's sweep values.
    fs : float
        Sampling rate (Hz).
    signal : str
        The analysed signal (``p_max``, ``p_max_defect``, ``acceleration``).
    bands : tuple of BandLimits
        In the order of ``analysis.bands``.
    kurtogram : dict or None
        Best kurtogram cell (``level``, ``fc``, ``bandwidth``, ``kurtosis``; Hz), None when no
        band uses the kurtogram.
    """

    case: str
    load_kN: float
    depth_um: float
    fs: float
    signal: str
    bands: tuple
    kurtogram: dict | None = None

    def band(self, name: str) -> BandLimits:
        """The band called ``name`` (KeyError naming the bands held otherwise)."""
        for b in self.bands:
            if b.name == name:
                return b
        raise KeyError(f"{self.case}: no band {name!r}; bands: {[b.name for b in self.bands]}")

    def to_dict(self) -> dict:
        return {"format": "bearing_envelope.bands", "format_version": ARTEFACT_FORMATS["bands"],
                "case": self.case, "load_kN": float(self.load_kN), "depth_um": float(self.depth_um),
                "fs": float(self.fs), "signal": self.signal,
                "kurtogram": None if self.kurtogram is None else
                {k: float(v) for k, v in self.kurtogram.items()},
                "bands": [b.to_dict() for b in self.bands]}

    @classmethod
    def from_dict(cls, doc) -> CaseBands:
        return cls(case=str(doc["case"]), load_kN=float(doc["load_kN"]),
                   depth_um=float(doc["depth_um"]), fs=float(doc["fs"]), signal=str(doc["signal"]),
                   bands=tuple(BandLimits(name=b["name"], strategy=b["strategy"],
                                          low_hz=float(b["low_hz"]), high_hz=float(b["high_hz"]),
                                          clamped=bool(b.get("clamped", False)),
                                          provenance=dict(b.get("provenance", {})))
                               for b in doc["bands"]),
                   kurtogram=None if doc.get("kurtogram") is None else dict(doc["kurtogram"]))


def write_bands(path: str | os.PathLike, bands: CaseBands) -> str:
    """Write a case's band limits as JSON (atomic). Returns the path."""
    with atomic_path(path, ".json") as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            json.dump(bands.to_dict(), fh, indent=1)
    return os.fspath(path)


def read_bands(path: str | os.PathLike) -> CaseBands:
    """Read a file written by :func:`write_bands`.

    Raises
    ------
    FileNotFoundError, ArtefactFormatError
    """
    path = _exists(path)
    try:
        with open(path, encoding="utf-8") as fh:
            doc = json.load(fh)
    except json.JSONDecodeError as exc:
        raise ArtefactFormatError(f"{path}: not JSON ({exc})") from exc
    if not isinstance(doc, dict):
        raise ArtefactFormatError(f"{path}: not a bands file (a JSON object expected)")
    _check_format(path, doc.get("format"), doc.get("format_version"), "bands")
    try:
        return CaseBands.from_dict(doc)
    except (KeyError, TypeError, ValueError) as exc:
        raise ArtefactFormatError(f"{path}: bands file lacks or mistypes a field ({exc!r})") from exc


# --------------------------------------------------------------------------- kurtogram (NPZ)
@dataclass(frozen=True)
class KurtogramMap:
    """The kurtogram of one case as stored (enough to draw it).

    Attributes
    ----------
    matrix : ndarray, shape (n_levels, n_freqs)
        Kurtosis of every cell, repeated over the columns each band spans.
    levels : ndarray
        Level of each row.
    freqs : ndarray
        Centre frequency of each column (Hz).
    level, fc, bandwidth, kurtosis : float
        The best cell (Hz for ``fc`` and ``bandwidth``).
    """

    matrix: np.ndarray
    levels: np.ndarray
    freqs: np.ndarray
    level: float
    fc: float
    bandwidth: float
    kurtosis: float


def write_kurtogram(path: str | os.PathLike, kurtogram) -> str:
    """Write a kurtogram (:class:`bearing_envelope.signal.Kurtogram` or :class:`KurtogramMap`) as
    compressed NPZ (keys ``matrix``, ``levels``, ``freqs``, ``best`` = level, fc, bandwidth,
    kurtosis); ``None`` writes a file holding no kurtogram (no band uses one)."""
    arrays = {"format": np.array("bearing_envelope.kurtogram"),
              "format_version": np.array(ARTEFACT_FORMATS["kurtogram"])}
    if kurtogram is not None:
        arrays.update(matrix=np.asarray(kurtogram.matrix), levels=np.asarray(kurtogram.levels),
                      freqs=np.asarray(kurtogram.freqs),
                      best=np.array([kurtogram.level, kurtogram.fc, kurtogram.bandwidth,
                                     kurtogram.kurtosis], dtype=float))
    with atomic_path(path, ".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez_compressed(fh, **arrays)
    return os.fspath(path)


def _load_npz(path, artefact):
    path = _exists(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
    except (OSError, ValueError) as exc:
        raise ArtefactFormatError(f"{path}: not an NPZ file ({exc})") from exc
    fmt = str(arrays.pop("format")) if "format" in arrays else None
    ver = int(arrays.pop("format_version")) if "format_version" in arrays else None
    _check_format(path, fmt, ver, artefact)
    return path, arrays


def read_kurtogram(path: str | os.PathLike) -> KurtogramMap | None:
    """Read a file written by :func:`write_kurtogram` (None if it holds no kurtogram)."""
    path, a = _load_npz(path, "kurtogram")
    if "matrix" not in a:
        return None
    missing = [k for k in ("levels", "freqs", "best") if k not in a]
    if missing:
        raise ArtefactFormatError(f"{path}: kurtogram file lacks {missing}")
    best = a["best"]
    return KurtogramMap(matrix=a["matrix"], levels=a["levels"], freqs=a["freqs"],
                        level=float(best[0]), fc=float(best[1]), bandwidth=float(best[2]),
                        kurtosis=float(best[3]))


# ----------------------------------------------------------------------------- spectra (NPZ)
@dataclass(frozen=True)
class CaseSpectra:
    """Spectra of one case (what the figures draw).

    Attributes
    ----------
    raw_f, raw_a : ndarray (float32)
        Raw one-sided amplitude spectrum: frequencies (Hz) and amplitudes (signal units).
    envelope : dict
        Band name -> ``(f, amplitude)`` of its envelope spectrum (Hz, signal units; squared units
        for a squared envelope), kept up to a maximum frequency chosen by the writer.
    """

    raw_f: np.ndarray
    raw_a: np.ndarray
    envelope: dict = field(default_factory=dict)


def write_spectra(path: str | os.PathLike, spectra: CaseSpectra) -> str:
    """Write a case's spectra as compressed NPZ: keys ``raw_f``, ``raw_a`` and, per band,
    ``env_<band>_f``, ``env_<band>_a``; ``bands`` lists the band names in order."""
    arrays = {"format": np.array("bearing_envelope.spectra"),
              "format_version": np.array(ARTEFACT_FORMATS["spectra"]),
              "bands": np.array(list(spectra.envelope), dtype=str),
              "raw_f": np.asarray(spectra.raw_f), "raw_a": np.asarray(spectra.raw_a)}
    for name, (f, a) in spectra.envelope.items():
        arrays[f"env_{name}_f"] = np.asarray(f)
        arrays[f"env_{name}_a"] = np.asarray(a)
    with atomic_path(path, ".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez_compressed(fh, **arrays)
    return os.fspath(path)


def read_spectra(path: str | os.PathLike) -> CaseSpectra:
    """Read a file written by :func:`write_spectra`."""
    path, a = _load_npz(path, "spectra")
    try:
        names = [str(n) for n in a["bands"]]
        env = {n: (a[f"env_{n}_f"], a[f"env_{n}_a"]) for n in names}
        return CaseSpectra(raw_f=a["raw_f"], raw_a=a["raw_a"], envelope=env)
    except KeyError as exc:
        raise ArtefactFormatError(f"{path}: spectra file lacks the array {exc}") from exc


# ------------------------------------------------------------------------ sensor (HDF5 / NPZ)
#: Output suffixes of :func:`write_sensor_case`.
SENSOR_SUFFIXES = (".h5", ".hdf5", ".npz")


@dataclass(frozen=True)
class SensorSignal:
    """A synthetic accelerometer signal as stored by :func:`write_sensor_case`.

    Attributes
    ----------
    acceleration : ndarray
        The signal (excitation units x mode gain; m/s^2 for gains in (m/s^2)/Pa).
    fs : float
        Sampling rate (Hz).
    provenance : dict
        Transfer model, SNR target and achieved, seed, source case, versions, commit.
    frequencies : dict
        ``fr``, ``bpfi``, ``bpfo``, ``ftf``, ``bsf`` (Hz) and ``load_kN``, ``depth_um`` of the
        source case, where known.
    """

    acceleration: np.ndarray
    fs: float
    provenance: dict
    frequencies: dict = field(default_factory=dict)

    @property
    def time(self) -> np.ndarray:
        return np.arange(self.acceleration.size) / self.fs


def check_sensor_output(path: str | os.PathLike) -> str:
    """Return the lower-case suffix of a sensor output path, or raise ValueError naming it."""
    suffix = _Path(path).suffix.lower()
    if suffix not in SENSOR_SUFFIXES:
        raise ValueError(f"output must end in .npz or .h5, got {os.fspath(path)!r}")
    return suffix


def _json_default(o):
    if hasattr(o, "tolist"):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


def write_sensor_case(path: str | os.PathLike, acceleration, *, case, source=None,
                      provenance: dict | None = None) -> str:
    """Write a synthetic acceleration with its provenance (atomic).

    Parameters
    ----------
    path : path-like
        ``.h5``/``.hdf5``: a copy of the case file ``source`` with the acceleration added as
        ``signals/acceleration`` (readable by :func:`read_case` like any case); ``.npz``: the
        acceleration, time, frequencies and provenance alone.
    acceleration : array_like
        1-D signal at the case's sampling rate.
    case : Case
        The source case (its ``fs``, frequencies and sweep values are recorded).
    source : path-like, optional
        The source case file; required for an HDF5 output.
    provenance : dict, optional
        JSON-able description of how the signal was made; ``package_version``, ``git_commit``
        and ``sensor_format_version`` are added.

    Returns
    -------
    str
        The path written.
    """
    from . import __version__

    suffix = check_sensor_output(path)
    acc = np.asarray(acceleration)
    fs = float(case.fs)
    info = dict(provenance or {})
    info.setdefault("package_version", __version__)
    info.setdefault("git_commit", git_commit())
    info["sensor_format_version"] = ARTEFACT_FORMATS["sensor"]
    text = json.dumps(info, default=_json_default, allow_nan=True, sort_keys=True)
    meta = {"fs": fs}
    for key in ("fr", "bpfi", "bpfo", "ftf", "bsf", "load_kN", "depth_um"):
        v = getattr(case, key, None)
        if v is not None:
            meta[key] = float(v)
    with atomic_path(path, suffix) as tmp:
        if suffix == ".npz":
            with open(tmp, "wb") as fh:
                np.savez(fh, acceleration=acc, time=np.arange(acc.size) / fs,
                         provenance=np.array(text), format=np.array("bearing_envelope.sensor"),
                         format_version=np.array(ARTEFACT_FORMATS["sensor"]),
                         **{k: np.array(v) for k, v in meta.items()})
        else:
            import h5py

            if source is None:
                raise ValueError("write_sensor_case: an .h5 output copies the case file; give source")
            _shutil.copyfile(os.fspath(source), tmp)
            with h5py.File(tmp, "a") as h5:
                sg = h5.require_group("signals")
                if "acceleration" in sg:
                    del sg["acceleration"]
                d = sg.create_dataset("acceleration", data=acc, compression="gzip",
                                      compression_opts=4, shuffle=True)
                d.attrs["units"] = "excitation units x mode gain (m/s^2 for gains in (m/s^2)/Pa)"
                d.attrs["description"] = "synthetic accelerometer signal (bearing-envelope sensor)"
                d.attrs["provenance"] = text
                if "time" not in h5:
                    h5.create_dataset("time", data=np.arange(acc.size) / fs)
                h5.attrs["sensor_json"] = text
                h5.attrs["sensor_format_version"] = ARTEFACT_FORMATS["sensor"]
    return os.fspath(path)


def read_sensor(path: str | os.PathLike) -> SensorSignal:
    """Read the acceleration written by :func:`write_sensor_case` (.h5 or .npz).

    Raises
    ------
    FileNotFoundError, ArtefactFormatError
    """
    path = _exists(path)
    if _Path(path).suffix.lower() == ".npz":
        path, a = _load_npz(path, "sensor")
        if "acceleration" not in a or "fs" not in a:
            raise ArtefactFormatError(f"{path}: sensor file lacks 'acceleration' or 'fs'")
        freqs = {k: float(a[k]) for k in ("fr", "bpfi", "bpfo", "ftf", "bsf", "load_kN", "depth_um")
                 if k in a}
        return SensorSignal(acceleration=a["acceleration"], fs=float(a["fs"]),
                            provenance=json.loads(str(a.get("provenance", "{}"))),
                            frequencies=freqs)
    case = read_case(path)
    ver = case.attrs.get("sensor_format_version")
    _check_format(path, "bearing_envelope.sensor" if "acceleration" in case.signals else None,
                  ver, "sensor")
    freqs = {k: float(getattr(case, k)) for k in ("fr", "bpfi", "bpfo", "ftf", "bsf", "load_kN",
                                                   "depth_um")}
    return SensorSignal(acceleration=case.signals["acceleration"], fs=case.fs,
                        provenance=json.loads(case.attrs.get("sensor_json", "{}")),
                        frequencies=freqs)


# ---------------------------------------------------------------------------- tables (CSV)
def _read_csv(path, required, what, **kwargs):
    import pandas as pd

    path = _exists(path)
    try:
        df = pd.read_csv(path, **kwargs)
    except (ValueError, pd.errors.ParserError) as exc:
        raise ArtefactFormatError(f"{path}: not a readable CSV {what} ({exc})") from exc
    missing = [c for c in required if c not in df.columns]
    if missing:
        raise ArtefactFormatError(f"{path}: {what} lacks the columns {missing}")
    return df


def write_tidy(path: str | os.PathLike, table) -> str:
    """Write a tidy harmonic table (per case or aggregated) as CSV, atomically.

    The columns must include :data:`bearing_envelope.tables.TIDY_COLUMNS` (ValueError naming the
    missing ones otherwise); extra columns follow them.
    """
    missing = [c for c in TIDY_COLUMNS if c not in table.columns]
    if missing:
        raise ValueError(f"tidy table lacks the columns {missing}")
    return write_csv_atomic(table, path)


def read_tidy(path: str | os.PathLike):
    """Read a tidy harmonic table written by :func:`write_tidy` (DataFrame)."""
    return _read_csv(path, TIDY_COLUMNS, "tidy harmonic table")


def write_case_table(path: str | os.PathLike, table) -> str:
    """Write the per-case summary table (one row per case) as CSV, atomically."""
    missing = [c for c in CASE_TABLE_COLUMNS if c not in table.columns]
    if missing:
        raise ValueError(f"case table lacks the columns {missing}")
    return write_csv_atomic(table, path)


def read_case_table(path: str | os.PathLike):
    """Read a table written by :func:`write_case_table` (DataFrame)."""
    return _read_csv(path, CASE_TABLE_COLUMNS, "case table")


def write_band_table(path: str | os.PathLike, table) -> str:
    """Write the band table (columns :data:`BAND_TABLE_COLUMNS`) as CSV, atomically."""
    missing = [c for c in BAND_TABLE_COLUMNS if c not in table.columns]
    if missing:
        raise ValueError(f"band table lacks the columns {missing}")
    return write_csv_atomic(table, path)


def read_band_table(path: str | os.PathLike):
    """Read a table written by :func:`write_band_table` (DataFrame)."""
    return _read_csv(path, BAND_TABLE_COLUMNS, "band table")


def write_pivots(directory: str | os.PathLike, pivots: dict) -> str:
    """Write load x depth pivots (``key -> DataFrame``) as ``<directory>/<key>.csv``.

    The files are written into a temporary sibling folder which then replaces ``directory``.
    """
    directory = _Path(directory)
    directory.parent.mkdir(parents=True, exist_ok=True)
    tmp = _Path(tempfile.mkdtemp(prefix=f".tmp-{directory.name}.", dir=directory.parent))
    try:
        for key, table in pivots.items():
            table.to_csv(tmp / f"{key}.csv")
        _public_mode_dir(tmp)
        _shutil.rmtree(directory, ignore_errors=True)
        os.replace(tmp, directory)
    except BaseException:
        _shutil.rmtree(tmp, ignore_errors=True)
        raise
    return os.fspath(directory)


def _public_mode_dir(path) -> None:
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(path, 0o777 & ~umask)
    for p in _Path(path).iterdir():
        os.chmod(p, 0o666 & ~umask)


def read_pivots(directory: str | os.PathLike) -> dict:
    """Read the pivots written by :func:`write_pivots`: ``key -> DataFrame`` indexed by
    ``load_kN`` with float ``depth_um`` columns."""
    import pandas as pd

    directory = _exists(directory)
    out = {}
    for p in sorted(_Path(directory).glob("*.csv")):
        t = pd.read_csv(p, index_col="load_kN")
        t.columns = pd.Index([float(c) for c in t.columns], name="depth_um")
        out[p.stem] = t
    return out
