import math

import numpy as np
import pytest

from bearing_envelope.physics.loads import (load_zone_integral, palmgren_stiffness, scene_load_distribution,
                                    solve_row)
from bearing_envelope.physics.scene import Scene


@pytest.mark.parametrize("clearance", [0.0, 20e-6, 80e-6])
@pytest.mark.parametrize("alpha", [0.0, 12.82])
def test_equilibrium(clearance, alpha):
    k = palmgren_stiffness(36e-3)
    ld = solve_row(125e3, 22, alpha, clearance, k)
    # sum Q cos(psi) cos(alpha) = F
    total = np.sum(ld.q * np.cos(ld.psi)) * math.cos(math.radians(alpha))
    assert total == pytest.approx(125e3, rel=1e-9)
    assert np.all(ld.q >= 0)


def test_zero_clearance_stribeck_constants():
    # Harris & Kotzalas (2007), Rolling Bearing Analysis, table 7.1 / Stribeck: with zero
    # clearance (eps = 0.5) Q_max = F / (Z J_r cos(alpha)) with 1/J_r = 4.08 (line contact,
    # n = 10/9) and 4.37 (point contact, n = 3/2).
    assert 1 / load_zone_integral(0.5) == pytest.approx(4.08, abs=0.01)
    assert 1 / load_zone_integral(0.5, 1.5) == pytest.approx(4.37, abs=0.01)
    F, alpha = 125e3, 12.82
    for z, tol in ((200, 0.003), (22, 0.01)):
        ld = solve_row(F, z, alpha, 0.0, 1e10)
        assert ld.q_max * z * math.cos(math.radians(alpha)) / F == pytest.approx(4.08, rel=tol)
        assert ld.epsilon == pytest.approx(0.5)
    ld = solve_row(F, 200, 0.0, 0.0, 1e10, exponent=1.5)
    assert ld.q_max * 200 / F == pytest.approx(4.37, rel=0.003)


def test_clearance_load_zone_law():
    # Q(psi) = Qmax [1 - (1 - cos psi)/(2 eps)]^(10/9) (Stribeck/Harris load-zone law)
    ld = solve_row(125e3, 22, 12.82, 40e-6, palmgren_stiffness(36e-3))
    assert ld.epsilon < 0.5
    psi = np.linspace(-math.pi, math.pi, 721)
    law = ld.q_max * np.clip(1 - (1 - np.cos(psi)) / (2 * ld.epsilon), 0, None) ** (10 / 9)
    np.testing.assert_allclose(ld.load_at(psi), law, rtol=1e-9, atol=1e-9 * ld.q_max)
    assert ld.half_angle < math.pi / 2
    # more clearance -> more concentrated load
    ld0 = solve_row(125e3, 22, 12.82, 0.0, palmgren_stiffness(36e-3))
    assert ld.q_max > ld0.q_max


def test_scene_modes():
    sb = Scene.default(load_kN=500, depth_um=0)
    lb = scene_load_distribution(sb)
    assert lb.force_row == pytest.approx(250e3)  # two rows share the radial load
    sc = Scene.from_mapping({"load": {"mode": "contact"}}, load_kN=lb.q_max / 1e3, depth_um=0)
    lc = scene_load_distribution(sc)
    assert lc.q_max == pytest.approx(lb.q_max, rel=1e-9)
    psi = np.linspace(-2, 2, 101)
    np.testing.assert_allclose(lc.load_at(psi), lb.load_at(psi), rtol=1e-7, atol=1e-6)


def test_bad_inputs():
    with pytest.raises(ValueError, match="force_row"):
        solve_row(0.0, 10)
    with pytest.raises(ValueError, match="n_rollers"):
        solve_row(1e3, 0)
