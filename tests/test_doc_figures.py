"""The figures docs/scene.md and docs/virtual_rig.md quote, regenerated (issue 43, part 4).

Each is computed here by the project's code and, where one exists, by an independent closed form,
and must appear in the doc as written.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from bearing_envelope.physics.loads import (hertz_point_stiffness, operating_clearance,
                                            row_load_distribution)
from bearing_envelope.physics.locations import scene_event_frequencies
from bearing_envelope.physics.scene import BEARING_STEEL_HARDNESS_GPA, Scene

ROOT = Path(__file__).resolve().parents[1]
SCENE_MD = (ROOT / "docs" / "scene.md").read_text()
RIG_MD = (ROOT / "docs" / "virtual_rig.md").read_text()
G = 9.80665            # standard gravity: kgf -> N


def _cwru(clearance_um: float, centrifugal: bool = True) -> Scene:
    return Scene.from_mapping({"bearing": {"designation": "SKF 6205-2RS",
                                           "radial_clearance_um": clearance_um},
                               "operation": {"shaft_rate_hz": 29.95, "fs_hz": 48000.0},
                               "load": {"centrifugal": centrifugal}}, load_kN=1.0, depth_um=0.0)


def _hamrock_brewe_approach(rx: float, ry: float, e_star: float) -> float:
    """Approach (m) of a point contact at 1 N from Hamrock & Brewe's (1983) fits (within 3 %)."""
    a = ry / rx
    k, e, f = 1.0339 * a ** 0.636, 1.0003 + 0.5968 / a, 1.5277 + 0.6023 * math.log(a)
    r = 1.0 / (1.0 / rx + 1.0 / ry)
    return f * (9.0 / (2.0 * e * r) * (1.0 / (math.pi * k * 2.0 * e_star)) ** 2) ** (1.0 / 3.0)


def _preload_for_12(k: float, z: int, force: float) -> float:
    """Clearance (m, negative) at which the element at 180 deg starts to carry load: the row's
    equilibrium sum K (delta_r cos psi - P_d/2)^1.5 cos psi = F with delta_r = -P_d/2."""
    psi = 2.0 * math.pi * np.arange(z) / z

    def dr(pd):
        return brentq(lambda d: float((k * np.clip(d * np.cos(psi) - pd / 2, 0, None) ** 1.5
                                       * np.cos(psi)).sum()) - force, max(0.0, pd / 2) + 1e-15, 1e-3)
    return brentq(lambda pd: dr(pd) + pd / 2, -50e-6, -1e-7)


def test_preload_that_loads_12_oclock():
    sc = _cwru(10.0)
    b = sc.bearing
    k = hertz_point_stiffness(b, sc.material.e_star_pa)
    pd = _preload_for_12(k, b.rollers_per_row, 1e3)
    # independent stiffness (Hamrock & Brewe) agrees to 1 %
    c = sum(_hamrock_brewe_approach(b.rx_for(r), b.ry_for(r), sc.material.e_star_pa)
            for r in ("inner", "outer"))
    assert _preload_for_12(c ** -1.5, b.rollers_per_row, 1e3) == pytest.approx(pd, rel=0.01)
    # the project's load distribution: 12:00 unloaded just above, loaded just below
    at = round(pd * 1e6, 1)
    assert at == -12.9
    assert row_load_distribution(_cwru(at + 0.05, False)).load_at(math.pi) == 0.0
    assert row_load_distribution(_cwru(at - 0.05, False)).load_at(math.pi) > 0.0
    assert "-12.9 um at\n  1 kN" in SCENE_MD and "-12.9 um, not a plausible" in RIG_MD
    assert "about -15 um" not in SCENE_MD and "-15 um, not" not in RIG_MD


def test_fit_fractions_of_the_6205():
    b = _cwru(10.0).bearing
    housing = -(operating_clearance(b, housing_interference_um=1.0) - b.radial_clearance_um)
    shaft = -(operating_clearance(b, shaft_interference_um=1.0) - b.radial_clearance_um)
    assert housing == pytest.approx((39.04 + 7.94) / 52.0) and round(housing, 3) == 0.903
    assert shaft == pytest.approx(25.0 / (39.04 - 7.94)) and round(shaft, 3) == 0.804
    assert "0.90 I_h" in SCENE_MD and "0.80 I_s" in SCENE_MD


def test_q_at_6_is_the_outer_contact_with_centrifugal_force():
    ld = row_load_distribution(_cwru(10.0))
    assert f"{ld.load_at(0.0, 'outer'):.1f} N" == "534.4 N"         # the table's figure
    assert f"{ld.load_at(0.0):.1f} N" == "534.1 N"                  # the inner contact
    assert f"{ld.centrifugal:.2f} N" == "0.22 N"
    assert "Q at 6:00 (outer, with F_c)" in SCENE_MD and "534.1 N at +10 um" in SCENE_MD


def test_case_file_rates_are_the_event_rates():
    sc = Scene.default()
    ev, geo = scene_event_frequencies(sc), sc.frequencies()
    assert f"{ev['bpfo']:.1f}" == "115.7" and f"{geo.bpfo:.1f}" == "153.4"
    assert ev["bpfo"] == pytest.approx(sc.bearing.rollers_per_row * sc.cage_rate_hz)
    assert "`bpfo` = Z f_c = 115.7" in SCENE_MD and "`bpfo_geometry` 153.4" in SCENE_MD


def test_hardness_is_750_hv():
    assert f"{750 * G / 1e3:.3f}" == "7.355"                   # 750 HV in GPa
    assert abs(750 * G / 1e3 - BEARING_STEEL_HARDNESS_GPA) < 0.0051   # taken as 7.36
    assert "7.355, taken as 7.36 GPa" in SCENE_MD
    for text in (SCENE_MD, (ROOT / "config_cwru.yaml").read_text(),
                 (ROOT / "src/bearing_envelope/data/config.schema.yaml").read_text()):
        assert "~61 HRC" not in text
        assert "750 HV" in text
