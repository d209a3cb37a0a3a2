"""The rig's config (``config_rig.yaml``): the scene every record is re-made in, and the rig's
own parameters (``rig:``: radial load, fidelity, the ball records' spin axis, the sensor)."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

from ...checks import check_number
from ...physics.fidelity import DEFAULT_PRESET
from ...physics.scene import DEFAULT_SCENE
from ..config_read import read_yaml

__all__ = ["RigSettings", "read_rig_config"]


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
    """

    scene: dict
    load_kN: float
    fidelity: str
    ball_spin_axis: str = DEFAULT_SCENE["defect"]["spin_axis"]
    sensor_deg: float = 180.0
    sensor_cross_axis: float = 1.0


def read_rig_config(path: str | os.PathLike) -> RigSettings:
    """Read ``config_rig.yaml``: ``scene:`` (as in the sweep's config) and ``rig:``.

    Parameters
    ----------
    path : path
        The rig config.

    Returns
    -------
    RigSettings

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
    return RigSettings(raw["scene"], load, str(rig.get("fidelity", DEFAULT_PRESET)),
                       str(rig.get("ball_spin_axis", RigSettings.ball_spin_axis)), sensor, cross)


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
