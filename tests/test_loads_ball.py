"""Load zone of a ball bearing (issue 23, part D): point-contact law Q = K delta^(3/2), force
balance, Stribeck's 4.37 at zero clearance and about 5 with clearance."""

import math

import numpy as np
import pytest

from bearing_envelope.contact import hertz
from bearing_envelope.physics.loads import (POINT_CONTACT_EXPONENT, hertz_point_stiffness,
                                            scene_load_distribution, solve_row)
from bearing_envelope.physics.scene import Scene

#: Stribeck's constant for point contact at zero clearance (Harris & Kotzalas 2007, section 7.4):
#: Q_max = 4.37 F_r / (Z cos alpha).
STRIBECK_POINT = 4.37
#: The design rule with nominal clearance: Q_max ~ 5 F_r / (Z cos alpha).
STRIBECK_DESIGN = 5.0


def _scene(load_kN, clearance_um=None, **bearing):
    b = {"designation": "SKF 6205-2RS", **bearing}
    if clearance_um is not None:
        b["radial_clearance_um"] = clearance_um
    return Scene.from_mapping({"bearing": b, "operation": {"bpfi_override_hz": None}},
                              load_kN=load_kN, depth_um=0.0)


@pytest.mark.parametrize("load_kN", [0.3, 1.0, 3.0])
@pytest.mark.parametrize("clearance_um", [0.0, 10.0, 30.0])
def test_ball_loads_balance_the_radial_load(load_kN, clearance_um):
    ld = scene_load_distribution(_scene(load_kN, clearance_um))
    assert ld.exponent == POINT_CONTACT_EXPONENT
    total = float(np.sum(ld.q * np.cos(ld.psi)) * math.cos(ld.contact_angle_rad))
    assert total == pytest.approx(load_kN * 1e3, rel=1e-9)
    assert np.all(ld.q >= 0)


def test_angular_contact_balance():
    """alpha = 25 deg: sum Q cos(psi) cos(alpha) = F_r."""
    ld = scene_load_distribution(_scene(1.0, 5.0, contact_angle_deg=25.0))
    total = float(np.sum(ld.q * np.cos(ld.psi)) * math.cos(math.radians(25.0)))
    assert total == pytest.approx(1e3, rel=1e-9)


def test_zero_clearance_gives_stribecks_point_contact_constant():
    """The 6205 (Z = 9) at zero clearance: Q_max Z / F_r within 0.5 % of 4.37 (measured 4.385,
    the discrete 9 balls); with many balls (Z = 40) within 0.1 %."""
    ld = scene_load_distribution(_scene(1.0, 0.0))
    assert ld.q_max * 9 / 1e3 == pytest.approx(STRIBECK_POINT, rel=5e-3)
    assert solve_row(1e3, 40, 0.0, 0.0, 1e10, 1.5).q_max * 40 / 1e3 == pytest.approx(
        STRIBECK_POINT, rel=1e-3)


@pytest.mark.parametrize("load_kN", [0.5, 1.0, 2.0])
def test_nominal_clearance_gives_about_five(load_kN):
    """10 um radial clearance (ISO 5753-1 group N for the 6205 bore) over 0.5-2 kN: Q_max Z / F_r
    within 10 % of the design rule's 5 (measured 5.02, 4.81, 4.67) and above the zero-clearance
    value."""
    ratio = scene_load_distribution(_scene(load_kN, 10.0)).q_max * 9 / (load_kN * 1e3)
    assert ratio == pytest.approx(STRIBECK_DESIGN, rel=0.10)
    assert ratio > STRIBECK_POINT


def test_point_contact_stiffness_is_two_hertz_contacts_in_series():
    """Deflection at the most loaded ball equals the sum of the two Hertz approaches at Q_max."""
    sc = _scene(1.0, 0.0)
    b, e = sc.bearing, sc.material.e_star_pa
    q = 700.0
    delta = (q / hertz_point_stiffness(b, e)) ** (2.0 / 3.0)
    hand = sum(hertz.elliptical(q, b.rx_for(r), b.ry_for(r), e).approach for r in ("inner", "outer"))
    assert delta == pytest.approx(hand, rel=1e-12)


def test_roller_law_unchanged():
    ld = scene_load_distribution(Scene.default(load_kN=500, depth_um=0))
    assert ld.exponent == 10.0 / 9.0
    assert ld.q_max == pytest.approx(51.03e3, rel=1e-3)   # docs/scene.md table
