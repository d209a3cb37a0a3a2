"""The load distribution's equilibrium in both directions (issue 42): the inner ring moves along
and across the load, and both force balances hold at any cage phase. Checked against answers
computed here: the balances summed from the returned loads, the deflection law (and with a
centrifugal force, the compatibility of the two contacts' deflections) evaluated by hand, an
independent 2-D solve (scipy's fsolve), Stribeck's closed form and an x-only Brent solve where
the elements sit symmetric about the load."""

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.optimize import brentq, fsolve

from bearing_envelope.physics.loads import solve_row

#: A 6205-like ball set (K of both contacts in series, N m^-1.5) and a roller set (N m^-10/9).
K_BALL, K_ROLLER = 8.0e9, 1.0e10

row_cases = st.fixed_dictionaries({
    "force": st.floats(100.0, 1e5), "z": st.integers(3, 25),
    "alpha_deg": st.floats(0.0, 30.0), "clearance_um": st.floats(-20.0, 40.0),
    "ball": st.booleans(), "phase": st.floats(0.0, 2.0 * math.pi),
    "fc": st.one_of(st.just(0.0), st.floats(0.01, 200.0))})


def solve_case(c):
    n = 1.5 if c["ball"] else 10.0 / 9.0
    k = K_BALL if c["ball"] else K_ROLLER
    comp = 0.5 * k ** (-1.0 / n)                       # equal contacts: (c_i + c_o)^(-n) = K
    kw = {"centrifugal": c["fc"], "compliances": (comp, comp)} if c["fc"] > 0 else {}
    ld = solve_row(c["force"], c["z"], c["alpha_deg"], 1e-6 * c["clearance_um"], k, n,
                   c["phase"], **kw)
    return ld, k, n, comp


def compression(ld, psi):
    """The element's compression along its normal, typed from the deflection law."""
    return (ld.delta_r * np.cos(psi) + ld.delta_y * np.sin(psi)
            - 0.5 * ld.clearance) * math.cos(ld.contact_angle_rad)


@settings(max_examples=150, deadline=None)
@given(row_cases)
def test_both_forces_balance_at_any_phase(c):
    ld, k, n, comp = solve_case(c)
    psi = c["phase"] + 2 * np.pi * np.arange(c["z"]) / c["z"]
    ca = math.cos(math.radians(c["alpha_deg"]))
    assert abs(np.sum(ld.q * np.cos(psi)) * ca - c["force"]) <= 1e-9 * c["force"]
    assert abs(np.sum(ld.q * np.sin(psi)) * ca) <= 1e-9 * c["force"]
    d = compression(ld, psi)
    if c["fc"] == 0:
        np.testing.assert_allclose(ld.q, k * np.clip(d, 0, None) ** n, rtol=1e-12,
                                   atol=1e-12 * c["force"])
    else:       # c_i Q^(1/n) + c_o (Q + F_c)^(1/n) = delta where the inner contact is closed
        on = ld.q > 1e-12 * c["force"]       # (an open contact's bisection leaves ~1e-20 N)
        lhs = comp * ld.q[on] ** (1 / n) + comp * (ld.q[on] + c["fc"]) ** (1 / n)
        np.testing.assert_allclose(lhs, d[on], rtol=1e-9)
        assert np.all(d[~on] <= comp * c["fc"] ** (1 / n) * (1 + 1e-9))


def fsolve_2d(force, z, clearance, k, n, phase):
    """Harris's law with both balances, solved by fsolve from a start of the test's own."""
    psi = phase + 2 * np.pi * np.arange(z) / z

    def loads(v):
        return k * np.clip(v[0] * np.cos(psi) + v[1] * np.sin(psi) - 0.5 * clearance, 0, None) ** n

    def residual(v):
        q = loads(1e-6 * v)
        return [np.sum(q * np.cos(psi)) / force - 1, np.sum(q * np.sin(psi)) / force]

    v, _, ok, msg = fsolve(residual, [20.0, 0.0], xtol=1e-13, full_output=True)
    assert ok == 1, msg
    return loads(1e-6 * v), 1e-6 * v


@pytest.mark.parametrize("phase_deg", [5.7, 13.0, 31.0, 203.0])
def test_asymmetric_phase_matches_an_independent_2d_solve(phase_deg):
    # the 6205 at 1 kN with 10 um clearance: nine balls
    ref, (x, y) = fsolve_2d(1000.0, 9, 10e-6, K_BALL, 1.5, math.radians(phase_deg))
    ld = solve_row(1000.0, 9, 0.0, 10e-6, K_BALL, 1.5, math.radians(phase_deg))
    np.testing.assert_allclose(ld.q, ref, atol=1e-9 * ref.max())
    assert ld.delta_r == pytest.approx(x, rel=1e-9) and ld.delta_y == pytest.approx(y, abs=1e-15)
    assert ld.delta_y != 0.0
    assert ld.q_max == pytest.approx(K_BALL * (math.hypot(x, y) - 5e-6) ** 1.5, rel=1e-9)


def x_only(force, z, clearance, k, n, phase):
    """The along-the-load balance alone (Brent), typed here: the answer where it is exact."""
    psi = phase + 2 * np.pi * np.arange(z) / z

    def f(x):
        return np.sum(k * np.clip(x * np.cos(psi) - 0.5 * clearance, 0, None) ** n * np.cos(psi)) - force

    return brentq(f, max(0.0, 0.5 * clearance), 1e-2, xtol=1e-20, rtol=1e-15)


@pytest.mark.parametrize("z, phase_k", [(9, 0), (9, 1), (9, 5), (22, 3), (10, 1)])
@pytest.mark.parametrize("clearance", [0.0, 10e-6, -5e-6])
def test_symmetric_phase_has_no_transverse_displacement(z, phase_k, clearance):
    # phase a multiple of pi/Z: the elements mirror about the load
    phase = phase_k * math.pi / z
    ld = solve_row(1000.0, z, 0.0, clearance, K_BALL, 1.5, phase)
    assert ld.delta_y == 0.0 and ld.zone_centre == 0.0
    assert ld.delta_r == pytest.approx(x_only(1000.0, z, clearance, K_BALL, 1.5, phase), rel=1e-12)


def test_stribeck_closed_forms_are_kept():
    # zero clearance, many elements: Q_max Z / F = 4.08 (line), 4.37 (point); epsilon 1/2
    for n, stribeck in ((10.0 / 9.0, 4.08), (1.5, 4.37)):
        ld = solve_row(1000.0, 200, 0.0, 0.0, 1e10, n)
        assert ld.q_max * 200 / 1000.0 == pytest.approx(stribeck, abs=0.01)
        assert ld.epsilon == pytest.approx(0.5, abs=1e-12)
    # nine balls at phase 0: Q_max = F / sum cos^(5/2) psi_j (4.385 F/Z)
    c = np.clip(np.cos(2 * np.pi * np.arange(9) / 9), 0, None)
    assert solve_row(1000.0, 9, 0.0, 0.0, K_BALL, 1.5).q_max == pytest.approx(
        1000.0 / np.sum(c ** 2.5), rel=1e-12)


def test_two_rollers_off_their_line_have_no_equilibrium():
    with pytest.raises(ValueError, match=r"n_rollers 2 at phase 0.3 rad cannot balance .*"
                                         r"allowed: >= 3 rollers, or a phase that is a multiple"):
        solve_row(1000.0, 2, 0.0, 0.0, K_BALL, 1.5, 0.3)
    assert solve_row(1000.0, 2, 0.0, 0.0, K_BALL, 1.5, 0.0).q_max == pytest.approx(1000.0)
