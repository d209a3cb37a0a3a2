"""The defect's characteristic scales of a roller: line contact, not a ball's point contact
(issue 42). Hand numbers from typed constants: Hertz's line-contact half-width
``b = sqrt(4 Q R_x / (pi l E*))`` and Palmgren's deflection ``delta = 3.84e-5 Q^0.9 / l^0.8``
(mm, N, mm) per contact, whose stiffness is ``dQ/d delta = Q / (0.9 delta)``."""

import math

import pytest

from bearing_envelope.contact import hertz
from bearing_envelope.physics.defect_contact import defect_scales
from bearing_envelope.physics.scene import Scene

#: The default scene's roller (FAG 534176, physics/scene.py), typed here: roller diameter d,
#: pitch (bore + OD)/2, contact angle, effective length (mm); steel E 210 GPa, nu 0.3.
D_MM, PITCH_MM, ALPHA_DEG, L_MM = 17.45, 0.5 * (110.0 + 180.0), 12.82, 34.0
E_STAR = 210e9 / (2 * (1 - 0.3 ** 2))
#: The inner contact's load (N): ``load.mode: contact`` sets it at the load zone's centre.
Q_N = 20e3


def roller_scene():
    m = {"load": {"mode": "contact"}, "defect": {"location": "inner_race"}}
    return Scene.from_mapping(m, load_kN=1e-3 * Q_N, depth_um=50.0)


def test_line_contact_half_width_by_hand():
    # Johnson 1985 eq. 4.43 with Q/l per unit length: a 20 kN roller on R_x = 10 mm, l = 30 mm
    b = math.sqrt(4 * (20e3 / 0.030) * 0.010 / (math.pi * E_STAR))
    assert b == pytest.approx(271.1e-6, rel=1e-3)
    assert hertz.line_half_width(20e3, 0.030, 0.010, E_STAR) == pytest.approx(b, rel=1e-12)
    with pytest.raises(ValueError, match="length"):
        hertz.line_half_width(20e3, 0.0, 0.010, E_STAR)


def test_roller_scales_are_the_line_contact():
    s = defect_scales(roller_scene())
    assert s.element_load_n == pytest.approx(Q_N, rel=1e-9)
    assert s.other_load_n == pytest.approx(Q_N, rel=1e-9)
    # inner contact: 1/R_x = 2/d + 1/R_i, R_i the inner race's radius along the contact normal
    r_i = 0.5 * (PITCH_MM - D_MM * math.cos(math.radians(ALPHA_DEG)))
    rx_m = 1e-3 / (2 / D_MM + 1 / r_i)
    b = math.sqrt(4 * Q_N * rx_m / (math.pi * 1e-3 * L_MM * E_STAR))
    assert b == pytest.approx(223.2e-6, rel=1e-3)
    assert s.contact_half_width_m == pytest.approx(b, rel=1e-9)
    assert s.contact_half_length_m == pytest.approx(0.5e-3 * L_MM)
    # Palmgren per contact: 3.84e-5 * 20000^0.9 / 34^0.8 mm = 16.99 um; k = Q / (0.9 delta)
    delta = 1e-3 * 3.84e-5 * Q_N ** 0.9 / L_MM ** 0.8
    assert delta == pytest.approx(16.99e-6, rel=1e-3)
    assert s.static_approach_m == pytest.approx(delta, rel=1e-9)
    k = Q_N / (0.9 * delta)
    assert s.stiffness_n_m == pytest.approx(k, rel=1e-9)
    assert s.other_stiffness_n_m == pytest.approx(k, rel=1e-9)
    # the roller between its two contacts: f_n = sqrt(2 k / m) / (2 pi), m = rho pi d^2 l / 4
    m = 7810.0 * math.pi * (1e-3 * D_MM) ** 2 * 1e-3 * L_MM / 4
    fn = math.sqrt(2 * k / m) / (2 * math.pi)
    assert s.natural_frequency_hz == pytest.approx(fn, rel=1e-9)
    assert fn == pytest.approx(32.31e3, rel=1e-3)


def test_ball_scales_stay_the_point_contact():
    # the 6205 (config_cwru.yaml's bearing): Hertz point contact, 1.5 K^(2/3) Q^(1/3)
    m = {"bearing": {"designation": "SKF 6205-2RS"}, "load": {"mode": "contact"},
         "defect": {"location": "inner_race", "shape": "cylinder", "width_um": 177.8}}
    sc = Scene.from_mapping(m, load_kN=0.05, depth_um=279.4)
    s = defect_scales(sc)
    b = sc.bearing
    h = hertz.elliptical(50.0, b.rx_for("inner"), b.ry_for("inner"), sc.material.e_star_pa)
    assert s.contact_half_width_m == pytest.approx(h.a, rel=1e-9)
    assert s.static_approach_m == pytest.approx(h.approach, rel=1e-9)
    assert s.stiffness_n_m == pytest.approx(1.5 * 50.0 / h.approach, rel=1e-6)   # Q/(2/3 delta)
