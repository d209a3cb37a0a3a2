"""Every default is written once: its home against every other place that could hold one.

Homes (docs/architecture.md, "Where defaults live"): the scene in ``physics/scene.py``
(``DEFAULT_SCENE``) with the study bearing's values in its catalogue entry
(``data/bearings.yaml``); the fidelity preset in ``physics/fidelity.py``; the analysis options in
``diagnosis.AnalysisOptions`` (the filter order in ``signal/envelope.py``); the trade-off study
in ``study/tradeoff_settings.py``; the pre-run limits in ``study/limits.py``. The schema file holds
defaults only for sections whose home it is (sensor, diagnosability, paper_run), and the
loader fills the others in from their homes.
"""

from __future__ import annotations

import inspect
from pathlib import Path

import pytest
import yaml

from bearing_envelope.diagnosis.options import AnalysisOptions
from bearing_envelope.physics import catalogue
from bearing_envelope.physics.fidelity import DEFAULT_PRESET, fidelity_from
from bearing_envelope.physics.scene import DEFAULT_SCENE, STUDY_DESIGNATION, Scene
from bearing_envelope.signal.envelope import DEFAULT_FILTER_ORDER, bandpass, envelope_spectrum
from bearing_envelope.study.limits import DEFAULT_LIMITS
from bearing_envelope.study.schema import full_schema
from bearing_envelope.study.settings import settings_from_mapping
from bearing_envelope.study.schema import SCHEMA_PATH
from bearing_envelope.study.tradeoff import TRADEOFF_DEFAULTS, tradeoff_study

ROOT = Path(__file__).resolve().parents[1]
RAW_SCHEMA = yaml.safe_load(SCHEMA_PATH.read_text())

#: Schema sections whose defaults live in code (none may be written in the schema file).
CODE_HOMED = ("fidelity", "scene", "limits", "tradeoff")


def _defaults(node, path=""):
    """Every ``default:`` under a schema node: dotted path -> value."""
    out = {}
    if isinstance(node, dict):
        if "default" in node:
            out[path] = node["default"]
        for key, sub in node.items():
            if key != "default":
                out.update(_defaults(sub, f"{path}.{key}" if path else key))
    elif isinstance(node, list):
        for i, sub in enumerate(node):
            out.update(_defaults(sub, f"{path}[{i}]"))
    return out


def _leaves(m, path=()):
    if isinstance(m, dict) and m:
        for k, v in m.items():
            yield from _leaves(v, path + (k,))
    else:
        yield path, m


@pytest.mark.parametrize("section", CODE_HOMED)
def test_schema_file_writes_no_default_whose_home_is_code(section):
    assert _defaults(RAW_SCHEMA["properties"][section]) == {}
    assert _defaults(RAW_SCHEMA["$defs"]) == {}   # the material: physics/scene.py


def test_schema_file_writes_no_analysis_option_default():
    """Only ``signal`` (which simulated signal: no analysis option) has its default in the file."""
    raw = _defaults(RAW_SCHEMA["properties"]["analysis"])
    assert set(raw) == {"properties.signal"}


def test_loaded_schema_takes_analysis_and_fidelity_defaults_from_their_homes():
    opt = AnalysisOptions()
    props = full_schema()["properties"]
    an = {k: v["default"] for k, v in props["analysis"]["properties"].items() if "default" in v}
    assert an["harmonics"] == opt.n_harmonics and an["sidebands"] == opt.n_sidebands
    assert an["raw_orders_fr"] == opt.n_raw_harmonics and an["nlevel"] == opt.nlevel
    assert an["filter_order"] == opt.filter_order == DEFAULT_FILTER_ORDER
    assert an["squared_envelope"] is opt.squared
    assert an["max_level"] == opt.max_level and an["min_bandwidth_hz"] == opt.min_bandwidth
    assert an["amplitude"] == ("interpolated" if opt.interpolate else "peak_bin")
    assert props["fidelity"]["default"] == DEFAULT_PRESET
    assert fidelity_from(None) == fidelity_from(DEFAULT_PRESET)


def test_filter_order_has_one_home():
    for fn in (bandpass, envelope_spectrum):
        assert inspect.signature(fn).parameters["order"].default == DEFAULT_FILTER_ORDER


def test_study_bearing_is_its_catalogue_entry_with_its_override():
    values = catalogue.bearing_values(STUDY_DESIGNATION)
    for key, value in values.items():
        assert DEFAULT_SCENE["bearing"][key] == value, key
    assert DEFAULT_SCENE["operation"]["bpfi_override_hz"] == \
        catalogue.entry(STUDY_DESIGNATION)["bpfi_override_hz"]["value"] == 231.9
    # naming the entry or not gives the same scene (the designation field aside)
    named = Scene.from_mapping({"bearing": {"designation": STUDY_DESIGNATION}}, load_kN=500,
                               depth_um=50)
    assert named.bpfi_hz == Scene.default().bpfi_hz == 231.9
    assert named.bearing.roller_diameter_mm == Scene.default().bearing.roller_diameter_mm


def test_config_yaml_restates_no_default():
    """config.yaml states what the default sweep chooses: no scene value (every one is the
    study's default), no analysis, limits, tradeoff, sensor or diagnosability value equal to its
    home's
    (``fidelity: standard`` is stated as the sweep's choice of preset)."""
    cfg = yaml.safe_load((ROOT / "config.yaml").read_text())
    assert cfg["scene"] == {}
    assert "limits" not in cfg
    for key, value in cfg.get("tradeoff", {}).items():
        default = TRADEOFF_DEFAULTS[key]
        assert value != (list(default) if isinstance(default, tuple) else default), key
    loaded = full_schema()["properties"]["analysis"]["properties"]
    for key, value in cfg["analysis"].items():
        assert "default" not in loaded[key] or loaded[key]["default"] != value, key
    schema_defaults = _defaults(RAW_SCHEMA["properties"])
    for path, value in _leaves({k: cfg[k] for k in ("sensor", "diagnosability")}):
        dotted = ".properties.".join(path)
        assert dotted not in schema_defaults or schema_defaults[dotted] != value, path


def test_catalogue_and_config_agree_on_nothing_twice():
    """bearings.yaml is the only file with the study bearing's numbers: config.yaml and the
    CWRU overlays name a designation instead of repeating an entry's values."""
    for name in ("config.yaml", "config_cwru.yaml", "config_cwru_or.yaml", "config_cwru_ball.yaml",
                 "config_cwru_locations.yaml"):
        scene = (yaml.safe_load((ROOT / name).read_text()) or {}).get("scene") or {}
        bearing = scene.get("bearing") or {}
        assert set(bearing) <= {"designation"}, name
        assert "bpfi_override_hz" not in (scene.get("operation") or {}), name


def test_tradeoff_and_limits_defaults_have_one_home():
    sig = inspect.signature(tradeoff_study).parameters
    for key in ("base", "reference", "reference_element", "element_series", "revolutions"):
        assert sig[key].default is TRADEOFF_DEFAULTS[key], key
    assert sig["cases"].default is TRADEOFF_DEFAULTS["cases"]
    st = settings_from_mapping({"sweep": {"loads_kN": [500], "depths_um": [0]}})
    assert "limits" not in st.config and "tradeoff" not in st.config
    assert DEFAULT_LIMITS["max_case_cpu_s"] > 0


def test_cli_simulate_has_no_scene_or_fidelity_default():
    """``bearing-envelope simulate``: a scene or fidelity option left out is None (the config's
    or the home's default), never a second default."""
    import argparse

    from bearing_envelope.commands import simulate

    parser = argparse.ArgumentParser()
    simulate.register(parser.add_subparsers())
    sub = parser._subparsers._group_actions[0].choices["simulate"]
    for action in sub._actions:
        if action.dest in ("fidelity", "width_um", "config"):
            assert action.default is None, action.dest
