"""The CWRU Bearing Data Center's drive-end records as manifests of the virtual rig.

Two ways in, both ending as manifest rows (:mod:`.manifest`):

- the data center's ``.mat`` files as downloaded (``105.mat`` holding ``X105_DE_time``,
  ``X105RPM``; read with ``scipy.io.loadmat`` through the project's reader, never unpickled):
  :func:`mat_rows` finds each file's record number (its ``X###_DE_time`` variable) in
  :data:`DRIVE_END` and takes the shaft rate from ``X###RPM``;
- the converted development records (``.npz``): the package's manifest
  ``data/rig_cwru_development.csv`` (:func:`development_rows`), its files found by name in the
  folders the user gives.

:data:`DRIVE_END` is the catalogue of the drive-end fault records (12 kHz and 48 kHz) and the
normal baseline: record number -> fault location, pit diameter, outer-race position, motor load,
sampling rate. Its sources (docs/virtual_rig.md, "The CWRU catalogue"): the data center's
pages "12k Drive End Bearing Fault Data", "48k Drive End Bearing Fault Data" and "Normal
Baseline Data" as listed, set by set, in the public ``Litchiware/cwru`` package's
``metadata.txt`` (set, nominal rpm, download URL of each record number); the 32 rows of the
12 kHz development records agree with their ``index.csv`` (record, fault, diameter, position,
load), checked row by row. The pit depth is the data center's: 0.011 in for the 0.007-0.021 in
pits, 0.050 in for 0.028 in. The nominal speeds (1797, 1772, 1750, 1730 rpm at 0-3 hp) are used
only where a file holds no ``X###RPM``.
"""

from __future__ import annotations

import csv
import os
import re
from importlib import resources
from pathlib import Path

__all__ = ["DRIVE_END", "catalogue_row", "mat_rows", "development_rows", "DEVELOPMENT_MANIFEST",
           "BEARING", "INCH_UM", "DEPTH_UM", "NOMINAL_RPM"]

#: micrometres per inch
INCH_UM = 25400.0
#: The drive-end bearing (the project's catalogue designation).
BEARING = "SKF 6205-2RS"
#: EDM pit depth by pit diameter (inch -> um): 0.011 in, 0.050 in for 0.028 in.
DEPTH_UM = {0.007: 0.011 * INCH_UM, 0.014: 0.011 * INCH_UM, 0.021: 0.011 * INCH_UM,
            0.028: 0.050 * INCH_UM}
#: Nominal shaft speed by motor load (hp -> rpm).
NOMINAL_RPM = {0: 1797.0, 1: 1772.0, 2: 1750.0, 3: 1730.0}

#: (fs Hz, location, pit diameter in, outer-race position deg, record numbers at 0, 1, 2, 3 hp)
_SETS = (
    (12000.0, "inner_race", 0.007, None, (105, 106, 107, 108)),
    (12000.0, "ball", 0.007, None, (118, 119, 120, 121)),
    (12000.0, "outer_race", 0.007, 0.0, (130, 131, 132, 133)),
    (12000.0, "outer_race", 0.007, 90.0, (144, 145, 146, 147)),
    (12000.0, "outer_race", 0.007, 180.0, (156, 158, 159, 160)),
    (12000.0, "inner_race", 0.014, None, (169, 170, 171, 172)),
    (12000.0, "ball", 0.014, None, (185, 186, 187, 188)),
    (12000.0, "outer_race", 0.014, 0.0, (197, 198, 199, 200)),
    (12000.0, "inner_race", 0.021, None, (209, 210, 211, 212)),
    (12000.0, "ball", 0.021, None, (222, 223, 224, 225)),
    (12000.0, "outer_race", 0.021, 0.0, (234, 235, 236, 237)),
    (12000.0, "outer_race", 0.021, 90.0, (246, 247, 248, 249)),
    (12000.0, "outer_race", 0.021, 180.0, (258, 259, 260, 261)),
    (12000.0, "inner_race", 0.028, None, (3001, 3002, 3003, 3004)),
    (12000.0, "ball", 0.028, None, (3005, 3006, 3007, 3008)),
    (48000.0, "inner_race", 0.007, None, (109, 110, 111, 112)),
    (48000.0, "ball", 0.007, None, (122, 123, 124, 125)),
    (48000.0, "outer_race", 0.007, 0.0, (135, 136, 137, 138)),
    (48000.0, "outer_race", 0.007, 90.0, (148, 149, 150, 151)),
    (48000.0, "outer_race", 0.007, 180.0, (161, 162, 163, 164)),
    (48000.0, "inner_race", 0.014, None, (174, 175, 176, 177)),
    (48000.0, "ball", 0.014, None, (189, 190, 191, 192)),
    (48000.0, "outer_race", 0.014, 0.0, (201, 202, 203, 204)),
    (48000.0, "inner_race", 0.021, None, (213, 214, 215, 217)),
    (48000.0, "ball", 0.021, None, (226, 227, 228, 229)),
    (48000.0, "outer_race", 0.021, 0.0, (238, 239, 240, 241)),
    (48000.0, "outer_race", 0.021, 90.0, (250, 251, 252, 253)),
    (48000.0, "outer_race", 0.021, 180.0, (262, 263, 264, 265)),
    (48000.0, "none", None, None, (97, 98, 99, 100)),
)


def _catalogue() -> dict:
    out = {}
    for fs, loc, dia, pos, numbers in _SETS:
        for hp, n in enumerate(numbers):
            out[n] = {"record": n, "fs_hz": fs, "location": loc, "load": float(hp),
                      "length_um": None if dia is None else dia * INCH_UM,
                      "depth_um": None if dia is None else DEPTH_UM[dia],
                      "position_deg": pos, "rpm": NOMINAL_RPM[hp]}
    return out


#: record number -> ``record``, ``fs_hz``, ``location`` (the data center's name), ``load``
#: (motor hp), ``length_um`` (the pit's diameter), ``depth_um``, ``position_deg`` (outer race:
#: 6:00 = 0, 3:00 = 90, 12:00 = 180; else None), ``rpm`` (nominal).
DRIVE_END = _catalogue()

#: The package's manifest of the converted CWRU development records (``.npz``, by file name).
DEVELOPMENT_MANIFEST = "rig_cwru_development.csv"

_VAR = re.compile(r"^X(\d+)_DE_time$")


def catalogue_row(number: int, *, where: str = "record") -> dict:
    """A manifest row (column -> text) of one drive-end record of :data:`DRIVE_END`.

    Parameters
    ----------
    number : int
        The data center's record number.
    where : str
        The caller's name of the record, for the message.

    Returns
    -------
    dict
        ``location``, ``length_um``, ``depth_um``, ``position_deg``, ``load``, ``fs_hz``,
        ``rpm``, ``bearing``, ``record`` as manifest text (``file`` not set).

    Raises
    ------
    ValueError
        A number not in the catalogue, in one line.
    """
    r = DRIVE_END.get(int(number))
    if r is None:
        raise ValueError(f"{where}: record {number} is not a drive-end record of the CWRU "
                         f"catalogue; allowed: {min(DRIVE_END)}-{max(DRIVE_END)} as listed in "
                         "study.rig.cwru.DRIVE_END (or describe it in a manifest)")
    return {k: "" if v is None else repr(v) if isinstance(v, float) else str(v)
            for k, v in r.items()} | {"bearing": BEARING}


def _mat_number(path: str) -> tuple[int, bool]:
    """The record number of a data-center ``.mat`` file (its ``X###_DE_time`` variable whose
    number is in the file name: a few files hold two records; else its only one) and whether
    the file holds that record's ``X###RPM``."""
    from scipy.io import whosmat  # the variables' names only, nothing executed

    try:
        names = [name for name, _, _ in whosmat(path)]
    except Exception as exc:  # scipy raises ValueError, TypeError, MatReadError, ... on junk
        raise ValueError(f"file: {path} is not a readable MATLAB .mat file "
                         f"({type(exc).__name__})") from None
    found = [int(m.group(1)) for name in names if (m := _VAR.match(name))]
    digits = {int(d) for d in re.findall(r"\d+", Path(path).name)}
    own = [n for n in found if n in digits]
    if len(own) == 1 or len(found) == 1:
        n = own[0] if own else found[0]
        return n, any(re.fullmatch(rf"X0*{n}RPM", name) for name in names)
    raise ValueError(f"file: {path}: {len(found)} drive-end variables X###_DE_time "
                     f"({', '.join(map(str, found)) or 'none'}); allowed: one, or one whose "
                     "number is in the file name")


def mat_rows(paths) -> list[dict]:
    """Manifest rows of the data center's ``.mat`` files (:data:`DRIVE_END` by the number of
    each file's ``X###_DE_time``; the shaft rate from the file's ``X###RPM``, the nominal
    speed of the record's load only where the file holds none).

    Parameters
    ----------
    paths : iterable of str
        ``.mat`` files as downloaded.

    Returns
    -------
    list of dict
        One row (column -> text, ``file`` the path) per file.
    """
    rows = []
    for p in paths:
        number, has_rpm = _mat_number(str(p))
        row = catalogue_row(number, where=f"file: {p}")
        if has_rpm:
            row["rpm"] = ""  # the file's own (io.records reads X###RPM)
        row["file"] = str(p)
        rows.append(row)
    return rows


def development_rows(paths) -> tuple[list[dict], list[str]]:
    """Rows of the package's CWRU development manifest for the files given (by file name).

    Parameters
    ----------
    paths : iterable of str
        Converted CWRU records (``.npz``).

    Returns
    -------
    (list of dict, list of str)
        The rows (column -> text, ``file`` the path given) and the files the manifest does not
        list.
    """
    text = resources.files("bearing_envelope").joinpath("data", DEVELOPMENT_MANIFEST)
    with text.open(encoding="utf-8", newline="") as fh:
        by_name = {r["file"]: r for r in csv.DictReader(fh)}
    rows, unknown = [], []
    for p in paths:
        r = by_name.get(os.path.basename(p))
        if r is None:
            unknown.append(str(p))
        else:
            rows.append({**r, "file": str(p)})
    return rows, unknown
