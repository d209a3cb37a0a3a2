"""Bearing catalogue (issue 23, parts A and B): entries, sources, overrides, bad input, and the
fault frequencies of the CWRU bearing against the data center's published multipliers."""

import math

import pytest

from bearing_envelope.physics import catalogue
from bearing_envelope.physics.scene import Scene

INCH_MM = 25.4

#: CWRU Bearing Data Center, drive-end bearing (SKF 6205-2RS JEM), published fault frequencies
#: as multiples of the shaft rate: inner ring, outer ring, cage train, rolling element (2 x BSF).
CWRU_BPFI, CWRU_BPFO, CWRU_FTF, CWRU_2BSF = 5.4152, 3.5848, 0.39828, 4.7135


def _scene(designation, **defect):
    return Scene.from_mapping({"bearing": {"designation": designation},
                               "operation": {"bpfi_override_hz": None, "shaft_rate_hz": 29.95,
                                             "fs_hz": 12000.0},
                               "defect": defect},
                              load_kN=2.0, depth_um=defect.pop("depth_um", 0.0) if defect else 0.0)


@pytest.mark.parametrize("designation", catalogue.designations())
def test_every_entry_builds_and_every_number_has_a_source(designation):
    values = catalogue.bearing_values(designation)
    sources = catalogue.bearing_sources(designation)
    assert set(values) == set(sources)
    assert all(isinstance(s, str) and len(s) > 10 for s in sources.values())
    sc = _scene(designation)
    assert sc.bearing.designation == designation
    assert sc.bearing.kind == values["kind"]


def test_catalogue_holds_the_common_bearings():
    assert {"FAG 534176", "SKF 6205-2RS", "SKF 6203", "MFPT", "Rexnord ZA-2115"} <= set(
        catalogue.designations())


def test_cwru_6205_numbers_are_the_published_inch_values():
    b = _scene("SKF 6205-2RS").bearing
    assert b.kind == "ball" and b.rollers_per_row == 9 and b.rows == 1
    assert b.roller_diameter_mm == pytest.approx(0.3126 * INCH_MM, abs=5e-3)
    assert b.pitch_diameter_mm == pytest.approx(1.537 * INCH_MM, abs=5e-3)
    assert b.contact_angle_deg == 0.0


def test_fag_entry_is_the_default_scene():
    a = Scene.from_mapping({"bearing": {"designation": "FAG 534176"}}, load_kN=500, depth_um=50)
    d = Scene.default()
    ma, md = a.to_mapping(), d.to_mapping()
    assert ma["bearing"].pop("designation") == "FAG 534176"
    md["bearing"].pop("designation")
    assert ma == md


def test_config_keys_override_the_entry():
    sc = Scene.from_mapping({"bearing": {"designation": "SKF 6205-2RS", "rollers_per_row": 8,
                                         "inner_groove_conformity": 0.51},
                             "operation": {"bpfi_override_hz": None}}, load_kN=2, depth_um=0)
    assert sc.bearing.rollers_per_row == 8
    assert sc.bearing.inner_groove_conformity == 0.51
    assert sc.bearing.outer_groove_conformity == 0.52   # from the entry


def test_cwru_fault_frequencies_match_the_published_multipliers():
    """B: the kinematics of the 6205 against the CWRU data center's numbers, within 0.1 %."""
    o = _scene("SKF 6205-2RS").frequencies().orders()
    assert o["bpfi"] == pytest.approx(CWRU_BPFI, rel=1e-3)
    assert o["bpfo"] == pytest.approx(CWRU_BPFO, rel=1e-3)
    assert o["ftf"] == pytest.approx(CWRU_FTF, rel=1e-3)
    assert 2.0 * o["bsf"] == pytest.approx(CWRU_2BSF, rel=1e-3)


def test_contact_angle_enters_every_frequency():
    """Angular contact: d/D cos(alpha) replaces d/D (an independent hand value: 6205 geometry at
    alpha = 40 deg, gamma = 7.94/39.04 cos 40 = 0.155796)."""
    sc = Scene.from_mapping({"bearing": {"designation": "SKF 6205-2RS", "contact_angle_deg": 40.0},
                             "operation": {"bpfi_override_hz": None}}, load_kN=2, depth_um=0)
    o = sc.frequencies().orders()
    g = 0.155796
    assert o["bpfo"] == pytest.approx(4.5 * (1 - g), rel=1e-5)
    assert o["bpfi"] == pytest.approx(4.5 * (1 + g), rel=1e-5)
    assert o["ftf"] == pytest.approx(0.5 * (1 - g), rel=1e-5)
    assert o["bsf"] == pytest.approx(39.04 / (2 * 7.94) * (1 - g * g), rel=1e-5)


@pytest.mark.parametrize("bearing, match", [
    ({"designation": "SKF 9999"}, r"scene\.bearing\.designation: got 'SKF 9999'; allowed: null or one of"),
    ({"designation": "SKF 6205-2RS", "inner_groove_conformity": 0.5},
     r"scene\.bearing\.inner_groove_conformity: got 0\.5; allowed: a number in \(0\.5, 1\]"),
    ({"designation": "SKF 6205-2RS", "outer_groove_conformity": 0.45},
     r"scene\.bearing\.outer_groove_conformity: got 0\.45"),
    ({"kind": "ball"}, r"scene\.bearing\.roller_length_mm: got 34\.0; allowed: for kind 'ball' the groove width"),
    ({"kind": "needle"}, r"scene\.bearing\.kind: got 'needle'; allowed: roller \| ball"),
    ({"inner_groove_conformity": 0.52}, r"scene\.bearing\.inner_groove_conformity: got 0\.52; allowed: null for kind 'roller'"),
])
def test_bad_bearing_is_refused_with_the_field(bearing, match):
    with pytest.raises(ValueError, match=match):
        Scene.from_mapping({"bearing": bearing, "operation": {"bpfi_override_hz": None}},
                           load_kN=2, depth_um=0)


@pytest.mark.parametrize("defect, depth, match", [
    ({"location": "outer_race", "position_deg": 360.0}, 10.0,
     r"scene\.defect\.position_deg: got 360\.0; allowed: a finite angle in \[0, 360\)"),
    ({"location": "outer_race", "position_deg": -1.0}, 10.0, r"scene\.defect\.position_deg: got -1\.0"),
    ({"location": "cage"}, 10.0, r"scene\.defect\.location: got 'cage'; allowed: inner_race \| outer_race"),
    ({"shape": "cylinder", "width_um": 177.8}, 4000.0,
     r"scene\.defect\.depth_um: got 4000\.0; allowed: a depth < the material under the inner_race"),
    ({"location": "rolling_element", "shape": "cylinder", "width_um": 177.8}, 3980.0,
     r"scene\.defect\.depth_um: got 3980\.0; allowed: a depth < the material under the rolling_element"),
    ({"shape": "cylinder", "width_um": 7000.0}, 100.0,
     r"scene\.defect\.(length|width)_um: got 7000\.0; allowed: an axial extent < roller_length_mm"),
    ({"location": "outer_race", "length_um": 100.0, "width_um": 9000.0}, 100.0,
     r"scene\.defect\.width_um: got 9000\.0; allowed: a rolling-direction extent < half the element spacing on the outer raceway"),
    ({"location": "rolling_element", "length_um": 100.0, "width_um": 13000.0}, 100.0,
     r"scene\.defect\.width_um: got 13000\.0; allowed: a rolling-direction extent < half the element's circumference"),
    ({"profile_file": "x.csv"}, 10.0, r"scene\.defect\.profile_file: got 'x\.csv'; allowed: null unless"),
])
def test_bad_defect_is_refused_before_any_solve(defect, depth, match):
    with pytest.raises(ValueError, match=match):
        Scene.from_mapping({"bearing": {"designation": "SKF 6205-2RS"}, "defect": defect,
                            "operation": {"bpfi_override_hz": None}}, load_kN=2, depth_um=depth)


def test_race_thickness_of_the_6205():
    """Hand values: inner (39.04 - 7.94)/2 - 25/2 = 3.05 mm, outer 52/2 - (39.04 + 7.94)/2 = 2.51 mm."""
    b = _scene("SKF 6205-2RS").bearing
    assert b.race_thickness_m("inner_race") == pytest.approx(3.05e-3, rel=1e-9)
    assert b.race_thickness_m("outer_race") == pytest.approx(2.51e-3, rel=1e-9)
    assert b.race_thickness_m("rolling_element") == pytest.approx(3.97e-3, rel=1e-9)


def test_ball_curvatures_are_the_hand_values():
    """6205, alpha = 0: R_x inner 1/(1/3.97 + 1/15.55) mm, outer 1/(1/3.97 - 1/23.49) mm,
    R_y = 1/(1/3.97 - 1/4.1288) mm (f = 0.52)."""
    b = _scene("SKF 6205-2RS").bearing
    assert b.rx_for("inner") == pytest.approx(1e-3 / (1 / 3.97 + 1 / 15.55), rel=1e-12)
    assert b.rx_for("outer") == pytest.approx(1e-3 / (1 / 3.97 - 1 / 23.49), rel=1e-12)
    assert b.ry_for("inner") == pytest.approx(1e-3 / (1 / 3.97 - 1 / 4.1288), rel=1e-12)
    assert math.isclose(b.ry_for("outer"), b.ry_for("inner"))


def test_package_yaml_files_read_alike_by_libyaml_and_python_loaders():
    """The catalogue and the config schema are read with libyaml's CSafeLoader (10x faster, 0.05
    CPU s of a simulate job) where PyYAML has it: the same documents as yaml.SafeLoader's."""
    import yaml

    from bearing_envelope.physics.catalogue import CATALOGUE_PATH
    from bearing_envelope.study.schema import SCHEMA_PATH

    for path in (CATALOGUE_PATH, SCHEMA_PATH):
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
        want = yaml.load(text, Loader=yaml.SafeLoader)
        assert yaml.load(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader)) == want
