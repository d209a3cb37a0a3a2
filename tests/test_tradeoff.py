"""The speed-accuracy study (bearing_envelope.study.tradeoff) on a tiny setting: draft base, one
defect case and one healthy case, one revolution, two knobs."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

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


def test_reference_row_has_zero_error(study):
    ref = study[study["is_reference"]]
    assert len(ref)
    assert (ref["estimate"] == ref["reference_value"]).all()
    defined = ref[ref["error"].notna()]
    assert (defined["error"] == 0.0).all()
    # the finest value of each knob is its own knob reference
    fine = study[(study["knob"] == "local_dx_um") & (study["value"] == "5")]
    assert (fine["error_knob"].dropna() == 0.0).all()


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
