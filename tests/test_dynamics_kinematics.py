"""Where the elements are: cage slip moves the element passing line, an inner-race pit is met at
the rate and for the time the kinematics give, a roller bearing's static limit."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from bearing_envelope.physics.dynamics import (StateLayout, params_from_scene, simulate_dynamics,
                                               slot_law)
from bearing_envelope.physics.loads import solve_row
from bearing_envelope.physics.scene import Scene
from test_dynamics_oracles import ROOT, cwru_scene


def test_cage_slip_moves_the_element_passing_line():
    m = yaml.safe_load((ROOT / "config_cwru.yaml").read_text())["scene"]
    m.setdefault("operation", {}).update(cage_slip_percent=2.0, slip_seed=3)
    p = params_from_scene(Scene.from_mapping(m, load_kN=1.0, depth_um=0.0))
    assert p.cage_angle is not None
    fs, dur = 2000.0, 2.0
    r = simulate_dynamics(p, dur, fs)
    rel = r.inner_displacement_m[:, 0] - r.housing_displacement_m[:, 0]
    win = np.hanning(rel.size)
    spec = np.abs(np.fft.rfft((rel - rel.mean()) * win))
    f = np.fft.rfftfreq(rel.size, 1 / fs)
    band = (f > 80) & (f < 130)
    f_line = f[band][np.argmax(spec[band])]
    theta = p.cage_angle(np.array([0.0, dur]))
    f_mean = p.z * (theta[1] - theta[0]) / (2 * math.pi * dur)    # the slipping cage's mean rate
    print(f"line {f_line:.2f} Hz; slipping cage x Z {f_mean:.2f} Hz; no slip {p.z * p.cage_rate_hz:.2f} Hz")
    assert abs(f_line - f_mean) <= 1.0 / dur
    assert p.z * p.cage_rate_hz - f_line > 1.0        # 2 % slip: 2.1 Hz lower


def test_inner_race_pit_is_met_at_the_inner_pass_rate_for_the_crossing_time():
    p = params_from_scene(cwru_scene())            # config_cwru.yaml: the inner-race set
    w = 177.8e-6
    law = slot_law(p.element_radius_m, w, 279.4e-6, p.k_inner, 1.5, 30e-6)
    # preloaded: every contact closed, so the defect force is on exactly while an element is on the pit
    p = p.with_(defect=law, defect_race="inner", defect_angle_rad=0.3, clearance_m=-30e-6)
    fs = 1e6
    r = simulate_dynamics(p, 0.02, fs, acquisition="point")
    on = r.defect_force_n > 0
    starts = np.nonzero(on[1:] & ~on[:-1])[0] + 1
    ends = np.nonzero(~on[1:] & on[:-1])[0] + 1
    f_rel = p.shaft_rate_hz - p.cage_rate_hz
    v = 2 * math.pi * f_rel * p.inner_race_radius_m
    spacing = np.diff(r.t_s[starts])
    print(f"entries every {1e3 * spacing.mean():.4f} ms (1/BPFI {1e3 / (p.z * f_rel):.4f} ms), "
          f"on the pit {1e6 * np.mean(r.t_s[ends[ends > starts[0]][:len(starts) - 1]] - r.t_s[starts[:-1]]):.1f} us "
          f"(w/v {1e6 * w / v:.1f} us)")
    assert len(starts) >= 3
    np.testing.assert_allclose(spacing, 1 / (p.z * f_rel), atol=2 / fs)
    dur = r.t_s[ends[ends > starts[0]][:len(starts) - 1]] - r.t_s[starts[:-1]]
    np.testing.assert_allclose(dur, w / v, atol=2 / fs)


def test_roller_bearing_static_limit_is_the_harris_load_distribution():
    sc = Scene.from_mapping(None, load_kN=20.0, depth_um=0.0)      # FAG 534176, line contact
    p = params_from_scene(sc, centrifugal=False)
    p = p.with_(cage_rate_hz=0.0, shaft_rate_hz=0.0, cage_angle=lambda t: np.full(np.shape(t), 0.05),
                contact_damping_ns_m=4 * p.contact_damping_ns_m, housing_damping_ns_m=1e5,
                housing_stiffness_n_m=1e9)
    lay = StateLayout(p.z)
    r = simulate_dynamics(p, 0.02, 20000.0, acquisition="point", settle_s=0.3, y0=np.zeros(lay.size))
    ref = solve_row(p.force_n, p.z, math.degrees(p.contact_angle_rad), p.clearance_m,
                    p.series_constant, 10 / 9, 0.05).q
    assert p.exponent == pytest.approx(10 / 9)
    assert np.max(np.abs(r.element_load_n[-1] - ref)) <= 0.01 * ref.max()
