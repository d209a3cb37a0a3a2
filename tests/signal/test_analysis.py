import numpy as np
import pandas as pd
import pytest

from bearing_envelope.physics.kinematics import fault_frequencies
from bearing_envelope.diagnosis import AnalysisOptions, COLUMNS, analyze_signal


def test_columns_and_whole_chain(fault):
    x, fs, fr, bpfi, fn = fault["x"], fault["fs"], fault["fr"], fault["bpfi"], fault["fn"]
    bands = [
        {"name": "kurtogram", "strategy": "kurtogram"},
        {"name": "fs4_3fs8", "strategy": "fraction", "low": 0.25, "high": 0.375},
        {"name": "bpfi_10_13", "strategy": "orders", "low": 10, "high": 13, "base": "bpfi"},
        {"name": "fixed", "strategy": "fixed", "low_hz": 5000.0, "high_hz": 7000.0},
    ]
    df, det = analyze_signal(
        x,
        fs,
        fr=fr,
        bpfi=bpfi,
        full_output=True,
        options=AnalysisOptions(bands=bands, n_harmonics=3, n_sidebands=2, n_raw_harmonics=1),
    )
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == COLUMNS
    for c in ["band", "band_strategy", "band_low_hz", "band_high_hz", "quantity", "order", "sideband",
              "frequency_hz", "amplitude"]:
        assert c in df.columns
    assert set(df.band) == {"raw", "kurtogram", "fs4_3fs8", "bpfi_10_13", "fixed"}
    env = df[df.quantity == "envelope_spectrum"]
    assert len(env) == 4 * 3 * 5
    kgrow = df[df.band == "kurtogram"].iloc[0]
    assert kgrow.band_low_hz <= fn <= kgrow.band_high_hz
    k1 = env[(env.band == "kurtogram") & (env.order == 1)]
    main = k1[k1.sideband == 0].amplitude.iloc[0]
    assert (k1[k1.sideband != 0].amplitude < main).all()
    # the fixed band around fn sees the same lines as the kurtogram band
    fx = env[(env.band == "fixed") & (env.order == 1) & (env.sideband == 0)]
    assert fx.amplitude.iloc[0] == pytest.approx(main, rel=0.5)
    raw = df[df.quantity == "raw_spectrum"].set_index("base")
    assert raw.loc["fr", "amplitude"] > 10 * raw.loc["bpfi", "amplitude"]  # the strong tone
    assert set(det["bands"]) == {"kurtogram", "fs4_3fs8", "bpfi_10_13", "fixed"}
    assert det["kurtogram"].nlevel == 8
    assert df.scaling.notna().all()


def test_am_amplitude_through_analyze():
    fs = 20000.0
    t = np.arange(2**16) / fs
    x = (1 + 0.5 * np.cos(2 * np.pi * 100.0 * t)) * np.cos(2 * np.pi * 6000.0 * t)
    df = analyze_signal(
        x,
        fs,
        fr=25.0,
        bpfi=100.0,
        options=AnalysisOptions(
            interpolate=True,
            bands=[{"name": "fixed", "strategy": "fixed", "low_hz": 4000, "high_hz": 8000}],
        ),
    )
    row = df[(df.quantity == "envelope_spectrum") & (df.order == 1) & (df.sideband == 0)]
    assert row.amplitude.iloc[0] == pytest.approx(0.5, rel=0.01)
    assert row.frequency_hz.iloc[0] == pytest.approx(100.0, abs=0.05)
    peak = df[df.quantity == "bandpass_peak"].amplitude.iloc[0]
    assert peak == pytest.approx(1.5, rel=0.01)


def test_fault_frequencies_object_and_defaults(fault):
    ff = fault_frequencies(fault["fr"], 9, 7.94, 39.04)
    df = analyze_signal(
        fault["x"][: 2**15],
        fault["fs"],
        fr=fault["fr"],
        fault_frequencies=ff,
        options=AnalysisOptions(n_harmonics=1, n_sidebands=0),
    )
    assert set(df.base.dropna()) >= {"dc", "fr", "bpfi", "bpfo", "ftf", "bsf"}
    assert list(df[df.quantity == "bandpass_peak"].band) == [
        "kurtogram", "fs4_3fs8", "bpfi_3_6", "bpfi_10_13"]


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"fr": 0.0, "bpfi": 100.0}, "fr must be"),
        ({"fr": 10.0}, "give bpfi or fault_frequencies"),
        ({"fr": 10.0, "bpfi": 100.0, "bands": [{"strategy": "fixed", "low_hz": 1, "high_hz": 2},
                                                {"strategy": "fixed", "low_hz": 3, "high_hz": 4}]},
         "duplicate band name"),
        ({"fr": 10.0, "bpfi": 100.0, "bands": [{"strategy": "fixed", "low_hz": 100,
                                                 "high_hz": 600}]}, "fixed band: high edge 600"),
    ],
)
def test_bad_arguments(kw, match):
    x = np.random.default_rng(0).standard_normal(4096)
    with pytest.raises(ValueError, match=match):
        bands = kw.pop("bands", None)
        analyze_signal(x, 1000.0, **kw, options=AnalysisOptions(bands=bands))


@pytest.mark.parametrize("kw, match", [
    ({"n_harmonics": 0}, r"AnalysisOptions.n_harmonics = 0: allowed an integer 1 \.\. 1000"),
    ({"pfa": 1.5}, r"AnalysisOptions.pfa = 1.5: allowed a number in \(0, 1\)"),
    ({"level0": "x"}, r"AnalysisOptions.level0 = 'x': allowed one of \('analytic', 'real'\)"),
    ({"kurtogram_min_orders": -1.0}, r"AnalysisOptions.kurtogram_min_orders = -1.0"),
    ({"bands": {"strategy": "fixed"}}, r"AnalysisOptions.bands = .*allowed a sequence"),
])
def test_bad_options(kw, match):
    with pytest.raises(ValueError, match=match):
        AnalysisOptions(**kw)


def test_nan_input_rejected():
    x = np.random.default_rng(0).standard_normal(4096)
    x[7] = np.nan
    with pytest.raises(ValueError, match="x holds 1 non-finite"):
        analyze_signal(x, 1000.0, fr=10.0, bpfi=50.0)
