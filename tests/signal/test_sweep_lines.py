"""The simulated sweep's tables after the +-1 % search (issue 14): simulated lines sit exactly at
k x BPFI +- m x fr, so every line the tidy table holds must read what the former narrow search
(+-max(2 df, 0.2 %) around the nominal target, at most fr/4) read. The oracle recomputes that
former rule with numpy on the same spectra."""

import types

import numpy as np
import pytest

from bearing_envelope.study.pipeline import case_bands, case_harmonics
from bearing_envelope.signal import amplitude_spectrum, envelope_spectrum
from bearing_envelope.study.pipeline import case_frequencies
from bearing_envelope.study.settings import AnalysisSettings

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


def _former(f, a, target, fr):
    df = f[1] - f[0]
    tol = min(max(2 * df, 0.002 * target), fr / 4)
    i0 = int(round(target / df))
    lo = max(0, min(i0, int(np.ceil((target - tol) / df - 1e-9))))
    hi = min(f.size - 1, max(i0, int(np.floor((target + tol) / df + 1e-9))))
    i = lo + int(np.argmax(a[lo:hi + 1]))
    return f[i], a[i]


def test_sweep_table_lines_unchanged(case):
    # the former rule read the largest bin: compare the search with the peak-bin estimator
    # (the sweep's default, the interpolated peak, is tested in test_amplitude_estimator.py)
    analysis = {"signal": "p_max", "harmonics": 3, "sidebands": 2, "raw_orders_fr": 3,
                "amplitude": "peak_bin", "nlevel": 6, "bands": [
                    {"name": "kurtogram", "strategy": "kurtogram"},
                    {"name": "fixed", "strategy": "fixed", "low_hz": 15000.0,
                     "high_hz": 25000.0}]}
    bands, _ = case_bands(case, typed(analysis, case))
    df = case_harmonics(case, typed(analysis, case), bands)
    for c in ("floor", "floor_ratio_db", "threshold_db", "detected"):
        assert c in df.columns  # the new columns reach the sweep's tidy table
    x = case.signals["p_max"]
    spectra = {"raw": amplitude_spectrum(x, FS)}
    for b in bands.bands:
        spectra[b.name] = envelope_spectrum(x, FS, (b.low_hz, b.high_hz))
    lines = df[df.quantity.isin(["raw_fr", "raw_bpfi", "envelope_bpfi"])]
    checked = 0
    for _, r in lines.iterrows():
        base = FR if r.quantity == "raw_fr" else BPFI
        target = r.order * base + r.sideband * FR
        f_old, a_old = _former(*spectra[r.band], target, FR)
        same = (r.frequency_hz == f_old) and (r.amplitude == a_old)
        if r.detected:
            assert same, (r.band, r.quantity, r.order, r.sideband)
            checked += 1
        elif not same:
            # where the former search read noise, the new one reads other noise: never a line
            assert r.floor_ratio_db < r.threshold_db
    # the lines built in: raw fr, raw BPFI; fixed band: 1, 2 x BPFI, 1 x BPFI +- fr, 2 x BPFI + 2 fr
    assert checked >= 7
    fixed = df[(df.band == "fixed") & (df.quantity == "envelope_bpfi")].set_index(
        ["order", "sideband"])
    for key in [(1, 0), (2, 0), (1, -1), (1, 1), (2, 2)]:
        assert fixed.loc[key, "detected"], key
