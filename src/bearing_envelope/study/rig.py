"""The virtual CWRU rig: every measured fault record re-made as a simulated record of that rig.

For each measured record (a CWRU drive-end record, or any record with the same meta layout) the
rig

1. builds the record's scene (:func:`record_conditions`, :func:`condition_scene`): the rig's
   scene (``config_rig.yaml``: bearing, material, radial load, clearance, cage slip) with the
   record's defect (location, diameter, outer-race position) and operation (its shaft rate, its
   sampling rate, its length);
2. simulates the contact history (:func:`simulate_excitations`): one contact table per defect
   (location, size, position), shared by the records of every load and sampling rate, then the
   acquisition of each record (the table is the cost, the synthesis is cheap);
3. turns the contact force into an accelerometer record of *that* machine (:func:`rig_record`):
   the record's own transfer path identified from it
   (:func:`bearing_envelope.diagnosis.transfer_path.identify_path`: every mode it holds, each
   with its resonance, damping and gain relative to the first) with the rig's one gain, plus the measured background (a healthy record of the same machine).

Why a study module and not a Snakemake overlay: the sweep's dimensions are load x depth x
width of one scene; the rig varies the defect location, the outer-race position, the shaft
rate and the sampling rate per record and reads the measured records themselves, none of which
the sweep's case grid names.
"""

from __future__ import annotations

import copy
import dataclasses
import json
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy import signal as sps

from ..checks import check_number
from ..diagnosis.transfer_path import WELCH_SEGMENT, background_noise, identify_path
from ..io.atomic import atomic_path
from ..physics.history import defect_angle, simulate, synthesize_case
from ..physics.scene import Scene
from ..physics.transfer import Mode, apply_structure, direction_gain, excitation_from_history
from .rig_records import pair_figure, read_record, record_pairs, rig_rates, save_figure
from .config_read import read_yaml

__all__ = ["RigCondition", "RigSettings", "record_conditions", "condition_scene",
           "read_rig_config", "simulate_excitations", "INCH_UM", "POSITION_DEG"]

#: micrometres per inch
INCH_UM = 25400.0

#: Outer-race clock positions of the CWRU records, degrees from the load direction (6:00).
POSITION_DEG = {"6:00": 0.0, "3:00": 90.0, "12:00": 180.0}

_LOCATIONS = {"inner_race": "inner_race", "outer_race": "outer_race", "ball": "rolling_element"}


@dataclass(frozen=True)
class RigCondition:
    """One measured record and the scene that re-makes it.

    Attributes
    ----------
    name : str
        Record name (file name without ``.npz``).
    path : str
        The measured record.
    location : str
        ``inner_race`` | ``outer_race`` | ``rolling_element``.
    diameter_in : float
        Pit diameter, inch.
    depth_um : float
        Pit depth, um.
    position_deg : float
        Outer-race position from the load direction, deg (0 elsewhere).
    load_hp : int
        Motor load, hp.
    shaft_hz : float
        The record's shaft rate, Hz.
    fs_hz : float
        The record's sampling rate, Hz.
    n_samples : int
        The record's length.
    """

    name: str
    path: str
    location: str
    diameter_in: float
    depth_um: float
    position_deg: float
    load_hp: int
    shaft_hz: float
    fs_hz: float
    n_samples: int

    @property
    def defect_key(self) -> str:
        """The contact table's key: location, size and position (shared over loads and fs)."""
        return f"{self.location}_{self.diameter_in * 1000:g}mil_{self.position_deg:g}deg"


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
    depth_um : dict
        Pit depth per diameter (mils as a string key), um.
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
    depth_um: dict
    ball_spin_axis: str = "fixed"
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
    """
    raw = read_yaml(path)
    for key in ("scene", "rig"):
        if not isinstance(raw, dict) or key not in raw:
            raise ValueError(f"{path}: {key}: missing section; allowed: a mapping")
    rig = raw["rig"]
    load = float(rig.get("load_kN", "nan"))
    if not (math.isfinite(load) and load > 0):
        raise ValueError(f"{path}: rig.load_kN: got {rig.get('load_kN')!r}; allowed: > 0 kN")
    depth = {str(k): float(v) for k, v in (rig.get("depth_um") or {}).items()}
    if not depth:
        raise ValueError(f"{path}: rig.depth_um: missing; allowed: a mapping mils -> um")
    sensor = _number_in(path, rig, "sensor_deg", 180.0, 0.0, 360.0)
    cross = _number_in(path, rig, "sensor_cross_axis", 1.0, 0.0, 1.0)
    return RigSettings(raw["scene"], load, str(rig.get("fidelity", "standard")), depth,
                       str(rig.get("ball_spin_axis", "fixed")), sensor, cross)


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


def _meta(path: str) -> dict:
    with np.load(path, allow_pickle=False) as z:
        meta = json.loads(str(z["meta_json"])) if "meta_json" in z.files else {}
        meta["_fs"] = float(z["fs"]) if "fs" in z.files else meta.get("fs_hz")
        meta["_n"] = int(z["x"].size)
    return meta


def record_conditions(paths, settings: RigSettings) -> list[RigCondition]:
    """The rig condition of each measured fault record (normal records are left out).

    Parameters
    ----------
    paths : sequence of str
        ``.npz`` records with ``x``, ``fs`` and ``meta_json`` (fault, fault_diameter_in,
        outer_race_position, shaft_hz, load_hp), as in /work/shared/data/real.
    settings : RigSettings

    Returns
    -------
    list of RigCondition
    """
    out = []
    for p in sorted(paths):
        meta = _meta(p)
        fault = meta.get("fault")
        if fault not in _LOCATIONS:
            continue
        mils = f"{float(meta['fault_diameter_in']) * 1000:g}"
        if mils not in settings.depth_um:
            raise ValueError(f"{p}: fault_diameter_in {meta['fault_diameter_in']}: no "
                             f"rig.depth_um entry; allowed: {sorted(settings.depth_um)} mils")
        pos = str(meta.get("outer_race_position") or "").split(" ")[0]
        out.append(RigCondition(
            Path(p).stem, str(p), _LOCATIONS[fault], float(meta["fault_diameter_in"]),
            settings.depth_um[mils], POSITION_DEG.get(pos, 0.0), int(meta.get("load_hp", 0)),
            float(meta["shaft_hz"]), float(meta["_fs"]), int(meta["_n"])))
    return out


def condition_scene(cond: RigCondition, settings: RigSettings) -> Scene:
    """The scene of one condition: the rig's scene with the record's defect and operation.

    Parameters
    ----------
    cond : RigCondition
        The record: its defect location, position and pit diameter (inch; the defect's
        length and width, in um) and depth (um), shaft rate and sampling rate (Hz), length.
    settings : RigSettings
        The rig's base scene mapping (not modified), load (kN) and the ball records'
        ``spin_axis``.

    Returns
    -------
    Scene
        The validated scene, its duration (``operation.revolutions``) covering the record's
        ``n_samples`` (plus half a sample).
    """
    m = copy.deepcopy(settings.scene)
    d = m.setdefault("defect", {})
    d.update(location=cond.location, position_deg=cond.position_deg,
             length_um=cond.diameter_in * INCH_UM, width_um=cond.diameter_in * INCH_UM)
    if cond.location == "rolling_element":
        d["spin_axis"] = settings.ball_spin_axis
    op = m.setdefault("operation", {})
    op.update(shaft_rate_hz=cond.shaft_hz, fs_hz=cond.fs_hz,
              revolutions=(cond.n_samples + 0.5) / cond.fs_hz * cond.shaft_hz)
    return Scene.from_mapping(m, load_kN=settings.load_kN, depth_um=cond.depth_um)


def _excitation_path(out_dir: Path, cond: RigCondition) -> Path:
    return out_dir / f"{cond.name}_contact.npz"


def simulate_excitations(conditions, settings: RigSettings, out_dir, *, log=print) -> dict:
    """Contact history of every condition, one contact table per defect key.

    Parameters
    ----------
    conditions : sequence of RigCondition
    settings : RigSettings
    out_dir : path
        Where ``<record>_contact.npz`` (time, contact_force, removed_force, p_max) is written;
        an existing file is kept (delete it to re-simulate).
    log : callable
        Progress lines.

    Returns
    -------
    dict
        ``{record name: path}``, and ``cpu_s`` per defect key under ``"_cpu_s"``.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    groups: dict[str, list[RigCondition]] = {}
    for c in conditions:
        groups.setdefault(c.defect_key, []).append(c)
    paths: dict[str, Any] = {"_cpu_s": {}}
    for key, conds in groups.items():
        todo = [c for c in conds if not _excitation_path(out_dir, c).exists()]
        t0 = _cpu()
        if todo:
            first = condition_scene(todo[0], settings)
            hist = simulate(first, settings.fidelity)
            for c in todo:
                scene = condition_scene(c, settings)
                tables = hist.table if scene.defect.location == "inner_race" else hist.tables
                t, sig, _ = synthesize_case(scene, tables, hist.load_distribution, hist.fidelity)
                _write_excitation(_excitation_path(out_dir, c), t, sig, c)
        paths["_cpu_s"][key] = _cpu() - t0
        log(f"rig: {key}: {len(todo)} of {len(conds)} simulated, {paths['_cpu_s'][key]:.1f} CPU s")
        for c in conds:
            paths[c.name] = str(_excitation_path(out_dir, c))
    return paths


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
#: f_n tolerance).
REFERENCE_MODE_TOL = 0.03


def path_modes(path, reference_hz: float | None = None) -> list:
    """The record's identified modes, each gain relative to the anchor mode's (gain 1 per N
    at resonance) as identified (:meth:`TransferPath.structure`: the same impulses ring every
    mode, so the ratio of the gains is the record's). The anchor is the record's mode at the
    rig's reference mode ``reference_hz`` (the structural mode whose gain the rig identifies
    on its reference records) where the record holds one, else its first mode.

    Parameters
    ----------
    path : TransferPath
    reference_hz : float, optional
        f_n of the rig's reference mode, Hz; None: the first mode is the anchor.

    Returns
    -------
    list of Mode
    """
    modes = path.structure()
    anchor = modes[0]
    if reference_hz is not None:
        near = [m for m in modes
                if abs(m.f_n_hz - reference_hz) <= REFERENCE_MODE_TOL * reference_hz]
        anchor = min(near, key=lambda m: abs(m.f_n_hz - reference_hz)) if near else anchor
    return [Mode(m.f_n_hz, m.zeta, m.gain / anchor.gain) for m in modes]


def _unit_response(cond: RigCondition, contact: dict, path, reference_hz: float | None = None,
                   settings: RigSettings | None = None) -> np.ndarray:
    """The modes' response (the anchor mode's gain 1 per N at resonance: :func:`path_modes`)
    to the force the defect removes from the contact (the blocked-force deficit; the roller
    load's own sweep through the load zone is a rotating load, not a force on the housing),
    seen by the rig's single-axis sensor (``settings``: :func:`sensor_gain`)."""
    e = excitation_from_history(-contact["removed_force"][:cond.n_samples])
    if settings is not None:
        e = e * sensor_gain(cond, settings, np.asarray(contact["time"][:cond.n_samples]))
    return apply_structure(e, cond.fs_hz, path_modes(path, reference_hz))


def sensor_gain(cond: RigCondition, settings: RigSettings, t: np.ndarray) -> np.ndarray:
    """The rig sensor's gain for the force the defect removes, at times ``t``: the force acts
    along the contact's radius where the defect is met (:func:`defect_angle`), the sensor reads
    it through :func:`direction_gain` (``settings.sensor_deg``, ``sensor_cross_axis``).

    Parameters
    ----------
    cond : RigCondition
    settings : RigSettings
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

    Returns
    -------
    dict
        ``{name: (TransferPath, "identified" | reason it was not)}``
    """
    out = {}
    for c in conditions:
        x, _ = read_record(c.path)
        try:
            p = identify_path(x, c.fs_hz, rig_rates(c.shaft_hz))
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
        x, _ = read_record(c.path)
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

    Returns
    -------
    (float, float, float, float)
        Median, min and max over the reference records, and the median f_n of their first
        modes (Hz: the mode the gain belongs to, :func:`path_modes`'s ``reference_hz``).
    """
    ratios, f_ref = [], []
    for c in conditions:
        p, status = paths[c.name]
        if reference not in c.name or status != "identified":
            continue
        with np.load(contact_paths[c.name]) as z:
            y = _unit_response(c, dict(z), p, settings=settings)
        tiny = 1e-3 * np.std(y) * np.random.default_rng(1).standard_normal(y.size)
        rates = rig_rates(c.shaft_hz)
        own = {p.event_name: rates.get(p.event_name, p.event_hz)}
        a = identify_path(y + tiny, c.fs_hz, own).amplitude
        ratios.append(p.amplitude / a)
        f_ref.append(p.f_n_hz)
    if not ratios:
        raise ValueError(f"rig.gain_reference: {reference!r} names no identified record")
    return (float(np.median(ratios)), float(min(ratios)), float(max(ratios)),
            float(np.median(f_ref)))


def write_rig_record(cond: RigCondition, contact_path: str, path, gain: float, out_dir,
                     *, seed: int = 0, reference_hz: float | None = None,
                     settings: RigSettings | None = None) -> str:
    """Simulated record of one condition: the contact force through the record's modes, the
    anchor mode (:func:`path_modes`) at the rig's gain, plus its background; written like the
    measured record (x, fs, meta_json)."""
    with np.load(contact_path) as z:
        y = gain * _unit_response(cond, dict(z), path, reference_hz, settings)
    x = y + background_noise(path, y.size, seed=seed)
    _, meta = read_record(cond.path)
    meta.update(simulated=True, source_record=cond.name, transfer_path={
        "f_n_hz": path.f_n_hz, "zeta": path.zeta, "gain_per_N": gain,
        "modes": [dataclasses.asdict(m) for m in path_modes(path, reference_hz)],
        "reference_mode_hz": reference_hz,
        "sensor_deg": None if settings is None else settings.sensor_deg,
        "sensor_cross_axis": None if settings is None else settings.sensor_cross_axis,
        "background": path.background_source, "flags": path.flags})
    out = Path(out_dir) / f"{cond.name}_sim.npz"
    with atomic_path(out, ".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez(fh, x=x, fs=np.float64(cond.fs_hz), meta_json=json.dumps(meta))
    return str(out)


# ------------------------------------------------------------------ scorecard
#: The family each defect location is judged on (analyze's family names).
TRUTH_FAMILY = {"inner_race": "bpfi", "outer_race": "bpfo", "rolling_element": "bsf2"}
#: Tolerances of the pass rules (docs/virtual_rig.md), dB or fraction.
TOL_DB, TOL_LINE = 6.0, 0.005


def _class(diag, conf, family) -> str:
    if diag != family:
        return "nothing" if not isinstance(diag, str) or not diag else f"other:{diag}"
    return "named" if conf in ("medium", "high") else "low"


def record_features(table, lines, name: str, family: str) -> dict:
    """The scorecard's features of one record from analyze's verdict table and lines CSV."""
    rows = table[(table.record == name) & (table.family == family)]
    if rows.empty:
        return {"diagnosis": None, "confidence": None}
    r = rows.iloc[0]
    diag = r.record_diagnosis if isinstance(r.record_diagnosis, str) else ""
    out = {"diagnosis": diag, "confidence": r.record_confidence,
           "class": _class(diag, r.record_confidence, family), "detected": bool(r.detected),
           "band_low_hz": float(r.band_low_hz), "band_high_hz": float(r.band_high_hz),
           "fr_hz": float(r.fr_hz)}
    if not r.detected:
        return out
    fr = float(r.fr_hz)
    out.update(line_orders=float(r.h1_hz) / fr, height_db=float(r.h1_db),
               h1=float(r.h1_amplitude),
               h2_db=20 * math.log10(max(r.h2_amplitude, 1e-300) / r.h1_amplitude),
               h3_db=20 * math.log10(max(r.h3_amplitude, 1e-300) / r.h1_amplitude))
    ln = lines[(lines.file.str.contains(name)) & (lines.band == r.band) &
               (lines.base == family) & (lines.order == 1)]
    sb = ln[ln.sideband.abs() == 1].amplitude  # the +-1 sidebands (the written rule)
    if family != "bpfo" and len(sb):
        out["sideband_db"] = 20 * math.log10(max(sb.mean(), 1e-300) / r.h1_amplitude)
    return out


def _pass(key, m, s) -> str:
    if m.get(key) is None or s.get(key) is None:
        return "n/a"
    tol = TOL_LINE * m[key] if key == "line_orders" else TOL_DB
    return "PASS" if abs(m[key] - s[key]) <= tol else "FAIL"


def scorecard(conditions, measured_table, measured_lines, sim_table, sim_lines):
    """One row per record: measured and simulated features and each rule's outcome.

    Parameters
    ----------
    conditions : sequence of RigCondition
    measured_table, sim_table : pandas.DataFrame
        ``analyze --table`` of the measured and of the simulated records.
    measured_lines, sim_lines : pandas.DataFrame
        ``analyze --csv`` of the same.

    Returns
    -------
    pandas.DataFrame
    """
    import pandas as pd  # lazy: pandas ~1.8 s, only the scorecard needs it

    rows = []
    for c in conditions:
        fam = TRUTH_FAMILY[c.location]
        m = record_features(measured_table, measured_lines, c.name, fam)
        s = record_features(sim_table, sim_lines, c.name + "_sim", fam)
        row = {"record": c.name, "family": fam, "load_hp": c.load_hp, "fs_hz": c.fs_hz,
               "position_deg": c.position_deg, "diameter_in": c.diameter_in}
        for k in ("diagnosis", "confidence", "class", "line_orders", "sideband_db", "h2_db",
                  "h3_db", "height_db", "h1", "band_low_hz", "band_high_hz", "fr_hz"):
            row[f"meas_{k}"], row[f"sim_{k}"] = m.get(k), s.get(k)
        row["rule_family"] = ("PASS" if m.get("diagnosis") == s.get("diagnosis") else "FAIL")
        row["rule_class"] = "PASS" if m.get("class") == s.get("class") else "FAIL"
        gate = m.get("detected", False)
        for k in ("line_orders", "sideband_db", "h2_db", "h3_db", "height_db"):
            row[f"rule_{k}"] = _pass(k, m, s) if gate else "n/a"
        rows.append(row)
    return pd.DataFrame(rows)


def _ratio_db(a, b):
    """20 log10(a / b), None where either is missing (no line detected)."""
    try:
        a, b = float(a), float(b)
    except (TypeError, ValueError):
        return None
    return 20 * math.log10(a / b) if np.isfinite(a) and np.isfinite(b) and a > 0 and b > 0 \
        else None


def load_trends(card, *, flat_db_per_hp: float = 1.0) -> list:
    """Slope of the outer race's line height over the motor load (dB/hp, least squares over the
    records of one position, size and fs with a line on both sides) and the written rule:
    same sign, or both within +-``flat_db_per_hp``."""
    out = []
    or_ = card[card.family == "bpfo"]
    for (pos, dia, fs), g in or_.groupby(["position_deg", "diameter_in", "fs_hz"]):
        g = g[g.meas_height_db.notna() & g.sim_height_db.notna()]
        if g.load_hp.nunique() < 2:
            continue
        hp = g.load_hp.to_numpy(float)
        m, s = (float(np.polyfit(hp, g[k].to_numpy(float), 1)[0])
                for k in ("meas_height_db", "sim_height_db"))
        flat = abs(m) <= flat_db_per_hp and abs(s) <= flat_db_per_hp
        out.append({"position_deg": pos, "diameter_in": dia, "fs_hz": fs, "n": len(g),
                    "meas_db_per_hp": m, "sim_db_per_hp": s,
                    "rule": "PASS" if flat or m * s > 0 else "FAIL"})
    return out


def outer_race_ratios(card) -> list:
    """BPFO fundamental at 3:00 over 6:00 (same size, load, fs), measured and simulated, dB."""
    out = []
    or_ = card[card.family == "bpfo"]
    for _, r3 in or_[or_.position_deg == 90.0].iterrows():
        r6 = or_[(or_.position_deg == 0.0) & (or_.load_hp == r3.load_hp) &
                 (or_.diameter_in == r3.diameter_in) & (or_.fs_hz == r3.fs_hz)]
        if r6.empty:
            continue
        r6 = r6.iloc[0]
        meas, sim = _ratio_db(r3.meas_h1, r6.meas_h1), _ratio_db(r3.sim_h1, r6.sim_h1)
        rule = "n/a" if meas is None else (
            "FAIL: no simulated line" if sim is None else
            "PASS" if abs(meas - sim) <= TOL_DB else "FAIL")
        out.append({"record_3": r3.record, "record_6": r6.record, "meas_db": meas,
                    "sim_db": sim, "rule": rule})
    return out


#: The bands the 3:00 / 6:00 ratio is also read in with both records in one band (not the
#: rule: a second reading of the same lines): analyze's fixed fs/4-3fs/8 band and the raw
#: signal's envelope.
RATIO_BANDS = ("fs4_3fs8", "raw")


def _line_amplitude(lines, name: str, band: str):
    """The BPFO fundamental's amplitude in one of analyze's bands (None: no such row)."""
    ln = lines[(lines.file.str.contains(name, regex=False)) & (lines.band == band) &
               (lines.base == "bpfo") & (lines.order == 1) & (lines.sideband == 0)]
    return float(ln.amplitude.iloc[0]) if len(ln) else None


def _band_ratios(lines, name: str, band: str, family: str) -> dict:
    """2x/1x, 3x/1x and (not BPFO) the +-1 sidebands over the line, dB, in one band."""
    g = lines[lines.file.str.contains(f"/{name}.npz", regex=False) & (lines.band == band)
              & (lines.base == family)]
    a = {(int(o), int(sb)): float(v) for o, sb, v in zip(g.order, g.sideband, g.amplitude)}
    h1 = a.get((1, 0), 0.0)
    if h1 <= 0:
        return {}
    out = {k: 20 * math.log10(max(a.get((o, 0), 0.0), 1e-300) / h1)
           for k, o in (("h2_db", 2), ("h3_db", 3))}
    if family != "bpfo" and (1, -1) in a and (1, 1) in a:
        out["sideband_db"] = 20 * math.log10(max(0.5 * (a[(1, -1)] + a[(1, 1)]), 1e-300) / h1)
    return out


def features_in_measured_band(card, measured_lines, sim_lines) -> list:
    """The harmonic and sideband ratios of both records read in the measured record's best band
    (a second reading, not the rule: the rule reads each record in its own best band, and the
    simulated record's can differ). Only where that band is one of analyze's fixed bands (a
    kurtogram band is the record's own).

    Parameters
    ----------
    card : pandas.DataFrame
        :func:`scorecard`.
    measured_lines, sim_lines : pandas.DataFrame
        analyze's lines tables of the measured and the simulated records.

    Returns
    -------
    list of dict
        Per record and feature: band, measured and simulated dB, ``within_tol``.
    """
    out = []
    for _, r in card[card.meas_h1.notna()].iterrows():
        m = measured_lines[measured_lines.file.str.contains(f"/{r.record}.npz", regex=False)
                           & np.isclose(measured_lines.band_low_hz, r.meas_band_low_hz)
                           & np.isclose(measured_lines.band_high_hz, r.meas_band_high_hz)]
        bands = set(m.band) - {"kurtogram"}
        if not bands:
            continue
        band = sorted(bands)[0]
        fm = _band_ratios(measured_lines, r.record, band, r.family)
        fs = _band_ratios(sim_lines, f"{r.record}_sim", band, r.family)
        for k in ("sideband_db", "h2_db", "h3_db"):
            if k in fm and k in fs:
                out.append({"record": r.record, "band": band, "feature": k, "meas_db": fm[k],
                            "sim_db": fs[k], "within_tol": abs(fm[k] - fs[k]) <= TOL_DB})
    return out


def outer_race_ratios_in_band(card, measured_lines, sim_lines, bands=RATIO_BANDS) -> list:
    """BPFO fundamental at 3:00 over 6:00 with both records read in the same band (each of
    ``bands``), measured and simulated, dB: the rule's ratio reads each record in its own
    best band, which mixes bands where the two records ring different resonances.

    Parameters
    ----------
    card : pandas.DataFrame
        :func:`scorecard`'s result.
    measured_lines, sim_lines : pandas.DataFrame
        ``analyze --csv`` of the measured and of the simulated records.
    bands : sequence of str
        analyze's band names.

    Returns
    -------
    list of dict
        Per pair and band: ``meas_db``, ``sim_db``, ``within_tol`` (the rule's 6 dB).
    """
    out = []
    for r in outer_race_ratios(card):
        for band in bands:
            a = [_line_amplitude(lines, rec + suffix, band)
                 for lines, suffix in ((measured_lines, ""), (sim_lines, "_sim"))
                 for rec in (r["record_3"], r["record_6"])]
            meas, sim = _ratio_db(a[0], a[1]), _ratio_db(a[2], a[3])
            ok = None if meas is None or sim is None else bool(abs(meas - sim) <= TOL_DB)
            out.append({"record_3": r["record_3"], "record_6": r["record_6"], "band": band,
                        "meas_db": meas, "sim_db": sim, "within_tol": ok})
    return out


def _analyze(files, out_prefix: Path):
    """``bearing-envelope analyze`` (defaults, --bearing 6205) over the files, one process:
    the verdict table and the lines, read back."""
    import subprocess
    import sys

    import pandas as pd  # lazy: pandas ~1.8 s

    table, lines = f"{out_prefix}_table.csv", f"{out_prefix}_lines.csv"
    cmd = [sys.executable, "-m", "bearing_envelope", "analyze", *files, "--bearing", "6205",
           "--jobs", "1", "--table", table, "--csv", lines]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return pd.read_csv(table), pd.read_csv(lines)


def run_scorecard(conditions, contact: dict, out_dir, gain_reference: str, *, log=print,
                  settings: RigSettings | None = None):
    """Paths, gain, simulated records, analyze on both sides, the scorecard and its files.

    Parameters
    ----------
    conditions : sequence of RigCondition
    contact : dict
        :func:`simulate_excitations`'s result.
    out_dir : path
        ``paths.json``, ``sim/`` (the simulated records), ``scorecard.csv``,
        ``outer_race.csv``, ``summary.json``.
    gain_reference : str
        Records (name contains) the rig's gain is identified on.
    log : callable
    settings : RigSettings, optional
        The rig's sensor (:func:`sensor_gain`); None: a sensor blind to direction.

    Returns
    -------
    pandas.DataFrame
        The scorecard.
    """
    import pandas as pd  # lazy: pandas ~1.8 s

    out_dir = Path(out_dir)
    conditions = [c for c in conditions if c.name in contact]
    paths = record_paths(conditions, log=log)
    gain = rig_gain(conditions, paths, contact, gain_reference, settings)
    log(f"rig: gain {gain[0]:.4g} (m/s^2 or g)/N at resonance of the {gain[3]:.0f} Hz mode, "
        f"{gain[1]:.4g}-{gain[2]:.4g} over the {gain_reference} records")
    sim = [write_rig_record(c, contact[c.name], paths[c.name][0], gain[0], out_dir / "sim",
                            seed=i, reference_hz=gain[3], settings=settings)
           for i, c in enumerate(conditions)]
    with open(out_dir / "paths.json", "w", encoding="utf-8") as fh:
        json.dump({n: {"status": s, **{k: v for k, v in p.to_dict().items()
                                       if not k.startswith("background_")}}
                   for n, (p, s) in paths.items()}, fh, indent=1)
    mt, ml = _analyze([c.path for c in conditions], out_dir / "measured")
    st, sl = _analyze(sim, out_dir / "simulated")
    card = scorecard(conditions, mt, ml, st, sl)
    ratios = pd.DataFrame(outer_race_ratios(card))
    card.to_csv(out_dir / "scorecard.csv", index=False)
    trends = pd.DataFrame(load_trends(card))
    trends.to_csv(out_dir / "outer_race_trend.csv", index=False)
    ratios.to_csv(out_dir / "outer_race.csv", index=False)
    pd.DataFrame(outer_race_ratios_in_band(card, ml, sl)).to_csv(
        out_dir / "outer_race_bands.csv", index=False)
    pd.DataFrame(features_in_measured_band(card, ml, sl)).to_csv(
        out_dir / "same_band.csv", index=False)
    with open(out_dir / "summary.json", "w", encoding="utf-8") as fh:
        json.dump({"gain": gain, "pass_rates": pass_rates(card)}, fh, indent=1)
    (out_dir / "scorecard.md").write_text(scorecard_markdown(card, ratios, trends),
                                          encoding="utf-8")
    with open(out_dir / "paths.json", encoding="utf-8") as fh:
        sizes = size_ranking(card, conditions, contact, json.load(fh))
    pd.DataFrame(sizes).to_csv(out_dir / "size.csv", index=False)
    (out_dir / "size.md").write_text(size_summary(sizes), encoding="utf-8")
    zero = [c for c in conditions if c.load_hp == 0 and c.fs_hz == 12000.0]
    if zero:
        plot_side_by_side(card, zero, out_dir / "sim", out_dir / "side_by_side.png")
    from .rig_events import event_outputs

    event_outputs(conditions, out_dir)
    return card


def pass_rates(card) -> dict:
    """Per rule: records passed, records compared."""
    out = {}
    for col in [c for c in card.columns if c.startswith("rule_")]:
        v = card[col]
        n = int((v != "n/a").sum())
        out[col[5:]] = [int((v == "PASS").sum()), n]
    return out


def plot_side_by_side(card, conditions, sim_dir, out_png, *, max_order: float = 12.0) -> str:
    """Envelope spectra (orders of fr) of measured and simulated records, side by side: one
    row per record, each in its own best band of its truth family (``card``'s bands).

    Parameters
    ----------
    card : pandas.DataFrame
        :func:`scorecard`'s result.
    conditions : sequence of RigCondition
        The records to draw (one row each).
    sim_dir : path
        Folder of the simulated records (``<name>_sim.npz``).
    out_png : path
    max_order : float

    Returns
    -------
    str
        The figure's path.
    """
    from ..signal.envelope import envelope_spectrum

    fig, axes = pair_figure(len(conditions), 1.7)
    for i, j, c, side, path in record_pairs(conditions, sim_dir):
        row = card[card.record == c.name].iloc[0]
        x, _ = read_record(path)
        lo, hi, fr = row[f"{side}_band_low_hz"], row[f"{side}_band_high_hz"], row.meas_fr_hz
        ax = axes[i, j]
        if lo is None or not np.isfinite(lo):
            ax.text(0.5, 0.5, "no band", transform=ax.transAxes, ha="center")
            continue
        f, a = envelope_spectrum(x - x.mean(), c.fs_hz, (lo, hi), clamp=True,
                                 fmax_hz=max_order * fr)[:2]
        ax.plot(f / fr, a, lw=0.6, color="k" if side == "meas" else "C1")
        ax.set_xlim(0, max_order)
        ax.set_title(f"{c.name} {'measured' if side == 'meas' else 'simulated'}: "
                     f"{row[side + '_diagnosis'] or 'nothing'} "
                     f"({row[side + '_confidence'] if row[side + '_diagnosis'] else '-'}), "
                     f"band {lo:.0f}-{hi:.0f} Hz", fontsize=7)
        ax.tick_params(labelsize=6)
    return save_figure(fig, axes, out_png, "envelope frequency / fr (orders)")


def scorecard_markdown(card, ratios, trends=()) -> str:
    """The scorecard as a markdown table (docs/virtual_rig.md), pass rates and OR ratios."""
    def num(v, fmt):
        return "-" if v is None or (isinstance(v, float) and not np.isfinite(v)) else fmt % v

    head = ("| record | measured | simulated | line (orders) m / s | sideband dB m / s | "
            "2x/1x dB m / s | 3x/1x dB m / s | height dB m / s | rules F C L S 2 3 H |\n"
            "|---|---|---|---|---|---|---|---|---|\n")
    rows = []
    for _, r in card.iterrows():
        rules = " ".join({"PASS": "P", "FAIL": "x", "n/a": "-"}[r[c]] for c in
                         ("rule_family", "rule_class", "rule_line_orders", "rule_sideband_db",
                          "rule_h2_db", "rule_h3_db", "rule_height_db"))
        cells = [r.record, f"{r.meas_diagnosis or 'nothing'} ({r.meas_confidence or '-'})",
                 f"{r.sim_diagnosis or 'nothing'} ({r.sim_confidence or '-'})"]
        for k, fmt in (("line_orders", "%.4f"), ("sideband_db", "%.1f"), ("h2_db", "%.1f"),
                       ("h3_db", "%.1f"), ("height_db", "%.1f")):
            cells.append(f"{num(r['meas_' + k], fmt)} / {num(r['sim_' + k], fmt)}")
        rows.append("| " + " | ".join(cells) + f" | {rules} |")
    rates = pass_rates(card)
    lines = [head + "\n".join(rows), "",
             "Pass rates (passed / compared): " + "; ".join(
                 f"{k} {v[0]}/{v[1]}" for k, v in rates.items())]
    if len(ratios):
        lines += ["", "| 3:00 record | 6:00 record | measured dB | simulated dB | rule |",
                  "|---|---|---|---|---|"]
        lines += [f"| {r.record_3} | {r.record_6} | {num(r.meas_db, '%.1f')} | "
                  f"{num(r.sim_db, '%.1f')} | {r.rule} |" for _, r in ratios.iterrows()]
    if len(trends):
        lines += ["", "| OR position deg | size in | fs Hz | records | measured dB/hp | "
                  "simulated dB/hp | rule |", "|---|---|---|---|---|---|---|"]
        lines += [f"| {r.position_deg:g} | {r.diameter_in:g} | {r.fs_hz:g} | {r.n} | "
                  f"{r.meas_db_per_hp:.2f} | {r.sim_db_per_hp:.2f} | {r.rule} |"
                  for _, r in trends.iterrows()]
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------ size
#: Size pairs compared record by record: (location, small in, large in).
SIZE_PAIRS = (("outer_race", 0.007, 0.014), ("rolling_element", 0.007, 0.014),
              ("inner_race", 0.007, 0.028))


def _pulse_features(contact_path: str, fs: float) -> dict:
    """Removed-force pulses of a simulated record: median peak (N) and width above half the
    peak (s)."""
    with np.load(contact_path) as z:
        rf = np.asarray(z["removed_force"], dtype=float)
    top = float(np.max(rf))
    if top <= 0:
        return {"model_removed_N": 0.0, "model_width_s": 0.0}
    k = np.flatnonzero((rf[1:-1] > rf[:-2]) & (rf[1:-1] >= rf[2:]) & (rf[1:-1] > 0.5 * top)) + 1
    peaks = rf[k]
    return {"model_removed_N": float(np.median(peaks)),
            "model_width_s": float(np.count_nonzero(rf > 0.5 * top) / max(k.size, 1) / fs)}


def size_ranking(card, conditions, contact: dict, paths_json: dict) -> list:
    """Does a feature rank the pit sizes right, record by record (same location, load, fs)?

    Features of the measured record (identified event amplitude, line height, 2x/1x, 3x/1x)
    and of the model (median removed force per event, pulse width). A pair is ranked right
    when the larger pit has the larger value.

    Returns
    -------
    list of dict
        One row per pair and feature: values of the small and the large pit, ``right``.
    """
    by = {c.name: c for c in conditions}
    rows = []
    for loc, small, large in SIZE_PAIRS:
        for c in [c for c in conditions if c.location == loc and c.diameter_in == small
                  and c.position_deg == 0.0]:
            big = [d for d in conditions if d.location == loc and d.diameter_in == large
                   and d.load_hp == c.load_hp and d.fs_hz == c.fs_hz and d.position_deg == 0.0]
            if not big:
                continue
            d = big[0]
            feats = {}
            for name in (c.name, d.name):
                r = card[card.record == name].iloc[0]
                p = paths_json.get(name, {})
                f = {"meas_amplitude": p.get("amplitude") if p.get("status") == "identified"
                     else None, "meas_height_db": r.meas_height_db, "meas_h2_db": r.meas_h2_db,
                     "meas_h3_db": r.meas_h3_db, "sim_height_db": r.sim_height_db}
                if name in contact:
                    f.update(_pulse_features(contact[name], by[name].fs_hz))
                feats[name] = f
            for key in feats[c.name]:
                a, b = feats[c.name].get(key), feats[d.name].get(key)
                ok = None if a is None or b is None or not (np.isfinite(a) and np.isfinite(b)) \
                    else bool(b > a)
                rows.append({"location": loc, "load_hp": c.load_hp, "fs_hz": c.fs_hz,
                             "small": c.name, "large": d.name, "feature": key, "small_value": a,
                             "large_value": b, "right": ok})
    return rows


# ------------------------------------------------------------------ rig-common clearance
def removed_force_exponent(contact_3: str, contact_6: str) -> float:
    """Exponent ``b`` of ``F_removed ~ Q^b`` through the two simulated points (the 3:00 and
    6:00 records of one pit: each event's removed force and the roller load it met)."""
    pts = []
    for path in (contact_3, contact_6):
        with np.load(path) as z:
            pts.append((float(np.max(z["roller_load"])), float(np.max(z["removed_force"]))))
    (q1, f1), (q2, f2) = pts
    if min(q1, q2, f1, f2) <= 0 or q1 == q2:
        raise ValueError(f"contact: roller loads {q1:g}, {q2:g} N and removed forces {f1:g}, "
                         f"{f2:g} N; allowed: two positive, different points")
    return math.log(f2 / f1) / math.log(q2 / q1)


def event_exponent(contact_path: str, event_hz: float) -> float:
    """Exponent ``b`` of ``F_removed ~ Q^b`` fitted (log-log, least squares) over the events of
    one contact history: each event's peak removed force against the roller load it met.

    Parameters
    ----------
    contact_path : str
        A ``<record>_contact.npz`` of :func:`simulate_excitations`.
    event_hz : float
        The events' rate (BPFI for an inner race), Hz.

    Returns
    -------
    float
        ``b``; a history whose events do not span two loads raises ``ValueError``.
    """
    with np.load(contact_path) as z:
        f, q, fs = np.asarray(z["removed_force"]), np.asarray(z["roller_load"]), float(z["fs"])
    # one peak per event (the acquisition's filter rings between them)
    peaks, _ = sps.find_peaks(f, height=1e-3 * f.max() if f.size and f.max() > 0 else np.inf,
                              distance=max(1, int(0.6 * fs / event_hz)))
    ok = peaks[q[peaks] > 0]
    if ok.size < 3 or np.ptp(np.log(q[ok])) < 1e-3:
        raise ValueError(f"{contact_path}: {ok.size} events over roller loads "
                         f"{np.unique(np.round(q[ok], 3))[:3]} N; allowed: events at >= 2 loads")
    return float(np.polyfit(np.log(q[ok]), np.log(f[ok]), 1)[0])


def directional_modulation(settings: RigSettings, inner: RigCondition, outer_3: RigCondition,
                           b_inner: float, b_outer: float, *, n: int = 720) -> dict:
    """What the rig's load zone and sensor predict for two record features, dB.

    An inner-race event's amplitude at the defect's angle theta is ``Q(theta)^b_inner g(theta)``
    (``g``: :func:`sensor_gain`'s direction gain): its Fourier coefficients over a turn are the
    envelope line's fr sidebands, ``sb_k = |c_k| / c_0`` (events that do not overlap). The
    outer race's 3:00 over 6:00 line: ``(Q(90 deg)/Q(0))^b_outer g(90 deg)/g(0)``.

    Parameters
    ----------
    settings : RigSettings
    inner, outer_3 : RigCondition
        An inner-race record and a 3:00 outer-race record (their shaft rates).
    b_inner, b_outer : float
        Removed-force exponents (:func:`event_exponent`, :func:`removed_force_exponent`).
    n : int
        Angles per turn.

    Returns
    -------
    dict
        ``sb1_db``, ``sb2_db`` (inner race), ``ratio_3_6_db`` (outer race).
    """
    from ..physics.loads import scene_load_distribution

    th = np.arange(n) * (2 * math.pi / n)
    sensor = math.radians(settings.sensor_deg)
    q = np.maximum(np.asarray(scene_load_distribution(condition_scene(inner, settings))
                              .load_at(th, "inner"), dtype=float), 0.0)
    a = q ** b_inner * direction_gain(th, sensor, settings.sensor_cross_axis)
    if a.sum() <= 0:
        raise ValueError("rig: the inner race carries no load at any angle")
    sb = [20 * math.log10(max(abs(np.sum(a * np.exp(1j * k * th))) / a.sum(), 1e-12))
          for k in (1, 2)]
    ld = scene_load_distribution(condition_scene(outer_3, settings))
    q0, q90 = float(ld.load_at(0.0, "outer")), float(ld.load_at(math.pi / 2, "outer"))
    g = direction_gain(np.array([math.pi / 2, 0.0]), sensor, settings.sensor_cross_axis)
    r = 20 * (b_outer * math.log10(max(q90 / q0, 1e-12)) + math.log10(max(g[0] / g[1], 1e-12)))
    return {"sb1_db": sb[0], "sb2_db": sb[1], "ratio_3_6_db": r}


def identify_load_zone(settings: RigSettings, inner: RigCondition, outer_3: RigCondition,
                       sb1_db: float, ratio_db: float, b_inner: float, b_outer: float,
                       *, bounds_um=(-40.0, 10.0)) -> tuple[float, float]:
    """The operating clearance and the sensor's cross-axis gain that give the measured inner-race
    fr sideband (``sb1_db``) and outer-race 3:00/6:00 ratio (``ratio_db``) at the rig's load
    (:func:`directional_modulation`). For each clearance the cross-axis gain is the one that
    closes the 3:00 ratio (capped to [0, 1]); the clearance then closes the sideband.

    Parameters
    ----------
    settings : RigSettings
        The rig (its load; clearance and cross-axis gain are replaced).
    inner, outer_3 : RigCondition
    sb1_db, ratio_db : float
        Measured, dB.
    b_inner, b_outer : float
    bounds_um : (float, float)
        Clearances searched, um.

    Returns
    -------
    (float, float)
        Clearance (um, negative: preload) and cross-axis gain.
    """
    from scipy import optimize  # lazy: only this function needs it

    def with_(c_um, kappa):
        m = copy.deepcopy(settings.scene)
        m.setdefault("bearing", {})["radial_clearance_um"] = c_um
        return dataclasses.replace(settings, scene=m, sensor_cross_axis=kappa)

    def kappa_for(c_um):
        src = directional_modulation(with_(c_um, 1.0), inner, outer_3, b_inner, b_outer)
        return min(1.0, 10 ** ((ratio_db - src["ratio_3_6_db"]) / 20))

    def miss(c_um):
        d = directional_modulation(with_(c_um, kappa_for(c_um)), inner, outer_3, b_inner, b_outer)
        return d["sb1_db"] - sb1_db

    lo, hi = bounds_um
    if miss(lo) * miss(hi) > 0:
        raise ValueError(f"sb1_db: {sb1_db:g} dB is outside what clearances {lo:g}..{hi:g} um "
                         f"give at {settings.load_kN:g} kN")
    c = float(optimize.brentq(miss, lo, hi, xtol=0.01))
    k = kappa_for(c)
    got = directional_modulation(with_(c, k), inner, outer_3, b_inner, b_outer)["ratio_3_6_db"]
    if abs(got - ratio_db) > 0.05:
        raise ValueError(f"ratio_db: {ratio_db:g} dB is above what the load zone gives at "
                         f"{c:.2f} um ({got:.1f} dB with a sensor blind to direction); allowed: "
                         "a ratio a cross-axis gain <= 1 reaches")
    return c, k


#: The rig's load-zone identification reads the inner-race fr sidebands of the 0.007 in
#: records at 12 kHz in every demodulation band analyze reports (the raw envelope aside).
SIDEBAND_BANDS = ("kurtogram", "fs4_3fs8", "bpfi_3_6", "bpfi_10_13")


def measured_sideband_db(measured_lines, names) -> list[float]:
    """The mean of the +-1 fr sidebands over the BPFI line, dB, of each record in ``names``
    and each of :data:`SIDEBAND_BANDS` (analyze's lines table of the measured records).

    Parameters
    ----------
    measured_lines : pandas.DataFrame
        ``measured_lines.csv`` of a rig run.
    names : sequence of str
        Record names (file names without ``.npz``).

    Returns
    -------
    list of float
        One value per record and band with a line and both sidebands.
    """
    ratios = (_band_ratios(measured_lines, name, band, "bpfi")
              for name in names for band in SIDEBAND_BANDS)
    return [r["sideband_db"] for r in ratios if "sideband_db" in r]


def identify_from_run(run_dir, conditions, settings: RigSettings) -> dict:
    """The rig's clearance and sensor cross-axis gain from a scored run (:func:`run_scorecard`):
    the measured inner-race fr sideband (median of :func:`measured_sideband_db` over the 0.007
    in inner-race records at 12 kHz), the measured 3:00/6:00 BPFO ratio (median of
    ``outer_race.csv`` at 12 kHz), the removed-force exponents of the run's contact histories
    (:func:`event_exponent`, :func:`removed_force_exponent`), then
    :func:`identify_load_zone` at the rig's load.

    Parameters
    ----------
    run_dir : path
        A scored rig run (``measured_lines.csv``, ``outer_race.csv``, ``contact/``).
    conditions : sequence of RigCondition
    settings : RigSettings

    Returns
    -------
    dict
        The measured targets, exponents, ``clearance_um`` and ``sensor_cross_axis``, and what
        the identified rig predicts (:func:`directional_modulation`).
    """
    import pandas as pd  # lazy: pandas ~1.8 s

    run = Path(run_dir)
    by = {c.name: c for c in conditions}
    ir = [c for c in conditions if c.location == "inner_race" and c.diameter_in == 0.007
          and c.fs_hz == 12000.0]
    ratios = pd.read_csv(run / "outer_race.csv")
    ratios = ratios[ratios.record_3.map(lambda n: n in by and by[n].fs_hz == 12000.0)]
    if not ir or ratios.empty or ratios.meas_db.isna().all():
        raise ValueError(f"{run}: needs 0.007 in inner-race and 3:00/6:00 outer-race records "
                         "at 12 kHz, scored")
    sb = measured_sideband_db(pd.read_csv(run / "measured_lines.csv"), [c.name for c in ir])
    r3 = ratios.iloc[0]
    contact = run / "contact"
    b_in = float(np.median([event_exponent(str(contact / f"{c.name}_contact.npz"),
                                           rig_rates(c.shaft_hz)["bpfi"]) for c in ir]))
    b_out = removed_force_exponent(str(contact / f"{r3.record_3}_contact.npz"),
                                   str(contact / f"{r3.record_6}_contact.npz"))
    target = {"sb1_db": float(np.median(sb)), "ratio_3_6_db": float(ratios.meas_db.median())}
    c, k = identify_load_zone(settings, ir[0], by[r3.record_3], target["sb1_db"],
                              target["ratio_3_6_db"], b_in, b_out)
    m = copy.deepcopy(settings.scene)
    m.setdefault("bearing", {})["radial_clearance_um"] = c
    fit = dataclasses.replace(settings, scene=m, sensor_cross_axis=k)
    return {"load_kN": settings.load_kN, "measured": target, "n_sideband_readings": len(sb),
            "b_inner": b_in, "b_outer": b_out, "clearance_um": c, "sensor_cross_axis": k,
            "predicted": directional_modulation(fit, ir[0], by[r3.record_3], b_in, b_out)}


def size_summary(rows) -> str:
    """Markdown: per pit pair and feature, pairs ranked right / pairs compared."""
    agg: dict = {}
    for r in rows:
        if r["right"] is None:
            continue
        key = (r["location"], int(r["fs_hz"]), r["feature"])
        n_ok, n = agg.get(key, (0, 0))
        agg[key] = (n_ok + int(r["right"]), n + 1)
    out = ["| location | fs Hz | feature | larger pit ranked larger |", "|---|---|---|---|"]
    out += [f"| {loc} | {fs} | {feat} | {ok}/{n} |" for (loc, fs, feat), (ok, n) in
            sorted(agg.items())]
    return "\n".join(out) + "\n"
