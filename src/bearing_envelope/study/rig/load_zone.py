"""The rig's load zone identified from its records: the operating clearance and the sensor's
cross-axis gain that give the measured inner-race fr sideband and outer-race 3:00/6:00 ratio
(docs/virtual_rig.md, "Identification")."""

from __future__ import annotations

import copy
import dataclasses
import math
from collections import Counter
from pathlib import Path

import numpy as np
from scipy import signal as sps

from ...physics.locations import get_location
from ...physics.transfer import direction_gain
from ...signal.envelope import bandpass, envelope, settling_samples
from .config import RigSettings
from .dynamic import dynamic_path, excitation_model
from .records import RigCondition
from .scoring import band_ratios
from .simulation import condition_scene

#: The line family the load zone is identified on: the shaft-rate sidebands of a defect that
#: turns with the shaft through the zone (the inner race's BPFI).
IDENTIFICATION_FAMILY = "bpfi"
#: A dynamic excitation's events are read in analyze's fixed band, fs/4-3fs/8 (as fractions of
#: fs): below it the housing (about 0.7 kHz) and the shaft ring at every element passage.
DYNAMIC_EVENT_BAND = (0.25, 0.375)

__all__ = ["removed_force_exponent", "event_exponent", "event_points", "event_level",
           "DYNAMIC_EVENT_BAND", "directional_modulation",
           "identify_load_zone", "measured_sideband_db", "identify_from_run",
           "identification_records", "structure_ratio_db", "SIDEBAND_BANDS"]


def removed_force_exponent(contact_3: str, contact_6: str, event_hz: float | None = None) -> float:
    """Exponent ``b`` of ``F_removed ~ Q^b`` through the two simulated points (the 3:00 and
    6:00 records of one pit: each one's event amplitude and the element load it met,
    :func:`event_level`).

    Parameters
    ----------
    contact_3, contact_6 : str
        The two excitation files: ``<record>_contact.npz``
        (:func:`~.simulation.simulate_excitations`) or ``<record>_dynamic.npz``
        (:func:`~.dynamic.simulate_dynamic_record`).
    event_hz : float, optional
        The events' rate (BPFO), Hz; needed by a dynamic excitation.

    Returns
    -------
    float
        ``b``; two points that do not define it raise ``ValueError``.

    Raises
    ------
    ValueError
        The two points do not define an exponent (a load or removed force <= 0, or equal
        loads).
    """
    (q1, f1), (q2, f2) = (event_level(p, event_hz) for p in (contact_3, contact_6))
    if min(q1, q2, f1, f2) <= 0 or q1 == q2:
        raise ValueError(f"contact: roller loads {q1:g}, {q2:g} N and removed forces {f1:g}, "
                         f"{f2:g} N; allowed: two positive, different points")
    return math.log(f2 / f1) / math.log(q2 / q1)


def event_level(path: str, event_hz: float | None = None) -> tuple[float, float]:
    """One record's element load and event amplitude: a contact history's largest roller
    load and removed force; a dynamic excitation's medians over its events
    (:func:`event_points`).

    Parameters
    ----------
    path : str
        The excitation file.
    event_hz : float, optional
        The events' rate, Hz; needed by a dynamic excitation.

    Returns
    -------
    (float, float)
        Load and amplitude, N.

    Raises
    ------
    ValueError
        A dynamic excitation without ``event_hz``.
    """
    if excitation_model(path) == "quasi_static":
        with np.load(path) as z:
            return float(np.max(z["roller_load"])), float(np.max(z["removed_force"]))
    if event_hz is None:
        raise ValueError(f"{path}: event_hz: got None for a dynamic excitation; allowed: the "
                         "events' rate, Hz")
    q, a = event_points(path, event_hz)
    return float(np.median(q)), float(np.median(a))


def event_points(path: str, event_hz: float) -> tuple[np.ndarray, np.ndarray]:
    """Each event's element load and amplitude in one excitation file.

    A contact history (quasi-static): the peaks of the removed force (one per event; the
    acquisition's filter rings between them) and the roller load at each. A dynamic excitation
    (:data:`~.dynamic.DYNAMIC_MODEL`): its removed force (the housing force's fluctuation along
    the defect's radius) rings the housing and shaft modes at every element passage, so the
    event is read where the rig reads it, in :data:`DYNAMIC_EVENT_BAND` (fs/4-3fs/8): per
    event period the envelope's highest value, and the element load as the median of the
    nearest element's load over that period (the load it carries into the pit, not its dip).

    Parameters
    ----------
    path : str
        The excitation file.
    event_hz : float
        The events' rate, Hz.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        Loads and amplitudes, N, one per event.
    """
    with np.load(path) as z:
        f, q, fs = np.asarray(z["removed_force"]), np.asarray(z["roller_load"]), float(z["fs"])
    if excitation_model(path) == "quasi_static":
        peaks, _ = sps.find_peaks(f, height=1e-3 * f.max() if f.size and f.max() > 0 else np.inf,
                                  distance=max(1, int(0.6 * fs / event_hz)))
        return q[peaks], f[peaks]
    band = (DYNAMIC_EVENT_BAND[0] * fs, DYNAMIC_EVENT_BAND[1] * fs)
    edge = settling_samples(fs, band)
    e = envelope(bandpass(f, fs, band))
    period = max(1, int(fs / event_hz))
    starts = np.arange(edge, e.size - edge - period, period)
    peaks = np.array([s + int(np.argmax(e[s:s + period])) for s in starts], dtype=np.int64)
    half = period // 2
    loads = np.array([np.median(q[max(0, i - half):i + half + 1]) for i in peaks])
    return loads, e[peaks]


def event_exponent(contact_path: str, event_hz: float) -> float:
    """Exponent ``b`` of ``F_removed ~ Q^b`` fitted (log-log, least squares) over the events of
    one excitation file (:func:`event_points`): each event's amplitude against the element
    load it met.

    Parameters
    ----------
    contact_path : str
        A ``<record>_contact.npz`` of :func:`simulate_excitations` or a ``<record>_dynamic.npz``.
    event_hz : float
        The events' rate (BPFI for an inner race), Hz.

    Returns
    -------
    float
        ``b``; a history whose events do not span two loads raises ``ValueError``.

    Raises
    ------
    ValueError
        The history's events do not span two roller loads.
    """
    q, f = event_points(contact_path, event_hz)
    ok = (q > 0) & (f > 0)
    if ok.sum() < 3 or np.ptp(np.log(q[ok])) < 1e-3:
        raise ValueError(f"{contact_path}: {ok.sum()} events over roller loads "
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
        The rig's settings (:func:`~.config.read_rig_config`): base scene, load (kN), fidelity,
        sensor direction and cross-axis gain.
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

    Raises
    ------
    ValueError
        The inner race carries no load at any angle.
    """
    from ...physics.loads import scene_load_distribution

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
        An inner-race record and a 3:00 outer-race record (their shaft rates).
    sb1_db, ratio_db : float
        Measured, dB.
    b_inner, b_outer : float
        Removed-force exponents (:func:`event_exponent`, :func:`removed_force_exponent`).
    bounds_um : (float, float)
        Clearances searched, um.

    Returns
    -------
    (float, float)
        Clearance (um, negative: preload) and cross-axis gain.

    Raises
    ------
    ValueError
        ``sb1_db`` outside what the clearances searched give, or ``ratio_db`` above what a
        cross-axis gain <= 1 reaches.
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
        Record names (file names without suffix).

    Returns
    -------
    list of float
        One value per record and band with a line and both sidebands.
    """
    ratios = (band_ratios(measured_lines, name, band, IDENTIFICATION_FAMILY)
              for name in names for band in SIDEBAND_BANDS)
    return [r["sideband_db"] for r in ratios if "sideband_db" in r]


def identify_from_run(run_dir, conditions, settings: RigSettings) -> dict:
    """The rig's clearance and sensor cross-axis gain from a scored run (:func:`run_scorecard`):
    the measured inner-race fr sideband (median of :func:`measured_sideband_db` over
    :func:`identification_records`: CWRU's 0.007 in records at 12 kHz), the measured 3:00/6:00
    BPFO ratio (median of ``outer_race.csv`` at their fs), the removed-force exponents of the
    run's excitations, contact histories or dynamic runs alike (:func:`event_exponent`: the
    median over the inner-race records; :func:`removed_force_exponent`: the first pair), then
    :func:`identify_load_zone` at the rig's load; and the same rule on each load's records
    alone (``per_load``: the spread).

    Parameters
    ----------
    run_dir : path
        A scored rig run (``measured_lines.csv``, ``outer_race.csv``, ``contact/``).
    conditions : sequence of RigCondition
        The run's records (:func:`~.manifest.record_conditions`).
    settings : RigSettings
        The rig's settings (:func:`~.config.read_rig_config`): base scene, load (kN), fidelity,
        sensor direction and cross-axis gain.

    Returns
    -------
    dict
        The measured targets, exponents, ``clearance_um`` and ``sensor_cross_axis``, what
        the identified rig predicts (:func:`directional_modulation`), and ``per_load`` (each
        load's inner-race record and 3:00/6:00 pair: exponents, clearance and gain, or the
        error that refused them).

    Raises
    ------
    ValueError
        The run lacks scored inner-race records or 3:00/6:00 outer-race pairs at one sampling
        rate.
    """
    import pandas as pd  # lazy: pandas ~1.8 s

    run = Path(run_dir)
    by = {c.name: c for c in conditions}
    ir = identification_records(conditions)
    ratios = pd.read_csv(run / "outer_race.csv")
    fs = ir[0].fs_hz if ir else None
    ratios = ratios[ratios.record_3.map(lambda n: n in by and by[n].fs_hz == fs)]
    if not ir or ratios.empty or ratios.meas_db.isna().all():
        raise ValueError(f"{run}: needs inner-race records and 3:00/6:00 (90/0 deg) outer-race "
                         "pairs at one fs, scored")
    lines = pd.read_csv(run / "measured_lines.csv")
    sb = measured_sideband_db(lines, [c.name for c in ir])
    r3 = ratios.iloc[0]
    b_each = _exponents(run / "contact", settings, ir, ratios, by)
    b_in, b_out = float(np.median(b_each["inner"])), b_each["outer"][0]
    target = {"sb1_db": float(np.median(sb)), "ratio_3_6_db": float(ratios.meas_db.median())}
    structure_db = structure_ratio_db(ratios, directional_modulation(
        settings, ir[0], by[r3.record_3], b_in, b_out)["ratio_3_6_db"])
    c, k = identify_load_zone(settings, ir[0], by[r3.record_3], target["sb1_db"],
                              target["ratio_3_6_db"] - structure_db, b_in, b_out)
    m = copy.deepcopy(settings.scene)
    m.setdefault("bearing", {})["radial_clearance_um"] = c
    fit = dataclasses.replace(settings, scene=m, sensor_cross_axis=k)
    predicted = directional_modulation(fit, ir[0], by[r3.record_3], b_in, b_out)
    predicted["ratio_3_6_db"] += structure_db
    per_load = []
    for cond, b_i, (_, row), b_o in zip(ir, b_each["inner"], ratios.iterrows(), b_each["outer"]):
        try:   # the same rule on one load's records: the spread over the records
            cl, kl = identify_load_zone(settings, cond, by[row.record_3], float(np.median(
                measured_sideband_db(lines, [cond.name]))), float(row.meas_db) - structure_db,
                b_i, b_o)
        except ValueError as err:
            cl, kl = None, str(err)
        per_load.append({"records": [cond.name, row.record_3, row.record_6], "b_inner": b_i,
                         "b_outer": b_o, "clearance_um": cl, "sensor_cross_axis": kl})
    return {"load_kN": settings.load_kN, "dynamics": settings.dynamics, "measured": target,
            "n_sideband_readings": len(sb), "b_inner": b_in, "b_outer": b_out,
            "structure_db": structure_db, "clearance_um": c, "sensor_cross_axis": k,
            "predicted": predicted, "per_load": per_load}


def _exponents(contact: Path, settings: RigSettings, ir, ratios, by) -> dict:
    """The exponents of each inner-race record and each 3:00/6:00 pair, read on the run's
    excitation files (the model ``settings.dynamics`` names)."""
    def path(name):
        return str(dynamic_path(contact, by[name]) if settings.dynamics == "dynamic"
                   else contact / f"{name}_contact.npz")

    inner = [event_exponent(path(c.name), c.rates[IDENTIFICATION_FAMILY]) for c in ir]
    outer = [removed_force_exponent(path(r.record_3), path(r.record_6),
                                    by[r.record_3].rates["bpfo"]) for _, r in ratios.iterrows()]
    return {"inner": inner, "outer": outer}


def structure_ratio_db(ratios, model_db: float) -> float:
    """What the 3:00/6:00 line ratio owes to the structure, dB: the simulated records' ratio
    (median over the pairs) less what the load zone and the sensor's direction give at the
    run's settings (:func:`directional_modulation`). The simulated 3:00 records ring their own
    modes (a 3:00 record's first mode at its group's gain re the reference mode,
    :func:`~.simulation.anchor_gains`) and are read in their own best band; the identification
    closes the measured ratio with this part held, so that the simulated ratio, not only the
    model's, meets the measured one.

    Parameters
    ----------
    ratios : pandas.DataFrame
        ``outer_race.csv`` rows of one fs (``sim_db``: the run's simulated ratio, dB).
    model_db : float
        :func:`directional_modulation`'s ``ratio_3_6_db`` at the run's settings.

    Returns
    -------
    float
        dB; 0 when the run scored no simulated pair.
    """
    sim = ratios.sim_db.dropna()
    return float(sim.median() - model_db) if len(sim) else 0.0




def identification_records(conditions) -> list:
    """The inner-race records the load zone is identified on: those of the smallest pit, at
    the sampling rate most of them have (ties: the lowest; CWRU: 0.007 in at 12 kHz).

    Parameters
    ----------
    conditions : sequence of RigCondition
        The rig's records (:func:`~.manifest.record_conditions`).

    Returns
    -------
    list of RigCondition
        Possibly empty.
    """
    ir = [c for c in conditions if get_location(c.location).family == IDENTIFICATION_FAMILY]
    if not ir:
        return []
    small = min(c.length_um for c in ir)
    ir = [c for c in ir if c.length_um == small]
    counts = Counter(c.fs_hz for c in ir)
    fs = min(counts, key=lambda f: (-counts[f], f))
    return [c for c in ir if c.fs_hz == fs]
