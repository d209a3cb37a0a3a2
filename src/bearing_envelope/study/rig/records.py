"""What the virtual rig knows of one record: its bearing, its defect, its operation, its samples.

A record enters the rig as a row of a manifest (:mod:`.manifest`): the file, the bearing (a
designation or its geometry), the fault's location and size (um), the outer race's position
(degrees from the load direction), the operating load, fs and the shaft rate. This module turns
a validated row into a :class:`RigCondition` (reading the file once for its length, its fs and
its shaft rate where the row gives none) and the rig's two look-ups, both the project's:

- :func:`resolve_bearing`: a designation or a geometry -> :class:`RigBearing` (the project's
  one resolver, :func:`bearing_envelope.physics.catalogue.bearing_geometry`);
- :func:`rig_event_rates`: the bearing's event rates at a shaft rate (the project's one rates
  function, :func:`bearing_envelope.physics.kinematics.bearing_rates`).
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from ...io.records import read_record as read_file
from ...physics.catalogue import bearing_geometry
from ...physics.kinematics import RADIAL_CONTACT_ANGLE_DEG
from ...physics.kinematics import bearing_rates as _rates

__all__ = ["RigBearing", "RigCondition", "resolve_bearing", "rig_event_rates", "read_samples",
           "read_simulated_record", "condition_from_row", "GEOMETRY_COLUMNS", "GEOMETRY_RTOL"]

#: The manifest columns that give a bearing by its geometry (instead of ``bearing``).
GEOMETRY_COLUMNS = ("n_rollers", "roller_diameter_mm", "pitch_diameter_mm", "contact_angle_deg")
#: Two bearings are the same when their geometries agree within this fraction (a geometry
#: given in inch and converted, 0.3126 in = 7.94004 mm, is the catalogue's 7.94 mm).
GEOMETRY_RTOL = 1e-3


@dataclass(frozen=True)
class RigBearing:
    """A record's bearing: its designation (None when given by geometry) and geometry.

    Attributes
    ----------
    designation : str or None
        The catalogue's designation (``SKF 6205-2RS``).
    n_rollers : int
        Rolling elements per row.
    roller_diameter_mm, pitch_diameter_mm : float
        Rolling element and pitch diameters, mm.
    contact_angle_deg : float
        Contact angle, degrees.
    """

    designation: str | None
    n_rollers: int
    roller_diameter_mm: float
    pitch_diameter_mm: float
    contact_angle_deg: float = RADIAL_CONTACT_ANGLE_DEG

    def same_geometry(self, other: "RigBearing") -> bool:
        """Whether two bearings have one geometry (within :data:`GEOMETRY_RTOL`).

        Parameters
        ----------
        other : RigBearing
            The bearing compared with.

        Returns
        -------
        bool
            Same number of elements; diameters and contact angle within the tolerance.
        """
        return (self.n_rollers == other.n_rollers
                and all(math.isclose(getattr(self, k), getattr(other, k), rel_tol=GEOMETRY_RTOL,
                                     abs_tol=1e-9) for k in GEOMETRY_COLUMNS[1:]))


def resolve_bearing(designation: str | None = None, geometry: dict | None = None, *,
                    name: str = "bearing") -> RigBearing:
    """The rig's one bearing look-up: a designation from the project's catalogue, or a geometry.

    Parameters
    ----------
    designation : str, optional
        ``6205``, ``SKF 6205-2RS``, ... (the catalogue's aliases).
    geometry : dict, optional
        :data:`GEOMETRY_COLUMNS` (``contact_angle_deg`` may be absent: 0).
    name : str
        How the caller names the field, for the message.

    Returns
    -------
    RigBearing
        The designation (None for a geometry) and the geometry (mm, deg).

    Raises
    ------
    ValueError
        Neither or both given, or an unknown designation (one line naming ``name``).
    """
    if (designation is None) == (geometry is None):
        raise ValueError(f"{name}: give the bearing by designation or by its geometry "
                         f"({', '.join(GEOMETRY_COLUMNS)}), one of the two")
    if designation is not None:
        g = bearing_geometry(designation, names={"designation": name})
        return RigBearing(g["designation"], int(g["n_rollers"]), float(g["roller_diameter_mm"]),
                          float(g["pitch_diameter_mm"]), float(g["contact_angle_deg"]))
    return RigBearing(None, int(geometry["n_rollers"]), float(geometry["roller_diameter_mm"]),
                      float(geometry["pitch_diameter_mm"]),
                      float(geometry.get("contact_angle_deg") or 0.0))


def rig_event_rates(bearing: RigBearing, fr: float) -> dict:
    """The bearing's event rates at a shaft rate (read from the project's one rates function).

    Parameters
    ----------
    bearing : RigBearing
        The record's bearing (its geometry in mm and deg).
    fr : float
        Shaft rate, Hz.

    Returns
    -------
    dict
        ``bpfo``, ``bpfi``, ``bsf``, ``bsf2`` (2 x BSF), Hz.
    """
    r = _rates(fr, bearing.n_rollers, bearing.roller_diameter_mm, bearing.pitch_diameter_mm,
               bearing.contact_angle_deg)
    return {k: r[k] for k in ("bpfo", "bpfi", "bsf", "bsf2")}


@dataclass(frozen=True)
class RigCondition:
    """One measured record and what the rig re-makes it from.

    Attributes
    ----------
    name : str
        Record name (the manifest's ``name``, else the file name without its suffix).
    path : str
        The measured record.
    location : str
        The project's fault location (``inner_race`` | ``outer_race`` | ``rolling_element``).
    length_um, width_um, depth_um : float
        The pit: along the rolling direction, across it, deep; um.
    position_deg : float
        Outer-race position from the load direction, deg (0 elsewhere).
    load : float
        The operating load as the record set states it (CWRU: motor load, hp): records of one
        load are paired, the outer race's trend is per unit of it.
    shaft_hz : float
        The record's shaft rate, Hz.
    fs_hz : float
        The record's sampling rate, Hz.
    n_samples : int
        The record's length.
    bearing : RigBearing
        The record's bearing (the rig's scene must have its geometry).
    """

    name: str
    path: str
    location: str
    length_um: float
    width_um: float
    depth_um: float
    position_deg: float
    load: float
    shaft_hz: float
    fs_hz: float
    n_samples: int
    bearing: RigBearing

    @property
    def defect_key(self) -> str:
        """The contact table's key: location, size and position (shared over loads and fs)."""
        return (f"{self.location}_{self.length_um:g}x{self.width_um:g}x{self.depth_um:g}um_"
                f"{self.position_deg:g}deg")

    @property
    def rates(self) -> dict:
        """The bearing's event rates at the record's shaft rate (:func:`rig_event_rates`), Hz."""
        return rig_event_rates(self.bearing, self.shaft_hz)

    def meta(self) -> dict:
        """The condition as a JSON-serialisable mapping (the simulated record's meta).

        Returns
        -------
        dict
            Every field (the bearing's as a mapping), ``fs_hz`` and ``shaft_hz`` included.
        """
        return asdict(self)


def read_samples(path: str) -> np.ndarray:
    """A record's samples, through the project's reader (any file ``analyze`` reads: ``.npz``,
    ``.npy``, ``.mat`` with CWRU's ``X###_DE_time``, ``.csv``, ``.wav``; never unpickled).

    Parameters
    ----------
    path : str
        The record.

    Returns
    -------
    numpy.ndarray
        The samples (float64).
    """
    return read_file(str(path))["x"]


def read_simulated_record(path: str) -> tuple[np.ndarray, dict]:
    """A simulated record of the rig: its samples and meta (``x``, ``meta_json``; never
    unpickled).

    Parameters
    ----------
    path : str
        A ``<name>_sim.npz`` of :func:`~bearing_envelope.study.rig.simulation.write_rig_record`.

    Returns
    -------
    (numpy.ndarray, dict)
        The samples (float) and the parsed meta.
    """
    with np.load(path, allow_pickle=False) as z:
        return np.asarray(z["x"], dtype=float), json.loads(str(z["meta_json"]))


def condition_from_row(row: dict) -> RigCondition:
    """The condition of one validated manifest row (:func:`.manifest.check_row`), the file read
    once for its length and, where the row gives none, its fs and shaft rate.

    Parameters
    ----------
    row : dict
        ``file``, ``name``, ``location`` (the project's), ``length_um``, ``width_um``,
        ``depth_um``, ``position_deg``, ``load``, ``fs_hz`` and ``shaft_hz`` (None: from the
        file), ``bearing`` (:class:`RigBearing`), ``where`` (the row, for messages).

    Returns
    -------
    RigCondition
        The record, its fault and pit (um), its position (deg), load, fs and shaft rate
        (Hz), its bearing.

    Raises
    ------
    ValueError
        One line naming the row: an fs or shaft rate neither given nor in the file, an fs that
        disagrees with the file's.
    """
    got = read_file(str(row["file"]))
    fs, fr = row["fs_hz"], row["shaft_hz"]
    if fs is None:
        fs = got["fs"]
    elif got["fs"] is not None and not math.isclose(fs, got["fs"], rel_tol=1e-9):
        raise ValueError(f"{row['where']}: fs_hz: got {fs:g}; the file says {got['fs']:g} Hz; "
                         "allowed: the file's sampling rate (or leave it empty)")
    fr = got["fr"] if fr is None else fr
    for key, v in (("fs_hz", fs), ("shaft_hz", fr)):
        if v is None:
            raise ValueError(f"{row['where']}: {key}: empty and not in the file; allowed: a "
                             "number > 0, Hz")
    name = row["name"] or os.path.splitext(Path(row["file"]).name)[0]
    return RigCondition(name, str(row["file"]), row["location"], row["length_um"],
                        row["width_um"], row["depth_um"], row["position_deg"], row["load"],
                        float(fr), float(fs), int(got["x"].size), row["bearing"])
