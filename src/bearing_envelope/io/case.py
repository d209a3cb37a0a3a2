"""HDF5 case format: one file per load x depth case (layout in ``docs/file-format.md``).

:func:`write_case` stores a :class:`bearing_envelope.physics.history.History` atomically (temporary file
in the same directory, then :func:`os.replace`); :func:`read_case` returns a typed :class:`Case`.
A file of another format version, or one missing a required dataset, raises :class:`CaseFormatError`
(a ``ValueError``) naming the problem.
"""

from __future__ import annotations

import datetime as _dt
import io as _io
import json
import os
import subprocess
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import __version__
from ..physics.locations import scene_event_frequencies
from .atomic import clean_stale_temps, public_mode, temp_path_for
from .integrity import (CHECKSUM_OPTIONS, seal, verify_file, DIGEST_ATTR, content_digest,
                        file_sha256, write_image)

__all__ = ["FORMAT_VERSION", "READABLE_VERSIONS", "Case", "CaseFormatError", "write_case", "read_case", "git_commit",
           "case_file_problem", "set_aside_unreadable", "read_error_model", "jsonable"]

#: Version of the layout written by :func:`write_case`.
#: 2: integral signals (removed_force, contact_force, approach, approach_change, contact_area),
#: their tables, and the acquisition (root attribute ``acquisition_json``).
#: 3: every array Fletcher-32 checksummed, root attribute ``content_sha256`` (digest of all
#: attributes and unchecksummed values, :func:`bearing_envelope.io.integrity.content_digest`).
FORMAT_VERSION = 3

#: Versions :func:`read_case` reads: 3 verified (checksums and digest), 2 as it is.
READABLE_VERSIONS = (2, 3)

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
        Scene mapping (:meth:`bearing_envelope.physics.scene.Scene.to_mapping`).
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
        The ``P(Q, x)`` table and its diagnostics (attribute ``race``: the contact it belongs to).
    other_tables : dict
        Race -> table of a second contact (``outer`` for a rolling-element defect, issue 23).
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
    other_tables: dict = field(default_factory=dict)


def git_commit(path: str | None = None) -> str:
    """Commit hash of the repository holding ``path`` (this package by default), ``+dirty`` if
    the tree has changes; ``"unknown"`` without git.

    Parameters
    ----------
    path : str, optional
        A path inside the repository (default: this package's folder).

    Returns
    -------
    str
        The commit hash, with ``+dirty`` if the tree has changes, or ``"unknown"``.
    """
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


def jsonable(obj):
    """``obj`` in JSON types, recursively.

    Parameters
    ----------
    obj : object
        Nested dicts, lists and tuples of numpy scalars and arrays and JSON values.

    Returns
    -------
    object
        The same structure in JSON types (dict keys as str, tuples and arrays as lists).
    """
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (np.floating, np.integer, np.bool_)):
        return obj.item()
    return obj


def _dset(group, name, data, units: str, description: str = "", chunk: bool = True):
    """One dataset with its ``units`` (and ``description``): Fletcher-32 checksummed wherever
    HDF5 allows it (non-empty arrays), gzip-compressed above 16 values (1-D: chunks of up to
    65,536 samples)."""
    data = np.asarray(data)
    kw = dict(_COMPRESSION) if (chunk and data.size > 16) else {}
    if kw and data.ndim == 1:
        kw["chunks"] = (min(data.size, 65536),)
    if data.ndim > 0 and data.size > 0 and data.dtype.kind not in "OSU":
        kw.update(CHECKSUM_OPTIONS)
    ds = group.create_dataset(name, data=data, **kw)
    ds.attrs["units"] = units
    if description:
        ds.attrs["description"] = description
    return ds


def _json(obj) -> str:
    return json.dumps(jsonable(obj), sort_keys=True)


def _write_root_attrs(f, history, extra_attrs: dict | None) -> None:
    """Stage 1 of :func:`write_case`: format, provenance, sweep values, frequencies and the
    JSON descriptions of scene, fidelity, solver, statistics, load distribution, acquisition."""
    sc = history.scene
    ff = sc.frequencies()
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
    # the rates the history's events run at (from the cage rate used: a BPFI override acts
    # through it), so that a file's fault frequencies are those of its own events; the
    # geometric ones beside them
    ev = scene_event_frequencies(sc)
    a["bpfi"] = ev["bpfi"]
    a["bpfo"] = ev["bpfo"]
    a["ftf"] = ev["ftf"]
    a["bsf"] = ev["bsf"]
    a["bpfi_geometry"] = ff.bpfi
    a["bpfo_geometry"] = ff.bpfo
    a["ftf_geometry"] = ff.ftf
    a["bsf_geometry"] = ff.bsf
    a["cage_rate_used"] = sc.cage_rate_hz
    a["scene_json"] = _json(sc.to_mapping())
    a["fidelity_json"] = _json(history.fidelity.to_dict())
    a["solver_json"] = _json({
        "solver": "bearing_envelope.contact.solve_contact (Polonsky-Keer CG, DC-FFT)",
        "tol": history.fidelity.tol, "max_iter": history.fidelity.max_iter,
        "hardness_Pa": sc.material.hardness_pa,
        "route": "zoom: global no-defect solve per roller load + local window under "
                 "displacement control with far-field displacement and approach",
    })
    a["stats_json"] = _json(history.stats)
    ld = history.load_distribution
    a["load_distribution_json"] = _json({
        "force_row_N": ld.force_row, "q_max_N": ld.q_max, "delta_r_m": ld.delta_r,
        "epsilon": ld.epsilon, "half_angle_rad": ld.half_angle,
        "clearance_m": ld.clearance, "stiffness_N_per_m_n": ld.stiffness,
        "exponent": ld.exponent})
    profile = getattr(sc.bearing, "profile_file", None)
    if profile:
        a["profile_file_sha256"] = file_sha256(profile)
    for k, v in (extra_attrs or {}).items():
        a[k] = v
    a["acquisition_json"] = _json(getattr(history, "acquisition", {}))


def _write_signals(f, history) -> None:
    """Stage 2 of :func:`write_case`: ``/time`` and the ``/signals`` group."""
    from ..physics.history import SIGNAL_UNITS

    _dset(f, "time", history.time, "s", "sample times")
    sg = f.create_group("signals")
    for name, arr in history.signals.items():
        base = name[:-6] if name.endswith("_clean") else name
        _dset(sg, name, arr, SIGNAL_UNITS.get(base, ""), _SIGNAL_DESCRIPTIONS.get(base, ""))
    _dset(sg, "roller_load", history.roller_load, "N", "load of the roller at the defect")
    _dset(sg, "defect_offset", history.defect_offset, "m",
          "arc-length offset of the defect from the nearest roller's contact centre")


def _write_tables(f, history) -> None:
    """Stage 3 of :func:`write_case`: ``/table`` (the contact of the defect's race) and
    ``/table_{race}`` for any other race's table (rolling-element defects)."""
    races = getattr(history, "tables", {}) or {}
    first = next((r for r, t in races.items() if t is history.table), "inner")
    _write_table(f.create_group("table"), history.table, first)
    for race, tb in races.items():
        if tb is not history.table:
            _write_table(f.create_group(f"table_{race}"), tb, race)


def _write_table(tg, tb, race: str) -> None:
    """The ``P(Q, x)`` table ``tb`` of the contact with the ``race`` (``inner``/``outer``) into
    the group ``tg`` (layout: docs/file-format.md, ``/table``)."""
    tg.attrs["race"] = race
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
    for k, unit, what in (("approach_out", "m", "no-defect approach"),
                          ("area_out", "m^2", "no-defect contact area")):
        if getattr(tb, k) is not None:
            _dset(tg, k, getattr(tb, k), unit, f"{what} at q_out (the p_out global solves)")
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
        tg["interp_checks"].attrs["columns"] = ("Q_N, x_m, P_direct, Pd_direct, P_interp, "
                                               "Pd_interp, P0")


def _write_snapshots(f, snapshots: dict) -> None:
    """Stage 4 of :func:`write_case`: the ``/snapshots`` group (pressure fields)."""
    sn = f.create_group("snapshots")
    for key, snap in snapshots.items():
        g = sn.create_group(key)
        for k, v in snap.items():
            if np.ndim(v) == 0:
                g.attrs[k] = v
            else:
                _dset(g, k, v, "Pa" if "pressure" in k else "m")
        g.attrs["roller_load_units"] = "N"


def write_case(path: str | os.PathLike, history, *, extra_attrs: dict | None = None,
               error_model=None) -> str:
    """Write a simulated case atomically to ``path`` (HDF5; layout ``docs/file-format.md``).

    Every array is Fletcher-32 checksummed and the file's attributes are sealed with a digest
    (:mod:`bearing_envelope.io.integrity`). The file is built in memory; free space is checked
    against its exact size before anything is written.

    Parameters
    ----------
    path : path-like
        Output file; its directory is created if needed.
    history : bearing_envelope.physics.history.History
    extra_attrs : dict, optional
        More root attributes (e.g. the config file name).
    error_model : bearing_envelope.study.accuracy.ErrorModel, optional
        Stored as the ``discretisation_error`` group.

    Returns
    -------
    str
        The path written.

    Raises
    ------
    DiskFullError
        Not enough free space (before writing, or ENOSPC while writing); nothing is left behind.
    """
    import h5py

    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    clean_stale_temps(directory, path)
    # Free space is checked against the finished file's exact size (write_image): the sum of
    # the uncompressed arrays (estimate_h5_bytes) is 3.9x the gzip-compressed file (36.0 MB for
    # 9.1 MB, the default case) and refused writes that fit.
    image = _io.BytesIO()  # built in memory: HDF5 never meets a full disk (write_image)
    with h5py.File(image, "w") as f:
        _write_root_attrs(f, history, extra_attrs)
        _write_signals(f, history)
        _write_tables(f, history)
        _write_snapshots(f, history.snapshots)
        if error_model is not None:
            _write_error_model(f, error_model)
        seal(f)
    tmp = temp_path_for(path)
    public_mode(tmp)
    write_image(tmp, path, image.getvalue())
    return path


def _write_error_model(f, em) -> None:
    """Group ``discretisation_error``: the estimated relative error of each amplitude at the
    case's fidelity, as given (:func:`bearing_envelope.study.accuracy.error_model` makes it)."""
    import h5py

    g = f.create_group("discretisation_error")
    g.attrs["point"] = em.point or ""
    g.attrs["kind"] = em.kind
    g.attrs["basis"] = em.basis
    for col in em.table.columns:
        v = em.table[col].to_numpy()
        if v.dtype == object or v.dtype.kind in "OUT":
            g.create_dataset(col, data=np.asarray(v, dtype=object), dtype=h5py.string_dtype())
        elif v.size:
            g.create_dataset(col, data=v, **CHECKSUM_OPTIONS)
        else:
            g.create_dataset(col, data=v)


def read_error_model(path: str | os.PathLike) -> tuple[dict[str, str], "pd.DataFrame"]:
    """The ``discretisation_error`` group of a case file: its attributes (``point``, ``kind``,
    ``basis``) and the table (empty when the fidelity has no estimate).

    Parameters
    ----------
    path : str or os.PathLike
        A case file.

    Returns
    -------
    tuple of (dict, pandas.DataFrame)
        The group's attributes and its table.
    """
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


def case_file_problem(path: str | os.PathLike) -> str | None:
    """Why an existing case file cannot be used (``None`` when it reads and is intact).

    Checks the format attributes (this version only: a file without checksums is rebuilt) and
    the required datasets, then verifies the whole file
    (:func:`bearing_envelope.io.integrity.verify_file`: every chunk read against its
    Fletcher-32 sum, the attribute digest recomputed). Reads every byte once: 16 ms CPU per
    MB (0.14 s for a default case file of 8.9 MB).

    Parameters
    ----------
    path : str or os.PathLike
        An existing case file.

    Returns
    -------
    str or None
        One line saying what is wrong, or None.
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
                return f"format_version {ver!r} is not the current one ({FORMAT_VERSION})"
            for name in _REQUIRED:
                if name not in f:
                    return f"required dataset '/{name}' is missing"
    except (OSError, KeyError, ValueError, RuntimeError) as exc:
        return f"unreadable HDF5 ({' '.join(str(exc).split())[:160]})"
    return verify_file(path)


def set_aside_unreadable(path: str | os.PathLike, *, warn=None) -> str | None:
    """Move an unreadable case file aside so that the workflow rebuilds it.

    If ``path`` exists and :func:`case_file_problem` finds a problem, the file is renamed to
    ``{path}.unreadable-{UTC time}`` (kept for inspection, never deleted) and a one-line warning
    naming both paths and the problem goes to ``warn`` (default: stderr). Returns the new path, or
    ``None`` when the file is missing or fine.

    Parameters
    ----------
    path : str or os.PathLike
        A case file (it may not exist).
    warn : callable, optional
        Receives the warning line (default: print to stderr).

    Returns
    -------
    str or None
        The path the file was moved to, or None when it was not moved.
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

    Parameters
    ----------
    path : str or os.PathLike
        A case file written by :func:`write_case`.

    Returns
    -------
    Case
        Signals, time, scene, fidelity, table, snapshots, fault frequencies and provenance.

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


def _check_digest(path: str, f, attrs: dict) -> None:
    """Raise :class:`CaseFormatError` unless the stored attribute digest matches the file's."""
    stored = attrs.get(DIGEST_ATTR)
    if stored is None:
        raise CaseFormatError(f"{path}: no '{DIGEST_ATTR}' attribute: the file was changed "
                              f"after writing or written by another program")
    if content_digest(f) != stored:
        raise CaseFormatError(f"{path}: attribute digest mismatch: an attribute changed after "
                              f"writing (bit flip or edit)")


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
        if ver not in READABLE_VERSIONS:
            raise CaseFormatError(f"{path}: format_version {ver!r} is not supported (this reader: "
                                  f"{', '.join(map(str, READABLE_VERSIONS))})")
        for name in _REQUIRED:
            if name not in f:
                raise CaseFormatError(f"{path}: required dataset '/{name}' is missing")
        if ver >= 3:
            _check_digest(path, f, attrs)
        signals = {k: v[()] for k, v in f["signals"].items()}
        table = _read_group(f["table"]) if "table" in f else {}
        more = {k[len("table_"):]: _read_group(f[k]) for k in f if k.startswith("table_")}
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
        other_tables=more,
    )
