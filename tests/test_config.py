"""The settings layer: exact case names, the sweep's cases, the one loader's defaults and checks."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from bearing_envelope.study.case_id import CaseId, format_number
from bearing_envelope.study.config_read import ConfigError
from bearing_envelope.study.sections import SweepSettings
from bearing_envelope.study.settings import load_settings, settings_from_mapping

ROOT = Path(__file__).resolve().parents[1]
DRAFT = yaml.safe_load((ROOT / "tests" / "data" / "config_draft.yaml").read_text())


@pytest.mark.parametrize("value, text", [(500, "500"), (500.0, "500"), (333.3333, "333.3333"),
                                         (50.0000001, "50.0000001"), (0.1, "0.1"), (1e-7, "0.0000001"),
                                         (-0.0, "0"), (2500.5, "2500.5")])
def test_format_number_is_exact(value, text):
    assert format_number(value) == text
    assert float(text) == float(value)


def test_case_names_round_trip_exactly():
    """Random floats of every magnitude the sweep allows: parse(name) gives the same values, and
    distinct values give distinct names (the %g names collapsed 333.3333 and 333.333)."""
    rng = np.random.default_rng(1)
    values = np.concatenate([rng.uniform(0, 5000, 300), rng.uniform(0, 1, 100),
                             np.round(rng.uniform(0, 1000, 100), 3), [333.3333, 333.333, 50.0000001]])
    names = set()
    for i, v in enumerate(values):
        c = CaseId(float(v), float(values[-i - 1]), None if i % 2 else float(v) + 1.0)
        back = CaseId.parse(c.name)
        assert back == c and back.name == c.name
        assert back.load_kN == float(v)  # exact, not approximately
        names.add(c.name)
    assert len(names) == len(values)
    assert CaseId(333.3333, 30).name != CaseId(333.333, 30).name


def test_case_name_parse_refuses_non_canonical_and_garbage():
    assert CaseId.parse("results/cases/F500kN_h50um.h5") == CaseId(500, 50)
    assert CaseId.parse("F500kN_h30um_w200um") == CaseId(500, 30, 200)
    with pytest.raises(ValueError, match="canonical name of this case is 'F500kN_h50um'"):
        CaseId.parse("F500.0kN_h50um")
    with pytest.raises(ValueError, match="does not match"):
        CaseId.parse("F500kN_h5e1um")
    with pytest.raises(ValueError, match="CaseId.depth_um"):
        CaseId(500, float("nan"))


def test_case_names_round_trip_exactly():
    assert CaseId(333.3333, 50.0000001).name == "F333.3333kN_h50.0000001um"
    c = CaseId.parse("F333.3333kN_h50.0000001um.csv")
    assert (c.load_kN, c.depth_um) == (333.3333, 50.0000001)


def test_sweep_cases_without_and_with_widths():
    s = SweepSettings.from_mapping({"loads_kN": [250, 750], "depths_um": [0, 15, 100]})
    assert [c.name for c in s.cases()] == ["F250kN_h0um", "F250kN_h15um", "F250kN_h100um",
                                           "F750kN_h0um", "F750kN_h15um", "F750kN_h100um"]
    w = SweepSettings.from_mapping({"loads_kN": [500], "depths_um": [0, 10, 30], "widths_um": [60, 200]})
    # the healthy race is one case per load; each defect depth gets every width
    assert [c.name for c in w.cases()] == ["F500kN_h0um", "F500kN_h10um_w60um", "F500kN_h10um_w200um",
                                           "F500kN_h30um_w60um", "F500kN_h30um_w200um"]
    with pytest.raises(ConfigError, match=r"sweep.depths_um\[2\]: 50.0 repeats sweep.depths_um\[1\]"):
        SweepSettings.from_mapping({"loads_kN": [500], "depths_um": [0, 50, 50.0]})


def test_default_config_has_the_study_cases_and_width_rule():
    st = load_settings(ROOT / "config.yaml")
    assert len(st.cases) == 27 and st.cases[0].name == "F250kN_h0um"
    assert st.sweep.widths_um is None
    sc = st.scene(CaseId(500, 30))
    assert sc.defect.width_um == 60.0  # w = 2 h
    assert st.scene(CaseId(500, 30, 200)).defect.width_um == 200.0


def test_defaults_filled_as_a_json_schema_validator_does(tmp_path):
    """The loader fills the schema's defaults (with those whose home is code filled in) as
    ``snakemake.utils.validate(set_default=True)`` fills them, so jobs receive the same values."""
    from snakemake.utils import validate

    from bearing_envelope.study.schema import full_schema

    for cfg in (copy.deepcopy(DRAFT), {"sweep": {"loads_kN": [1], "depths_um": [0]},
                                       "scene": {"material": {"roller": {}}},
                                       "analysis": {"bands": [{"name": "k", "strategy": "kurtogram"}]}}):
        ours = settings_from_mapping(cfg).config
        theirs = copy.deepcopy(cfg)
        schema = tmp_path / "schema.yaml"
        schema.write_text(yaml.safe_dump(full_schema()))
        validate(theirs, str(schema))
        assert json.dumps(ours, sort_keys=True) == json.dumps(theirs, sort_keys=True)
    # no scene default is filled: the scene's defaults live in physics/scene.py alone
    assert ours["scene"]["material"]["roller"] == {}


def test_cage_slip_schema_matches_the_implementation():
    """cage_slip_percent is the mean slip s in [0, 50) (history.cage_angle draws U[0, 2s]); the
    schema and the scene agree on the bound, and the mean slip is s."""
    from bearing_envelope.physics.history import cage_angle

    cfg = copy.deepcopy(DRAFT)
    cfg["scene"]["operation"]["cage_slip_percent"] = 49.0
    st = settings_from_mapping(cfg)
    cfg["scene"]["operation"]["cage_slip_percent"] = 50.0
    with pytest.raises(ConfigError, match="cage_slip_percent"):
        settings_from_mapping(cfg)
    # mean slip: the cage turns (1 - s) as far as without slip, over many BPFI periods
    m = copy.deepcopy(DRAFT["scene"])
    m["operation"].update(cage_slip_percent=10.0, revolutions=400)
    sc = CaseId(500, 0).scene(m)
    t = np.array([0.0, 400 / sc.operation.shaft_rate_hz])
    ratio = cage_angle(sc, t)[-1] / (2 * np.pi * sc.cage_rate_hz * t[-1])
    assert ratio == pytest.approx(0.90, abs=0.005)
    assert st.scene(CaseId(500, 0)).operation.cage_slip_percent == 49.0


def test_fidelity_defaults_are_the_standard_preset():
    # issue 15: Fidelity() was labelled "standard" but differed from the preset in six fields,
    # so files claimed a preset they did not use
    import dataclasses

    from bearing_envelope.physics.fidelity import PRESETS, Fidelity, fidelity_from

    assert Fidelity() == PRESETS["standard"] == fidelity_from(None) == fidelity_from("standard")
    for name, preset in PRESETS.items():
        assert preset.name == name
        assert fidelity_from({"preset": name}) == preset        # no override: still the preset
    tweaked = fidelity_from({"preset": "standard", "tol": 1e-7})
    assert tweaked.name == "custom" and tweaked.tol == 1e-7
    assert dataclasses.replace(tweaked, name="standard", tol=1e-5) == Fidelity()
