"""Fault locations as a sweep axis (issue 23 part 5): case names, the sweep's settings, the
family each location's analysis searches (lines known by construction), the tables' location
column, and the BPFI override kept to the study's bearing. Independent answers: the CWRU
Bearing Data Center's published multipliers, synthetic envelopes whose lines are set by
construction, names written by hand."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from bearing_envelope.io.vocabulary import quantity_name
from bearing_envelope.physics.locations import LOCATION_FAMILIES, event_frequencies
from bearing_envelope.physics.scene import Scene
from bearing_envelope.study.pipeline import case_bands, case_fault_lines, case_harmonics
from bearing_envelope.study.case_id import CaseId
from bearing_envelope.study.config_read import ConfigError, read_configs
from bearing_envelope.study.sections import AnalysisSettings, SweepSettings
from bearing_envelope.study.settings import settings_from_mapping
from bearing_envelope.study.figures import fig_diagnosability_maps, fig_harmonics_vs_depth
from bearing_envelope.study.tables import add_location, concat_tidy, pivot_tables

#: CWRU Bearing Data Center, drive-end bearing SKF 6205-2RS, multipliers of the shaft rate.
CWRU_PUBLISHED = {"bpfi": 5.4152, "bpfo": 3.5848, "ftf": 0.39828, "bsf": 2.3568}
#: 6205 geometry (CWRU): 9 balls, d = 0.3126 in, D = 1.537 in, contact angle 0.
CWRU_GEOMETRY = {"rollers_per_row": 9, "roller_diameter_mm": 7.94004,
                 "pitch_diameter_mm": 39.0398, "contact_angle_deg": 0.0}
FR_HZ = 29.95          # 1797 rpm
FS_HZ = 12000.0        # the CWRU development records' rate
CARRIER_HZ = 3000.0    # resonance the synthetic envelopes modulate
N_SAMPLES = 2 ** 17    # 10.9 s: 0.09 Hz bins, FTF sidebands resolved


def test_case_names_carry_the_location_only_when_set_and_parse_back():
    assert CaseId(500, 50).name == "F500kN_h50um"
    assert CaseId(1, 279.4, 177.8, "outer_race").name == "F1kN_h279.4um_w177.8um_or"
    assert CaseId(1, 0, None, "rolling_element").name == "F1kN_h0um_re"
    assert CaseId(250, 15, None, "inner_race").name == "F250kN_h15um_ir"
    for c in (CaseId(500, 50), CaseId(1, 279.4, 177.8, "outer_race"),
              CaseId(1, 0, None, "rolling_element"), CaseId(2.5, 3, None, "inner_race")):
        assert CaseId.parse(c.name) == c
    assert CaseId(1, 279.4, 177.8, "outer_race").healthy.name == "F1kN_h0um_or"
    with pytest.raises(ValueError, match="CaseId.location: got 'cage'; allowed"):
        CaseId(1, 0, None, "cage")
    with pytest.raises(ValueError, match="does not match"):
        CaseId.parse("F1kN_h0um_xx")


def test_sweep_locations_repeat_every_case_and_bad_values_name_the_field():
    s = SweepSettings.from_mapping({"loads_kN": [1], "depths_um": [0, 10],
                                    "locations": ["outer_race", "inner_race"]})
    assert [c.name for c in s.cases()] == ["F1kN_h0um_or", "F1kN_h10um_or", "F1kN_h0um_ir",
                                           "F1kN_h10um_ir"]
    assert [c.name for c in SweepSettings.from_mapping(
        {"loads_kN": [1], "depths_um": [0, 10]}).cases()] == ["F1kN_h0um", "F1kN_h10um"]
    with pytest.raises(ConfigError, match=r"^sweep.locations\[1\]: got 'cage'; allowed: one of"):
        SweepSettings.from_mapping({"loads_kN": [1], "depths_um": [0],
                                    "locations": ["inner_race", "cage"]})
    with pytest.raises(ConfigError, match=r"sweep.locations\[1\]: 'inner_race' repeats"):
        SweepSettings.from_mapping({"loads_kN": [1], "depths_um": [0],
                                    "locations": ["inner_race", "inner_race"]})


def _cwru_config(**defect):
    cfg = read_configs(["config.yaml", "config_cwru.yaml"])
    cfg.pop("tradeoff", None)
    cfg["scene"]["defect"].update(defect)
    return cfg


def test_scene_location_other_than_inner_race_is_in_the_names_and_given_in_one_place():
    s = settings_from_mapping(_cwru_config(location="outer_race"))
    assert [c.name for c in s.cases] == ["F1kN_h0um_or", "F1kN_h279.4um_w177.8um_or"]
    cfg = _cwru_config(location="outer_race")
    cfg["sweep"]["locations"] = ["inner_race"]
    with pytest.raises(ConfigError, match="sweep.locations: got \\['inner_race'\\]; allowed: null "
                                          "while scene.defect.location is 'outer_race'"):
        settings_from_mapping(cfg)
    cfg = _cwru_config()
    cfg["sweep"]["locations"] = ["inner_race", "outer_race", "rolling_element"]
    s = settings_from_mapping(cfg)
    assert [c.name for c in s.cases][::2] == ["F1kN_h0um_ir", "F1kN_h0um_or", "F1kN_h0um_re"]
    assert s.scene(s.cases[3]).defect.location == "outer_race"


def test_bpfi_override_is_refused_on_another_bearing_in_one_line():
    m = {"bearing": {"designation": "SKF 6205-2RS"}, "operation": {"bpfi_override_hz": 231.9,
                                                                  "shaft_rate_hz": 29.95}}
    with pytest.raises(ValueError) as e:
        Scene.from_mapping(m, load_kN=1.0, depth_um=0.0)
    msg = str(e.value)
    assert msg.startswith("scene.operation.bpfi_override_hz: got 231.9; allowed: null for "
                          "bearing.designation 'SKF 6205-2RS'") and "\n" not in msg
    # without the key the catalogue bearing is geometric; the study's keeps its override
    sc = Scene.from_mapping({"bearing": {"designation": "SKF 6205-2RS"},
                             "operation": {"shaft_rate_hz": 29.95}}, load_kN=1.0, depth_um=0.0)
    assert sc.operation.bpfi_override_hz is None
    fag = Scene.from_mapping({"bearing": {"designation": "FAG 534176"}}, load_kN=500, depth_um=0)
    assert fag.bpfi_hz == 231.9 and Scene.default().bpfi_hz == 231.9


def test_event_frequencies_are_the_published_cwru_multipliers():
    g = CWRU_GEOMETRY
    # without an override BPFI is Z (fr - FTF); start from the published FTF's BPFI
    bpfi = g["rollers_per_row"] * (1.0 - 0.5 * (1 - g["roller_diameter_mm"]
                                                 / g["pitch_diameter_mm"]))
    ev = event_frequencies(1.0, bpfi, g["rollers_per_row"], g["roller_diameter_mm"],
                           g["pitch_diameter_mm"], g["contact_angle_deg"])
    for key, published in CWRU_PUBLISHED.items():
        assert ev[key] == pytest.approx(published, rel=2e-4), key
    assert ev["bsf2"] == pytest.approx(2 * CWRU_PUBLISHED["bsf"], rel=2e-4)
    assert quantity_name("envelope_spectrum", "bsf2") == "envelope_2bsf"
    assert quantity_name("envelope_spectrum", "bpfo") == "envelope_bpfo"


def _synthetic_case(location: str, lines_hz, modulation_hz: float | None):
    """A case whose envelope is 1 + sum_k a_k cos(2 pi k f t), times (1 + 0.5 cos(2 pi f_m t))
    when ``modulation_hz`` is given, on a 3 kHz carrier: envelope lines at k f and, with the
    modulation, k f +- f_m (by construction)."""
    t = np.arange(N_SAMPLES) / FS_HZ
    env = 1.0 + sum(a * np.cos(2 * np.pi * k * lines_hz * t) for k, a in ((1, 0.3), (2, 0.2),
                                                                           (3, 0.1)))
    if modulation_hz is not None:
        env = env * (1.0 + 0.5 * np.cos(2 * np.pi * modulation_hz * t))
    x = env * np.cos(2 * np.pi * CARRIER_HZ * t)
    m = read_configs(["config.yaml", "config_cwru.yaml"])["scene"]
    m["defect"]["location"] = location
    sc = Scene.from_mapping(m, load_kN=1.0, depth_um=0.0)
    ff = sc.frequencies()
    return SimpleNamespace(signals={"p_max": x}, fs=FS_HZ, fr=FR_HZ, bpfi=sc.bpfi_hz,
                           bpfo=ff.bpfo, ftf=ff.ftf, bsf=ff.bsf, load_kN=1.0, depth_um=10.0,
                           scene=sc.to_mapping(), attrs={"case": CaseId(1, 10, None, location).name})


def _analysis(case) -> AnalysisSettings:
    return AnalysisSettings.from_mapping(
        {"bands": [{"name": "fixed", "strategy": "fixed", "low_hz": 2000.0, "high_hz": 4000.0},
                   {"name": "bpfi_3_6", "strategy": "orders", "low": 3, "high": 6,
                    "base": "bpfi"}],
         "harmonics": 3, "sidebands": 2, "nlevel": 4},
        fs=FS_HZ, freqs={"fr": FR_HZ, "bpfi": case.bpfi, "bpfo": case.bpfo, "ftf": case.ftf,
                         "bsf": case.bsf}, has_sensor=False)


@pytest.mark.parametrize("location, modulated", [("outer_race", False), ("rolling_element", True)])
def test_each_location_searches_its_family_from_the_scene(location, modulated):
    probe = _synthetic_case(location, 1.0, None)
    family, spacing = LOCATION_FAMILIES[location]
    lines, sb = case_fault_lines(probe)
    f_line, (sb_name, f_sb) = lines[family], sb[family]
    assert sb_name == spacing
    case = _synthetic_case(location, f_line, f_sb if modulated else None)
    analysis = _analysis(case)
    bands, _ = case_bands(case, analysis)
    # the orders band keeps its configured base: 3-6 x BPFI whatever the location
    b36 = next(b for b in bands.bands if b.name == "bpfi_3_6")
    assert (b36.low_hz, b36.high_hz) == pytest.approx((3 * case.bpfi, 6 * case.bpfi))
    df = case_harmonics(case, analysis, bands)
    env = df[(df["band"] == "fixed") & df["quantity"].str.startswith("envelope_")]
    assert set(env["quantity"]) == {quantity_name("envelope_spectrum", family)}
    df_hz = FS_HZ / N_SAMPLES
    for k in (1, 2, 3):
        r = env[(env["order"] == k) & (env["sideband"] == 0)].iloc[0]
        assert abs(r["frequency_hz"] - k * f_line) <= 1.5 * df_hz and bool(r["detected"])
        for m in (-1, 1):
            s = env[(env["order"] == k) & (env["sideband"] == m)].iloc[0]
            if modulated:   # 2 x BSF +- FTF, by construction
                assert abs(s["frequency_hz"] - (k * f_line + m * f_sb)) <= 1.5 * df_hz
                assert bool(s["detected"])
            else:           # BPFO: the fr sidebands are a check, none is there
                assert not bool(s["detected"])


def test_inner_race_analysis_is_todays_bpfi_search():
    case = _synthetic_case("inner_race", 1.0, None)
    case.attrs = {"case": "F1kN_h10um"}
    lines, sb = case_fault_lines(case)
    assert lines == {"bpfi": case.bpfi} and sb is None


def test_tables_get_a_location_column_and_one_pivot_per_location():
    def frame(name, quantity):
        c = CaseId.parse(name)
        return pd.DataFrame([{"case": name, "load_kN": c.load_kN, "depth_um": c.depth_um,
                              "band": "fixed", "band_strategy": "fixed", "band_low_hz": 1.0,
                              "band_high_hz": 2.0, "quantity": quantity, "order": 1,
                              "sideband": 0, "frequency_hz": 1.0, "amplitude": c.depth_um + 1}])

    plain_cases = [CaseId(1, 0), CaseId(1, 5)]
    plain = concat_tidy([frame("F1kN_h0um", "envelope_bpfi"), frame("F1kN_h5um", "envelope_bpfi")],
                        plain_cases)
    assert "location" not in plain.columns and add_location(plain, plain_cases) is plain
    cases = SweepSettings(loads_kN=(1.0,), depths_um=(0.0, 5.0),
                          locations=("outer_race", "rolling_element")).cases()
    tidy = concat_tidy([frame("F1kN_h5um_re", "envelope_2bsf"), frame("F1kN_h0um_or", "envelope_bpfo"),
                        frame("F1kN_h5um_or", "envelope_bpfo"), frame("F1kN_h0um_re", "envelope_2bsf")],
                       cases)
    assert list(tidy.columns[:4]) == ["case", "load_kN", "depth_um", "location"]
    assert list(tidy["case"]) == ["F1kN_h0um_or", "F1kN_h5um_or", "F1kN_h0um_re", "F1kN_h5um_re"]
    piv = pivot_tables(tidy)
    assert set(piv) == {"fixed__envelope_bpfo__1__outer_race",
                        "fixed__envelope_2bsf__1__rolling_element"}
    assert piv["fixed__envelope_bpfo__1__outer_race"].loc[1.0].tolist() == [1.0, 6.0]


def test_figures_and_detection_maps_carry_the_location(tmp_path):
    rows, cells, cases = [], [], []
    for loc, q in (("outer_race", "envelope_bpfo"), ("rolling_element", "envelope_2bsf")):
        for depth in (0.0, 10.0):
            cases.append(CaseId(1.0, depth, None, loc))
            name = cases[-1].name
            for k in (1, 2):
                rows.append({"case": name, "load_kN": 1.0, "depth_um": depth, "band": "fixed",
                             "band_strategy": "fixed", "band_low_hz": 1.0, "band_high_hz": 2.0,
                             "quantity": q, "order": k, "sideband": 0, "frequency_hz": 1.0,
                             "amplitude": 1e6 * (depth + k)})
            for snr in (0.0, 10.0):
                cells.append({"case": name, "load_kN": 1.0, "depth_um": depth, "snr_db": snr,
                              "band": "fixed", "statistic_db": snr + depth, "detected": depth > 0})
    tidy = concat_tidy([pd.DataFrame(rows)], cases)
    fig_harmonics_vs_depth(tidy, "fixed", tmp_path / "h.png")
    assert (tmp_path / "h.png").stat().st_size > 0
    out = fig_diagnosability_maps(add_location(pd.DataFrame(cells), cases), tmp_path / "maps")
    assert sorted(p.name for p in out) == ["diagnosability_fixed_outer_race.png",
                                           "diagnosability_fixed_rolling_element.png"]
