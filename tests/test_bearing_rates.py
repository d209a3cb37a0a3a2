"""One bearing resolver (physics.catalogue.resolve_designation) and one rates function
(physics.kinematics.bearing_rates), used by the config, ``analyze``, ``identify-path``, the rig
and the sweep.

Truths: the CWRU Bearing Data Center's published fault-frequency multipliers of its drive-end
SKF 6205-2RS (BPFO 3.5848, BPFI 5.4152, FTF 0.3983, BSF 2.357 x fr), the identity
BPFO + BPFI = Z fr of a rotating inner ring (with or without a stated BPFI), and the names a
user writes for that bearing.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from bearing_envelope.physics.catalogue import bearing_geometry, resolve_designation
from bearing_envelope.physics.kinematics import bearing_rates, fault_frequencies
from bearing_envelope.physics.locations import scene_event_frequencies
from bearing_envelope.physics.scene import Scene

#: CWRU Bearing Data Center, drive-end bearing information: multiples of the shaft rate.
CWRU_6205 = {"bpfo": 3.5848, "bpfi": 5.4152, "ftf": 0.3983, "bsf": 2.357}

ALIASES = ["6205", "SKF 6205", "SKF 6205-2RS", "skf 6205-2rs", "SKF_6205-2RS",
           "SKF 6205-2RS JEM", "6205-2RS JEM SKF", "6205-2RS"]


def test_the_published_6205_rates():
    g = bearing_geometry("6205")
    r = bearing_rates(29.95, g["n_rollers"], g["roller_diameter_mm"], g["pitch_diameter_mm"],
                      g["contact_angle_deg"])
    for name, order in CWRU_6205.items():
        assert r[name] / 29.95 == pytest.approx(order, abs=5e-4 if name == "bsf" else 5e-5)
    assert r["bsf2"] / 29.95 == pytest.approx(2 * 2.357, abs=1e-3)
    assert r["fr"] == 29.95
    assert fault_frequencies(29.95, 9, 7.94, 39.04).as_dict() == r   # the typed view


def test_a_stated_bpfi_sets_the_cage_rate():
    """FAG 534176 of the study: 22 rollers per row, the stated BPFI 231.9 Hz at the study's
    shaft rate replaces the geometric 194.2 Hz; BPFO + BPFI = Z fr still, FTF = fr - BPFI/Z."""
    g = bearing_geometry("FAG 534176")
    fr = Scene.default().operation.shaft_rate_hz
    geo = bearing_rates(fr, g["n_rollers"], g["roller_diameter_mm"], g["pitch_diameter_mm"],
                        g["contact_angle_deg"])
    over = bearing_rates(fr, g["n_rollers"], g["roller_diameter_mm"], g["pitch_diameter_mm"],
                         g["contact_angle_deg"], bpfi=231.9)
    assert geo["bpfi"] == pytest.approx(194.2, abs=0.05)
    for r in (geo, over):
        assert r["bpfo"] + r["bpfi"] == pytest.approx(22 * fr, rel=1e-12)
        assert r["bsf2"] == 2 * r["bsf"]
    assert over["bpfi"] == 231.9 and over["ftf"] == pytest.approx(fr - 231.9 / 22, rel=1e-12)
    # the geometric BPFI stated gives the geometric rates back (to rounding)
    again = bearing_rates(fr, g["n_rollers"], g["roller_diameter_mm"],
                          g["pitch_diameter_mm"], g["contact_angle_deg"], bpfi=geo["bpfi"])
    assert again == pytest.approx(geo, rel=1e-12)
    # the sweep's rates are these
    assert scene_event_frequencies(Scene.default()) == pytest.approx(over, rel=1e-12)


@pytest.mark.parametrize("alias", ALIASES)
def test_every_alias_names_the_entry_everywhere(alias):
    assert resolve_designation(alias) == "SKF 6205-2RS"
    assert bearing_geometry(alias)["designation"] == "SKF 6205-2RS"
    # a config
    sc = Scene.from_mapping({"bearing": {"designation": alias}}, load_kN=1.0, depth_um=0.0)
    assert sc.bearing.designation == "SKF 6205-2RS" and sc.bearing.rollers_per_row == 9
    # identify-path
    from bearing_envelope.commands.identify_path import event_rates

    rates = event_rates(SimpleNamespace(event_hz=None, bearing=alias), 10.0)
    assert rates["bpfi"] / 10.0 == pytest.approx(CWRU_6205["bpfi"], abs=5e-5)
    # analyze's library call
    from bearing_envelope.diagnosis.records import fault_sources

    src = fault_sources(10.0, bearing=alias)
    assert src["bpfo"].hz / 10.0 == pytest.approx(CWRU_6205["bpfo"], abs=5e-5)
    assert src["bsf2"].hz == pytest.approx(2 * src["bsf"].hz, rel=1e-15)


def test_the_rig_reads_its_bearing_from_the_catalogue():
    from bearing_envelope.study.rig.records import resolve_bearing, rig_event_rates

    b = resolve_bearing("6205")
    assert b.designation == "SKF 6205-2RS"
    r = rig_event_rates(b, 29.95)
    assert r["bpfi"] / 29.95 == pytest.approx(CWRU_6205["bpfi"], abs=5e-5)
    assert set(r) == {"bpfo", "bpfi", "bsf", "bsf2"}


def test_a_config_naming_an_alias_loads(tmp_path):
    from bearing_envelope.study.settings import settings_from_mapping

    cfg = {"sweep": {"loads_kN": [1.0], "depths_um": [0.0]},
           "scene": {"bearing": {"designation": "6205"}}}
    s = settings_from_mapping(cfg)
    assert s.scene(s.cases[0]).bearing.designation == "SKF 6205-2RS"


@pytest.mark.parametrize("where, call", [
    ("scene.bearing.designation",
     lambda: Scene.from_mapping({"bearing": {"designation": "6299"}}, load_kN=1, depth_um=0)),
    ("--bearing", lambda: bearing_geometry("6299", names={"designation": "--bearing"})),
    ("bearing", lambda: bearing_geometry("6299")),
])
def test_an_unknown_bearing_is_refused_naming_the_field(where, call):
    with pytest.raises(ValueError, match=rf"^{where}: got '6299'; allowed: .*'SKF 6205-2RS'"):
        call()


@pytest.mark.parametrize("extra, message", [
    (["--bearing", "6205", "--n-rollers", "9"],
     "--bearing: give the bearing by designation or by its geometry"),
    (["--n-rollers", "9", "--roller-diameter-mm", "7.94", "--roller-diameter-in", "0.3126",
      "--pitch-diameter-mm", "39.04"], "--roller-diameter-in: give the roller diameter once"),
    (["--n-rollers", "9", "--roller-diameter-mm", "7.94"],
     "bearing geometry: give --n-rollers, --roller-diameter-mm and --pitch-diameter-mm"),
    (["--n-rollers", "0", "--roller-diameter-mm", "7.94", "--pitch-diameter-mm", "39.04"],
     "--n-rollers: got 0; allowed: an integer >= 1"),
    (["--n-rollers", "9", "--roller-diameter-mm", "40", "--pitch-diameter-mm", "39.04"],
     "--roller-diameter-mm: got 40 mm; allowed: below the pitch diameter"),
    (["--n-rollers", "9", "--roller-diameter-mm", "7.94", "--pitch-diameter-mm", "39.04",
      "--contact-angle-deg", "90"], "--contact-angle-deg: got 90.0; allowed: 0 <= angle < 90"),
])
def test_analyze_maps_its_options_onto_the_library_rules(tmp_path, capsys, extra, message):
    from bearing_envelope.cli import main

    np.save(tmp_path / "x.npy", np.zeros(1000))
    assert main(["analyze", str(tmp_path / "x.npy"), "--fs", "1000", "--fr", "10",
                 *extra]) == 2
    assert message in capsys.readouterr().err


def test_inch_and_mm_give_one_bearing():
    mm = bearing_geometry(n_rollers=9, roller_diameter_mm=7.94, pitch_diameter_mm=39.04)
    inch = bearing_geometry(n_rollers=9, roller_diameter_in=0.3126, pitch_diameter_in=1.537)
    assert inch["roller_diameter_mm"] == pytest.approx(mm["roller_diameter_mm"], abs=1e-3)
    assert inch["pitch_diameter_mm"] == pytest.approx(mm["pitch_diameter_mm"], abs=1e-3)
    assert bearing_geometry() is None
