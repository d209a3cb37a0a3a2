"""The rig's load zone identified with the dynamic model's excitation (``rig.dynamics:
dynamic``): the event amplitude's exponent read on a synthetic dynamic excitation whose law is
known (bursts in fs/4-3fs/8 of amplitude c Q^b under a strong housing ring below the band), and
the one identification (:func:`identify_from_run`) recovering a known rig from a synthetic
dynamic run."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pandas as pd
import pytest

from bearing_envelope.study import rig
from bearing_envelope.study.rig import load_zone
from bearing_envelope.study.rig.dynamic import DYNAMIC_MODEL

FS = 12_000.0


def _dynamic_file(path, rate, load, b, *, c=0.02, seconds=1.0):
    """Bursts at ``rate`` ringing at 0.31 fs (1 ms decay), amplitude ``c Q^b``, ``Q = load(t)``,
    over a 5 N ring at 700 Hz (the housing's mode, below the band)."""
    t = np.arange(int(seconds * FS)) / FS
    q = load(t)
    f = 5.0 * np.sin(2 * math.pi * 700.0 * t)
    for ti in np.arange(0.003, seconds - 0.01, 1 / rate):
        i = int(ti * FS)
        s = t[i:] - t[i]
        f[i:] += c * q[i] ** b * np.exp(-s / 1e-3) * np.sin(2 * math.pi * 0.31 * FS * s)
    np.savez(path, time=t, fs=np.float64(FS), model=np.str_(DYNAMIC_MODEL), removed_force=f,
             roller_load=q, housing_force=np.zeros((t.size, 2)))
    return str(path)


def test_dynamic_event_exponent_of_a_known_law(tmp_path):
    """b = 0.6 over loads 5-50 N (the peaks of the raw force would read the 700 Hz ring: b = 0);
    two records at 20 and 50 N with b = 0.3 give 0.3; a dynamic file without its rate is
    refused."""
    fr, bpfi = 29.95, 162.2
    p = _dynamic_file(tmp_path / "ir_dynamic.npz", bpfi,
                      lambda t: 5.0 + 45.0 * (0.5 + 0.5 * np.cos(2 * math.pi * fr * t)), 0.6)
    assert rig.event_exponent(p, bpfi) == pytest.approx(0.6, abs=0.03)
    a = _dynamic_file(tmp_path / "a.npz", 107.4, lambda t: np.full(t.size, 20.0), 0.3)
    b = _dynamic_file(tmp_path / "b.npz", 107.4, lambda t: np.full(t.size, 50.0), 0.3)
    assert rig.removed_force_exponent(a, b, 107.4) == pytest.approx(0.3, abs=0.01)
    with pytest.raises(ValueError, match=r"event_hz: got None for a dynamic excitation"):
        rig.removed_force_exponent(a, b)
    # a contact history (quasi-static) keeps its reading: the largest load and removed force
    for name, q in (("qa", 0.5), ("qb", 500.0)):
        np.savez(tmp_path / f"{name}.npz", roller_load=np.array([0.0, q]),
                 removed_force=np.array([0.0, 2.0 * q ** 0.4]))
    assert load_zone.event_level(str(tmp_path / "qb.npz")) == (500.0, pytest.approx(
        2.0 * 500.0 ** 0.4))


def _run(tmp_path, truth_settings, b_in, b_out, structure_db):
    """A synthetic scored dynamic run: records ir, or3 (90 deg), or6 (0 deg); the measured
    sideband and 3:00/6:00 ratio those of ``truth_settings`` (plus ``structure_db`` on the
    ratio, which the run's simulated pair also carries); excitations of known exponents."""
    for name in ("ir", "or3", "or6"):
        np.savez(tmp_path / f"{name}.npz", x=np.zeros(1200), fs=np.float64(FS))
    (tmp_path / "manifest.csv").write_text(
        "file,location,length_um,depth_um,position_deg,load,shaft_hz,bearing\n"
        "ir.npz,inner_race,177.8,279.4,,0,29.95,6205\n"
        "or3.npz,outer_race,177.8,279.4,90,0,29.95,6205\n"
        "or6.npz,outer_race,177.8,279.4,0,0,29.95,6205\n")
    conds = rig.record_conditions([str(tmp_path)])
    by = {c.name: c for c in conds}
    truth = rig.directional_modulation(truth_settings, by["ir"], by["or3"], b_in, b_out)
    run = tmp_path / "run"
    (run / "contact").mkdir(parents=True)
    bpfi, bpfo = by["ir"].rates["bpfi"], by["or3"].rates["bpfo"]
    _dynamic_file(run / "contact" / "ir_dynamic.npz", bpfi,
                  lambda t: 5.0 + 45.0 * (0.5 + 0.5 * np.cos(2 * math.pi * 29.95 * t)), b_in)
    for name, q in (("or3", 20.0), ("or6", 50.0)):
        _dynamic_file(run / "contact" / f"{name}_dynamic.npz", bpfo,
                      lambda t, q=q: np.full(t.size, q), b_out)
    sb = 10 ** (truth["sb1_db"] / 20)
    pd.DataFrame([{"file": str(tmp_path / "ir.npz"), "band": band, "base": "bpfi", "order": 1,
                   "sideband": k, "amplitude": a}
                  for band in load_zone.SIDEBAND_BANDS for k, a in ((-1, sb), (0, 1.0), (1, sb))]
                 ).to_csv(run / "measured_lines.csv", index=False)
    return run, conds, truth


def test_identify_from_a_dynamic_run_recovers_a_known_rig(tmp_path):
    """The rig at -6 um and cross-axis gain 0.1 (0.2 kN), events of exponents 0.6 (inner) and
    0.3 (outer) in the run's dynamic excitations, the simulated pair 4 dB above what the load
    zone gives at the run's settings (0 um, gain 1: the structure's part): the identification
    reads the exponents on the dynamic files and returns -6 um and 0.1."""
    base = {"bearing": {"designation": "SKF 6205-2RS"}}
    run_s = rig.RigSettings(scene=base, load_kN=0.2, fidelity="draft", sensor_cross_axis=1.0,
                            dynamics="dynamic")
    truth_s = dataclasses.replace(run_s, scene={"bearing": {**base["bearing"],
                                                            "radial_clearance_um": -6.0}},
                                  sensor_cross_axis=0.1)
    run, conds, truth = _run(tmp_path, truth_s, 0.6, 0.3, 4.0)
    by = {c.name: c for c in conds}
    model_run = rig.directional_modulation(run_s, by["ir"], by["or3"], 0.6, 0.3)["ratio_3_6_db"]
    pd.DataFrame([{"record_3": "or3", "record_6": "or6",
                   "meas_db": truth["ratio_3_6_db"] + 4.0, "sim_db": model_run + 4.0}]
                 ).to_csv(run / "outer_race.csv", index=False)
    fit = rig.identify_from_run(run, conds, run_s)
    assert fit["b_inner"] == pytest.approx(0.6, abs=0.03)
    assert fit["b_outer"] == pytest.approx(0.3, abs=0.01)
    assert fit["structure_db"] == pytest.approx(4.0, abs=0.3)
    assert fit["clearance_um"] == pytest.approx(-6.0, abs=0.5)
    assert fit["sensor_cross_axis"] == pytest.approx(0.1, abs=0.01)
    assert fit["per_load"][0]["clearance_um"] == pytest.approx(fit["clearance_um"])
