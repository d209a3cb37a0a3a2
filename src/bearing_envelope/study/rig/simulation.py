"""The rig's simulation: each record's scene, its contact history, and the simulated record made
of it through the record's identified transfer path.

1. :func:`condition_scene`: the rig's scene (``config_rig.yaml``: bearing, material, radial
   load, clearance, cage slip) with the record's defect (location, size, outer-race position)
   and operation (its shaft rate, its sampling rate, its length);
2. :func:`simulate_excitations`: one contact table per defect (location, size, position), shared
   by the records of every load and sampling rate, then the acquisition of each record (the
   table is the cost, the synthesis is cheap);
3. :func:`write_rig_record`: the force the defect removes, through the record's own transfer
   path identified from it (:func:`record_paths`: every mode it holds, each with its resonance,
   damping and gain relative to the first) at the rig's one gain (:func:`rig_gain`), seen by
   the rig's single-axis sensor (:func:`sensor_gain`), plus the record's background.
"""

from __future__ import annotations

import copy
import dataclasses
import json
import math
import os
import zlib
from pathlib import Path
from typing import Any

import numpy as np
from scipy import signal as sps

from ...diagnosis.transfer_path import WELCH_SEGMENT, background_noise, identify_path
from ...io.atomic import atomic_path
from ...physics.history import defect_angle, simulate, synthesize_case
from ...physics.locations import get_location
from ...physics.scene import DEFAULT_SCENE, Scene
from ...physics.transfer import Mode, apply_structure, direction_gain, excitation_from_history
from .config import RigSettings
from .dynamic import (dynamic_path, dynamic_supported, is_dynamic, sensor_excitation,
                      simulate_dynamic_record)
from .records import RigBearing, RigCondition, read_samples

__all__ = ["condition_scene", "simulate_excitations", "existing_excitations", "path_modes",
           "sensor_gain", "record_paths", "rig_gain", "write_rig_record", "REFERENCE_MODE_TOL",
           "REFERENCE_ZETA_FACTOR", "reference_mode", "anchor_gains", "record_spin_seed"]


def _scene_bearing(scene: Scene) -> RigBearing:
    b = scene.bearing
    return RigBearing(b.designation, int(b.rollers_per_row), float(b.roller_diameter_mm),
                      float(b.pitch_diameter_mm), float(b.contact_angle_deg))


def condition_scene(cond: RigCondition, settings: RigSettings) -> Scene:
    """The scene of one condition: the rig's scene with the record's defect and operation.

    Parameters
    ----------
    cond : RigCondition
        The record: its defect location, position, size (um), shaft rate and sampling rate
        (Hz), length, bearing.
    settings : RigSettings
        The rig's base scene mapping (not modified), load (kN) and the ball records'
        ``spin_axis``.

    Returns
    -------
    Scene
        The validated scene, its duration (``operation.revolutions``) covering the record's
        ``n_samples`` (plus half a sample).

    Raises
    ------
    ValueError
        The record's bearing is not the scene's (one line naming both geometries).
    """
    m = copy.deepcopy(settings.scene)
    d = m.setdefault("defect", {})
    d.update(location=cond.location, position_deg=cond.position_deg,
             length_um=cond.length_um, width_um=cond.width_um)
    if get_location(cond.location).spins:  # a defect on a spinning body: the ball's axis
        d["spin_axis"] = settings.ball_spin_axis
        d["spin_seed"] = record_spin_seed(cond.name, d.get("spin_seed", DEFAULT_SCENE["defect"]["spin_seed"]))
    op = m.setdefault("operation", {})
    op.update(shaft_rate_hz=cond.shaft_hz, fs_hz=cond.fs_hz,
              revolutions=(cond.n_samples + 0.5) / cond.fs_hz * cond.shaft_hz)
    scene = Scene.from_mapping(m, load_kN=settings.load_kN, depth_um=cond.depth_um)
    have = _scene_bearing(scene)
    if not cond.bearing.same_geometry(have):
        raise ValueError(f"{cond.name}: bearing: {_geometry(cond.bearing)} is not the rig "
                         f"scene's {_geometry(have)}; allowed: records of the scene's bearing "
                         "(config scene.bearing)")
    return scene


def record_spin_seed(name: str, base: int) -> int:
    """The seed of a record's ball orientations: each record is its own run of the rig (its own
    draw of the ball's orientation, kept through the record where loaded contacts hold the
    spin axis), deterministic from the record's name and the rig scene's ``defect.spin_seed``.

    Parameters
    ----------
    name : str
        The record's name.
    base : int
        The rig scene's ``defect.spin_seed``.

    Returns
    -------
    int
        A seed in [0, 2**32) (CRC-32 of ``"<base>:<name>"``: the same on every platform).
    """
    return zlib.crc32(f"{int(base)}:{name}".encode())


def _geometry(b: RigBearing) -> str:
    return (f"{b.designation or 'geometry'} ({b.n_rollers} x {b.roller_diameter_mm:g} mm on "
            f"{b.pitch_diameter_mm:g} mm, {b.contact_angle_deg:g} deg)")


def _excitation_path(out_dir: Path, cond: RigCondition) -> Path:
    return out_dir / f"{cond.name}_contact.npz"


def simulate_excitations(conditions, settings: RigSettings, out_dir, *, log=print,
                         gain_reference: str | None = None) -> dict:
    """Excitation of every condition: with ``rig.dynamics: quasi_static`` the contact history
    (one contact table per defect key), with ``dynamic`` the dynamic model's run of each record
    (:func:`~.dynamic.simulate_dynamic_record`: a pit on either race or on a rolling element).

    Parameters
    ----------
    conditions : sequence of RigCondition
        The records to re-make (:func:`~.manifest.record_conditions`).
    settings : RigSettings
        The rig's settings (:func:`~.config.read_rig_config`): base scene, load (kN), fidelity,
        sensor direction and cross-axis gain, ``dynamics`` and the structure.
    out_dir : path
        Where ``<record>_contact.npz`` (time, contact_force, removed_force, p_max) and
        ``<record>_dynamic.npz`` (:func:`~.dynamic.simulate_dynamic_record`) are written; an
        existing file is kept (delete it to re-simulate).
    log : callable
        Progress lines.
    gain_reference : str, optional
        Unused (kept for the callers; every record of a run is made by one model, whose gain
        the scorecard identifies).

    Returns
    -------
    dict
        ``{record name: path}`` and CPU s per defect key (or record) under ``"_cpu_s"``.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    for c in conditions:  # every scene (and its bearing) checked before the first table
        condition_scene(c, settings)
    dyn = [c for c in conditions if settings.dynamics == "dynamic" and dynamic_supported(c)]
    qs = [c for c in conditions if c not in dyn]
    paths: dict[str, Any] = {"_cpu_s": {}}
    paths.update(_quasi_static_histories(qs, settings, out_dir, paths["_cpu_s"], log))
    for c in dyn:
        f = dynamic_path(out_dir, c)
        t0 = _cpu()
        if not f.exists():
            info = simulate_dynamic_record(c, condition_scene(c, settings), settings, f)
            log(f"rig: {c.name}: dynamic, table {info['table_cpu_s']:.1f} + run "
                f"{info['run_cpu_s']:.1f} CPU s (step {1e6 * info['step_s']:.3g} us)")
        paths["_cpu_s"][c.name] = _cpu() - t0
        paths[c.name] = str(f)
    return paths


def _quasi_static_histories(conditions, settings: RigSettings, out_dir: Path, cpu: dict,
                            log) -> dict:
    """Contact history of every condition, one contact table per defect key: ``{name:
    path}``; CPU s per key into ``cpu``."""
    groups: dict[str, list[RigCondition]] = {}
    for c in conditions:
        groups.setdefault(c.defect_key, []).append(c)
    paths = {}
    for key, conds in groups.items():
        todo = [c for c in conds if not _excitation_path(out_dir, c).exists()]
        t0 = _cpu()
        if todo:
            first = condition_scene(todo[0], settings)
            hist = simulate(first, settings.fidelity)
            for c in todo:
                scene = condition_scene(c, settings)
                t, sig, _ = synthesize_case(scene, hist.tables, hist.load_distribution,
                                            hist.fidelity)
                _write_excitation(_excitation_path(out_dir, c), t, sig, c)
        cpu[key] = cpu.get(key, 0.0) + _cpu() - t0
        log(f"rig: {key}: {len(todo)} of {len(conds)} simulated, {cpu[key]:.1f} CPU s")
        for c in conds:
            paths[c.name] = str(_excitation_path(out_dir, c))
    return paths


def existing_excitations(conditions, settings: RigSettings, out_dir) -> dict:
    """The excitations a previous run left in ``out_dir`` (``--score-only``): as
    :func:`simulate_excitations` returns them, for the records whose file exists.

    Parameters
    ----------
    conditions : sequence of RigCondition
        The rig's records.
    settings : RigSettings
        The rig's settings (``dynamics``).
    out_dir : path
        The run's contact folder.

    Returns
    -------
    dict
        ``{name: path}`` (the dynamic file where ``dynamics`` is ``dynamic`` and it exists,
        else the contact history) and ``"_quasi_static"``: every contact history found.
    """
    out: dict[str, Any] = {"_quasi_static": {}}
    for c in conditions:
        q, d = _excitation_path(Path(out_dir), c), dynamic_path(out_dir, c)
        if q.exists():
            out["_quasi_static"][c.name] = str(q)
        if settings.dynamics == "dynamic" and dynamic_supported(c) and d.exists():
            out[c.name] = str(d)
        elif q.exists() and not (settings.dynamics == "dynamic" and dynamic_supported(c)):
            out[c.name] = str(q)
    return out


def _cpu() -> float:
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def _write_excitation(path: Path, t, sig: dict, cond: RigCondition) -> None:
    arrays = {"time": t, "fs": np.float64(cond.fs_hz),
              **{k: np.asarray(sig[k]) for k in ("contact_force", "removed_force", "p_max",
                                                 "roller_load") if k in sig}}

    with atomic_path(path, ".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)


# ------------------------------------------------------------------ simulated records
#: A record's mode is the rig's reference mode (whose gain the reference records identify)
#: when its f_n is within this fraction of the reference mode's (3 %: the identification's
#: f_n tolerance) ...
REFERENCE_MODE_TOL = 0.03
#: ... and its damping within this factor of the reference mode's (either way): a broad hump
#: identified near the reference frequency (zeta 0.22 at 3.35 kHz in record 146, against
#: 0.015-0.026 on the reference records) is not the reference mode.
REFERENCE_ZETA_FACTOR = 2.0


def path_modes(path, first_gain: float) -> list:
    """The record's identified modes, the first (strongest) at gain ``first_gain`` and each
    other at its gain relative to the first as identified (:meth:`TransferPath.structure`: the
    same impulses ring every mode, so the ratio of the gains is the record's own).

    Parameters
    ----------
    path : TransferPath
        The record's identified transfer path (f_n in Hz, damping, gains).
    first_gain : float
        Gain of the first mode relative to the rig's reference mode (:func:`anchor_gains`;
        1: the first mode rings at the rig's gain).

    Returns
    -------
    list of Mode
        The record's modes, gains relative to the rig's reference mode (dimensionless).
    """
    modes = path.structure()
    first = modes[0].gain
    return [Mode(m.f_n_hz, m.zeta, first_gain * m.gain / first) for m in modes]


def reference_mode(path, reference_hz: float, reference_zeta: float):
    """The record's mode that is the rig's reference mode, if it holds one: f_n within
    :data:`REFERENCE_MODE_TOL` and damping within :data:`REFERENCE_ZETA_FACTOR` of the
    reference's, the nearest in f_n.

    Parameters
    ----------
    path : TransferPath
        The record's identified transfer path.
    reference_hz, reference_zeta : float
        The reference mode's f_n (Hz) and damping ratio (:func:`rig_gain`).

    Returns
    -------
    Mode or None
        The matching mode (gain as :meth:`TransferPath.structure` gives it), None if none.
    """
    near = [m for m in path.structure()
            if abs(m.f_n_hz - reference_hz) <= REFERENCE_MODE_TOL * reference_hz
            and reference_zeta / REFERENCE_ZETA_FACTOR <= m.zeta
            <= reference_zeta * REFERENCE_ZETA_FACTOR]
    return min(near, key=lambda m: abs(m.f_n_hz - reference_hz)) if near else None


def anchor_gains(conditions, paths: dict, reference_hz: float, reference_zeta: float) -> dict:
    """Each record's first-mode gain relative to the rig's reference mode, one per group of
    records that share the structure's path (fault location, outer-race position, fs): the
    median over the group's records that hold the reference mode (:func:`reference_mode`) of
    their first mode's gain over it; for a group where none holds it, the same median over the
    records of its location and position at any fs; 1 where none of those holds it either (the
    first mode rings at the rig's gain). The ratio is a property of the rig and the fault's
    place, not of the load: one record's weak or missing reference mode does not move its level.

    Parameters
    ----------
    conditions : sequence of RigCondition
        The rig's records.
    paths : dict
        :func:`record_paths`.
    reference_hz, reference_zeta : float
        The reference mode's f_n (Hz) and damping ratio (:func:`rig_gain`).

    Returns
    -------
    dict
        ``{name: (first_gain, number of records it is the median of)}``.
    """
    ratio = {}
    for c in conditions:
        p = paths[c.name][0]
        ref = None if p is None else reference_mode(p, reference_hz, reference_zeta)
        if ref is not None:
            ratio[c.name] = p.structure()[0].gain / ref.gain
    out = {}
    for c in conditions:
        for same in (lambda o: (o.location, o.position_deg, o.fs_hz) ==
                     (c.location, c.position_deg, c.fs_hz),
                     lambda o: (o.location, o.position_deg) == (c.location, c.position_deg)):
            got = [ratio[o.name] for o in conditions if o.name in ratio and same(o)]
            if got:
                out[c.name] = (float(np.median(got)), len(got))
                break
        else:
            out[c.name] = (1.0, 0)
    return out


def _unit_response(cond: RigCondition, contact: dict, path, first_gain: float,
                   settings: RigSettings | None = None) -> np.ndarray:
    """The modes' response (the reference mode's gain 1 per N at resonance: :func:`path_modes`)
    to the force the defect removes from the contact (the blocked-force deficit; the roller
    load's own sweep through the load zone is a rotating load, not a force on the housing),
    seen by the rig's single-axis sensor (``settings``: :func:`sensor_gain`); for a dynamic
    excitation (:func:`~.dynamic.is_dynamic`) the force on the housing read by the same sensor
    (:func:`~.dynamic.sensor_excitation`; None: blind to direction)."""
    if is_dynamic(contact):
        f = np.asarray(contact["housing_force"][:cond.n_samples])
        e = (sensor_excitation(f, 0.0, 1.0) if settings is None else
             sensor_excitation(f, settings.sensor_deg, settings.sensor_cross_axis))
        return apply_structure(e, cond.fs_hz, path_modes(path, first_gain))
    e = excitation_from_history(-contact["removed_force"][:cond.n_samples])
    if settings is not None:
        e = e * sensor_gain(cond, settings, np.asarray(contact["time"][:cond.n_samples]))
    return apply_structure(e, cond.fs_hz, path_modes(path, first_gain))


def sensor_gain(cond: RigCondition, settings: RigSettings, t: np.ndarray) -> np.ndarray:
    """The rig sensor's gain for the force the defect removes, at times ``t``: the force acts
    along the contact's radius where the defect is met (:func:`defect_angle`), the sensor reads
    it through :func:`direction_gain` (``settings.sensor_deg``, ``sensor_cross_axis``).

    Parameters
    ----------
    cond : RigCondition
        The record (its fault location, position in deg and shaft rate in Hz).
    settings : RigSettings
        The rig's settings (:func:`~.config.read_rig_config`): base scene, load (kN), fidelity,
        sensor direction and cross-axis gain.
    t : ndarray
        Times of the record, s.

    Returns
    -------
    ndarray
        Gain in [sensor_cross_axis, 1], shape of ``t``.
    """
    if settings.sensor_cross_axis >= 1.0:
        return np.ones(np.shape(t))
    theta = defect_angle(condition_scene(cond, settings), t)
    return direction_gain(theta, math.radians(settings.sensor_deg), settings.sensor_cross_axis)


def record_paths(conditions, *, log=print) -> dict:
    """The transfer path of every record: its own where identified, else the rig's common one
    (median f_n and zeta of the identified records without flags at its fs, else at any fs)
    with its own background (the whole record's spectrum).

    Parameters
    ----------
    conditions : sequence of RigCondition
        The rig's records (:func:`~.manifest.record_conditions`).
    log : callable
        Progress lines.

    Returns
    -------
    dict
        ``{name: (TransferPath, "identified" | reason it was not)}``

    Raises
    ------
    ValueError
        No record's transfer path could be identified.
    """
    out = {}
    for c in conditions:
        try:
            p = identify_path(read_samples(c.path), c.fs_hz, c.rates)
        except ValueError as exc:
            out[c.name] = (None, str(exc))
            continue
        unresolved = [f for f in p.flags if "not resolved" in f]
        out[c.name] = (None, unresolved[0]) if unresolved else (p, "identified")
    for c in conditions:
        if out[c.name][0] is not None:
            continue
        ident = [p for p, st in out.values() if st == "identified"]
        if not ident:
            raise ValueError("records: no record's transfer path could be identified")
        same = ([p for p in ident if p.fs_hz == c.fs_hz and not p.flags]
                or [p for p in ident if not p.flags] or ident)
        x = read_samples(c.path)
        f, psd = sps.welch(x - x.mean(), c.fs_hz, nperseg=WELCH_SEGMENT)
        common = dataclasses.replace(
            same[0], fs_hz=c.fs_hz, f_n_hz=float(np.median([p.f_n_hz for p in same])),
            zeta=float(np.median([p.zeta for p in same])), background_freq_hz=list(map(float, f)),
            background_psd=list(map(float, psd)), background_source="record (no events found)",
            flags=[f"rig's common path: {out[c.name][1]}"], modes=[], modes_rejected=[])
        out[c.name] = (common, out[c.name][1])
    log(f"rig: {sum(1 for _, s in out.values() if s == 'identified')} of {len(out)} paths "
        "identified")
    return out


def rig_gain(conditions, paths: dict, contact_paths: dict, reference: str,
             settings: RigSettings | None = None) -> tuple:
    """The rig's one gain (acceleration per N at resonance): measured event amplitude over the
    simulated one at unit gain, on the reference records (names containing ``reference``).

    Parameters
    ----------
    conditions : sequence of RigCondition
        The rig's records (:func:`~.manifest.record_conditions`).
    paths : dict
        :func:`record_paths`.
    contact_paths : dict
        :func:`simulate_excitations`.
    reference : str
        Records (name contains) the gain is identified on.
    settings : RigSettings, optional
        The rig's sensor (:func:`sensor_gain`).

    Returns
    -------
    (float, float, float, float, float)
        Median, min and max over the reference records, and the median f_n (Hz) and damping
        ratio of their first modes: the reference mode the gain belongs to
        (:func:`anchor_gains`).

    Raises
    ------
    ValueError
        ``reference`` names no identified record.
    """
    ratios, f_ref, z_ref = [], [], []
    for c in conditions:
        p, status = paths[c.name]
        if reference not in c.name or status != "identified":
            continue
        with np.load(contact_paths[c.name]) as z:
            # a reference record's first mode is the reference mode
            y = _unit_response(c, dict(z), p, 1.0, settings=settings)
        tiny = 1e-3 * np.std(y) * np.random.default_rng(1).standard_normal(y.size)
        rates = c.rates
        own = {p.event_name: rates.get(p.event_name, p.event_hz)}
        a = identify_path(y + tiny, c.fs_hz, own).amplitude
        ratios.append(p.amplitude / a)
        f_ref.append(p.f_n_hz)
        z_ref.append(p.zeta)
    if not ratios:
        raise ValueError(f"rig.gain_reference: {reference!r} names no identified record")
    return (float(np.median(ratios)), float(min(ratios)), float(max(ratios)),
            float(np.median(f_ref)), float(np.median(z_ref)))


def write_rig_record(cond: RigCondition, contact_path: str, path, gain: float, out_dir,
                     *, seed: int = 0, first_gain: float = 1.0,
                     settings: RigSettings | None = None) -> str:
    """Simulated record of one condition: the contact force through the record's modes, the
    anchor mode (:func:`path_modes`) at the rig's gain, plus its background; written like a
    measured record (``x``, ``fs``, ``meta_json``: the condition, ``shaft_hz`` among it, and the
    transfer path).

    Parameters
    ----------
    cond : RigCondition
        The record re-made (its name, fs and shaft rate in Hz, its fault).
    contact_path : str
        Its ``<name>_contact.npz`` (:func:`simulate_excitations`).
    path : TransferPath
        Its transfer path (:func:`record_paths`).
    gain : float
        The rig's gain (:func:`rig_gain`).
    out_dir : path
        Where ``<name>_sim.npz`` is written.
    seed : int
        Seed of the background noise.
    first_gain : float
        The record's first mode's gain relative to the rig's reference mode
        (:func:`anchor_gains`; 1: the first mode rings at the rig's gain).
    settings : RigSettings, optional
        The rig's sensor (:func:`sensor_gain`); None: blind to direction.

    Returns
    -------
    str
        The simulated record's path.
    """
    with np.load(contact_path) as z:
        contact = dict(z)
    y = gain * _unit_response(cond, contact, path, first_gain, settings)
    x = y + background_noise(path, y.size, seed=seed)
    meta = cond.meta()
    meta.update(simulated=True, source_record=cond.name,
                excitation="dynamic" if is_dynamic(contact) else "quasi_static", transfer_path={
        "f_n_hz": path.f_n_hz, "zeta": path.zeta, "gain_per_N": gain,
        "modes": [dataclasses.asdict(m) for m in path_modes(path, first_gain)],
        "first_mode_gain_re_reference": first_gain,
        "sensor_deg": None if settings is None else settings.sensor_deg,
        "sensor_cross_axis": None if settings is None else settings.sensor_cross_axis,
        "background": path.background_source, "flags": path.flags})
    out = Path(out_dir) / f"{cond.name}_sim.npz"
    with atomic_path(out, ".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez(fh, x=x, fs=np.float64(cond.fs_hz), meta_json=json.dumps(meta))
    return str(out)
