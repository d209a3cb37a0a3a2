"""The rig's single-axis sensor and the load zone it is identified with: the direction gain
against its closed form, the defect's angle against the published kinematics, the sidebands of
a uniformly loaded inner race seen along one axis against the Fourier series of |cos|."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from bearing_envelope.physics.history import defect_angle
from bearing_envelope.physics.transfer import direction_gain
from bearing_envelope.study import rig

FS = 12_000.0


def test_direction_gain_closed_form():
    th = np.radians([0.0, 90.0, 180.0, 270.0, 45.0])
    assert direction_gain(th, 0.0, 1.0) == pytest.approx(np.ones(5))
    assert direction_gain(th, 0.0, 0.0) == pytest.approx(np.abs(np.cos(th)), abs=1e-15)
    # along the axis 1, across it the cross-axis gain, at 45 deg sqrt((1 + k^2) / 2)
    assert direction_gain(th, math.pi, 0.25) == pytest.approx(
        [1.0, 0.25, 1.0, 0.25, math.sqrt((1 + 0.0625) / 2)])
    with pytest.raises(ValueError, match=r"cross_axis: got 1.5; allowed: 0 to 1"):
        direction_gain(th, 0.0, 1.5)


def _write_record(path, n=1200):
    np.savez(path, x=np.zeros(n), fs=np.float64(FS))
    return str(path)


def _settings(load_kN=1.0, clearance_um=None, cross=1.0):
    scene = {"bearing": {"designation": "SKF 6205-2RS"}}
    if clearance_um is not None:
        scene["bearing"]["radial_clearance_um"] = clearance_um
    return rig.RigSettings(scene=scene, load_kN=load_kN, fidelity="draft",
                           sensor_cross_axis=cross)


def _conds(tmp_path, settings):
    for name in ("ir", "or3", "ball"):
        _write_record(tmp_path / f"{name}.npz")
    (tmp_path / "manifest.csv").write_text(
        "file,location,length_um,depth_um,position_deg,load,shaft_hz,bearing\n"
        "ir.npz,inner_race,177.8,279.4,,0,29.95,6205\n"
        "or3.npz,outer_race,177.8,279.4,90,0,29.95,6205\n"
        "ball.npz,ball,177.8,279.4,,0,29.95,6205\n")
    by = {c.location: c for c in rig.record_conditions([str(tmp_path)])}
    return by["inner_race"], by["outer_race"], by["rolling_element"]


def test_defect_angle_follows_the_published_kinematics(tmp_path):
    s = _settings()
    ir, or3, ball = _conds(tmp_path, s)
    t = np.linspace(0.0, 0.5, 7)
    fr = 29.95
    assert defect_angle(rig.condition_scene(ir, s), t) == pytest.approx(2 * math.pi * fr * t)
    assert defect_angle(rig.condition_scene(or3, s), t) == pytest.approx(np.full(7, math.pi / 2))
    ftf = fr / 2 * (1 - 7.94 / 39.04)
    assert defect_angle(rig.condition_scene(ball, s), t) == pytest.approx(
        2 * math.pi * ftf * t, rel=2e-3)


def test_uniform_load_seen_along_one_axis_has_the_cos_series_sidebands(tmp_path):
    """A preload far above the radial load loads the inner race evenly; a sensor blind across
    its axis then sees the events weighted by |cos theta|: its Fourier series 2/pi + 4/(3 pi)
    cos 2 theta - ... gives the 2 fr sideband at 1/3 of the line (-9.54 dB), no fr sideband,
    and a 3:00 outer race silent."""
    s = _settings(load_kN=0.001, clearance_um=-30.0, cross=0.0)
    ir, or3, _ = _conds(tmp_path, s)
    d = rig.directional_modulation(s, ir, or3, 1.0, 0.5)
    assert d["sb2_db"] == pytest.approx(20 * math.log10(1 / 3), abs=0.05)
    assert d["sb1_db"] < -40.0
    assert d["ratio_3_6_db"] < -200.0
    # blind to direction: no 2 fr sideband, the 3:00 ratio the load's (equal loads: 0 dB)
    d = rig.directional_modulation(dataclasses.replace(s, sensor_cross_axis=1.0), ir, or3,
                                   1.0, 0.5)
    assert d["sb2_db"] < -40.0 and d["ratio_3_6_db"] == pytest.approx(0.0, abs=0.05)


def test_identify_load_zone_recovers_a_known_rig(tmp_path):
    s = _settings(load_kN=0.2, clearance_um=-6.0, cross=0.3)
    ir, or3, _ = _conds(tmp_path, s)
    truth = rig.directional_modulation(s, ir, or3, 0.5, 0.26)
    c, k = rig.identify_load_zone(s, ir, or3, truth["sb1_db"], truth["ratio_3_6_db"], 0.5, 0.26)
    assert c == pytest.approx(-6.0, abs=0.05) and k == pytest.approx(0.3, abs=0.005)
    with pytest.raises(ValueError, match=r"sb1_db: -80 dB is outside"):
        rig.identify_load_zone(s, ir, or3, -80.0, truth["ratio_3_6_db"], 0.5, 0.26)
    # a 3:00 line louder than the load zone can make even with a direction-blind sensor
    with pytest.raises(ValueError, match=r"ratio_db: 3 dB is above what the load zone gives"):
        rig.identify_load_zone(s, ir, or3, truth["sb1_db"], 3.0, 0.5, 0.26)


def test_structure_part_of_the_3_oclock_ratio(tmp_path):
    """The simulated pairs' median ratio less the load zone's and sensor's model: what the
    structure adds (the 2026-12-05 quasi-static run's pairs: -1.3, -2.2, -2.2, -5.9 dB against
    the model's -13.6 dB: 11.4 dB); a pair without a simulated line is left out; no simulated
    pair: 0. Identifying with that part held recovers a known rig whose simulated ratio
    carries it."""
    import pandas as pd

    got = rig.structure_ratio_db(pd.DataFrame({"sim_db": [-1.3, -2.2, -2.2, -5.9, np.nan]}),
                                 -13.6)
    assert got == pytest.approx(11.4)
    assert rig.structure_ratio_db(pd.DataFrame({"sim_db": [np.nan]}), -13.6) == 0.0
    s = _settings(load_kN=0.2, clearance_um=-6.0, cross=0.1)
    ir, or3, _ = _conds(tmp_path, s)
    truth = rig.directional_modulation(s, ir, or3, 0.5, 0.26)
    measured = truth["ratio_3_6_db"] + 11.4
    c, k = rig.identify_load_zone(s, ir, or3, truth["sb1_db"], measured - 11.4, 0.5, 0.26)
    assert c == pytest.approx(-6.0, abs=0.05) and k == pytest.approx(0.1, abs=0.005)


def test_each_ball_record_draws_its_own_orientation(tmp_path):
    """Each record is its own run of the rig: its ball's orientation is its own draw (a seed
    from its name), so over many records the defect lies within the contact's axial
    semi-axis b of the track in a fraction b / (d/2) of them (sin(latitude) uniform on the
    sphere); before, every ball record of the rig shared one draw, and all 15 development
    records missed their contacts alike."""
    from bearing_envelope.physics.locations.rolling_element import rolling_element_kinematics

    s = _settings()
    _, _, ball = _conds(tmp_path, s)
    s = dataclasses.replace(s, ball_spin_axis="wandering")
    half_d = 0.5 * 7.94e-3
    b = 0.25 * half_d  # a semi-axis a quarter of the radius: a strike probability of 1/4
    offsets = []
    for i in range(400):
        scene = rig.condition_scene(dataclasses.replace(ball, name=f"rec_{i}"), s)
        k = rolling_element_kinematics(scene, np.zeros(1), redraw=False)
        offsets.append(float(k["track_offset"][0]))
    assert len({rig.record_spin_seed(f"rec_{i}", 0) for i in range(400)}) == 400
    frac = np.mean(np.abs(offsets) < b)
    assert frac == pytest.approx(0.25, abs=3 * math.sqrt(0.25 * 0.75 / 400))
    # the same record, the same draw
    again = rig.condition_scene(dataclasses.replace(ball, name="rec_7"), s)
    assert rolling_element_kinematics(again, np.zeros(1), redraw=False)["track_offset"][0] == \
        offsets[7]


def test_sensor_gain_scales_a_3_oclock_record_by_the_cross_axis_gain(tmp_path):
    """A 3:00 defect's force acts across a 12:00 sensor's axis: the simulated record is the
    cross-axis gain times the direction-blind one (the path is linear)."""
    s = _settings(cross=0.25)
    _, or3, _ = _conds(tmp_path, s)
    t = np.arange(or3.n_samples) / FS
    assert rig.sensor_gain(or3, s, t) == pytest.approx(np.full(t.size, 0.25))
    assert rig.sensor_gain(or3, dataclasses.replace(s, sensor_cross_axis=1.0), t) == \
        pytest.approx(np.ones(t.size))


def test_rig_config_refuses_a_bad_sensor(tmp_path):
    p = tmp_path / "rig.yaml"
    p.write_text("scene: {}\nrig: {load_kN: 1, sensor_cross_axis: 2}\n")
    with pytest.raises(ValueError, match=r"rig.sensor_cross_axis: got 2; allowed: a number "
                                         r"from 0 to 1"):
        rig.read_rig_config(p)
    p.write_text("scene: {}\nrig: {load_kN: 1, sensor_deg: x}\n")
    with pytest.raises(ValueError, match=r"rig.sensor_deg: got 'x'"):
        rig.read_rig_config(p)
    p.write_text("scene: {}\nrig: {load_kN: 1}\n")
    got = rig.read_rig_config(p)
    assert got.sensor_deg == 180.0 and got.sensor_cross_axis == 1.0
    # the depth per diameter in mils is gone: each record's depth is in its manifest
    p.write_text("scene: {}\nrig: {load_kN: 1, depth_um: {'7': 279.4}}\n")
    with pytest.raises(ValueError, match=r"rig.depth_um: no longer read; allowed: each "
                                         r"record's pit depth in its manifest's depth_um"):
        rig.read_rig_config(p)


def test_event_exponent_of_a_power_law_event_train(tmp_path):
    """Events at 160 Hz whose peak removed force is 0.02 Q^0.6 over loads 5-500 N, each
    followed by a smaller ringing lobe (as the acquisition's filter leaves): b = 0.6."""
    fs, rate, n = 12_000.0, 160.0, 12_000
    t = np.arange(n) / fs
    q = 5.0 + 495.0 * (0.5 + 0.5 * np.cos(2 * math.pi * 29.6 * t))
    f = np.zeros(n)
    for i in (np.arange(0.002, 0.99, 1 / rate) * fs).astype(int):
        f[i] = 0.02 * q[i] ** 0.6
        f[i + 3] = 0.3 * f[i]          # a ringing lobe: not an event
    np.savez(tmp_path / "c.npz", removed_force=f, roller_load=q, fs=np.float64(fs), time=t)
    assert rig.event_exponent(str(tmp_path / "c.npz"), rate) == pytest.approx(0.6, abs=0.01)
    np.savez(tmp_path / "z.npz", removed_force=np.zeros(n), roller_load=q, fs=np.float64(fs),
             time=t)
    with pytest.raises(ValueError, match=r"allowed: events at >= 2 loads"):
        rig.event_exponent(str(tmp_path / "z.npz"), rate)


def test_measured_sideband_db_reads_the_lines_table():
    """Sidebands of 0.1 and 0.3 over a line of 1: their mean 0.2, -13.98 dB, in each band."""
    rows = []
    for band in ("kurtogram", "fs4_3fs8", "raw"):
        for sb, a in ((-1, 0.1), (0, 1.0), (1, 0.3)):
            rows.append({"file": "/x/rec_a.npz", "band": band, "base": "bpfi", "order": 1,
                         "sideband": sb, "amplitude": a})
    import pandas as pd

    got = rig.measured_sideband_db(pd.DataFrame(rows), ["rec_a", "rec_b"])
    assert got == pytest.approx([20 * math.log10(0.2)] * 2)  # raw is not read; rec_b absent


def test_features_in_measured_band_read_both_records_in_one_band():
    """The measured record's best band is bpfi_10_13; both records are read there: measured
    2x/1x 0.5 (-6.02 dB), simulated 0.3 (-10.46 dB); the sidebands 0.1/0.1 over 1 both."""
    import pandas as pd

    def rows(name, h2, low):
        out = []
        for band, lo in (("bpfi_10_13", 1620.0), ("kurtogram", low)):
            for o, sb, a in ((1, 0, 1.0), (2, 0, h2), (3, 0, 0.1), (1, -1, 0.1), (1, 1, 0.1)):
                out.append({"file": f"/d/{name}.npz", "band": band, "band_low_hz": lo,
                            "band_high_hz": lo + 500.0, "base": "bpfi", "order": o,
                            "sideband": sb, "amplitude": a})
        return pd.DataFrame(out)

    card = pd.DataFrame([{"record": "r", "family": "bpfi", "meas_h1": 1.0,
                          "meas_band_low_hz": 1620.0, "meas_band_high_hz": 2120.0}])
    got = rig.features_in_measured_band(card, rows("r", 0.5, 3000.0), rows("r_sim", 0.3, 0.0))
    by = {g["feature"]: g for g in got}
    assert by["h2_db"]["meas_db"] == pytest.approx(-6.0206, abs=1e-3)
    assert by["h2_db"]["sim_db"] == pytest.approx(-10.4576, abs=1e-3)
    assert by["h2_db"]["within_tol"] and by["h3_db"]["meas_db"] == pytest.approx(-20.0)
    assert by["sideband_db"]["sim_db"] == pytest.approx(-20.0) and by["h2_db"]["band"] == \
        "bpfi_10_13"
    card["meas_band_low_hz"] = 3000.0   # best band a kurtogram band: not read
    assert rig.features_in_measured_band(card, rows("r", 0.5, 3000.0),
                                         rows("r_sim", 0.3, 0.0)) == []
