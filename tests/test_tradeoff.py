"""The speed-accuracy study (bearing_envelope.study.tradeoff) on a tiny setting: draft base, one
defect case and one healthy case, one revolution, two knobs."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from bearing_envelope.physics.fidelity import fidelity_from

from bearing_envelope.study.tradeoff import (COLUMNS, pareto_front, pareto_points, pareto_table,
                                       plot_tradeoff, study_from_config, tradeoff_study)

KNOBS = {"local_dx_um": [20.0, 10.0, 5.0], "tol": [1e-4, 1e-5]}


@pytest.fixture(scope="module")
def study():
    return tradeoff_study([(750.0, 100.0), (250.0, 0.0)], knobs=KNOBS, base="draft",
                          element_series=(), revolutions=1.0)


def test_tidy_columns_and_rows(study):
    df = study
    assert list(df.columns) == COLUMNS
    assert set(df["case"]) == {"F750kN_h100um", "F250kN_h0um"}
    assert set(df["knob"]) == {"reference", "local_dx_um", "tol"}
    metrics = set(df["metric"])
    assert metrics == {"peak_pressure", "p_max_rms", "raw_bpfi_1", "envelope_bpfi_1", "envelope_bpfi_2"}
    env = df[df["metric"] == "envelope_bpfi_1"]
    assert set(env["band"]) == {"kurtogram", "fs4_3fs8", "bpfi_3_6", "bpfi_10_13", "fixed"}
    # one row per case x knob x value x metric x band
    assert not df.duplicated(["case", "knob", "value", "metric", "band"]).any()
    assert (df["cpu_s"] > 0).all() and (df["n_solves"] >= 1).all()
    assert np.isfinite(df["estimate"]).all()
    # the base point is marked under every knob, with the same numbers
    base = df[df["is_base"] & (df["metric"] == "peak_pressure")]
    assert set(base["knob"]) == {"local_dx_um", "tol"}
    assert base.groupby("case")["estimate"].nunique().eq(1).all()
    # no defect signature in a healthy case: BPFI errors are undefined there
    healthy = df[(df["depth_um"] == 0) & df["metric"].str.contains("bpfi")]
    assert healthy["error"].isna().all()


def test_reference_is_the_finest_setting_and_errors_are_relative_to_it(study):
    """The reference run is the draft preset with every knob at its finest listed value (read
    here from KNOBS and the preset), and every error is ``|estimate - reference| / |reference|``
    with the reference row's estimate of the same case, metric and band (p_max_rms: the rms of
    the difference of the histories, not in the table; it vanishes where the variant is the
    reference setting)."""
    ref = study[study["is_reference"]]
    assert set(ref["knob"]) == {"reference"} and len(ref)
    expected = {k: v for k, v in fidelity_from("draft").to_dict().items() if k != "name"}
    expected.update({k: vals[-1] for k, vals in KNOBS.items()})
    assert {json.dumps(expected, sort_keys=True)} == set(ref["fidelity"])
    keys = ["case", "metric", "band"]
    rows = study[~study["is_reference"]].merge(
        ref[keys + ["estimate"]].rename(columns={"estimate": "ref_estimate"}), on=keys,
        how="left", validate="many_to_one")
    assert rows["ref_estimate"].notna().all()
    assert (rows["reference_value"] == rows["ref_estimate"]).all()
    relative = rows[rows["metric"] != "p_max_rms"]
    signature = (relative["depth_um"] > 0) | (relative["metric"] == "peak_pressure")
    by_hand = (relative["estimate"] - relative["ref_estimate"]).abs() / relative["ref_estimate"].abs()
    np.testing.assert_allclose(relative["error"][signature], by_hand[signature], rtol=1e-12, atol=0)
    assert relative["error"][~signature].isna().all()  # no defect signature in a healthy case
    # local_dx_um = 5 at the draft's tol = 1e-5 is the reference setting: no error at all
    same = rows[(rows["knob"] == "local_dx_um") & (rows["value"] == "5")]
    assert expected["tol"] == fidelity_from("draft").tol and len(same)
    assert (same["estimate"] == same["ref_estimate"]).all()
    assert (same["error"].dropna() == 0.0).all() and (same["metric"] == "p_max_rms").any()
    # error_knob: against the finest value of the same knob (local_dx_um = 5), by hand
    knob = rows[(rows["knob"] == "local_dx_um") & (rows["metric"] != "p_max_rms")
                & ((rows["depth_um"] > 0) | (rows["metric"] == "peak_pressure"))]
    fine = knob[knob["value"] == "5"].set_index(keys)["estimate"]
    fine_of = fine.reindex(pd.MultiIndex.from_frame(knob[keys])).to_numpy()
    np.testing.assert_allclose(knob["error_knob"], np.abs(knob["estimate"] - fine_of) / np.abs(fine_of),
                               rtol=1e-12, atol=0)


def test_errors_shrink_as_the_grid_is_refined(study):
    d = study[(study["knob"] == "local_dx_um") & (study["case"] == "F750kN_h100um")]
    for metric in ("p_max_rms", "raw_bpfi_1"):
        e = d[d["metric"] == metric].set_index("value")["error"]
        assert e["20"] >= e["10"] > e["5"] == 0.0, (metric, e.to_dict())
    # and the finer grid costs more
    t = d[d["metric"] == "peak_pressure"].set_index("value")["n_iterations"]
    assert t["5"] > t["20"]


def test_pareto_front_is_non_dominated(study):
    pts = pareto_points(study)
    for (metric, band), g in pts.groupby(["metric", "band"]):
        front = g[g["pareto"]]
        assert len(front) >= 1
        for _, p in front.iterrows():
            dominated = ((g["time_s"] <= p["time_s"]) & (g["error"] <= p["error"])
                         & ((g["time_s"] < p["time_s"]) | (g["error"] < p["error"])))
            assert not dominated.any(), (metric, band, p.to_dict())
        # every point off the front is dominated by a point on it
        for _, p in g[~g["pareto"] & g["error"].notna()].iterrows():
            assert ((front["time_s"] <= p["time_s"]) & (front["error"] <= p["error"])).any()
    pt = pareto_table(study, "peak_pressure")
    assert pt["is_reference"].sum() == 1 and (pt["knob"] == "base").sum() == 1


def test_pareto_front_unit():
    t = np.array([1.0, 2.0, 3.0, 2.5, 0.5, 4.0])
    e = np.array([0.5, 0.2, 0.1, 0.3, np.nan, 0.1])
    assert pareto_front(t, e).tolist() == [True, True, True, False, False, False]


def test_plot(study, tmp_path):
    fig = plot_tradeoff(study, tmp_path / "t.png")
    assert (tmp_path / "t.png").stat().st_size > 10_000
    assert len([a for a in fig.axes if a.get_visible()]) == 2 + 1 + 2 * 5


def test_config_errors():
    with pytest.raises(ValueError, match="unknown key"):
        study_from_config({"knbos": {}})
    with pytest.raises(ValueError, match="unknown knob"):
        tradeoff_study([(250.0, 0.0)], knobs={"grid": [1.0]}, base="draft", element_series=())
    with pytest.raises(ValueError, match="revolutions"):
        tradeoff_study([(250.0, 0.0)], knobs=KNOBS, revolutions=0)


def test_element_series_and_presets_on_a_healthy_case():
    df = tradeoff_study([(250.0, 0.0)], knobs={"local_dx_um": [20.0, 10.0], "element": ["uniform", "linear"]},
                        base="draft", element_series=("local_dx_um",), presets={"draft": "draft"},
                        revolutions=1.0, reference="per_knob")
    assert {"local_dx_um[linear]", "preset"} <= set(df["knob"])
    assert set(df[df["knob"] == "local_dx_um[linear]"]["element"]) == {"linear"}
    assert not df["is_reference"].any()
    assert isinstance(df, pd.DataFrame)


def test_the_section_is_checked_once_by_the_loader_and_never_by_the_study(monkeypatch):
    """The loader types the section (``Settings.tradeoff``) and refuses a bad one in one line
    naming the key; ``study_from_config`` runs the typed section without checking it again."""
    from bearing_envelope.study.config_read import ConfigError
    from bearing_envelope.study.settings import settings_from_mapping
    from bearing_envelope.study.tradeoff import TradeoffSettings

    sweep = {"sweep": {"loads_kN": [250], "depths_um": [0]}}
    with pytest.raises(ConfigError, match=r"^<mapping>: tradeoff\.knobs: unknown knob 'warp'"):
        settings_from_mapping({**sweep, "tradeoff": {"knobs": {"warp": [1.0]}}})
    with pytest.raises(ConfigError, match=r"^<mapping>: tradeoff\.knobs\.tol: -1\.0: "):
        settings_from_mapping({**sweep, "tradeoff": {"knobs": {"tol": [-1.0]}}})
    with pytest.raises(ConfigError, match=r"tradeoff\.element_series: 'tol' is not one of"):
        settings_from_mapping({**sweep, "tradeoff": {"knobs": {"n_loads": [3]},
                                                     "element_series": ["tol"]}})
    section = {"cases": [[250, 0]], "revolutions": 1, "base": "draft", "reference": "per_knob",
               "element_series": [], "presets": [], "knobs": {"tol": [1e-4]}}
    typed = settings_from_mapping({**sweep, "tradeoff": section}).tradeoff
    assert isinstance(typed, TradeoffSettings) and typed.section == section

    def refuse(*a, **k):
        raise AssertionError("the study checked its section again")

    monkeypatch.setattr(TradeoffSettings, "from_mapping", refuse)
    df = study_from_config(typed)
    assert set(df["knob"]) == {"tol"} and set(df["case"]) == {"F250kN_h0um"}
