"""The integration of the dynamic model: the step rule, time-step convergence of the envelope
lines, the right-hand side under scipy's solve_ivp, the refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from scipy.integrate import solve_ivp

from bearing_envelope.physics.dynamics import (DynamicParams, StateLayout, contact_stiffness,
                                               highest_frequency_hz, initial_state,
                                               linearised_frequencies_hz, params_from_scene,
                                               quasi_static, rhs, simulate_dynamics, slot_law,
                                               step_size)
from bearing_envelope.physics.dynamics.model import arrays
from bearing_envelope.physics.dynamics.params import (STEPS_PER_PERIOD, STEPS_PER_PERIOD_LOADED,
                                                      rule_steps)
from bearing_envelope.signal.envelope import envelope_spectrum
from bearing_envelope.signal.spectrum import amplitude_at
from bearing_envelope.physics.scene import Scene
from test_dynamics_oracles import ROOT, at_rest, cwru_scene, harris_2d


def test_contact_stiffness_is_the_derivative_of_hertz():
    k, q = 2.6e10, 300.0
    d = (q / k) ** (2 / 3)
    h = 1e-6 * d
    num = (k * (d + h) ** 1.5 - k * (d - h) ** 1.5) / (2 * h)
    assert contact_stiffness(k, q, 1.5) == pytest.approx(num, rel=1e-8)
    assert contact_stiffness(k, q, 1.5) == pytest.approx(1.5 * k ** (2 / 3) * q ** (1 / 3), rel=1e-12)


def test_step_rule_bounds_the_linearised_frequencies():
    p = params_from_scene(cwru_scene())
    q = 2.0 * quasi_static(p).q.max()
    f_elem = math.sqrt((1.5 * p.k_inner ** (2 / 3) * q ** (1 / 3)
                        + 1.5 * p.k_outer ** (2 / 3) * (q + p.centrifugal_n) ** (1 / 3))
                       / p.element_mass_kg) / (2 * math.pi)
    assert highest_frequency_hz(p) == pytest.approx(f_elem, rel=1e-12)
    assert step_size(p) == pytest.approx(1 / (30 * f_elem), rel=1e-12)
    assert 40e3 < f_elem < 80e3 and 0.2e-6 < step_size(p) < 1.5e-6   # design.md: near 1 us
    rest = at_rest(0.0, contact_damping_ns_m=0.0, housing_damping_ns_m=0.0, resonator_zeta=0.0)
    assert linearised_frequencies_hz(rest, initial_state(rest)).max() < highest_frequency_hz(rest)


def preloaded(**defect):
    """The 6205 as the rig runs it: 0.1 kN on 4.1 um of preload (negative clearance), every
    element loaded all round."""
    m = yaml.safe_load((ROOT / "config_cwru.yaml").read_text())["scene"]
    m["defect"].update(defect)
    m["bearing"]["radial_clearance_um"] = -4.1
    return params_from_scene(Scene.from_mapping(m, load_kN=0.1, depth_um=0.0))


def test_step_rule_of_a_scene_loaded_all_round():
    p = preloaded()
    assert harris_2d(p, 0.0)[0].min() > 0.0     # Harris's row: every element loaded
    f = highest_frequency_hz(p)
    assert rule_steps(p) == STEPS_PER_PERIOD_LOADED < STEPS_PER_PERIOD
    assert step_size(p) == pytest.approx(1 / (STEPS_PER_PERIOD_LOADED * f), rel=1e-12)
    assert rule_steps(params_from_scene(cwru_scene())) == STEPS_PER_PERIOD   # elements unloaded
    assert step_size(p, 30.0) == pytest.approx(1 / (30.0 * f), rel=1e-12)


def test_preloaded_lines_change_under_one_percent_when_the_loaded_rule_step_halves():
    p = preloaded()
    law = slot_law(p.element_radius_m, 177.8e-6, 279.4e-6, p.k_outer, 1.5, 30e-6)
    p = p.with_(defect=law, defect_race="outer")
    a, b = lines(p, STEPS_PER_PERIOD_LOADED), lines(p, 2 * STEPS_PER_PERIOD_LOADED)
    change = np.max(np.abs(a - b) / b)
    print(f"preloaded, 0.007 in at 6:00: lines {np.round(b, 5)}, largest change {change:.2e}")
    assert change <= 0.01


def lines(p, steps, duration=0.5, fs=12000.0):
    r = simulate_dynamics(p, duration, fs, steps_per_period=steps)
    bpfo = p.z * p.cage_rate_hz
    out = []
    for x in (r.resonator_acceleration_m_s2, r.housing_force_n[:, 0]):
        f, a = envelope_spectrum(x - x.mean(), fs, (0.25 * fs, 0.375 * fs))
        out += [amplitude_at(f, a, k * bpfo, 0.01 * bpfo)[1] for k in (1, 2, 3)]
    return np.array(out)


@pytest.mark.parametrize("width_um, position_deg", [(177.8, 0.0), (533.4, 90.0)])
def test_envelope_lines_change_under_one_percent_when_the_step_halves(width_um, position_deg):
    p = params_from_scene(cwru_scene())
    law = slot_law(p.element_radius_m, 1e-6 * width_um, 279.4e-6, p.k_outer, 1.5, 30e-6)
    p = p.with_(defect=law, defect_angle_rad=math.radians(position_deg), defect_race="outer")
    a, b = lines(p, STEPS_PER_PERIOD), lines(p, 2 * STEPS_PER_PERIOD)
    change = np.max(np.abs(a - b) / b)
    print(f"{width_um} um at {position_deg} deg: lines {np.round(b, 5)}, largest change {change:.2e}")
    assert change <= 0.01


def test_rhs_under_solve_ivp_agrees_with_the_rk4_kernel():
    p = params_from_scene(cwru_scene())
    law = slot_law(p.element_radius_m, 177.8e-6, 279.4e-6, p.k_outer, 1.5, 30e-6)
    p = p.with_(defect=law, defect_angle_rad=math.radians(2.0), defect_race="outer")
    y0 = initial_state(p)
    T = 1e-3                                     # the element crosses the slot at 0.4-0.5 ms
    r = simulate_dynamics(p, T, 1e5, acquisition_mode="point", settle_s=0.0, y0=y0)
    a = arrays(p, -1e-3, 2 * T)
    lay = StateLayout(p.z)
    sol = solve_ivp(rhs, (0.0, r.t_end_s), y0, method="DOP853", args=(p, a), rtol=1e-10,
                    atol=np.r_[np.full(lay.n_dof, 1e-14), np.full(lay.n_dof, 1e-10)])
    assert sol.success
    scale = np.abs(y0[:lay.n_dof]).max()
    err = np.abs(sol.y[:lay.n_dof, -1] - r.state_end[:lay.n_dof]).max() / scale
    print(f"end state: RK4 vs DOP853 {err:.2e} of the largest displacement")
    assert err < 1e-4


def test_bad_input_is_refused_before_the_run():
    p = params_from_scene(cwru_scene())
    with pytest.raises(ValueError, match="duration_s got -1"):
        simulate_dynamics(p, -1, 12000.0)
    with pytest.raises(ValueError, match="acquisition_mode got 'linear'"):
        simulate_dynamics(p, 0.1, 12000.0, acquisition_mode="linear")
    with pytest.raises(ValueError, match="steps_per_period: got 2"):
        step_size(p, 2)
    with pytest.raises(ValueError, match="element_mass_kg: got -1"):
        p.with_(element_mass_kg=-1)
    with pytest.raises(ValueError, match="defect_race: got 'ball'"):
        p.with_(defect_race="ball")
    with pytest.raises(ValueError, match="y0 has shape"):
        simulate_dynamics(p, 0.01, 12000.0, y0=np.zeros(3))
    assert isinstance(p, DynamicParams)


def test_diverging_integration_raises_with_the_time():
    p = params_from_scene(cwru_scene())
    with pytest.raises(FloatingPointError, match="not finite at t ="):
        simulate_dynamics(p, 0.01, 12000.0, dt_s=2e-5, settle_s=0.0, oversample=1)


def test_recorded_housing_force_balances_the_load_and_point_samples_agree():
    # momentum: over whole element passes the mean force through the bearing is the load
    p = params_from_scene(cwru_scene())
    dur = 20 / (p.z * p.cage_rate_hz)               # 20 element passes
    fs = 12000.0
    r = simulate_dynamics(p, dur, fs)
    mean = r.housing_force_n.mean(axis=0)
    print(f"mean housing force {mean} N for {p.force_n} N; oversample {r.oversample}")
    assert mean[0] == pytest.approx(p.force_n, rel=2e-4) and abs(mean[1]) < 2e-4 * p.force_n
    pt = simulate_dynamics(p, dur, fs, acquisition_mode="point")
    # the rings' relative displacement (varying compliance, well below fs/2): the anti-aliased
    # record equals the point samples to 1 % of its ripple (measured 0.2 %)
    x_aa = r.inner_displacement_m[:, 0] - r.housing_displacement_m[:, 0]
    x_pt = pt.inner_displacement_m[:, 0] - pt.housing_displacement_m[:, 0]
    assert np.max(np.abs(x_aa - x_pt)) < 0.01 * np.ptp(x_pt)
