"""Unit tests of bearing_envelope.study.pipeline on in-memory cases whose answer is known by
construction (issue 15 part 5): an amplitude-modulated carrier with every line on an FFT bin,
an impulsive burst train for the kurtogram band, the signal selection and its errors."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from bearing_envelope.io import CaseBands
from bearing_envelope.study.pipeline import (case_bands, case_frequencies, case_harmonics, case_signal,
                                       case_summary)
from bearing_envelope.io.vocabulary import TIDY_COLUMNS
from bearing_envelope.study.pipeline import case_frequencies
from bearing_envelope.study.sections import AnalysisSettings

# fs / BPFI = 256 and fs / fr = 4096 samples: k x BPFI + m x fr lie on bins of a record of
# 16 BPFI periods x 16 (65,536 samples), so the envelope lines carry no scalloping loss
FS = 64000.0
BPFI = 250.0
FR = 15.625
N = 65536
A, M, FC = 2.0e9, 0.25, 12000.0      # carrier amplitude (Pa), modulation depth, carrier (Hz)


def typed(analysis, case):
    """The pipeline takes typed settings: build them for this (synthetic) case."""
    return AnalysisSettings.from_mapping(analysis, fs=float(case.fs), freqs=case_frequencies(case),
                                         has_sensor=True)


def am_case(x=None, *, load=500.0, depth=50.0, **signals):
    t = np.arange(N) / FS
    if x is None:
        x = A * (1.0 + M * np.cos(2 * np.pi * BPFI * t)) * np.cos(2 * np.pi * FC * t) + 3.0e9
    sig = {"p_max": x, "p_max_defect": 0.5 * x, **signals}
    return SimpleNamespace(signals=sig, fs=FS, fr=FR, bpfi=BPFI, bpfo=150.0, ftf=7.0, bsf=60.0,
                           load_kN=load, depth_um=depth, attrs={})


FIXED = {"name": "fixed", "strategy": "fixed", "low_hz": 8000.0, "high_hz": 16000.0}
ANALYSIS = {"signal": "p_max", "nlevel": 6, "filter_order": 4, "harmonics": 2, "sidebands": 1,
            "raw_orders_fr": 1, "bands": [FIXED]}


def _row(df, quantity, band, order=1, sideband=0):
    r = df[(df["quantity"] == quantity) & (df["band"] == band) & (df["order"] == order)
           & (df["sideband"] == sideband)]
    assert len(r) == 1, (quantity, band, order, sideband, len(r))
    return r.iloc[0]


def test_am_carrier_envelope_line_is_a_times_m():
    case = am_case()
    bands, kg = case_bands(case, typed(ANALYSIS, case))
    assert kg is None and bands.kurtogram is None       # no band asks for the kurtogram
    assert isinstance(bands, CaseBands) and bands.case == "F500kN_h50um"
    b = bands.band("fixed")
    assert (b.low_hz, b.high_hz, b.strategy, b.clamped) == (8000.0, 16000.0, "fixed", False)
    df = case_harmonics(case, typed(ANALYSIS, case), bands)
    assert list(df.columns[:len(TIDY_COLUMNS)]) == TIDY_COLUMNS
    env = _row(df, "envelope_bpfi", "fixed")
    assert env["frequency_hz"] == pytest.approx(BPFI)
    assert env["amplitude"] == pytest.approx(A * M, rel=1e-3)         # docs/signal.md scaling
    # no second harmonic and no fr sidebands in this envelope
    assert _row(df, "envelope_bpfi", "fixed", order=2)["amplitude"] < 1e-3 * A * M
    assert _row(df, "envelope_bpfi", "fixed", sideband=1)["amplitude"] < 1e-3 * A * M
    # raw spectrum: the mean, and nothing at fr or BPFI (the carrier sits at 12 kHz)
    assert _row(df, "raw_dc", "raw", order=0)["amplitude"] == pytest.approx(3.0e9, rel=1e-9)
    assert _row(df, "raw_fr", "raw")["amplitude"] < 1e-6 * A
    # band-passed peak: the carrier's peak A (1 + m), in the middle of a flat pass band
    assert _row(df, "bandpass_peak", "fixed", order=0)["amplitude"] == pytest.approx(A * (1 + M),
                                                                                     rel=0.01)
    assert set(df["signal"]) == {"p_max"} and set(df["case"]) == {"F500kN_h50um"}
    assert (df.loc[df["band"] == "fixed", "band_strategy"] == "fixed").all()


def test_the_selected_signal_is_the_one_analysed():
    case = am_case()
    an = dict(ANALYSIS, signal="p_max_defect")
    bands, _ = case_bands(case, typed(an, case))
    assert bands.signal == "p_max_defect"
    env = _row(case_harmonics(case, typed(an, case), bands), "envelope_bpfi", "fixed")
    assert env["amplitude"] == pytest.approx(0.5 * A * M, rel=1e-3)


def test_kurtogram_band_contains_the_resonance_of_an_impulse_train():
    # decaying 20 kHz bursts (0.5 ms) at every BPFI period in white noise: the kurtogram's best
    # cell must contain 20 kHz, and the envelope in that band shows BPFI
    rng = np.random.default_rng(1)
    t = np.arange(N) / FS
    x = 0.2 * rng.standard_normal(N)
    tau = (t % (1.0 / BPFI))
    x += np.exp(-tau / 5e-4) * np.sin(2 * np.pi * 20000.0 * tau)
    case = am_case(x)
    an = dict(ANALYSIS, bands=[{"name": "kg", "strategy": "kurtogram"}])
    bands, kg = case_bands(case, typed(an, case))
    b = bands.band("kg")
    assert b.strategy == "kurtogram" and b.low_hz < 20000.0 < b.high_hz
    assert bands.kurtogram["kurtosis"] == pytest.approx(kg.kurtosis)
    df = case_harmonics(case, typed(an, case), bands)
    env = _row(df, "envelope_bpfi", "kg")
    noise = _row(df, "envelope_bpfi", "kg", sideband=1)["amplitude"]
    assert env["amplitude"] > 20 * noise       # the line stands out of its neighbourhood
    kk = df[df["quantity"] == "kurtogram_kurtosis"]
    assert len(kk) == 1 and kk["amplitude"].iloc[0] == pytest.approx(kg.kurtosis)


def test_band_above_nyquist_is_refused_and_clamped_on_request():
    case = am_case()
    high = {"name": "hi", "strategy": "fixed", "low_hz": 30000.0, "high_hz": 40000.0}
    with pytest.raises(ValueError, match="Nyquist"):
        case_bands(case, typed(dict(ANALYSIS, bands=[high]), case))
    bands, _ = case_bands(case, typed(dict(ANALYSIS, bands=[dict(high, clamp=True)]), case))
    b = bands.band("hi")
    assert b.clamped and b.high_hz < FS / 2 and b.low_hz == 30000.0


def test_signal_selection_and_its_errors():
    rf = np.linspace(0.0, 1.0, N)
    case = am_case(removed_force=rf)
    np.testing.assert_array_equal(case_signal(case, "removed_force"), rf)
    with pytest.raises(ValueError, match=r"analysis.signal = 'approach'.*removed_force"):
        case_signal(case, "approach")
    bad = am_case(np.full(N, np.nan))
    with pytest.raises(ValueError, match="non-finite"):
        case_signal(bad, "p_max")
    assert case_frequencies(case) == {"fr": FR, "bpfi": BPFI, "bpfo": 150.0, "ftf": 7.0,
                                      "bsf": 60.0}


def test_case_summary_row():
    x = np.linspace(1.0e9, 4.0e9, N)
    case = am_case(x)
    case.p_max, case.p_max_defect = x, 0.5 * x
    case.roller_load = np.full(N, 7.5e4)
    case.bpfi_geometry = 194.2
    case.table = {"attrs": {"interp_max_rel_error_p_max": 0.01}}
    # as an io.Case holds them: each *_json attribute also as its value
    case.attrs = {"stats_json": '{"n_solves": 12, "wall_seconds": 3.5}',
                  "stats": {"n_solves": 12, "wall_seconds": 3.5}, "git_commit": "abc"}
    row = case_summary(case)
    assert row["p_max_peak_Pa"] == 4.0e9 and row["p_max_mean_Pa"] == pytest.approx(2.5e9)
    assert row["p_max_defect_peak_Pa"] == 2.0e9 and row["roller_load_max_N"] == 7.5e4
    assert (row["n_solves"], row["simulate_wall_s"], row["git_commit"]) == (12, 3.5, "abc")
    assert row["interp_max_rel_error_p_max"] == 0.01 and row["n_samples"] == N
