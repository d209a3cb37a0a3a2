"""The rig with the dynamics (``rig.dynamics: dynamic``, docs/virtual_rig.md "With the
dynamics"): the option's validation, the one-axis sensor's reading of a force on the housing
against the closed-form direction gain, the dynamic excitation against momentum and the
kinematic event rate, and a tiny rig run end to end on synthetic records of another bearing
(the fixture of tests/test_rig_sets.py)."""

from __future__ import annotations

import dataclasses
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import signal as sps

from bearing_envelope.physics.scene import Scene
from bearing_envelope.study import rig
from bearing_envelope.physics.kinematics import bearing_rates
from bearing_envelope.study.rig.dynamic import (dynamic_path, excitation_model, rig_params,
                                                sensor_excitation)

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_rig_sets import FS, _bpfi, _bpfo, _ringing  # noqa: E402  (the shared fixture)

Z, D, PITCH, FR = 8, 6.75, 28.55, 25.0     # the catalogue's SKF 6203 by its geometry


def _config(tmp_path, rig_lines: str) -> Path:
    p = tmp_path / "rig.yaml"
    p.write_text("scene:\n  bearing: {designation: SKF 6203}\nrig:\n  load_kN: 1.0\n" + rig_lines)
    return p


def test_dynamics_option_is_validated_once(tmp_path):
    s = rig.read_rig_config(_config(tmp_path, "  dynamics: dynamic\n  structure: "
                                               "{housing_mass_kg: 8, contact_zeta: 0.03}\n"))
    assert s.dynamics == "dynamic" and s.structure == {"housing_mass_kg": 8.0,
                                                        "contact_zeta": 0.03}
    assert rig.read_rig_config(_config(tmp_path, "")).dynamics == "quasi_static"
    bad = {"  dynamics: implicit\n": "rig.dynamics: got 'implicit'; allowed: quasi_static | "
                                     "dynamic",
           "  structure: {housing_mas_kg: 8}\n": "rig.structure.housing_mas_kg: unknown key",
           "  structure: {housing_mass_kg: 0}\n": "rig.structure.housing_mass_kg: got 0",
           "  structure: {contact_zeta: -0.1}\n": "rig.structure.contact_zeta: got -0.1",
           "  structure: 5\n": "rig.structure: got 5"}
    for lines, msg in bad.items():
        with pytest.raises(ValueError, match=msg.replace("|", r"\|")):
            rig.read_rig_config(_config(tmp_path, lines))


@pytest.mark.parametrize("angle_deg", [0.0, 30.0, 90.0, 150.0])
@pytest.mark.parametrize("k", [0.0, 0.255, 1.0])
def test_sensor_reads_a_housing_force_with_the_direction_gain(angle_deg, k):
    """A burst ringing 3 kHz along a fixed direction: the sensor's reading, band-passed, has the
    envelope of the burst's magnitude times ``sqrt(cos^2 d + k^2 sin^2 d)`` (the power sum
    written out here, not the code's ``direction_gain``)."""
    fs, n = 48_000.0, 4800
    t = np.arange(n) / fs
    mag = np.exp(-0.5 * ((t - 0.05) / 2e-3) ** 2) * np.cos(2 * math.pi * 3000.0 * t)
    a = math.radians(angle_deg)
    f = 100.0 + np.stack([mag * math.cos(a), mag * math.sin(a)], axis=1)  # plus a static load
    sensor = 180.0
    y = sensor_excitation(f, sensor, k)
    d = a - math.radians(sensor)
    gain = math.sqrt(math.cos(d) ** 2 + k ** 2 * math.sin(d) ** 2)
    env = np.abs(sps.hilbert(y))[1000:-1000]
    ref = np.abs(sps.hilbert(mag))[1000:-1000]
    assert abs(np.mean(y)) < 1e-9
    assert env.max() == pytest.approx(gain * ref.max(), rel=2e-3, abs=1e-6)


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    """Synthetic records of the 6203 (two outer-race records at 0 deg, the gain's reference,
    and an inner-race one, 2 s each), their manifest, and their dynamic excitations (draft
    defect tables, the rig at 0.1 kN)."""
    tmp = tmp_path_factory.mktemp("dyn")
    n = int(2 * FS)
    recs = {"ref_or_500N": ("outer_race", _bpfo(FR, Z, D, PITCH), 500),
            "ref_or_1000N": ("outer_race", _bpfo(FR, Z, D, PITCH), 1000),
            "ir_500N": ("inner_race", _bpfi(FR, Z, D, PITCH), 500)}
    lines = ["file,location,length_um,depth_um,position_deg,load,shaft_hz,n_rollers,"
             "roller_diameter_mm,pitch_diameter_mm"]
    for i, (name, (loc, rate, load)) in enumerate(recs.items()):
        np.savez(tmp / f"{name}.npz", x=_ringing(rate, n, seed=i), fs=np.float64(FS))
        pos = "0" if loc == "outer_race" else ""
        lines.append(f"{name}.npz,{loc},400,100,{pos},{load},{FR},{Z},{D},{PITCH}")
    (tmp / "records.csv").write_text("\n".join(lines) + "\n")
    conds = rig.record_conditions([str(tmp / "records.csv")])
    contact = rig.simulate_excitations(conds, _settings(), tmp / "run" / "contact",
                                       log=lambda s: None, gain_reference="ref")
    return tmp, recs, conds, contact


def _settings(**kw):
    return rig.RigSettings(scene={"bearing": {"designation": "SKF 6203"}}, load_kN=0.1,
                           fidelity="draft", sensor_deg=180.0, sensor_cross_axis=0.255,
                           dynamics="dynamic", **kw)


def test_dynamic_excitation_passes_the_load_and_events_at_the_kinematic_rate(records):
    """Momentum: over the record the force the elements pass to the housing averages the
    applied load (0.1 kN along x, none across); the housing force's deficit along the pit's
    radius has its envelope line at the outer race's kinematic rate ``Z/2 fr (1 - d/D)``."""
    tmp, _, conds, contact = records
    c = [c for c in conds if c.name == "ref_or_1000N"][0]
    with np.load(contact[c.name]) as z:
        f, rf, fs = z["housing_force"], z["removed_force"], float(z["fs"])
        assert float(z["defect_force_peak"]) > 0
    assert f.shape == (c.n_samples, 2)
    # a whole number of element passes: the first k passes of the record
    passes = int(c.n_samples / fs * _bpfo(FR, Z, D, PITCH))
    m = int(round(passes / _bpfo(FR, Z, D, PITCH) * fs))
    assert np.mean(f[:m, 0]) == pytest.approx(100.0, rel=2e-3)
    assert abs(np.mean(f[:m, 1])) < 0.1
    e = np.abs(sps.hilbert(sps.sosfiltfilt(sps.butter(4, [1500, 4500], "bandpass", fs=fs,
                                                      output="sos"), rf))) ** 2
    spec = np.abs(np.fft.rfft(e - e.mean()))
    freq = np.fft.rfftfreq(e.size, 1 / fs)
    band = (freq > 20) & (freq < 200)
    peak = freq[band][np.argmax(spec[band])]
    assert peak == pytest.approx(_bpfo(FR, Z, D, PITCH), abs=1.5)   # 1 Hz bins


def test_rig_params_take_the_rig_structure():
    s = _settings(structure={"housing_mass_kg": 8.0, "housing_stiffness_n_m": 2e8,
                             "housing_zeta": 0.1, "resonator_hz": 3300.0})
    scene = Scene.from_mapping({"bearing": {"designation": "SKF 6203"},
                                "defect": {"location": "outer_race"}}, load_kN=1.0,
                                depth_um=50.0)
    p = rig_params(scene, s, None)
    assert p.housing_mass_kg == 8.0 and p.resonator_hz == 3300.0
    assert p.housing_damping_ns_m == pytest.approx(2 * 0.1 * math.sqrt(2e8 * 8.0))
    assert p.sensor_angle_rad == pytest.approx(math.pi)
    assert p.contact_damping_ns_m > 0


def test_tiny_dynamic_rig_runs_end_to_end(records):
    """The rig with ``dynamics: dynamic`` on the synthetic records: every record made by the
    dynamic model (draft table), scored, its twin's line at the measured record's line."""
    tmp, recs, conds, contact = records
    out = tmp / "run"
    assert all(contact[c.name] == str(dynamic_path(out / "contact", c)) for c in conds)
    assert "_quasi_static" not in contact        # no record stays quasi-static
    card = rig.run_scorecard(conds, contact, out, "ref", settings=_settings(),
                             log=lambda s: None)
    fam = {"outer_race": "bpfo", "inner_race": "bpfi"}
    for name, (loc, rate, _) in recs.items():
        r = card[card.record == name].iloc[0]
        assert r.family == fam[loc] and r.meas_diagnosis == fam[loc]
        assert r.sim_line_orders == pytest.approx(rate / FR, rel=0.005)
        with np.load(out / "sim" / f"{name}_sim.npz") as z:
            meta = json.loads(str(z["meta_json"]))
        assert meta["excitation"] == "dynamic"
    summary = json.loads((out / "summary.json").read_text())
    assert list(summary["gains"]) == ["dynamic"]
    again = rig.existing_excitations(conds, _settings(), out / "contact")
    assert {k: again[k] for k in recs} == {k: contact[k] for k in recs}


def test_a_ball_record_is_made_by_the_dynamic_model_at_twice_the_ball_spin(records):
    """A pit on a rolling element is in the dynamic model: the ball record's excitation is the
    dynamic model's, its pit meets a contact, and the envelope of the sensor's reading has its
    line at twice the ball spin frequency (the pit meets the inner and the outer race once per
    spin; ``2 BSF`` from the kinematics, independent of the model), well above the band's
    floor, and its strongest line is of that family: ``2 BSF`` or a cage-rate sideband of it
    (the ball carries load only through the load zone, once per cage turn)."""
    tmp, _, conds, _ = records
    ball = dataclasses.replace(conds[1], name="ball_1000N", location="rolling_element")
    assert rig.dynamic_supported(ball)
    contact = rig.simulate_excitations([ball], _settings(), tmp / "ball" / "contact",
                                       log=lambda s: None, gain_reference="ref")
    assert contact["ball_1000N"] == str(dynamic_path(tmp / "ball" / "contact", ball))
    assert "_quasi_static" not in contact
    assert excitation_model(contact["ball_1000N"]) == "dynamic"
    with np.load(contact["ball_1000N"]) as z:
        f, fs, peak = z["housing_force"], float(z["fs"]), float(z["defect_force_peak"])
    assert peak > 0
    x = sensor_excitation(f, 180.0, 0.255)
    e = np.abs(sps.hilbert(sps.sosfiltfilt(sps.butter(4, [1500, 4500], "bandpass", fs=fs,
                                                      output="sos"), x))) ** 2
    spec = np.abs(np.fft.rfft(e - e.mean()))
    freq = np.fft.rfftfreq(e.size, 1 / fs)
    band = (freq > 20) & (freq < 200)
    k = bearing_rates(FR, Z, D, PITCH)
    at = spec[np.argmin(np.abs(freq - 2 * k["bsf"]))]
    assert at > 10 * np.median(spec[band])
    line = freq[band][np.argmax(spec[band])]
    family = [2 * k["bsf"] + j * k["ftf"] for j in (-1, 0, 1)]
    assert min(abs(line - f) for f in family) <= 2 * fs / e.size

