"""The rig's config (``config_rig.yaml``): the scene every record is re-made in, and the rig's
own parameters (``rig:``: radial load, fidelity, the ball records' spin axis, the sensor, the
excitation model ``dynamics`` and the dynamic model's ``structure``)."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

from ...checks import check_number
from ...physics.dynamics.params import STRUCTURE_DEFAULTS
from ...physics.fidelity import DEFAULT_PRESET
from ...physics.scene import DEFAULT_SCENE
from ..config_read import read_yaml

__all__ = ["RigSettings", "read_rig_config", "RIG_DYNAMICS", "RIG_STRUCTURE_KEYS"]

#: Values of ``rig.dynamics``: the excitation of each simulated record. ``quasi_static``: the
#: force the defect removes from the quasi-static contact history (the rig before);
#: ``dynamic``: the force the outer ring passes to the housing in the lumped-parameter model
#: (:mod:`bearing_envelope.physics.dynamics`, docs/virtual_rig.md "With the dynamics").
RIG_DYNAMICS = ("quasi_static", "dynamic")
#: Keys ``rig.structure`` may set (the dynamic model's structure, defaults in
#: :data:`~bearing_envelope.physics.dynamics.params.STRUCTURE_DEFAULTS`; the sensor's axis is
#: ``rig.sensor_deg``).
RIG_STRUCTURE_KEYS = tuple(k for k in STRUCTURE_DEFAULTS if k != "sensor_angle_deg")
#: Of those, the ones that must be > 0 (the rest >= 0).
_POSITIVE = ("shaft_mass_kg", "housing_mass_kg", "resonator_hz", "resonator_mass_kg")


@dataclass(frozen=True)
class RigSettings:
    """The rig's parameters (``rig:`` section of the rig config) and its base scene mapping.

    Attributes
    ----------
    scene : dict
        The ``scene:`` mapping (validated by :meth:`Scene.from_mapping` per record).
    load_kN : float
        Radial load on the bearing, kN.
    fidelity : str
        Fidelity preset of the contact tables.
    ball_spin_axis : str
        ``defect.spin_axis`` of the ball records (``fixed`` | ``wandering``).
    sensor_deg : float
        Direction of the accelerometer's axis from the load direction, deg (CWRU: 12:00, 180).
    sensor_cross_axis : float
        Gain of a force across the sensor's axis relative to one along it, in [0, 1]
        (:func:`~bearing_envelope.physics.transfer.direction_gain`; 1: blind to direction).
    dynamics : str
        The excitation model of the simulated records (:data:`RIG_DYNAMICS`).
    structure : dict
        The dynamic model's structure (keys of :data:`RIG_STRUCTURE_KEYS`, SI with units in
        the names); a key not given keeps its ``STRUCTURE_DEFAULTS`` value.
    """

    scene: dict
    load_kN: float
    fidelity: str
    ball_spin_axis: str = DEFAULT_SCENE["defect"]["spin_axis"]
    sensor_deg: float = 180.0
    sensor_cross_axis: float = 1.0
    dynamics: str = RIG_DYNAMICS[0]
    structure: dict = field(default_factory=dict)


def read_rig_config(path: str | os.PathLike) -> RigSettings:
    """Read ``config_rig.yaml``: ``scene:`` (as in the sweep's config) and ``rig:``.

    Parameters
    ----------
    path : path
        The rig config.

    Returns
    -------
    RigSettings
        The base scene mapping and the ``rig:`` values, typed (load in kN, sensor
        direction in deg, cross-axis gain).

    Raises
    ------
    ValueError
        A missing section or a bad value, in one line naming the key (``rig.load_kN``).
    """
    raw = read_yaml(path)
    for key in ("scene", "rig"):
        if not isinstance(raw, dict) or key not in raw:
            raise ValueError(f"{path}: {key}: missing section; allowed: a mapping")
    rig = raw["rig"]
    if "depth_um" in rig:
        raise ValueError(f"{path}: rig.depth_um: no longer read; allowed: each record's pit "
                         "depth in its manifest's depth_um column (docs/virtual_rig.md)")
    load = float(rig.get("load_kN", "nan"))
    if not (math.isfinite(load) and load > 0):
        raise ValueError(f"{path}: rig.load_kN: got {rig.get('load_kN')!r}; allowed: > 0 kN")
    sensor = _number_in(path, rig, "sensor_deg", RigSettings.sensor_deg, 0.0, 360.0)
    cross = _number_in(path, rig, "sensor_cross_axis", RigSettings.sensor_cross_axis, 0.0, 1.0)
    dyn = rig.get("dynamics", RigSettings.dynamics)
    if dyn not in RIG_DYNAMICS:
        raise ValueError(f"{path}: rig.dynamics: got {dyn!r}; allowed: {' | '.join(RIG_DYNAMICS)}")
    return RigSettings(raw["scene"], load, str(rig.get("fidelity", DEFAULT_PRESET)),
                       str(rig.get("ball_spin_axis", RigSettings.ball_spin_axis)), sensor, cross,
                       dyn, _structure(path, rig.get("structure", {})))


def _structure(path, raw) -> dict:
    """``rig.structure`` checked: a mapping of :data:`RIG_STRUCTURE_KEYS` to finite numbers,
    > 0 for the masses and the resonator's frequency, >= 0 for the rest; else one line."""
    if not isinstance(raw, dict):
        raise ValueError(f"{path}: rig.structure: got {raw!r}; allowed: a mapping of "
                         f"{', '.join(RIG_STRUCTURE_KEYS)}")
    out = {}
    for key, v in raw.items():
        if key not in RIG_STRUCTURE_KEYS:
            raise ValueError(f"{path}: rig.structure.{key}: unknown key; allowed: "
                             f"{', '.join(RIG_STRUCTURE_KEYS)}")
        try:
            x = check_number(v, f"rig.structure.{key}")
        except ValueError:
            x = math.nan
        if not (math.isfinite(x) and (x > 0 if key in _POSITIVE else x >= 0)):
            raise ValueError(f"{path}: rig.structure.{key}: got {v!r}; allowed: a number "
                             f"{'> 0' if key in _POSITIVE else '>= 0'}")
        out[key] = x
    return out


def _number_in(path, rig: dict, key: str, default: float, lo: float, hi: float) -> float:
    """``rig.<key>`` as a float in ``[lo, hi]`` (its default when absent), else one line."""
    v = rig.get(key, default)
    try:
        x = check_number(v, f"rig.{key}")
    except ValueError:
        x = math.nan
    if not lo <= x <= hi:
        raise ValueError(f"{path}: rig.{key}: got {v!r}; allowed: a number from {lo:g} to {hi:g}")
    return x
