"""One analysis-options type: every range, default and rule of the analysis options in
``AnalysisOptions`` (diagnosis/options.py), read the same by the library, a config and the
``analyze`` command.

Truths: the bounds written here by hand (the ranges the project documents: harmonics 1..1000,
sidebands 0..100, nlevel 1..30, filter order 1..20), the config's own key names, and that a
value one past a bound is refused by each entry point while the bound itself is accepted.
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml

from bearing_envelope.diagnosis import AnalysisOptions, fault_frequency_map
from bearing_envelope.diagnosis.options import OPTION_SPECS
from bearing_envelope.study.config_read import ConfigError
from bearing_envelope.study.schema import SCHEMA_PATH, full_schema
from bearing_envelope.study.settings import settings_from_mapping

ROOT = Path(__file__).resolve().parents[1]
DRAFT = yaml.safe_load((ROOT / "tests" / "data" / "config_draft.yaml").read_text())

#: (field, config key, low, high): the documented integer ranges (written here by hand).
INT_RANGES = [("n_sidebands", "sidebands", 0, 100), ("nlevel", "nlevel", 1, 30),
              ("filter_order", "filter_order", 1, 20), ("n_harmonics", "harmonics", 1, 1000),
              ("n_raw_harmonics", "raw_orders_fr", 1, 1000)]


def _config(**analysis):
    cfg = copy.deepcopy(DRAFT)
    cfg.pop("sensor", None)
    cfg["analysis"].update(analysis)
    return cfg


def test_the_schema_file_writes_no_type_range_or_default_of_an_option():
    raw = yaml.safe_load(SCHEMA_PATH.read_text())["properties"]["analysis"]["properties"]
    keyed = [s.config for s in OPTION_SPECS.values() if s.config is not None]
    assert set(keyed) == {"bands", "harmonics", "sidebands", "raw_orders_fr", "nlevel",
                          "max_level", "min_bandwidth_hz", "filter_order",
                          "squared_envelope", "amplitude"}
    for key in keyed:
        if key != "bands":   # the band items' schema stays in the file (not an option range)
            assert set(raw[key]) == {"description"}, key
    loaded = full_schema()["properties"]["analysis"]["properties"]
    assert loaded["harmonics"]["maximum"] == 1000 and loaded["sidebands"]["maximum"] == 100
    assert loaded["nlevel"]["maximum"] == 30 and loaded["filter_order"]["maximum"] == 20
    assert loaded["amplitude"]["enum"] == ["interpolated", "peak_bin"]
    assert loaded["nlevel"]["type"] == "integer"     # null is the library's, not a config's


@pytest.mark.parametrize("field, key, lo, hi", INT_RANGES)
def test_library_and_config_share_each_range(field, key, lo, hi):
    for ok in (lo, hi):
        assert getattr(AnalysisOptions(**{field: ok}), field) == ok
    for bad in (lo - 1, hi + 1):
        with pytest.raises(ValueError, match=rf"^AnalysisOptions\.{field} = {bad}: allowed "
                                             rf"an integer {lo} \.\. {hi}"):
            AnalysisOptions(**{field: bad})
        with pytest.raises(ConfigError, match=rf"analysis\.{key}"):
            settings_from_mapping(_config(**{key: bad}))
    if key in ("sidebands", "filter_order", "nlevel"):   # the others meet Nyquist first
        s = settings_from_mapping(_config(**{key: hi}))
        assert getattr(s.analysis.options, field) == hi


def test_the_config_loads_straight_into_the_options():
    s = settings_from_mapping(_config(harmonics=4, sidebands=1, amplitude="interpolated",
                                      max_level=5, squared_envelope=True))
    opt = s.analysis.options
    assert (opt.n_harmonics, opt.n_sidebands, opt.nlevel, opt.max_level) == (4, 1, 6, 5.0)
    assert opt.interpolate is True and opt.squared is True
    assert [b["name"] for b in opt.bands] == [b["name"] for b in DRAFT["analysis"]["bands"]]
    assert AnalysisOptions.from_config(opt.config_values()) == opt
    assert s.analysis.to_mapping()["amplitude"] == "interpolated"


def test_max_level_above_nlevel_is_one_rule_everywhere(tmp_path, capsys):
    with pytest.raises(ValueError, match=r"^AnalysisOptions\.max_level = 7\.0: allowed None "
                                         r"or a level <= nlevel \(6\)$"):
        AnalysisOptions(nlevel=6, max_level=7)
    assert AnalysisOptions(nlevel=6, max_level=6).max_level == 6.0          # the bound
    with pytest.raises(ConfigError, match=r"analysis\.max_level: got 7\.0; allowed: None or a "
                                          r"level <= analysis\.nlevel \(6\)"):
        settings_from_mapping(_config(nlevel=6, max_level=7))
    from bearing_envelope.cli import main

    np.save(tmp_path / "x.npy", np.zeros(1000))
    assert main(["analyze", str(tmp_path / "x.npy"), "--fs", "1000", "--fr", "10", "--bpfi",
                 "55", "--nlevel", "6", "--max-level", "7"]) == 2
    assert "--max-level: got 7.0; allowed: None or a level <= --nlevel (6)" in \
        capsys.readouterr().err


@pytest.mark.parametrize("name", ["fr", "dc"])
def test_reserved_line_names_are_the_library_rule(name, tmp_path, capsys):
    with pytest.raises(ValueError, match=rf"fault_frequencies\['{name}'\]: '{name}' is reserved"):
        fault_frequency_map(fault_frequencies={name: 10.0})
    assert fault_frequency_map(fault_frequencies={"gear": 10.0}) == {"gear": 10.0}
    from bearing_envelope.cli import main

    np.save(tmp_path / "x.npy", np.zeros(1000))
    assert main(["analyze", str(tmp_path / "x.npy"), "--fs", "1000", "--fr", "10",
                 "--fault", f"{name}=10"]) == 2
    assert f"--fault {name}: '{name}' is reserved" in capsys.readouterr().err


@pytest.mark.parametrize("field, bad", [("squared", 1), ("interpolate", "yes"),
                                        ("min_bandwidth", 0.0), ("max_level", -1.0),
                                        ("tolerance_hz", float("nan")),
                                        ("nyquist_margin", 1.01), ("search_percent", 50.0)])
def test_options_the_library_did_not_check_are_checked(field, bad):
    with pytest.raises(ValueError, match=rf"^AnalysisOptions\.{field} = "):
        AnalysisOptions(**{field: bad})
