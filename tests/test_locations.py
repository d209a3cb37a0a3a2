"""Fault locations (issue 23, part E): outer race and rolling element on the CWRU bearing (SKF
6205-2RS, 1797 rpm, 0.007 in EDM pit 0.011 in deep) at draft fidelity, 20 shaft revolutions."""

import math

import numpy as np
import pytest

from bearing_envelope.physics.history import evaluate_signals, simulate
from bearing_envelope.physics.scene import Scene
from bearing_envelope.signal import envelope_spectrum
from bearing_envelope.signal.spectrum import amplitude_at

FR = 1797.0 / 60.0       # CWRU 0 hp shaft rate (Hz)
FS = 12000.0             # CWRU drive-end sampling rate (Hz)
INCH_UM = 25400.0
BAND = (600.0, 5000.0)   # demodulation band (Hz): above the fault lines, below Nyquist


def _scene(location, position_deg=0.0, revolutions=20):
    m = {"bearing": {"designation": "SKF 6205-2RS"},
         "operation": {"bpfi_override_hz": None, "shaft_rate_hz": FR, "fs_hz": FS,
                       "revolutions": revolutions},
         "defect": {"location": location, "position_deg": position_deg, "shape": "cylinder",
                    "width_um": 0.007 * INCH_UM}}
    return Scene.from_mapping(m, load_kN=1.0, depth_um=0.011 * INCH_UM)


@pytest.fixture(scope="module")
def outer():
    return simulate(_scene("outer_race"), "draft")


@pytest.fixture(scope="module")
def inner():
    return simulate(_scene("inner_race"), "draft")


@pytest.fixture(scope="module")
def ball():
    return simulate(_scene("rolling_element"), "draft")


def _lines(h, signal, freqs):
    f, a = envelope_spectrum(h.signals[signal], FS, BAND)
    df = f[1] - f[0]
    return [amplitude_at(f, a, t, 0.6 * df, interpolate=True, n=h.signals[signal].size)[1]
            for t in freqs]


def test_outer_race_load_is_steady_and_events_equal(outer):
    sc, ld = outer.scene, outer.load_distribution
    assert np.all(outer.roller_load == ld.load_at(0.0))
    ff = sc.frequencies()
    # an element is centred on the defect (phi_d = 0) at t_k = k / BPFO: every event the same
    t = np.arange(1, 21) / ff.bpfo
    ev = evaluate_signals(sc, outer.tables, ld, t)
    assert np.all(np.abs(ev["defect_offset"]) < 1e-12)
    rf = ev["removed_force"]
    assert rf.min() > 0 and rf.max() / rf.min() - 1 < 1e-9
    assert np.ptp(ev["p_max"]) <= 1e-9 * ev["p_max"].max()


@pytest.mark.parametrize("signal", ["removed_force", "p_max"])
def test_outer_race_lines_at_bpfo_without_shaft_sidebands(outer, inner, signal):
    """Steady load, fixed defect: lines at k x BPFO and no +-fr sidebands (< 1 % of the line);
    the inner-race defect of the same bearing, for contrast, has them (> 10 %)."""
    ff = outer.scene.frequencies()
    line, lo, hi = _lines(outer, signal, [ff.bpfo, ff.bpfo - FR, ff.bpfo + FR])
    assert line > 0
    assert max(lo, hi) < 0.01 * line
    iline, ilo, ihi = _lines(inner, signal, [ff.bpfi, ff.bpfi - FR, ff.bpfi + FR])
    assert max(ilo, ihi) > 0.1 * iline


def test_outer_race_defect_outside_the_load_zone_is_silent():
    """12:00 (180 deg from the load): no element load there (10 um clearance: load zone
    < +-90 deg), no defect signal."""
    h = simulate(_scene("outer_race", 180.0, revolutions=3), "draft")
    assert np.all(h.roller_load == 0.0)
    assert np.all(h.signals["removed_force"] == 0.0)


def test_rolling_element_meets_both_races_at_twice_bsf(ball):
    """The defect's events alternate between the outer (beta = 0) and the inner race
    (beta = pi), each with its own contact: at equal load the inner (more curved) contact loses a
    different force than the outer."""
    sc, ld = ball.scene, ball.load_distribution
    b = sc.bearing
    d = 1e-3 * b.roller_diameter_mm
    ratio = (b.pitch_diameter_m + d) / d            # beta / theta_c
    fc = sc.cage_rate_hz
    # instants with beta = 0 (outer) and beta = pi (inner), near the load-zone centre
    t_out = np.array([2.0 * math.pi * 1 / ratio]) / (2 * math.pi * fc)
    t_in = np.array([math.pi / ratio]) / (2 * math.pi * fc)
    eo = evaluate_signals(sc, ball.tables, ld, t_out)
    ei = evaluate_signals(sc, ball.tables, ld, t_in)
    assert abs(eo["defect_offset"][0]) < 1e-12 and abs(ei["defect_offset"][0]) < 1e-12
    assert eo["removed_force"][0] > 0 and ei["removed_force"][0] > 0
    assert abs(eo["removed_force"][0] / ei["removed_force"][0] - 1) > 0.01


def test_rolling_element_lines_at_twice_bsf_with_ftf_sidebands(ball):
    """Envelope spectrum: a line at 2 x BSF carrying sidebands at +-FTF (the element's load
    zone passage), at least 10 % of the line; no line at fr (nothing turns with the shaft)."""
    ff = ball.scene.frequencies()
    two_bsf = 2.0 * ff.bsf
    line, lo, hi, at_fr = _lines(ball, "removed_force",
                                 [two_bsf, two_bsf - ff.ftf, two_bsf + ff.ftf, FR])
    assert line > 0
    assert min(lo, hi) > 0.1 * line
    assert at_fr < 0.1 * line


def test_case_file_holds_both_contact_tables(ball, outer, tmp_path):
    from bearing_envelope.io import read_case, write_case

    write_case(tmp_path / "ball.h5", ball)
    c = read_case(tmp_path / "ball.h5")
    assert c.scene["defect"]["location"] == "rolling_element"
    assert c.table["race"] == "inner" and c.other_tables["outer"]["race"] == "outer"
    assert set(c.other_tables) == {"outer"}
    np.testing.assert_array_equal(c.other_tables["outer"]["p0"], ball.tables["outer"].p0)
    np.testing.assert_array_equal(c.table["p0"], ball.tables["inner"].p0)
    write_case(tmp_path / "outer.h5", outer)
    c = read_case(tmp_path / "outer.h5")
    assert c.other_tables == {} and c.table["race"] == "outer"
    np.testing.assert_array_equal(c.table["p0"], outer.tables["outer"].p0)
