"""The shaft rate measured from the raw spectrum and the line search at that speed (issue 24):
synthetic records whose actual speed differs from the nominal one by construction, and the
CWRU records of ``tests/data/real`` (the data center's nominal 1797 rpm, 1796 rpm measured).
"""

import json
from pathlib import Path

import numpy as np
import pytest

from bearing_envelope.diagnosis import AnalysisOptions, analyze_signal
from bearing_envelope.diagnosis.speed import (MEASURED_SPEED_SEARCH_PERCENT, ShaftRate,
                                              estimate_shaft_rate)

FS, N = 12000.0, 2**17
FR_NOMINAL = 29.95
#: SKF 6205 multiples of the shaft rate (CWRU rig).
MULT = {"bpfo": 3.5848, "bpfi": 5.4152, "ftf": 0.39828, "bsf": 2.3568}
DATA = Path(__file__).resolve().parents[1] / "data" / "real"


def _shaft(fr, n=N, seed=0):
    """Rotor lines at 1, 2, 3 x fr (unbalance, misalignment) plus white noise."""
    t = np.arange(n) / FS
    rng = np.random.default_rng(seed)
    x = sum(a * np.sin(2 * np.pi * k * fr * t + rng.uniform(0, 6.28))
            for k, a in ((1, 0.3), (2, 0.2), (3, 0.1)))
    return x + 0.3 * rng.standard_normal(n)


def _outer_race_train(rate, n=N, seed=1):
    """Impulses at ``rate`` (0.5 % jitter), each the sum of three decaying resonances (0.8,
    1.9, 3.7 kHz: one in each default band)."""
    rng = np.random.default_rng(seed)
    m = int(n / FS * rate) + 1
    times = np.arange(m) / rate + 0.005 / rate * rng.standard_normal(m)
    tt = np.arange(256) / FS
    h = sum(np.exp(-tt / tau) * np.sin(2 * np.pi * fc * tt)
            for fc, tau in ((800.0, 2e-3), (1900.0, 1.5e-3), (3700.0, 1e-3)))
    x = np.zeros(n + tt.size)
    for ti in times:
        i = int(round(ti * FS))
        if 0 <= i < n:
            x[i:i + tt.size] += h
    return x[:n]


@pytest.mark.parametrize("fr", [29.95, 29.70, 29.50, 30.30])
def test_estimate_is_the_actual_rate(fr):
    """Within 0.01 % of the rate the record was built with, up to 1.5 % from nominal."""
    est = estimate_shaft_rate(_shaft(fr), FS, FR_NOMINAL)
    assert isinstance(est, ShaftRate) and len(est.per_order) == 3
    assert abs(est.hz / fr - 1.0) < 1e-4
    assert est.ratio == pytest.approx(est.hz / FR_NOMINAL)


def test_median_survives_one_masked_order():
    """A strong electrical line next to 2 x fr moves that order's estimate only."""
    fr = 29.70
    t = np.arange(N) / FS
    x = _shaft(fr) + 3.0 * np.sin(2 * np.pi * 59.8 * t)
    est = estimate_shaft_rate(x, FS, FR_NOMINAL)
    assert abs(est.hz - fr) < 0.005
    assert abs(est.per_order[1] - 59.8 / 2) < 0.01


def test_line_outside_the_nominal_window_is_found_at_the_measured_speed():
    """Actual speed 1.6 % below nominal (an unloaded-speed rating on a loaded motor): the BPFO
    line lies outside the +- 1 % window around its nominal value, so the nominal-speed search
    misses it; measured, the speed puts it inside +- 0.5 % and the outer race is diagnosed with
    high confidence."""
    fr = FR_NOMINAL * (1.0 - 0.016)
    x = _shaft(fr) + _outer_race_train(MULT["bpfo"] * fr)
    faults = {k: v * FR_NOMINAL for k, v in MULT.items()}
    base = AnalysisOptions(n_harmonics=3)
    nominal = analyze_signal(x, FS, fr=FR_NOMINAL, fault_frequencies=faults, options=base,
                             full_output=True)[1]
    measured = analyze_signal(x, FS, fr=FR_NOMINAL, fault_frequencies=faults, full_output=True,
                              options=AnalysisOptions(n_harmonics=3, measure_speed=True))[1]
    assert nominal["speed"] is None
    assert nominal["verdict"].diagnosis is None or nominal["verdict"].diagnosis.family != "bpfo"
    v = measured["verdict"]
    assert abs(measured["speed"].hz - fr) < 0.01 and measured["fr"] == measured["speed"].hz
    assert measured["frequencies"]["bpfo"] == pytest.approx(MULT["bpfo"] * measured["speed"].hz)
    assert v.diagnosis.family == "bpfo" and v.confidence == "high"
    assert abs(v.diagnosis.frequency_hz / (MULT["bpfo"] * fr) - 1.0) < 0.002


def test_off_by_default_and_window_validated():
    assert AnalysisOptions().measure_speed is False
    assert AnalysisOptions().measured_speed_search_percent == MEASURED_SPEED_SEARCH_PERCENT
    with pytest.raises(ValueError, match="measured_speed_search_percent"):
        AnalysisOptions(measured_speed_search_percent=0.0)


@pytest.mark.parametrize("name, rpm, family", [("cwru_105_IR007_0hp_DE12", 1796.0, "bpfi"),
                                               ("cwru_130_OR007at6_0hp_DE12", 1796.0, "bpfo")])
def test_cwru_speed(name, rpm, family):
    """The 0 hp records run at about 1796 rpm (nominal 1797); the diagnosis at the measured
    speed stays the clear, high-confidence one."""
    with np.load(DATA / f"{name}.npz", allow_pickle=False) as z:
        x, fs, meta = z["x"], float(z["fs"]), json.loads(str(z["meta_json"]))
    est = estimate_shaft_rate(x, fs, meta["shaft_hz"])
    assert abs(60.0 * est.hz - rpm) < 1.0
    faults = {k.lower(): v for k, v in meta["fault_freqs_hz"].items()}
    v = analyze_signal(x, fs, fr=meta["shaft_hz"], fault_frequencies=faults, full_output=True,
                       options=AnalysisOptions(n_harmonics=3, measure_speed=True))[1]["verdict"]
    assert v.diagnosis.family == family and v.confidence == "high"


def test_cwru_ball_record_not_confident_at_the_measured_speed():
    """Ball record 118 (no usable ball signature, Smith & Randall 2015): the narrower search at
    the measured speed must not turn its BPFO-like series into a confident verdict."""
    with np.load(DATA / "cwru_118_B007_0hp_DE12.npz", allow_pickle=False) as z:
        x, fs, meta = z["x"], float(z["fs"]), json.loads(str(z["meta_json"]))
    faults = {k.lower(): v for k, v in meta["fault_freqs_hz"].items()}
    v = analyze_signal(x, fs, fr=meta["shaft_hz"], fault_frequencies=faults, full_output=True,
                       options=AnalysisOptions(n_harmonics=3, measure_speed=True))[1]["verdict"]
    assert v.confidence not in ("high", "medium")


def test_noise_without_shaft_lines_keeps_the_nominal_speed():
    """No rotor lines: the largest bin of each 2 % window is noise; the speed is not 'measured'
    from it (which would move every fault line by up to 2 %) and the nominal rate is kept."""
    rng = np.random.default_rng(7)
    for trial in range(20):
        est = estimate_shaft_rate(rng.standard_normal(N), FS, FR_NOMINAL)
        assert not est.measured and est.hz == FR_NOMINAL
    assert estimate_shaft_rate(_shaft(29.70), FS, FR_NOMINAL).measured
