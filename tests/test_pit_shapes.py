"""Defect shapes of issue 23 (part F): the cylindrical EDM pit and a measured profile from a
file, and the CWRU configs (part G)."""

from pathlib import Path

import numpy as np
import pytest
import yaml

from bearing_envelope.contact import solve_contact
from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.geometry import defect_depth, gap_field, make_grid
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene
from bearing_envelope.physics.solves import SolveStats, defect_solve, solve_load
from bearing_envelope.study.config_read import ConfigError, read_configs
from bearing_envelope.study.settings import settings_from_mapping

ROOT = Path(__file__).resolve().parents[1]


def _pit(depth_um=279.4, diameter_um=177.8, edge_um=20.0, **defect):
    return Scene.from_mapping({"bearing": {"designation": "SKF 6205-2RS"},
                               "operation": {"bpfi_override_hz": None},
                               "defect": {"shape": "cylinder", "width_um": diameter_um,
                                          "edge_radius_um": edge_um, **defect}},
                              load_kN=1.0, depth_um=depth_um)


def test_cylindrical_pit_is_round_with_a_flat_bottom_and_rounded_rim():
    """Hand values: radius R = 88.9 um, rim radius r = 20 um, depth h = 279.4 um; at distance
    rho from the axis the depth is min(h, r - sqrt(r^2 - (R - rho)^2)) inside, 0 outside."""
    d = _pit().defect
    assert d.extent_x_m == d.extent_y_m == pytest.approx(177.8e-6)
    R, r = 88.9e-6, 20e-6
    rho = np.array([0.0, 50e-6, 70e-6, 80e-6, 88e-6, 89.5e-6, 120e-6])
    for ang in (0.0, 0.7, 2.0):
        got = defect_depth(d, rho * np.cos(ang), rho * np.sin(ang))
        dist = R - rho
        want = np.where(dist > 0, np.minimum(279.4e-6, np.where(
            dist < r, r - np.sqrt(np.clip(r * r - dist * dist, 0, None)), np.inf)), 0.0)
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-18)


def test_measured_profile_is_scaled_to_the_depth_and_extruded(tmp_path):
    f = tmp_path / "spall.csv"
    f.write_text("# x_um, depth_um\n-60,0\n-30,10\n0,20\n30,10\n60,0\n")
    sc = Scene.from_mapping({"defect": {"shape": "profile", "profile_file": str(f),
                                        "width_um": 120.0, "length_um": 400.0}},
                            load_kN=500, depth_um=40.0)
    d = sc.defect
    u = np.array([-60e-6, -45e-6, -30e-6, 0.0, 15e-6, 80e-6])
    got = defect_depth(d, u, np.zeros_like(u))
    np.testing.assert_allclose(got, [0.0, 10e-6, 20e-6, 40e-6, 30e-6, 0.0], atol=1e-15)
    assert defect_depth(d, np.array([0.0]), np.array([0.25e-3]))[0] == 0.0   # beyond the length
    grid = make_grid(-1e-4, 1e-4, -1e-4, 1e-4, 5e-6, 5e-6)
    assert np.all(np.isfinite(gap_field(sc, grid, 0.0)))


def test_bad_profile_file_is_refused(tmp_path):
    f = tmp_path / "bad.csv"
    f.write_text("0,1\n0,2\n1,0\n")
    with pytest.raises(ValueError, match=r"scene\.defect\.profile_file: got .*; allowed: a "
                                         r"readable two-column file \(x_um, depth_um\)"):
        Scene.from_mapping({"defect": {"shape": "profile", "profile_file": str(f)}},
                           load_kN=500, depth_um=40.0)


def _merged(*names):
    """The files merged as the workflow merges them (the one merge function)."""
    return read_configs([ROOT / n for n in names])


@pytest.mark.parametrize("extra, location", [((), "inner_race"),
                                             (("config_cwru_or.yaml",), "outer_race"),
                                             (("config_cwru_ball.yaml",), "rolling_element")])
def test_cwru_configs_are_valid(extra, location):
    # as Snakemake merges them: config.yaml, then each --configfile
    m = _merged("config.yaml", "config_cwru.yaml", *extra)
    s = settings_from_mapping(m)
    case = [c for c in s.cases if c.depth_um > 0][0]
    sc = s.scene(case)
    assert sc.bearing.designation == "SKF 6205-2RS" and sc.bearing.kind == "ball"
    assert sc.defect.location == location and sc.defect.shape == "cylinder"
    assert sc.bearing.roller_diameter_mm == 7.94 and sc.defect.width_um == 177.8
    assert sc.frequencies().orders()["bpfi"] == pytest.approx(5.4152, rel=1e-4)


def test_cwru_larger_pits_are_bridged_and_a_pit_too_long_is_refused_before_any_solve():
    # 0.014 and 0.021 in are wider than 2a = 228 um but short against 2b = 2128 um: the ball
    # bridges them (issue 23 parts 5-6); beyond 0.26 x 2b = 553 um the sweep refuses
    m = _merged("config.yaml", "config_cwru.yaml")
    m["sweep"]["widths_um"] = [177.8, 355.6, 533.4]
    assert len(settings_from_mapping(m).cases) == 4
    m["sweep"]["widths_um"] = [600.0]
    with pytest.raises(ConfigError, match=r"sweep\.widths_um\[0\]: got 600\.0; allowed: a width "
                                          r"below the contact width 2a = 227\.8 um .* at most "
                                          r"0\.26 x 2b = 553\.3 um$"):
        settings_from_mapping(m)


def test_window_solve_of_a_pit_wider_than_the_ball_contact_matches_a_whole_ellipse_solve():
    """Independent answer: the whole contact ellipse solved directly (no window, no frozen far
    field) with the same gap field, on the window's own spacing, at its no-defect approach."""
    m = _merged("config.yaml", "config_cwru.yaml")["scene"]
    m["defect"]["width_um"] = 355.6
    sc = Scene.from_mapping(m, load_kN=1.0, depth_um=279.4)
    q = scene_load_distribution(sc).q_max
    fid, stats = fidelity_from("fast"), SolveStats()       # the window solve without rim strips
    node = solve_load(sc, fid, q, 1.0, stats)
    ds = defect_solve(sc, fid, node, 0.0, stats)
    win = node.window
    grid = make_grid(-420e-6, 420e-6, -1.4e-3, 1.4e-3, win.dx, win.dy)
    e = sc.material.e_star_pa
    s0 = solve_contact(gap_field(sc, grid, None), grid.dx, grid.dy, q, e, tol=1e-8, max_iter=5000)
    g = gap_field(sc, grid, 0.0)
    s1 = solve_contact(g, grid.dx, grid.dy, None, e, tol=1e-8, max_iter=5000,
                       approach=s0.approach)
    removed = q - float(s1.pressure.sum()) * grid.dx * grid.dy
    assert ds.P == pytest.approx(float(s1.pressure.max()), rel=0.01)
    assert ds.removed_force == pytest.approx(removed, rel=0.15)   # measured +11 %
    # under force control the ball sinks < 1 um into a 279 um pit: the bottom carries nothing
    s2 = solve_contact(g, grid.dx, grid.dy, q, e, tol=1e-8, max_iter=5000)
    assert 0 < s2.approach - s0.approach < 1e-6
    assert not np.any(s2.pressure[g - gap_field(sc, grid, None) > 100e-6] > 0)
