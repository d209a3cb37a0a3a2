"""Elements loaded outside the radial load zone: centrifugal force, preload, the exposure of a
defect known before any solve (issue 33, parts 1 and 6). Checked against independent answers:
Harris' centrifugal formula from hand numbers, Stribeck's 4.385 F_r/Z, the force balance of the
inner ring, the compatibility of the two contact deflections, Lame's press fit."""

import math

import numpy as np
import pytest

from bearing_envelope.contact import hertz
from bearing_envelope.physics.exposure import exposure, exposure_line, passage_loads
from bearing_envelope.physics.loads import (centrifugal_force, operating_clearance,
                                            race_compliances, row_load_distribution)
from bearing_envelope.physics.scene import Scene
from bearing_envelope.physics.table import unloaded_table

CWRU = {"bearing": {"designation": "SKF 6205-2RS", "radial_clearance_um": 10.0},
        "operation": {"shaft_rate_hz": 29.95, "fs_hz": 48000.0, "revolutions": 2},
        "defect": {"shape": "cylinder", "width_um": 177.8, "location": "outer_race"}}


def cwru(position_deg=0.0, centrifugal=False, clearance_um=10.0, location="outer_race"):
    m = {k: dict(v) for k, v in CWRU.items()}
    m["bearing"]["radial_clearance_um"] = clearance_um
    m["defect"].update(location=location, position_deg=position_deg)
    m["load"] = {"centrifugal": centrifugal}
    return Scene.from_mapping(m, load_kN=1.0, depth_um=279.4)


def test_centrifugal_force_of_a_6205_ball_by_hand():
    # Harris: F_c = m omega_c^2 d_m/2; 6205 ball d = 7.94 mm of 52100 (7810 kg/m^3), cage at the
    # FTF 0.3983 x 29.95 Hz, pitch 39.04 mm -- every number typed here, not taken from the code
    m = 7810.0 * math.pi * 0.00794 ** 3 / 6.0
    w = 2.0 * math.pi * 0.39828 * 29.95
    expected = m * w ** 2 * 0.03904 / 2.0
    sc = cwru()
    assert centrifugal_force(sc.bearing, sc.cage_rate_hz) == pytest.approx(expected, rel=1e-3)
    assert expected == pytest.approx(0.2245, rel=1e-3)    # the "~0.22 N"


def test_off_is_the_closed_form_law_bit_for_bit():
    a = row_load_distribution(cwru())
    assert a.centrifugal == 0.0 and a.law_nodes is None
    psi = np.linspace(-math.pi, math.pi, 101)
    d = np.clip((a.delta_r * np.cos(psi) - 0.5 * a.clearance), 0, None)
    np.testing.assert_array_equal(a.load_at(psi), a.stiffness * d ** a.exponent)
    np.testing.assert_array_equal(a.load_at(psi, "outer"), a.load_at(psi))


def test_stribeck_and_balance_with_centrifugal_force():
    # zero clearance: Q_max = 4.385 F_r / Z for 9 balls (Stribeck's 4.37 for many); the
    # centrifugal force (0.22 N against 487 N) moves it by less than 0.05 %
    for cf in (False, True):
        ld = row_load_distribution(cwru(centrifugal=cf, clearance_um=0.0))
        assert ld.q_max == pytest.approx(4.385 * 1000.0 / 9, rel=1e-3)
        # the inner ring's equilibrium: sum Q_i cos psi = F_r (solved loads exactly; the law
        # read per sample from its nodes to 1e-6)
        assert float(np.sum(ld.q * np.cos(ld.psi))) == pytest.approx(1000.0, rel=1e-9)
        assert float(np.sum(ld.load_at(ld.psi) * np.cos(ld.psi))) == pytest.approx(1000.0, rel=1e-6)


def test_outer_contact_carries_the_centrifugal_force_everywhere():
    sc = cwru(centrifugal=True)
    ld = row_load_distribution(sc)
    fc = centrifugal_force(sc.bearing, sc.cage_rate_hz)
    # outside the load zone (+-75.4 deg at 10 um): inner contact open, outer carries F_c
    for psi in (math.radians(90), math.radians(180)):
        assert ld.load_at(psi) == 0.0
        assert ld.load_at(psi, "outer") == pytest.approx(fc, rel=1e-12)
    # inside: compatibility of the element's two Hertz deflections, each from hertz.elliptical
    b, e = sc.bearing, sc.material.e_star_pa
    c_i = hertz.elliptical(1.0, b.rx_for("inner"), b.ry_for("inner"), e).approach
    c_o = hertz.elliptical(1.0, b.rx_for("outer"), b.ry_for("outer"), e).approach
    assert race_compliances(sc) == pytest.approx((c_i, c_o), rel=1e-12)
    for deg in (0.0, 30.0, 60.0, 74.0):
        psi = math.radians(deg)
        qi, qo = float(ld.load_at(psi)), float(ld.load_at(psi, "outer"))
        delta = ld.delta_r * math.cos(psi) - 0.5 * ld.clearance
        assert c_i * qi ** (2 / 3) + c_o * qo ** (2 / 3) == pytest.approx(delta, rel=1e-6)
        assert qo - qi == pytest.approx(fc, rel=1e-9)


def test_preload_loads_three_oclock():
    # operating clearance -5 um: the zone spans more than 180 deg; the radial ring
    # displacement and the ball law, recomputed by hand, give the 3:00 load
    ld = row_load_distribution(cwru(clearance_um=-5.0))
    assert math.degrees(ld.half_angle) > 90.0
    q90 = ld.stiffness * (2.5e-6) ** 1.5                  # delta(90 deg) = -P_d/2
    assert float(ld.load_at(math.pi / 2)) == pytest.approx(q90, rel=1e-9)
    assert float(ld.load_at(math.pi)) == 0.0              # 12:00 stays unloaded at 1 kN
    assert float(np.sum(ld.q * np.cos(ld.psi))) == pytest.approx(1000.0, rel=1e-9)


def test_operating_clearance_lame_fits():
    # same-material solid shaft: raceway grows by I * bore / D_i (Lame); 6205: 25 / 31.1 mm
    b = cwru().bearing
    assert operating_clearance(b, shaft_interference_um=10.0) == pytest.approx(
        10.0 - 10.0 * 25.0 / 31.1, rel=1e-9)
    assert operating_clearance(b, housing_interference_um=10.0) == pytest.approx(
        10.0 - 10.0 * 46.98 / 52.0, rel=1e-9)
    assert operating_clearance(b, inner_warmer_by_K=10.0) == pytest.approx(
        10.0 - 11.9e-6 * 10.0 * 31.1e3, rel=1e-9)


def test_exposure_before_any_solve():
    # 3:00 outside the zone: never loaded, one line; with the centrifugal force: loaded at F_c,
    # and the 0.007 in pit is longer than the 0.22 N contact (2b = 154 um, Hertz by hand below)
    sc = cwru(position_deg=90.0)
    e = exposure(sc, row_load_distribution(sc))
    assert not e["loaded"]
    line = exposure_line(sc, e)
    assert "never meets a loaded contact" in line and "\n" not in line
    sc = cwru(position_deg=90.0, centrifugal=True)
    e = exposure(sc, row_load_distribution(sc))
    r = e["races"]["outer"]
    assert e["loaded"] and r["q_min_N"] == pytest.approx(0.2245, rel=2e-3)
    two_b = 2 * hertz.elliptical(r["q_min_N"], sc.bearing.rx_for("outer"),
                                 sc.bearing.ry_for("outer"), sc.material.e_star_pa).b
    assert two_b < 177.8e-6 and r["longer_than_contact_fraction"] == 1.0
    # 0.021 in on the inner race: the 478 N (bridge limit) and 8.4 N (longer)
    m = {k: dict(v) for k, v in CWRU.items()}
    m["defect"].update(location="inner_race", width_um=533.4)
    sc = Scene.from_mapping(m, load_kN=1.0, depth_um=279.4)
    r = exposure(sc, row_load_distribution(sc))["races"]["inner"]
    assert r["bridge_load_N"] == pytest.approx(478.0, rel=0.01)
    assert r["longer_load_N"] == pytest.approx(8.4, rel=0.01)
    assert 0 < r["longer_than_contact_fraction"] < r["beyond_bridge_fraction"] < 1


def test_passage_loads_of_a_ball_defect_cover_both_contacts():
    sc = cwru(centrifugal=True, location="rolling_element")
    ld = row_load_distribution(sc)
    p = passage_loads(sc, ld)
    assert set(p) == {"inner", "outer"}
    assert p["inner"].max() == pytest.approx(ld.q_max, rel=1e-12)
    assert p["outer"].min() == pytest.approx(ld.centrifugal, rel=1e-12)


def test_unloaded_table_reads_zero_at_zero_load():
    tab = unloaded_table(cwru(position_deg=90.0).for_race("outer"))
    q, x = np.zeros(5), np.linspace(-1e-3, 1e-3, 5)
    P, Pd = tab.evaluate(q, x)
    assert not np.any(P) and not np.any(Pd)
    assert all(not np.any(v) for v in tab.evaluate_integrals(q, x).values())


def test_wandering_spin_axis_strikes_with_the_geometric_probability():
    # independent answer: a point uniform on the sphere lies within b of a great circle of a
    # sphere of radius r with probability b / r (Archimedes' hat-box theorem)
    from bearing_envelope.physics.locations import on_track, rolling_element_kinematics
    sc = cwru(location="rolling_element")
    m = {k: dict(v) for k, v in CWRU.items()}
    m["defect"].update(location="rolling_element", spin_axis="wandering", spin_seed=3)
    sw = Scene.from_mapping(m, load_kN=1.0, depth_um=279.4)
    turns = 4000
    theta = 2 * math.pi * np.arange(turns)          # one sample per cage turn
    kin = rolling_element_kinematics(sw, theta)
    q = 500.0
    b = hertz.elliptical(q, sw.bearing.rx_for("outer"), sw.bearing.ry_for("outer"),
                         sw.material.e_star_pa).b
    p = b / (0.5e-3 * sw.bearing.roller_diameter_mm)
    hits = on_track(sw, "outer", np.full(turns, q), kin["track_offset"])
    assert hits.mean() == pytest.approx(p, abs=4 * math.sqrt(p * (1 - p) / turns))
    # deterministic, and a block of the record sees the same orientations as the whole
    half = rolling_element_kinematics(sw, theta[turns // 2:])
    np.testing.assert_array_equal(half["track_offset"], kin["track_offset"][turns // 2:])
    # fixed (the default): on the track, the offsets of before
    kf = rolling_element_kinematics(sc, theta[:10] + 0.3)
    assert not np.any(kf["track_offset"])
    beta = (theta[:10] + 0.3) * (39.04 + 7.94) / 7.94
    np.testing.assert_allclose(kf["offset_outer"], 0.5 * 7.94e-3 * (
        (beta + math.pi) % (2 * math.pi) - math.pi), atol=1e-12)


def test_wandering_spin_axis_is_a_rolling_element_option():
    m = {k: dict(v) for k, v in CWRU.items()}
    m["defect"]["spin_axis"] = "wandering"
    with pytest.raises(ValueError, match=r"scene.defect.spin_axis: got 'wandering'"):
        Scene.from_mapping(m, load_kN=1.0, depth_um=279.4)
