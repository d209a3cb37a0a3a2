"""HDF5 case format: one file per load x depth case (layout in ``docs/file-format.md``).

The one in-memory case type is :class:`Case`: :meth:`Case.from_history` turns the simulator's
return (:class:`bearing_envelope.physics.history.History`) into one, the only place that
conversion is made; :func:`write_case` stores a Case (or a History, through that method)
atomically (temporary file in the same directory, then :func:`os.replace`); :func:`read_case`
returns the Case the file stores: the two agree field by field.
A file of another format version, or one missing a required dataset, raises :class:`CaseFormatError`
(a ``ValueError``) naming the problem.
"""

from __future__ import annotations

import datetime as _dt
import io as _io
import json
import os
import subprocess
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import __version__
from ..physics.dynamics.case import DYNAMIC_SIGNAL_DESCRIPTIONS, DYNAMIC_SIGNAL_UNITS
from ..physics.dynamics.params import MODEL_NAME as DYNAMIC_MODEL
from ..physics.history import SIGNAL_UNITS
from ..physics.locations import scene_event_frequencies
from .atomic import clean_stale_temps, public_mode, temp_path_for
from .integrity import (CHECKSUM_OPTIONS, seal, verify_file, DIGEST_ATTR, content_digest,
                        file_sha256, write_image)

__all__ = ["FORMAT_VERSION", "READABLE_VERSIONS", "Case", "CaseFormatError", "write_case", "read_case", "git_commit",
           "case_file_problem", "set_aside_unreadable", "read_error_model", "jsonable", "ErrorModel"]

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
#: A dynamic case's required datasets (root attribute ``model`` = ``lumped_dynamic``): what a
#: sensor sees and the element loads (``docs/dynamics.md``, "Model only what the scene needs").
_REQUIRED_DYNAMIC = ("time", "signals/sensor_acceleration", "signals/housing_force_x",
                     "signals/housing_force_y", "signals/defect_force", "dynamics/element_load")
#: The model a case file without a ``model`` attribute was made by.
QUASI_STATIC_MODEL = "quasi_static"
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
    "roller_load": "load of the roller at the defect",
    "defect_offset": "arc-length offset of the defect from the nearest roller's contact centre",
    **DYNAMIC_SIGNAL_DESCRIPTIONS,
}
_UNITS = {**SIGNAL_UNITS, **DYNAMIC_SIGNAL_UNITS}


def _required(attrs) -> tuple[str, ...]:
    """The datasets a case file of its model must hold."""
    return _REQUIRED_DYNAMIC if _attr(attrs.get("model")) == DYNAMIC_MODEL else _REQUIRED


class CaseFormatError(ValueError):
    """The file is not a case file of the supported format version."""


@dataclass(frozen=True)
class ErrorModel:
    """The error estimates that apply to one case: made once, from the case's fidelity, depth and
    scene, by :func:`bearing_envelope.study.accuracy.error_model` when the case is simulated;
    stored in its file (group ``discretisation_error``) and read back with it
    (:attr:`Case.error_model`). Defined here, below the study layer, so that a case read from
    its file carries it; ``bearing_envelope.study.accuracy.ErrorModel`` is the same class.

    Attributes
    ----------
    point : str or None
        The measured fidelity point the case's fidelity equals (None: no estimate).
    kind : {"defect", "healthy"}
    basis : str
        One sentence: the source of the estimate, or why there is none.
    table : pandas.DataFrame
        Columns ``signal, quantity_class, rel_error, n_values`` (empty when ``point`` is None).
    withheld : tuple of str
        Signals whose bars are withheld: the case's far field is not the model's.
    """

    point: str | None
    kind: str
    basis: str
    table: "pd.DataFrame"
    withheld: tuple[str, ...] = ()


@dataclass
class Case:
    """A case file's content (SI units).

    Attributes
    ----------
    fs, fr : float
        Sampling rate and shaft rate (Hz).
    bpfi, bpfo, ftf, bsf : float
        The rates the history's events run at (Hz; from the cage rate used, so with the BPFI
        override if any); the geometric ones are ``attrs["*_geometry"]``.
    bpfi_geometry : float
        Geometric BPFI (Hz).
    time : ndarray
        Sample times (s).
    p_max, p_max_defect : ndarray or None
        Maximum pressure over the whole contact / in the defect neighbourhood (Pa); with noise on,
        the noisy signals (the clean ones are in ``signals``). None in a dynamic case.
    roller_load : ndarray or None
        Load of the roller at the defect (N). None in a dynamic case.
    defect_offset : ndarray or None
        Arc-length offset of the defect from that roller's contact centre (m). None in a
        dynamic case.
    load_kN, depth_um : float
        The case's sweep values.
    scene : dict
        Scene mapping (:meth:`bearing_envelope.physics.scene.Scene.to_mapping`).
    attrs : dict
        All root attributes (versions, commit, fidelity, solver settings, diagnostics); each
        ``*_json`` one also as its value (``attrs["fidelity"]``: the fidelity's mapping).
    signals : dict
        Name -> 1-D array: ``p_max``, ``p_max_defect``, ``roller_load``, ``defect_offset``, the
        integral signals ``removed_force`` (N), ``contact_force`` (N), ``approach`` (m),
        ``approach_change`` (m), ``contact_area`` (m^2) and, with noise, ``p_max_clean``,
        ``p_max_defect_clean``; a dynamic case: ``housing_force_x/y`` (N),
        ``housing_displacement_x/y`` (m), ``housing_acceleration_x/y`` and
        ``sensor_acceleration`` (m/s^2), ``sensor_displacement`` (m), ``defect_force`` (N).
    snapshots : dict
        ``load_<i>`` -> dict of pressure fields and coordinates.
    table : dict
        The ``P(Q, x)`` table and its diagnostics (attribute ``race``: the contact it belongs to).
    other_tables : dict
        Race -> table of a second contact (``outer`` for a rolling-element defect, issue 23).
    error_model : ErrorModel or None
        The discretisation errors stored with the case (None: its file stores none).
    dynamics : dict
        A dynamic case's ``element_load`` (n, Z), N (group ``/dynamics``); empty otherwise.
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
    error_model: ErrorModel | None = None
    dynamics: dict = field(default_factory=dict)

    @property
    def model(self) -> str:
        """The model that made the case: ``lumped_dynamic`` or ``quasi_static`` (a file without
        the ``model`` attribute)."""
        return str(self.attrs.get("model") or QUASI_STATIC_MODEL)

    @classmethod
    def from_history(cls, history, *, extra_attrs: dict | None = None,
                     error_model: ErrorModel | None = None) -> "Case":
        """The case a simulated history is: what :func:`read_case` gives back from the file
        :func:`write_case` makes of it, without writing one (the only place a History becomes
        a Case).

        Parameters
        ----------
        history : bearing_envelope.physics.history.History
            The return of :func:`bearing_envelope.physics.history.simulate`.
        extra_attrs : dict, optional
            More root attributes (the workflow's case id, the config file name).
        error_model : ErrorModel, optional
            The case's discretisation errors
            (:func:`bearing_envelope.study.accuracy.case_error_model` makes it).

        Returns
        -------
        Case
            Field by field what reading its file gives (the digest attribute aside).
        """
        if hasattr(history, "element_load_n"):   # physics.dynamics.case.DynamicHistory
            return _case_of(_dynamic_attrs(history, extra_attrs), history.time,
                            dict(history.signals), {}, {}, {}, error_model,
                            {"element_load": history.element_load_n})
        table, more = _history_tables(history)
        return _case_of(_root_attrs(history, extra_attrs), history.time,
                        _history_signals(history), table, more,
                        _history_snapshots(history.snapshots), error_model)


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
    """``obj`` in JSON types, recursively (case attributes, a job's provenance).

    Parameters
    ----------
    obj : object
        Nested mappings, lists and tuples of numpy scalars and arrays and JSON values.

    Returns
    -------
    object
        The same structure in JSON types: mappings as dicts with str keys, tuples and arrays
        as lists, numpy scalars as Python ones; anything else unchanged.
    """
    if isinstance(obj, Mapping):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
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


#: Root attributes holding JSON text; a :class:`Case` also holds each as its value, under the
#: name without ``_json`` (``attrs["fidelity"]``).
_JSON_ATTRS = ("scene_json", "fidelity_json", "solver_json", "stats_json",
               "load_distribution_json", "acquisition_json")

#: Units and description of every dataset of a table group (other arrays: the table's
#: diagnostics, no units).
_TABLE_DATASETS = {
    "roller_load": ("N", "roller-load nodes"),
    "xi": ("1", "normalised offset nodes |x|/s(Q)"),
    "offset": ("m", "offset nodes x = xi s(Q), (load, xi)"),
    "p0": ("Pa", "no-defect maximum pressure P0(Q)"),
    "w0": ("Pa", "no-defect maximum in the window's read strip W0(Q)"),
    "q_out": ("N", "dense roller loads of p_out"),
    "p_out": ("Pa", "no-defect maximum outside the read strip (ends)"),
    "p_max": ("Pa", "P(Q, x), whole contact"),
    "p_max_defect": ("Pa", "P_d(Q, x), defect neighbourhood"),
    "removed_force": ("N", "force the defect removes at the no-defect approach, dF(Q, x)"),
    "area_change": ("m^2", "contact-area change with the defect at the no-defect approach, "
                           "dA(Q, x)"),
    "approach0": ("m", "no-defect approach delta0(Q) (global solves)"),
    "area0": ("m^2", "no-defect contact area A0(Q) (global solves)"),
    "approach_out": ("m", "no-defect approach at q_out (the p_out global solves)"),
    "area_out": ("m^2", "no-defect contact area at q_out (the p_out global solves)"),
}

_INTERP_COLUMNS = "Q_N, x_m, P_direct, Pd_direct, P_interp, Pd_interp, P0"


def _stored(v):
    """A value as a case file gives it back: arrays as they are, scalars as Python scalars."""
    return v if isinstance(v, np.ndarray) else _attr(v)


def _root_attrs(history, extra_attrs: dict | None) -> dict[str, Any]:
    """The root attributes of a history's case: format, provenance, sweep values, frequencies,
    the JSON text of scene, fidelity, solver, statistics, load distribution and acquisition,
    and (what a :class:`Case` holds besides) each of those values under its name without
    ``_json``."""
    sc = history.scene
    ff = sc.frequencies()
    # the rates the history's events run at (from the cage rate used: a BPFI override acts
    # through it), so that a file's fault frequencies are those of its own events; the
    # geometric ones beside them
    ev = scene_event_frequencies(sc)
    a: dict[str, Any] = {
        "format": "bearing_envelope.case", "format_version": FORMAT_VERSION,
        "package_version": __version__, "git_commit": git_commit(),
        "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "load_kN": sc.load.load_kN, "depth_um": sc.defect.depth_um, "load_mode": sc.load.mode,
        "fs": sc.operation.fs_hz, "fr": sc.operation.shaft_rate_hz,
        "bpfi": ev["bpfi"], "bpfo": ev["bpfo"], "ftf": ev["ftf"], "bsf": ev["bsf"],
        "bpfi_geometry": ff.bpfi, "bpfo_geometry": ff.bpfo, "ftf_geometry": ff.ftf,
        "bsf_geometry": ff.bsf, "cage_rate_used": sc.cage_rate_hz}
    ld = history.load_distribution
    values = {
        "scene": sc.to_mapping(),
        "fidelity": history.fidelity.to_dict(),
        "solver": {
            "solver": "bearing_envelope.contact.solve_contact (Polonsky-Keer CG, DC-FFT)",
            "tol": history.fidelity.tol, "max_iter": history.fidelity.max_iter,
            "hardness_Pa": sc.material.hardness_pa,
            "route": "zoom: global no-defect solve per roller load + local window under "
                     "displacement control with far-field displacement and approach"},
        "stats": history.stats,
        "load_distribution": {
            "force_row_N": ld.force_row, "q_max_N": ld.q_max, "delta_r_m": ld.delta_r,
            "epsilon": ld.epsilon, "half_angle_rad": ld.half_angle,
            "clearance_m": ld.clearance, "stiffness_N_per_m_n": ld.stiffness,
            "exponent": ld.exponent},
        "acquisition": getattr(history, "acquisition", {}),
    }
    for key in _JSON_ATTRS[:-1]:
        a[key] = _json(values[key[:-5]])
    profile = getattr(sc.bearing, "profile_file", None)
    if profile:
        a["profile_file_sha256"] = file_sha256(profile)
    a.update(extra_attrs or {})
    a["acquisition_json"] = _json(values["acquisition"])
    a.update({k: jsonable(v) for k, v in values.items()})
    return a


def _dynamic_attrs(history, extra_attrs: dict | None) -> dict[str, Any]:
    """The root attributes of a dynamic case: those of a quasi-static one (scene, fidelity of
    the defect law, load zone, acquisition, statistics), the integrator for the solver, and
    ``model`` with ``dynamics_json`` (step, oversample, CPU, structure, the criterion's line,
    the defect law's metadata)."""
    a = _root_attrs(history, extra_attrs)
    solver = {"solver": "bearing_envelope.physics.dynamics (RK4, fixed step, numba)",
              "step_s": history.model["step_s"], "oversample": history.model["oversample"]}
    a.update(model=history.model["model"], solver_json=_json(solver), solver=jsonable(solver),
             dynamics_json=_json(history.model), dynamics=jsonable(history.model))
    return a


def _history_signals(history) -> dict[str, np.ndarray]:
    """Every signal of a history, with the roller load and the defect offset."""
    return {**history.signals, "roller_load": history.roller_load,
            "defect_offset": history.defect_offset}


def _table_values(tb) -> dict[str, Any]:
    """A ``P(Q, x)`` table as its group stores it: arrays (datasets, :data:`_TABLE_DATASETS`)
    and scalars (attributes); the diagnostics of ``tb.info`` likewise."""
    d: dict[str, Any] = {
        "roller_load": tb.q_nodes, "xi": tb.xi_nodes, "offset": tb.offsets(), "p0": tb.p0,
        "w0": tb.w0, "q_out": tb.q_out, "p_out": tb.p_out, "p_max": tb.p_max_nodes(),
        "p_max_defect": tb.w0[:, None] * tb.ratio_defect, "out_density": tb.out_density,
        "removed_force": tb.q_nodes[:, None] * tb.ratio_force,
        "area_change": tb.area0[:, None] * tb.ratio_area,
        "approach0": tb.approach0, "area0": tb.area0}
    for k in ("approach_out", "area_out"):
        if getattr(tb, k) is not None:
            d[k] = getattr(tb, k)
    d.update(a_coef=tb.a_coef, kappa=tb.kappa, s_const=tb.s_const, s_max=tb.s_max)
    d.update(tb.info)
    return {k: _stored(v) for k, v in d.items()}


def _history_tables(history) -> tuple[dict, dict]:
    """The group of the defect race's table (attribute ``race``) and those of any other race
    (rolling-element defects), as :func:`read_case` gives them back."""
    races = getattr(history, "tables", {}) or {}
    first = next((r for r, t in races.items() if t is history.table), "inner")
    table = {"race": first, **_table_values(history.table)}
    more = {race: {"race": race, **_table_values(tb)} for race, tb in races.items()
            if tb is not history.table}
    return table, more


def _history_snapshots(snapshots: dict) -> dict[str, dict]:
    return {key: {**{k: _stored(v) for k, v in snap.items()}, "roller_load_units": "N"}
            for key, snap in snapshots.items()}


def _write_root_attrs(f, attrs: dict) -> None:
    """Stage 1 of :func:`write_case`: the case's root attributes (not the parsed values of the
    ``*_json`` ones, nor a read file's digest: :func:`seal` makes it)."""
    skip = {k[:-5] for k in _JSON_ATTRS} | {DIGEST_ATTR, "dynamics"}
    for k, v in attrs.items():
        if k not in skip:
            f.attrs[k] = v


def _write_signals(f, case: "Case") -> None:
    """Stage 2 of :func:`write_case`: ``/time`` and the ``/signals`` group."""
    _dset(f, "time", case.time, "s", "sample times")
    sg = f.create_group("signals")
    for name, arr in case.signals.items():
        base = name[:-6] if name.endswith("_clean") else name
        _dset(sg, name, arr, _UNITS.get(base, ""), _SIGNAL_DESCRIPTIONS.get(base, ""))
    if case.dynamics:
        _dset(f.create_group("dynamics"), "element_load", case.dynamics["element_load"], "N",
              "each element's outer contact load (samples x elements)")


def _write_table(tg, table: dict) -> None:
    """One table group (layout: docs/file-format.md, ``/table``): arrays as datasets, scalars
    as attributes."""
    for k, v in table.items():
        if isinstance(v, np.ndarray) and v.ndim > 0:
            _dset(tg, k, v, *_TABLE_DATASETS.get(k, ("", "")))
        else:
            tg.attrs[k] = v
    if "interp_checks" in tg:
        tg["interp_checks"].attrs["columns"] = _INTERP_COLUMNS


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


def write_case(path: str | os.PathLike, case, *, extra_attrs: dict | None = None,
               error_model=None) -> str:
    """Write a simulated case atomically to ``path`` (HDF5; layout ``docs/file-format.md``).

    Every array is Fletcher-32 checksummed and the file's attributes are sealed with a digest
    (:mod:`bearing_envelope.io.integrity`). The file is built in memory; free space is checked
    against its exact size before anything is written.

    Parameters
    ----------
    path : path-like
        Output file; its directory is created if needed.
    case : Case or bearing_envelope.physics.history.History
        The case; a History becomes one through :meth:`Case.from_history` (with
        ``extra_attrs`` and ``error_model``).
    extra_attrs : dict, optional
        More root attributes (e.g. the config file name); only with a History.
    error_model : ErrorModel, optional
        Stored as the ``discretisation_error`` group; only with a History (a Case carries its
        own).

    Returns
    -------
    str
        The path written.

    Raises
    ------
    DiskFullError
        Not enough free space (before writing, or ENOSPC while writing); nothing is left behind.
    TypeError
        ``extra_attrs`` or ``error_model`` given with a :class:`Case` (they go with a History).
    """
    import h5py

    if not isinstance(case, Case):
        case = Case.from_history(case, extra_attrs=extra_attrs, error_model=error_model)
    elif extra_attrs or error_model is not None:
        raise TypeError("write_case: extra_attrs and error_model go with a History; a Case "
                        "carries its own (Case.from_history)")
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    clean_stale_temps(directory, path)
    # Free space is checked against the finished file's exact size (write_image): the sum of
    # the uncompressed arrays (estimate_h5_bytes) is 3.9x the gzip-compressed file (36.0 MB for
    # 9.1 MB, the default case) and refused writes that fit.
    image = _io.BytesIO()  # built in memory: HDF5 never meets a full disk (write_image)
    with h5py.File(image, "w") as f:
        _write_root_attrs(f, case.attrs)
        _write_signals(f, case)
        _write_table(f.create_group("table"), case.table)
        for race, tb in case.other_tables.items():
            _write_table(f.create_group(f"table_{race}"), tb)
        _write_snapshots(f, case.snapshots)
        if case.error_model is not None:
            _write_error_model(f, case.error_model)
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
    g.attrs["withheld"] = ",".join(em.withheld)
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
    ``basis``, ``withheld``) and the table (empty when the fidelity has no estimate).

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
        return _read_error_group(f["discretisation_error"])


def _read_error_group(g) -> tuple[dict[str, str], "pd.DataFrame"]:
    import pandas as pd

    attrs = {k: _attr(v) for k, v in g.attrs.items()}
    cols = {k: [_attr(x) for x in g[k][()]] if g[k].dtype.kind == "O" else g[k][()] for k in g}
    return attrs, pd.DataFrame(cols)


def _error_model_of(f) -> ErrorModel | None:
    """The stored :class:`ErrorModel` of an open case file (None when it stores none)."""
    if "discretisation_error" not in f:
        return None
    attrs, table = _read_error_group(f["discretisation_error"])
    withheld = tuple(w for w in str(attrs.get("withheld", "")).split(",") if w)
    return ErrorModel(attrs["point"] or None, attrs["kind"], attrs["basis"], table, withheld)


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
            for name in _required(f.attrs):
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

    Examples
    --------
    One shaft revolution of the default scene at 250 kN with a 50 um defect, written and read
    back:

    >>> import os, tempfile
    >>> from bearing_envelope.physics.scene import Scene
    >>> from bearing_envelope.physics.history import simulate
    >>> from bearing_envelope.io.case import read_case, write_case
    >>> scene = Scene.from_mapping({"operation": {"revolutions": 1}}, load_kN=250.0,
    ...                            depth_um=50.0)
    >>> path = write_case(os.path.join(tempfile.mkdtemp(), "case.h5"), simulate(scene, "draft"))
    >>> case = read_case(path)
    >>> case.load_kN, case.depth_um, case.fs
    (250.0, 50.0, 65000.0)
    >>> case.p_max.shape == case.time.shape
    True
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
        for name in _required(attrs):
            if name not in f:
                raise CaseFormatError(f"{path}: required dataset '/{name}' is missing")
        if ver >= 3:
            _check_digest(path, f, attrs)
        signals = {k: v[()] for k, v in f["signals"].items()}
        table = _read_group(f["table"]) if "table" in f else {}
        more = {k[len("table_"):]: _read_group(f[k]) for k in f if k.startswith("table_")}
        snaps = _read_group(f["snapshots"]) if "snapshots" in f else {}
        time = f["time"][()]
        error_model = _error_model_of(f)
        dyn = {"element_load": f["dynamics/element_load"][()]} if "dynamics" in f else {}
    for k in _JSON_ATTRS + ("dynamics_json",):
        if k in attrs:
            attrs[k[:-5]] = json.loads(attrs[k])
    return _case_of(attrs, time, signals, table, more, snaps, error_model, dyn)


def _case_of(attrs: dict, time, signals: dict, table: dict, more: dict, snaps: dict,
             error_model: ErrorModel | None, dynamics: dict | None = None) -> Case:
    """The :class:`Case` of a file's (or a history's) parts."""
    return Case(
        fs=float(attrs["fs"]), fr=float(attrs["fr"]), bpfi=float(attrs["bpfi"]),
        bpfi_geometry=float(attrs["bpfi_geometry"]), bpfo=float(attrs["bpfo"]),
        ftf=float(attrs["ftf"]), bsf=float(attrs["bsf"]), time=time,
        p_max=signals.get("p_max"), p_max_defect=signals.get("p_max_defect"),
        roller_load=signals.get("roller_load"), defect_offset=signals.get("defect_offset"),
        load_kN=float(attrs["load_kN"]), depth_um=float(attrs["depth_um"]),
        scene=attrs.get("scene", {}), attrs=attrs, signals=signals, snapshots=snaps, table=table,
        other_tables=more, error_model=error_model, dynamics=dynamics or {},
    )
