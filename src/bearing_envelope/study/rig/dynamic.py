"""The rig with the dynamics (``rig.dynamics: dynamic``; docs/virtual_rig.md, "With the
dynamics").

Each race record's scene in the lumped-parameter model (:mod:`bearing_envelope.physics.dynamics`:
the rings, every element's radial motion, the defect contact read from the project's own
non-Hertzian law :func:`~bearing_envelope.physics.defect_contact.defect_table`), its structure
from ``rig.structure``; the excitation of the simulated record is the force the elements pass to
the outer ring (the housing), its fluctuation about the applied load, read by the rig's one-axis
sensor: the component along the axis, plus the component across it at the cross-axis gain in
quadrature (:func:`sensor_excitation`), so that their envelopes add in power as
:func:`~bearing_envelope.physics.transfer.direction_gain` says. The transfer path and the gain
are the quasi-static rig's (:mod:`.simulation`): only the excitation changes.

Every record's defect is in the model (:func:`dynamic_supported`): a pit on a race, and a pit
on a rolling element, which meets both races (:func:`~bearing_envelope.physics.dynamics.case.case_params`
joins each race's defect law), so every record goes through the one gain identified on the
dynamic reference records.
"""

from __future__ import annotations

import dataclasses
import math
import time
from pathlib import Path

import numpy as np
from scipy import signal as sps

from ...io.atomic import atomic_path
from ...physics.dynamics import DefectLaw, params_from_scene, simulate_dynamics
from ...physics.dynamics.case import case_params
from ...physics.dynamics.params import STRUCTURE_DEFAULTS, contact_damping
from ...physics.history import defect_angle
from .config import RigSettings

__all__ = ["DYNAMIC_MODEL", "dynamic_supported", "rig_params", "rig_scene", "simulate_dynamic_record",
           "dynamic_path", "sensor_excitation", "is_dynamic", "excitation_model"]

#: ``model`` of a dynamic excitation file (that of :func:`simulate_dynamics`' results).
DYNAMIC_MODEL = "lumped_dynamic"


def dynamic_supported(cond) -> bool:
    """Whether the dynamic model holds the record's defect: a pit on a race or on a rolling
    element (element 0).

    Parameters
    ----------
    cond : RigCondition
        The record (its fault location).

    Returns
    -------
    bool
        True for the inner race, the outer race and a rolling element.
    """
    return cond.location in ("inner_race", "outer_race", "rolling_element")


def dynamic_path(out_dir, cond) -> Path:
    """The dynamic excitation file of a record, ``<name>_dynamic.npz``.

    Parameters
    ----------
    out_dir : path
        The run's contact folder.
    cond : RigCondition
        The record.

    Returns
    -------
    pathlib.Path
        The file.
    """
    return Path(out_dir) / f"{cond.name}_dynamic.npz"


def rig_params(scene, settings: RigSettings, law: DefectLaw | None):
    """The dynamic model of one record's scene with the rig's structure.

    ``rig.structure`` overrides :data:`STRUCTURE_DEFAULTS`; the damping ratios become
    coefficients (the housing's ``2 zeta sqrt(k m)``, the contacts' by
    :func:`~bearing_envelope.physics.dynamics.params.contact_damping`); the resonator's axis is
    the rig's sensor (``rig.sensor_deg``).

    Parameters
    ----------
    scene : Scene
        The record's scene (:func:`~.simulation.condition_scene`).
    settings : RigSettings
        The rig's settings (its structure and sensor).
    law : DefectLaw or None
        The defect contact law.

    Returns
    -------
    DynamicParams
        The model, SI.
    """
    s = {**STRUCTURE_DEFAULTS, **settings.structure}
    kw = {k: s[k] for k in ("shaft_mass_kg", "shaft_stiffness_n_m", "shaft_damping_ns_m",
                            "housing_mass_kg", "housing_stiffness_n_m", "resonator_hz",
                            "resonator_zeta", "resonator_mass_kg")}
    kw["housing_damping_ns_m"] = 2.0 * s["housing_zeta"] * math.sqrt(
        s["housing_stiffness_n_m"] * s["housing_mass_kg"])
    kw["sensor_angle_rad"] = math.radians(settings.sensor_deg)
    p = params_from_scene(scene, defect=law, contact_damping_ns_m=0.0, **kw)
    return p.with_(contact_damping_ns_m=contact_damping(p, s["contact_zeta"]))


def rig_scene(scene, settings: RigSettings):
    """The scene with the rig's structure (``rig.structure`` over :data:`STRUCTURE_DEFAULTS`)
    and its sensor axis (``rig.sensor_deg``) as ``scene.dynamics.structure``, the model
    :func:`~bearing_envelope.physics.dynamics.case.case_params` builds.

    Parameters
    ----------
    scene : Scene
        The record's scene.
    settings : RigSettings
        The rig's settings.

    Returns
    -------
    Scene
        The same scene, its structure the rig's.
    """
    s = {**STRUCTURE_DEFAULTS, **settings.structure, "sensor_angle_deg": settings.sensor_deg}
    dyn = dataclasses.replace(scene.dynamics, structure=tuple(sorted(s.items())))
    return dataclasses.replace(scene, dynamics=dyn)


def simulate_dynamic_record(cond, scene, settings: RigSettings, path) -> dict:
    """Run one record's scene in the dynamic model for the record's length at its fs and
    write its excitation file.

    Parameters
    ----------
    cond : RigCondition
        The record (defect, shaft rate, fs in Hz, ``n_samples``).
    scene : Scene
        Its scene (:func:`~.simulation.condition_scene`).
    settings : RigSettings
        The rig's settings (fidelity of the defect table, structure, sensor).
    path : path
        The ``.npz`` written: ``time``, ``fs``, ``model``, ``housing_force`` (n, 2; N, x along
        the load), ``defect_force`` (N), ``removed_force`` (N: the housing force's deficit
        along the radius where the defect is met), ``roller_load`` (N: the outer contact load of
        the element nearest the defect), ``cpu_s``, ``step_s``, ``defect_force_peak``.

    Returns
    -------
    dict
        ``cpu_s`` of the table and of the run, the step (s), steps and the defect contact's
        peak (N).
    """
    t0 = time.process_time()
    p, _ = case_params(rig_scene(scene, settings), settings.fidelity)
    t_table = time.process_time() - t0
    r = simulate_dynamics(p, cond.n_samples / cond.fs_hz, cond.fs_hz)
    theta = defect_angle(scene, r.t_s)
    e = np.stack([np.cos(theta), np.sin(theta)], axis=1)
    dF = r.housing_force_n - r.housing_force_n.mean(axis=0)
    cage = (p.cage_angle(r.t_s) if p.cage_angle is not None
            else 2 * math.pi * p.cage_rate_hz * r.t_s)
    nearest = np.rint((theta - cage) * p.z / (2 * math.pi)).astype(np.int64) % p.z
    arrays = {"time": r.t_s, "fs": np.float64(cond.fs_hz), "model": np.str_(r.model),
              "housing_force": r.housing_force_n, "defect_force": r.defect_force_n,
              "removed_force": -np.sum(e * dF, axis=1),
              "roller_load": r.element_load_n[np.arange(r.t_s.size), nearest],
              "cpu_s": np.float64(r.cpu_s), "step_s": np.float64(r.step_s),
              "defect_force_peak": np.float64(r.defect_force_peak_n)}
    with atomic_path(Path(path), ".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)
    return {"table_cpu_s": t_table, "run_cpu_s": r.cpu_s, "step_s": r.step_s,
            "steps": r.steps, "defect_force_peak_n": r.defect_force_peak_n}


def is_dynamic(contact: dict) -> bool:
    """Whether an excitation file's contents (``dict(np.load(...))``) come from the dynamic
    model.

    Parameters
    ----------
    contact : dict
        The file's arrays.

    Returns
    -------
    bool
        True for :data:`DYNAMIC_MODEL`.
    """
    return "model" in contact and str(contact["model"]) == DYNAMIC_MODEL


def sensor_excitation(force_xy: np.ndarray, sensor_deg: float, cross_axis: float) -> np.ndarray:
    """The excitation a one-axis sensor reads from a force on the housing (x along the load):
    the fluctuation's component along the axis ``a(t)``, plus the component across it ``c(t)``
    at the cross-axis gain ``k`` and a quarter period later (its Hilbert transform), so that
    through any narrow-band mode the envelope is ``sqrt(a^2 + k^2 c^2)``: the power sum of
    :func:`~bearing_envelope.physics.transfer.direction_gain` (``k = 1``: the force's
    magnitude, a sensor blind to direction; ``k = 0``: the projection).

    Parameters
    ----------
    force_xy : ndarray
        ``(n, 2)``: force on the housing, N.
    sensor_deg : float
        Sensor axis from the load direction, deg.
    cross_axis : float
        Cross-axis gain, in [0, 1].

    Returns
    -------
    numpy.ndarray
        ``(n,)``, N, zero mean.
    """
    f = np.asarray(force_xy, dtype=float)
    f = f - f.mean(axis=0)
    s = math.radians(sensor_deg)
    along = f[:, 0] * math.cos(s) + f[:, 1] * math.sin(s)
    if cross_axis == 0.0:
        return along
    across = -f[:, 0] * math.sin(s) + f[:, 1] * math.cos(s)
    return along + cross_axis * np.imag(sps.hilbert(across))


def excitation_model(path) -> str:
    """The model of an excitation file: ``"dynamic"`` (:func:`simulate_dynamic_record`) or
    ``"quasi_static"`` (a contact history).

    Parameters
    ----------
    path : path
        The ``.npz``.

    Returns
    -------
    str
        ``"dynamic"`` or ``"quasi_static"``.
    """
    with np.load(path, allow_pickle=False) as z:
        return "dynamic" if "model" in z.files and str(z["model"]) == DYNAMIC_MODEL \
            else "quasi_static"
