"""A record set described by a manifest: what the virtual rig needs of each record.

A manifest is a CSV file (``,`` separated, a header row), one row per record:

==================== ========= ==============================================================
column               required  meaning
==================== ========= ==============================================================
file                 yes       the record, relative to the manifest's folder (or absolute):
                               any file ``analyze`` reads (``.npz``, ``.mat``, ``.csv``, ...)
name                 no        the record's name (default: the file name without suffix)
location             yes       the fault's location: ``inner_race``, ``outer_race``,
                               ``rolling_element`` (or ``ball``); ``none`` / ``normal``: a
                               record without fault (left out)
length_um            fault     the pit's size along the rolling direction, um
width_um             no        its size across (default: ``length_um``, a round pit), um
depth_um             fault     its depth, um
position_deg         outer     the outer-race defect's angle from the load direction, degrees
                               in [0, 360) (the load zone's centre 0; CWRU 6:00 = 0, 3:00 =
                               90, 12:00 = 180); empty or 0 for the other locations
load                 yes       the operating load as the record set states it (a number; CWRU:
                               motor load, hp): records of one load are paired
fs_hz                no        sampling rate, Hz (default: the file's; if both, they agree)
shaft_hz             no        shaft rate, Hz (or ``rpm``; default: the file's ``X###RPM``,
                               ``fr``/``rpm`` scalar or meta ``shaft_hz``)
bearing              one of    the bearing's designation (``6205``, ``SKF 6205-2RS``) ...
n_rollers, ...       the two   ... or its geometry: ``n_rollers``, ``roller_diameter_mm``,
                               ``pitch_diameter_mm``, ``contact_angle_deg`` (default 0)
==================== ========= ==============================================================

Every row is checked before any record is simulated; a bad value is refused in one line that
names the manifest, the row (its line in the file) and the column. Other columns are kept as
notes (``record``, ``grade``, ...). The bearing's radial load is the rig's (``rig.load_kN`` of
its config): one rig, one load zone.

Fault names: :func:`fault_location` is the one place a manifest's fault name becomes the
project's location (a name of the location registry, or the data center's ``ball``).
"""

from __future__ import annotations

import csv
import math
import os
from pathlib import Path

from ...physics.locations import get_location, location_names
from .cwru import development_rows, mat_rows
from .records import GEOMETRY_COLUMNS, RigCondition, condition_from_row, resolve_bearing

__all__ = ["record_conditions", "manifest_rows", "read_rig_manifest", "check_row", "fault_location",
           "conditions_of_rows", "FAULT_ALIASES", "NO_FAULT", "COLUMNS", "MANIFEST_NAME"]

#: Names a manifest may give a location by besides the registry's own (the data center's).
FAULT_ALIASES = {"ball": "rolling_element"}
#: Names of a record without a fault (left out of the rig).
NO_FAULT = ("none", "normal", "healthy")
#: The columns the rig reads (others are notes).
COLUMNS = ("file", "name", "location", "length_um", "width_um", "depth_um", "position_deg",
           "load", "fs_hz", "shaft_hz", "rpm", "bearing", *GEOMETRY_COLUMNS)


def fault_location(name: str, *, where: str = "location") -> str | None:
    """The project's fault location of a manifest's fault name (the rig's one mapping): a name
    of the location registry (:func:`bearing_envelope.physics.locations.get_location`) or an
    alias of :data:`FAULT_ALIASES`.

    Parameters
    ----------
    name : str
        ``inner_race``, ``outer_race``, ``rolling_element``, ``ball`` (any case), any other
        registered location; ``none``, ``normal``, ``healthy`` or empty: no fault.
    where : str
        The field, for the message (``manifest.csv row 3: location``).

    Returns
    -------
    str or None
        The registered location's name; None for a record without fault.

    Raises
    ------
    ValueError
        An unknown name, in one line.
    """
    key = (name or "").strip().lower()
    if key in NO_FAULT or not key:
        return None
    key = FAULT_ALIASES.get(key, key)
    if key not in location_names():
        raise ValueError(f"{where}: got {name!r}; allowed: "
                         f"{', '.join((*location_names(), *FAULT_ALIASES))}, {', '.join(NO_FAULT)}")
    return get_location(key).name


def _number(row: dict, key: str, where: str, *, lo: float = 0.0, lo_open: bool = True,
            hi: float = math.inf, hi_open: bool = True, unit: str = "") -> float | None:
    """``row[key]`` as a float in the range (None when empty), else one line."""
    text = (row.get(key) or "").strip()
    if not text:
        return None
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    ok = (math.isfinite(v) and (v > lo if lo_open else v >= lo)
          and (v < hi if hi_open else v <= hi))
    if not ok:
        rng = (f"{'>' if lo_open else '>='} {lo:g}" if hi == math.inf else
               f"{lo:g} to {hi:g}{' (excluded)' if hi_open else ''}")
        raise ValueError(f"{where}: {key}: got {text!r}; allowed: a number {rng}{unit}")
    return v


def _bearing(row: dict, where: str):
    given = [k for k in GEOMETRY_COLUMNS if (row.get(k) or "").strip()]
    name = (row.get("bearing") or "").strip()
    if name and given:
        raise ValueError(f"{where}: bearing: got {name!r} and {', '.join(given)}; allowed: a "
                         "designation or the geometry, not both")
    if name:
        return resolve_bearing(name, name=f"{where}: bearing")
    missing = [k for k in GEOMETRY_COLUMNS[:3] if k not in given]
    if missing:
        raise ValueError(f"{where}: {missing[0]}: empty; allowed: a bearing designation in "
                         f"'bearing' or its geometry ({', '.join(GEOMETRY_COLUMNS)})")
    geo = {"n_rollers": _number(row, "n_rollers", where, lo=1, lo_open=False)}
    if geo["n_rollers"] != int(geo["n_rollers"]):
        raise ValueError(f"{where}: n_rollers: got {row['n_rollers']!r}; allowed: an integer >= 1")
    for k in GEOMETRY_COLUMNS[1:3]:
        geo[k] = _number(row, k, where, unit=" mm")
    geo["contact_angle_deg"] = _number(row, "contact_angle_deg", where, lo=0.0, lo_open=False,
                                       hi=90.0, unit=" deg") or 0.0
    if geo["roller_diameter_mm"] >= geo["pitch_diameter_mm"]:
        raise ValueError(f"{where}: roller_diameter_mm: got {geo['roller_diameter_mm']:g}; "
                         f"allowed: below pitch_diameter_mm ({geo['pitch_diameter_mm']:g})")
    return resolve_bearing(geometry=geo, name=f"{where}: bearing")


def _fault(row: dict, where: str, location: str) -> dict:
    out = {}
    for key, what in (("length_um", "size along the rolling direction"), ("depth_um", "depth")):
        out[key] = _number(row, key, where, unit=" um")
        if out[key] is None:
            raise ValueError(f"{where}: {key}: empty; allowed: a number > 0 um (the pit's "
                             f"{what})")
    width = _number(row, "width_um", where, unit=" um")
    out["width_um"] = out["length_um"] if width is None else width
    pos = _number(row, "position_deg", where, lo=0.0, lo_open=False, hi=360.0, unit=" deg")
    positioned = get_location(location).positioned  # a defect fixed in space: the outer race
    if positioned and pos is None:
        raise ValueError(f"{where}: position_deg: empty; allowed: the {location} defect's angle "
                         "from the load direction, 0 to 360 deg (6:00 = 0, 3:00 = 90)")
    if not positioned and pos:
        raise ValueError(f"{where}: position_deg: got {pos:g}; allowed: empty or 0 unless "
                         "location is outer_race")
    out["position_deg"] = pos or 0.0
    return out


def check_row(row: dict, where: str, base: str | os.PathLike = ".") -> dict | None:
    """One manifest row, validated (None: a record without fault, left out).

    Parameters
    ----------
    row : dict
        The row as read (column -> text).
    where : str
        The row, for messages (``records.csv row 3``).
    base : path
        The folder a relative ``file`` is read from.

    Returns
    -------
    dict or None
        ``file`` (a path), ``name``, ``location`` (the project's), ``length_um``,
        ``width_um``, ``depth_um``, ``position_deg``, ``load``, ``fs_hz``, ``shaft_hz`` (None:
        from the file), ``bearing`` (:class:`~.records.RigBearing`), ``where``.

    Raises
    ------
    ValueError
        One line naming the row and the column.
    """
    row = {(k or "").strip().lower(): (v or "").strip() for k, v in row.items()}
    if not row.get("file"):
        raise ValueError(f"{where}: file: empty; allowed: the record's path (relative to the "
                         "manifest's folder)")
    location = fault_location(row.get("location", ""), where=f"{where}: location")
    if location is None:
        return None
    path = Path(base) / row["file"]
    if not path.is_file():
        raise ValueError(f"{where}: file: no such file: {path}")
    load = _number(row, "load", where, lo=-math.inf)
    if load is None:
        raise ValueError(f"{where}: load: empty; allowed: the record's operating load as the "
                         "record set states it (a number, e.g. motor hp)")
    fr = _number(row, "shaft_hz", where, unit=" Hz")
    rpm = _number(row, "rpm", where, unit=" rpm")
    return {"file": str(path), "name": row.get("name") or None, "location": location,
            **_fault(row, where, location), "load": load,
            "fs_hz": _number(row, "fs_hz", where, unit=" Hz"),
            "shaft_hz": fr if fr is not None else (None if rpm is None else rpm / 60.0),
            "bearing": _bearing(row, where), "where": where}


def read_rig_manifest(path: str | os.PathLike) -> list[dict]:
    """The fault records of a manifest, every row validated (:func:`check_row`).

    Parameters
    ----------
    path : path
        The manifest (CSV with a header row; columns: this module's table).

    Returns
    -------
    list of dict
        One validated row per fault record, in the file's order.

    Raises
    ------
    ValueError
        No such file, no ``file`` or ``location`` column, or a bad row (one line naming it).

    Examples
    --------
    A manifest of two records of a 6205 (the second a healthy one, left out)::

        file,location,length_um,depth_um,position_deg,load,shaft_hz,bearing
        a.npz,outer_race,177.8,279.4,90,2,29.17,6205
        b.npz,none,,,,2,29.17,6205

    >>> rows = read_rig_manifest("records/manifest.csv")   # doctest: +SKIP
    >>> [(r["location"], r["position_deg"]) for r in rows]   # doctest: +SKIP
    [('outer_race', 90.0)]
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"manifest: no such file: {path}")
    with open(path, encoding="utf-8-sig", newline="") as fh:
        reader = csv.DictReader(fh)
        head = [(k or "").strip().lower() for k in (reader.fieldnames or [])]
        for need in ("file", "location", "load"):
            if need not in head:
                raise ValueError(f"manifest: {path}: no {need!r} column; allowed columns: "
                                 f"{', '.join(COLUMNS)}")
        rows = [check_row(r, f"{path} row {i + 2}", path.parent) for i, r in enumerate(reader)]
    return [r for r in rows if r is not None]


def conditions_of_rows(rows) -> list:
    """The rig condition of each validated row (:func:`~.records.condition_from_row`); two rows
    of one name are refused.

    Parameters
    ----------
    rows : iterable of dict
        :func:`check_row`'s results.

    Returns
    -------
    list of RigCondition
        One per row, in the rows' order.

    Raises
    ------
    ValueError
        Two rows with the same record name.
    """
    out, seen = [], {}
    for r in rows:
        c = condition_from_row(r)
        if c.name in seen:
            raise ValueError(f"{r['where']}: name: {c.name!r} is also {seen[c.name]}; allowed: "
                             "one record per name (give a 'name' column)")
        seen[c.name] = r["where"]
        out.append(c)
    return out


#: A folder holding this file is read through it.
MANIFEST_NAME = "manifest.csv"


def _files(item: str) -> list[str]:
    if os.path.isdir(item):
        return sorted(os.path.join(item, f) for f in os.listdir(item)
                      if os.path.isfile(os.path.join(item, f)))
    if not os.path.isfile(item):
        raise ValueError(f"records: no such file or folder: {item}")
    return [item]


def manifest_rows(items, *, log=print) -> list[dict]:
    """The validated fault records (:func:`.manifest.check_row`) of files, folders and
    manifests (:data:`MANIFEST_NAME` in a folder).

    Each item is read as: a ``.csv`` file: a manifest; a folder holding ``manifest.csv``: that
    manifest; otherwise its files (a folder's, sorted): ``.mat`` files as the CWRU data
    center's (:func:`.cwru.mat_rows`), ``.npz`` files by the package's CWRU development
    manifest (:func:`.cwru.development_rows`; a file it does not list is left out, counted in
    the log).

    Parameters
    ----------
    items : iterable of str
        Files, folders, manifests.
    log : callable
        Progress lines.

    Returns
    -------
    list of dict
        One validated row per fault record.
    """
    rows: list = []
    for item in map(str, items):
        own = Path(item) / MANIFEST_NAME
        if item.lower().endswith(".csv") or own.is_file():
            rows += read_rig_manifest(own if own.is_file() else item)
            continue
        files = _files(item)
        mats = [f for f in files if f.lower().endswith(".mat")]
        found, unknown = development_rows([f for f in files if f.lower().endswith(".npz")])
        raw = mat_rows(mats) + found
        checked = (check_row(r, f"{r['file']} (CWRU catalogue)") for r in raw)
        rows += [r for r in checked if r is not None]
        if unknown:
            log(f"rig: {item}: {len(unknown)} file(s) not in the CWRU development manifest, "
                "left out")
    return rows


def record_conditions(items, *, log=print) -> list[RigCondition]:
    """The rig condition of every fault record of files, folders and manifests
    (:func:`manifest_rows`), in the order of their paths; records without fault are left out
    (the first function a user of the rig calls).

    Parameters
    ----------
    items : iterable of str
        Files, folders, manifests.
    log : callable
        Progress lines.

    Returns
    -------
    list of RigCondition
        One per fault record (file, fault location, pit size in um, position in deg,
        load, fs and shaft rate in Hz).

    Examples
    --------
    >>> from bearing_envelope.study.rig import record_conditions      # doctest: +SKIP
    >>> [c.name for c in record_conditions(["records/manifest.csv"])]  # doctest: +SKIP
    ['rec_a', 'rec_b']
    """
    rows = sorted(manifest_rows(items, log=log), key=lambda r: r["file"])
    return conditions_of_rows(rows)
