"""The virtual rig on tiny inputs: manifests and their one-line refusals, record conditions and
scenes, a simulated record made of a known excitation through an identified path, the
scorecard's rules."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from bearing_envelope.diagnosis.transfer_path import identify_path
from bearing_envelope.study import rig

FS = 12_000.0

#: The manifest's columns as these tests write them.
HEAD = ("file,location,length_um,width_um,depth_um,position_deg,load,fs_hz,shaft_hz,bearing,"
        "n_rollers,roller_diameter_mm,pitch_diameter_mm")


def _settings(scene=None):
    return rig.RigSettings(scene={"bearing": {"designation": "SKF 6205-2RS"}}
                           if scene is None else scene, load_kN=1.0, fidelity="draft")


def _write_record(path, x, fs=FS):
    np.savez(path, x=x, fs=np.float64(fs))
    return str(path)


def _manifest(tmp_path, rows, name="manifest.csv"):
    path = tmp_path / name
    path.write_text(HEAD + "\n" + "\n".join(rows) + "\n")
    return str(path)


def test_conditions_read_the_manifest(tmp_path):
    _write_record(tmp_path / "a.npz", np.zeros(1000))
    _write_record(tmp_path / "b.npz", np.zeros(500))
    _write_record(tmp_path / "n.npz", np.zeros(10))
    m = _manifest(tmp_path, [
        "a.npz,outer_race,177.8,,279.4,90,2,,29.17,6205,,,",
        "b.npz,inner_race,711.2,500,1270,,0,12000,29.95,,9,7.94,39.04",
        "n.npz,normal,,,,,0,,,,,,"])
    conds = rig.record_conditions([m])
    assert [c.name for c in conds] == ["a", "b"]
    a, b = conds
    assert a.location == "outer_race" and a.position_deg == 90.0 and a.width_um == 177.8
    assert a.n_samples == 1000 and a.load == 2.0 and a.fs_hz == FS  # fs from the file
    assert a.bearing.designation == "SKF 6205-2RS" and b.bearing.designation is None
    assert a.bearing.same_geometry(b.bearing)
    assert b.location == "inner_race" and b.depth_um == 1270.0 and b.width_um == 500.0
    assert b.defect_key == "inner_race_711.2x500x1270um_0deg"
    # the rates are the kinematics' (Harris): BPFO = Z/2 fr (1 - d/D cos alpha)
    assert a.rates["bpfo"] == pytest.approx(4.5 * 29.17 * (1 - 7.94 / 39.04), rel=1e-12)
    # a folder holding manifest.csv is read through it
    assert [c.name for c in rig.record_conditions([str(tmp_path)])] == ["a", "b"]


@pytest.mark.parametrize("row, message", [
    ("a.npz,inner_race,177.8,,279.4,90,0,,30,6205,,,", r"row 2: position_deg: got 90; allowed: "
                                                      r"empty or 0 unless location is outer_race"),
    ("a.npz,outer_race,177.8,,279.4,,0,,30,6205,,,", r"row 2: position_deg: empty"),
    ("a.npz,outer_race,177.8,,279.4,360,0,,30,6205,,,", r"position_deg: got '360'; allowed: a "
                                                        r"number 0 to 360 \(excluded\) deg"),
    ("a.npz,inner_race,,,279.4,,0,,30,6205,,,", r"row 2: length_um: empty"),
    ("a.npz,inner_race,-5,,279.4,,0,,30,6205,,,", r"length_um: got '-5'; allowed: a number > 0 um"),
    ("a.npz,cage,177.8,,279.4,,0,,30,6205,,,", r"row 2: location: got 'cage'; allowed: inner_race"),
    ("a.npz,inner_race,177.8,,279.4,,0,,30,6205,9,7.94,39.04", r"bearing: got '6205' and "
                                                             r"n_rollers"),
    ("a.npz,inner_race,177.8,,279.4,,0,,30,,9,,39.04", r"row 2: roller_diameter_mm: empty"),
    ("a.npz,inner_race,177.8,,279.4,,0,,30,9999,,,", r"row 2: bearing: got '9999'; allowed"),
    ("a.npz,inner_race,177.8,,279.4,,0,,x,6205,,,", r"row 2: shaft_hz: got 'x'"),
    ("a.npz,inner_race,177.8,,279.4,,,,30,6205,,,", r"row 2: load: empty"),
    ("a.npz,inner_race,177.8,,279.4,,0,48000,30,6205,,,", r"row 2: fs_hz: got 48000; the file "
                                                          r"says 12000 Hz"),
    ("a.npz,inner_race,177.8,,279.4,,0,,,6205,,,", r"row 2: shaft_hz: empty and not in the file"),
    ("b.npz,inner_race,177.8,,279.4,,0,,30,6205,,,", r"row 2: file: no such file"),
])
def test_bad_manifest_rows_are_refused_in_one_line(tmp_path, row, message):
    _write_record(tmp_path / "a.npz", np.zeros(100))
    m = _manifest(tmp_path, [row])
    with pytest.raises(ValueError, match=message) as err:
        rig.record_conditions([m])
    assert "\n" not in str(err.value)


def test_manifest_without_a_location_column_is_refused(tmp_path):
    (tmp_path / "m.csv").write_text("file,load\na.npz,0\n")
    with pytest.raises(ValueError, match=r"m.csv: no 'location' column; allowed columns: file"):
        rig.record_conditions([str(tmp_path / "m.csv")])


def test_condition_scene_takes_the_record_operation_and_defect(tmp_path):
    _write_record(tmp_path / "a.npz", np.zeros(12_000))
    m = _manifest(tmp_path, ["a.npz,outer_race,177.8,,279.4,90,2,,29.17,6205,,,"])
    cond = rig.record_conditions([m])[0]
    scene = rig.condition_scene(cond, _settings())
    assert scene.defect.location == "outer_race"
    assert scene.defect.position_deg == 90.0
    assert scene.defect.width_um == pytest.approx(177.8)
    assert scene.defect.depth_um == pytest.approx(279.4)
    assert scene.operation.shaft_rate_hz == pytest.approx(29.17)
    assert scene.n_samples >= cond.n_samples


def test_a_record_of_another_bearing_than_the_scene_is_refused(tmp_path):
    _write_record(tmp_path / "a.npz", np.zeros(1200))
    m = _manifest(tmp_path, ["a.npz,inner_race,177.8,,279.4,,0,,29.95,SKF 6203,,,"])
    cond = rig.record_conditions([m])[0]
    with pytest.raises(ValueError, match=r"a: bearing: SKF 6203 \(8 x 6.75 mm on 28.55 mm, 0 "
                                         r"deg\) is not the rig scene's SKF 6205-2RS"):
        rig.condition_scene(cond, _settings())
    rig.condition_scene(cond, _settings({"bearing": {"designation": "SKF 6203"}}))


def _record_cond(tmp_path, x):
    _write_record(tmp_path / "m.npz", x)
    m = _manifest(tmp_path, [f"m.npz,outer_race,177.8,,279.4,90,2,,{107.0 / 3.5848!r},6205,,,"])
    return rig.record_conditions([m])[0]


def test_simulated_record_rings_the_identified_mode(tmp_path):
    """A removed-force pulse train through a path identified from a synthetic record: the
    simulated record's own identification finds the same mode and the pulse rate."""
    n = int(3 * FS)
    rng = np.random.default_rng(0)
    # the "measured" record: 107 Hz impulses ringing a 3300 Hz, zeta 0.03 mode, in noise
    wn, z = 2 * math.pi * 3300.0, 0.03
    t = np.arange(n) / FS
    meas = 0.5 * rng.standard_normal(n)
    for t0 in np.arange(0.01, 2.99, 1 / 107.0):
        tau = t[t >= t0] - t0
        meas[t >= t0] += 5 * np.exp(-z * wn * tau) * np.cos(wn * math.sqrt(1 - z * z) * tau)
    path = identify_path(meas, FS, {"bpfo": 107.0})
    cond = _record_cond(tmp_path, meas)
    # the simulated excitation: 3 N removed for one sample at 111 Hz (a different rate)
    rf = np.zeros(n)
    rf[(np.arange(0.005, 2.99, 1 / 111.0) * FS).astype(int)] = 3.0
    contact = tmp_path / "c.npz"
    np.savez(contact, removed_force=rf)
    gain = path.mode(impulse_area=3.0 / FS).gain  # each pulse rings as the measured events
    out = rig.write_rig_record(cond, str(contact), path, gain, tmp_path / "sim", seed=2)
    with np.load(out) as zf:
        x, meta = zf["x"], json.loads(str(zf["meta_json"]))
    assert meta["simulated"] and meta["transfer_path"]["f_n_hz"] == path.f_n_hz
    again = identify_path(x, FS, {"a": 111.0, "b": 107.0})
    assert again.event_name == "a"
    assert again.f_n_hz == pytest.approx(3300.0, rel=0.03)
    assert again.zeta == pytest.approx(path.zeta, rel=0.25)
    assert again.amplitude == pytest.approx(path.amplitude, rel=0.25)


def test_simulated_record_rings_every_identified_mode_at_its_gain(tmp_path):
    """A "measured" record of two analytic resonators (2.6 kHz and 3.4 kHz, as the CWRU 3:00
    and 6:00 records ring), re-made from a pulse train through its identified path: the
    simulated record's own identification finds both modes, each with the measured event
    amplitude (the first mode's gain set from the measured record, the second's as
    identified)."""
    n = int(3 * FS)
    rng = np.random.default_rng(0)
    t = np.arange(n) / FS
    meas = 0.5 * rng.standard_normal(n)
    for f_n, z, a in ((2600.0, 0.04, 5.0), (3400.0, 0.025, 3.0)):
        wn = 2 * math.pi * f_n
        for t0 in np.arange(0.01, 2.99, 1 / 107.0):
            tau = t[t >= t0] - t0
            meas[t >= t0] += a * np.exp(-z * wn * tau) * np.cos(wn * math.sqrt(1 - z * z) * tau)
    path = identify_path(meas, FS, {"bpfo": 107.0})
    assert len(path.modes) == 2
    modes = rig.path_modes(path, 1.0)
    assert modes[0].gain == 1.0 and modes[1].gain > 0
    # the rig's reference mode (3.4 kHz, within 3 %, damping within a factor 2): found; the
    # first mode's gain over it is the analytic ratio g(2.6 kHz) / g(3.4 kHz) = (5 / (0.04 x
    # 2600)) / (3 / (0.025 x 3400)) = 1.362 (a ringing amplitude a = g 2 zeta wn A)
    ref = rig.reference_mode(path, 3400.0 * 1.01, 0.025)
    assert ref is not None and ref.f_n_hz == pytest.approx(3400.0, rel=0.03)
    assert path.structure()[0].gain / ref.gain == pytest.approx(1.362, rel=0.3)
    assert rig.reference_mode(path, 5000.0, 0.025) is None  # no such mode
    assert rig.reference_mode(path, 3400.0, 0.2) is None  # not within a factor 2 of its damping
    by_f = sorted(rig.path_modes(path, first_gain=1.362), key=lambda m: m.f_n_hz)
    assert by_f[0].gain == 1.362 and by_f[1].gain == pytest.approx(1.0, rel=0.3)
    cond = _record_cond(tmp_path, meas)
    rf = np.zeros(n)
    rf[(np.arange(0.005, 2.99, 1 / 111.0) * FS).astype(int)] = 3.0
    contact = tmp_path / "c.npz"
    np.savez(contact, removed_force=rf)
    gain = path.mode(impulse_area=3.0 / FS).gain
    out = rig.write_rig_record(cond, str(contact), path, gain, tmp_path / "sim", seed=2)
    with np.load(out) as zf:
        x, meta = zf["x"], json.loads(str(zf["meta_json"]))
    assert len(meta["transfer_path"]["modes"]) == 2
    again = identify_path(x, FS, {"a": 111.0, "b": 107.0})
    assert again.event_name == "a" and len(again.modes) == 2
    for m, (f_n, a) in zip(sorted(again.modes, key=lambda m: m["f_n_hz"]),
                           ((2600.0, 5.0), (3400.0, 3.0))):
        assert m["f_n_hz"] == pytest.approx(f_n, rel=0.03)
        assert m["amplitude"] == pytest.approx(a, rel=0.3)


def _table(name, diag, conf, fam, h1, h2, h3, db, detected=True):
    return {"record": name, "record_diagnosis": diag, "record_confidence": conf,
            "family": fam, "detected": detected, "fr_hz": 30.0, "h1_hz": 30.0 * 3.58,
            "h1_amplitude": h1, "h2_amplitude": h2, "h3_amplitude": h3, "h1_db": db,
            "band": "b", "band_low_hz": 3000.0, "band_high_hz": 4000.0}


def test_scorecard_rules_follow_the_written_tolerances():
    cond = rig.RigCondition("r", "r.npz", "outer_race", 177.8, 177.8, 279.4, 0.0, 0, 30.0, FS,
                            100, rig.resolve_bearing("6205"))
    mt = pd.DataFrame([_table("r", "bpfo", "high", "bpfo", 1.0, 0.5, 0.25, 30.0)])
    # simulated: 2x/1x -6.0 dB vs measured -6.0 (pass), 3x/1x -20 vs -12 (fail), height +5 dB
    st = pd.DataFrame([_table("r_sim", "bpfo", "medium", "bpfo", 1.0, 0.5, 0.1, 35.0)])
    lines = pd.DataFrame(columns=["file", "band", "base", "order", "sideband", "amplitude"])
    card = rig.scorecard([cond], mt, lines, st, lines)
    r = card.iloc[0]
    assert r.rule_family == "PASS" and r.rule_class == "PASS"
    assert r.rule_h2_db == "PASS" and r.rule_h3_db == "FAIL" and r.rule_height_db == "PASS"
    assert r.rule_sideband_db == "n/a"  # BPFO: no sidebands expected
    assert rig.pass_rates(card)["h3_db"] == [0, 1]


def test_outer_race_ratio_in_db():
    rows = []
    for pos, m, s in ((0.0, 1.0, 1.0), (90.0, 0.1, 0.5)):
        rows.append({"record": f"p{pos:g}", "family": "bpfo", "position_deg": pos,
                     "load": 1, "length_um": 177.8, "fs_hz": FS, "meas_h1": m,
                     "sim_h1": s})
    out = rig.outer_race_ratios(pd.DataFrame(rows))
    assert out[0]["meas_db"] == pytest.approx(-20.0)
    assert out[0]["sim_db"] == pytest.approx(20 * math.log10(0.5))
    assert out[0]["rule"] == "FAIL"
    rows[1]["sim_h1"] = None  # no simulated line at 3:00
    assert rig.outer_race_ratios(pd.DataFrame(rows))[0]["rule"] == "FAIL: no simulated line"


def test_outer_race_ratio_read_in_one_band_for_both_records():
    # the rule's best bands differ; read in the same band: 0.1 / 1.0 measured (-20 dB) and
    # 0.5 / 1.0 simulated (-6.02 dB) in fs4_3fs8; raw: 0.2 / 0.4 (-6.02 dB) vs 0.3 / 0.6
    rows = [{"record": f"p{pos:g}", "family": "bpfo", "position_deg": pos, "load": 1,
             "length_um": 177.8, "fs_hz": FS, "meas_h1": 1.0, "sim_h1": 1.0}
            for pos in (0.0, 90.0)]
    amp = {("p0", "fs4_3fs8"): (1.0, 1.0), ("p90", "fs4_3fs8"): (0.1, 0.5),
           ("p0", "raw"): (0.4, 0.6), ("p90", "raw"): (0.2, 0.3)}
    lines = [[], []]
    for (rec, band), pair in amp.items():
        for side, (suffix, a) in enumerate((("", pair[0]), ("_sim", pair[1]))):
            for base, order, sb, v in (("bpfo", 1, 0, a), ("bpfo", 2, 0, 9.0),
                                       ("bpfi", 1, 0, 7.0), ("bpfo", 1, 1, 5.0)):
                lines[side].append({"file": f"/x/{rec}{suffix}.npz", "band": band,
                                    "base": base, "order": order, "sideband": sb,
                                    "amplitude": v})
    out = rig.outer_race_ratios_in_band(pd.DataFrame(rows), pd.DataFrame(lines[0]),
                                        pd.DataFrame(lines[1]))
    got = {r["band"]: r for r in out}
    assert got["fs4_3fs8"]["meas_db"] == pytest.approx(-20.0)
    assert got["fs4_3fs8"]["sim_db"] == pytest.approx(20 * math.log10(0.5))
    assert got["fs4_3fs8"]["within_tol"] is False
    assert got["raw"]["meas_db"] == pytest.approx(got["raw"]["sim_db"])
    assert got["raw"]["within_tol"] is True


def test_removed_force_exponent_of_a_power_law(tmp_path):
    for name, q in (("a", 0.5), ("b", 500.0)):
        np.savez(tmp_path / f"{name}.npz", roller_load=np.array([0.0, q]),
                 removed_force=np.array([0.0, 2.0 * q ** 0.4]))
    b = rig.removed_force_exponent(str(tmp_path / "a.npz"), str(tmp_path / "b.npz"))
    assert b == pytest.approx(0.4, rel=1e-9)


def test_load_trend_rule():
    rows = []
    for hp in range(4):
        rows.append({"family": "bpfo", "position_deg": 0.0, "length_um": 177.8, "fs_hz": FS,
                     "load": hp, "meas_height_db": 50.0 - 2.0 * hp,
                     "sim_height_db": 40.0 + 0.5 * hp})
    out = rig.load_trends(pd.DataFrame(rows))
    assert out[0]["meas_db_per_load"] == pytest.approx(-2.0)
    assert out[0]["sim_db_per_load"] == pytest.approx(0.5)
    assert out[0]["rule"] == "FAIL"  # opposite signs, not both flat
    for r in rows:
        r["meas_height_db"] = 50.0 - 0.8 * r["load"]
    assert rig.load_trends(pd.DataFrame(rows))[0]["rule"] == "PASS"  # both within 1 dB/hp


def test_anchor_gain_is_one_per_group_not_per_record():
    """The first mode's gain relative to the reference mode is the rig's and the fault place's,
    not the load's: every record of a group (location, position, fs) gets the median over the
    records holding the reference mode (f_n within 3 %, damping within a factor 2); a broad hump
    near the reference frequency does not count (record 146's 3.35 kHz at zeta 0.22 made its
    2.64 kHz mode 38 x the rig's gain, 32 dB above its neighbours at the other loads); a
    group without the reference mode takes its place's ratio at another fs, and a place
    without one rings its first mode at the rig's gain."""
    from types import SimpleNamespace as NS

    from bearing_envelope.physics.transfer import Mode

    def path(*modes):
        return NS(structure=lambda: [Mode(f, z, g) for f, z, g in modes])

    def cond(name, pos):
        return NS(name=name, location="outer_race", position_deg=pos, fs_hz=12000.0)

    conds = [cond("a0", 90.0), cond("a1", 90.0), cond("a2", 90.0), cond("a3", 90.0),
             cond("b0", 0.0), cond("a48", 90.0)]
    conds[-1].fs_hz = 48000.0
    paths = {"a0": (path((2660.0, 0.024, 12.0), (3398.0, 0.032, 3.0)), "identified"),  # 4
             "a1": (path((2660.0, 0.023, 7.0), (1758.0, 0.26, 0.2)), "identified"),  # none
             "a2": (path((2637.0, 0.020, 38.0), (3352.0, 0.224, 1.0)), "identified"),  # hump
             "a3": (path((2672.0, 0.018, 5.0), (3430.0, 0.020, 0.5)), "identified"),  # 10
             "b0": (path((3000.0, 0.02, 1.0)), "identified"),
             "a48": (path((2824.0, 0.015, 3.0)), "identified")}
    got = rig.anchor_gains(conds, paths, 3422.0, 0.024)
    for n in ("a0", "a1", "a2", "a3"):
        assert got[n] == (pytest.approx(7.0), 2)  # median of 4 and 10
    assert got["b0"] == (1.0, 0)
    # a group (here another fs) with no reference mode: its place's ratio at any fs
    assert got["a48"] == (pytest.approx(7.0), 2)
