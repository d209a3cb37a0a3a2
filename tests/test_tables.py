"""Unit tests of bearing_envelope.study.tables (issue 15 part 5): the tidy vocabulary conversion, the
aggregation's checks and order, the band table and the load x depth pivots, on small frames
whose content is known by construction."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from bearing_envelope.io import BandLimits, CaseBands
from bearing_envelope.diagnosis import AnalysisOptions, analyze_signal
from bearing_envelope.study.tables import band_table, concat_tidy, pivot_tables, tidy_from_analysis
from bearing_envelope.io.vocabulary import BAND_STRATEGIES, TIDY_COLUMNS, TIDY_SORT


def tidy_frame(load, depth, bands=("fixed", "bpfi_10_13")):
    """Per-case tidy rows whose amplitude encodes (load, depth, band, order): 1000 load + depth
    + 0.1 order (+ 0.01 for the second band)."""
    rows = []
    for ib, band in enumerate(bands):
        for order in (1, 2):
            for sb in (-1, 0, 1):
                rows.append({"case": f"F{load:g}kN_h{depth:g}um", "load_kN": load,
                             "depth_um": depth, "band": band, "band_strategy": "fixed",
                             "band_low_hz": 100.0, "band_high_hz": 200.0,
                             "quantity": "envelope_bpfi", "order": order, "sideband": sb,
                             "frequency_hz": order * 231.9 + sb * 15.8,
                             "amplitude": 1000 * load + depth + 0.1 * order + 0.01 * ib + sb})
    return pd.DataFrame(rows)


def test_concat_tidy_orders_rows_deterministically_whatever_the_input_order():
    frames = [tidy_frame(l, d) for l in (750.0, 250.0) for d in (50.0, 0.0)]
    a = concat_tidy(frames)
    b = concat_tidy(frames[::-1])
    pd.testing.assert_frame_equal(a, b)
    assert list(a.columns) == TIDY_COLUMNS
    assert len(a) == 4 * 2 * 2 * 3
    keys = a[TIDY_SORT].to_records(index=False).tolist()
    assert keys == sorted(keys)


def test_concat_tidy_refuses_missing_columns_and_non_finite_amplitudes():
    f = tidy_frame(250.0, 0.0)
    with pytest.raises(ValueError, match=r"lacks columns \['band_strategy'\]"):
        concat_tidy([f.drop(columns=["band_strategy"])])
    g = f.copy()
    g.loc[3, "amplitude"] = np.nan
    with pytest.raises(ValueError, match="non-finite amplitudes in 1 rows"):
        concat_tidy([f, g])
    with pytest.raises(ValueError, match="no per-case tables"):
        concat_tidy([])


def test_pivots_put_each_amplitude_in_its_load_depth_cell():
    tidy = concat_tidy([tidy_frame(l, d) for l in (250.0, 500.0, 750.0) for d in (0.0, 15.0, 50.0)])
    piv = pivot_tables(tidy)
    assert set(piv) == {f"{b}__envelope_bpfi__{o}" for b in ("fixed", "bpfi_10_13") for o in (1, 2)}
    p = piv["bpfi_10_13__envelope_bpfi__2"]
    assert list(p.index) == [250.0, 500.0, 750.0] and list(p.columns) == [0.0, 15.0, 50.0]
    for load in p.index:
        for depth in p.columns:
            assert p.loc[load, depth] == pytest.approx(1000 * load + depth + 0.2 + 0.01)
    side = pivot_tables(tidy, sideband=-1)["fixed__envelope_bpfi__1"]
    assert side.loc[500.0, 15.0] == pytest.approx(500000 + 15 + 0.1 - 1)


def test_band_table_one_row_per_case_and_band():
    docs = [CaseBands(case=f"F{l:g}kN_h0um", load_kN=l, depth_um=0.0, fs=65000.0, signal="p_max",
                      bands=(BandLimits("kg", "kurtogram", 16250.0, 32000.0, True),
                             BandLimits("fixed", "fixed", 8125.0, 16250.0)))
            for l in (250.0, 750.0)]
    t = band_table(docs)
    assert list(t.columns) == ["case", "load_kN", "depth_um", "band", "strategy", "low_hz",
                               "high_hz", "clamped"]
    assert len(t) == 4
    r = t[(t["load_kN"] == 750.0) & (t["band"] == "kg")].iloc[0]
    assert (r["strategy"], r["high_hz"], bool(r["clamped"])) == ("kurtogram", 32000.0, True)


def test_tidy_from_analysis_speaks_the_tidy_vocabulary():
    fs = 8000.0
    t = np.arange(16000) / fs
    x = (1 + 0.5 * np.cos(2 * np.pi * 50.0 * t)) * np.cos(2 * np.pi * 2000.0 * t)
    raw = analyze_signal(
        x,
        fs,
        fr=10.0,
        bpfi=50.0,
        options=AnalysisOptions(
            n_harmonics=1,
            n_sidebands=1,
            n_raw_harmonics=1,
            nlevel=None,
            bands=[{"name": "mine", "strategy": "fraction", "low": 0.125, "high": 0.375}],
        ),
    )
    df = tidy_from_analysis(raw)
    assert set(df["band"]) == {"raw", "mine"}
    assert set(df["band_strategy"]) <= set(BAND_STRATEGIES)
    assert set(df.loc[df["band"] == "mine", "band_strategy"]) == {"fraction"}
    assert {"raw_dc", "raw_fr", "raw_bpfi", "envelope_bpfi", "bandpass_peak"} <= set(df["quantity"])
    # the sweep applies its bands as fixed limits: the strategy that chose them is passed in
    df2 = tidy_from_analysis(raw, {"mine": "kurtogram"})
    assert set(df2.loc[df2["band"] == "mine", "band_strategy"]) == {"kurtogram"}
    assert set(df2.loc[df2["band"] == "raw", "band_strategy"]) == {"raw"}
    pd.testing.assert_frame_equal(tidy_from_analysis(df), df)       # idempotent
    with pytest.raises(ValueError, match="band_strategy"):
        tidy_from_analysis(df.drop(columns=["band_strategy"]))
