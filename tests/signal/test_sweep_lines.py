"""The simulated sweep's tables after the +-1 % search (issue 14): simulated lines sit exactly at
k x BPFI +- m x fr, so every line built into a synthetic case must be read at the bin nearest
its frequency with the amplitude a Hann-windowed bin reads there; the answers are known by
construction (the amplitudes put into the signal) and the closed-form Hann response, not
recomputed with the search under test."""

import types

import numpy as np
import pytest

from bearing_envelope.study.pipeline import case_bands, case_harmonics
from bearing_envelope.study.pipeline import case_frequencies
from bearing_envelope.study.sections import AnalysisSettings

FS, FR, BPFI, N = 65000.0, 15.8, 231.9, 2**18


def typed(analysis, case):
    """The pipeline takes typed settings: build them for this (synthetic) case."""
    return AnalysisSettings.from_mapping(analysis, fs=float(case.fs), freqs=case_frequencies(case),
                                         has_sensor=True)


@pytest.fixture(scope="module")
def case():
    t = np.arange(N) / FS
    env = (1 + 0.3 * np.cos(2 * np.pi * BPFI * t) + 0.1 * np.cos(2 * np.pi * 2 * BPFI * t)
           + 0.05 * np.cos(2 * np.pi * (BPFI - FR) * t) + 0.04 * np.cos(2 * np.pi * (BPFI + FR) * t)
           + 0.02 * np.cos(2 * np.pi * (2 * BPFI + 2 * FR) * t))
    p = 1e9 + 1e8 * (0.2 * np.cos(2 * np.pi * FR * t) + 0.1 * np.cos(2 * np.pi * BPFI * t)
                     + env * np.cos(2 * np.pi * 20000.0 * t))
    p += 1e6 * np.random.default_rng(0).standard_normal(N)  # a noise floor for the statistic
    return types.SimpleNamespace(signals={"p_max": p}, fs=FS, fr=FR, bpfi=BPFI, bpfo=150.0,
                                 ftf=6.0, bsf=50.0, load_kN=250.0, depth_um=50.0,
                                 attrs={"case": "F250kN_h50um"}, scene=None)


def _hann_reading(amplitude, f_true, df):
    """What the nearest bin of a Hann-windowed spectrum reads for a sinusoid of ``amplitude``
    at ``f_true`` (closed form, large N): ``A |sinc(d)| / (1 - d^2)`` with ``d`` the offset
    from the bin in bins; returns ``(bin frequency, reading)``."""
    k = round(f_true / df)
    d = f_true / df - k
    return k * df, amplitude * abs(np.sinc(d)) / (1.0 - d * d)


#: The lines built into the signal: quantity, band -> {(order, sideband): (Hz, amplitude)}.
#: The carrier at 20 kHz is 1e8 x env(t), so the envelope reads 1e8 x each term of env; the raw
#: spectrum reads the 0.2 fr and 0.1 BPFI terms of p.
BUILT = {
    ("envelope_bpfi", "fixed"): {(1, 0): (BPFI, 3e7), (2, 0): (2 * BPFI, 1e7),
                                 (1, -1): (BPFI - FR, 5e6), (1, 1): (BPFI + FR, 4e6),
                                 (2, 2): (2 * BPFI + 2 * FR, 2e6)},
    ("raw_fr", "raw"): {(1, 0): (FR, 2e7)},
    ("raw_bpfi", "raw"): {(1, 0): (BPFI, 1e7)},
}


def test_sweep_table_lines_unchanged(case):
    """Every line built into the signal is in the sweep's tidy table where it was built (the
    bin nearest its frequency) with the amplitude a Hann-windowed bin reads there (closed
    form); every other line the table holds is below its threshold."""
    analysis = {"signal": "p_max", "harmonics": 3, "sidebands": 2, "raw_orders_fr": 3,
                "amplitude": "peak_bin", "nlevel": 6, "bands": [
                    {"name": "kurtogram", "strategy": "kurtogram"},
                    {"name": "fixed", "strategy": "fixed", "low_hz": 15000.0,
                     "high_hz": 25000.0}]}
    bands, _ = case_bands(case, typed(analysis, case))
    df = case_harmonics(case, typed(analysis, case), bands)
    for c in ("floor", "floor_ratio_db", "threshold_db", "detected"):
        assert c in df.columns  # the new columns reach the sweep's tidy table
    df_hz = FS / N
    for (quantity, band), lines in BUILT.items():
        rows = df[(df.quantity == quantity) & (df.band == band)].set_index(["order", "sideband"])
        for key, (f_true, amp) in lines.items():
            r = rows.loc[key]
            f_bin, reading = _hann_reading(amp, f_true, df_hz)
            assert r.frequency_hz == pytest.approx(f_bin, abs=1e-6 * df_hz), (quantity, key)
            assert r.amplitude == pytest.approx(reading, rel=0.01), (quantity, key)
            assert r.detected, (quantity, key)
    # no other line in the fixed band or the raw spectrum is detected
    built = {(q, b, k) for (q, b), lines in BUILT.items() for k in lines}
    others = df[df.quantity.isin(["raw_fr", "raw_bpfi", "envelope_bpfi"])
                & df.band.isin(["fixed", "raw"])]
    for r in others.itertuples():
        if (r.quantity, r.band, (r.order, r.sideband)) not in built:
            assert not r.detected, (r.quantity, r.band, r.order, r.sideband)
