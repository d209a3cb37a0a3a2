"""The verdict's confidence on impulse trains whose fault, rate and modulation are known by
construction (issue 24): an inner-race train modulated at the shaft rate, an outer-race train
without modulation, a rolling-element train at 2 x BSF modulated at the cage rate, a cage-rate
train, two trains on a bearing where 3 x BPFO = 2 x BPFI exactly, and pure noise.

The trains are built here with numpy only: impulses at ``n / rate`` (0.5 % random jitter, as
slip gives), each the same sum of three decaying resonances (0.8, 1.9, 3.7 kHz), scaled by
``1 + 0.8 cos(2 pi f_mod t_n)``, plus white noise.
"""

import numpy as np
import pytest

from bearing_envelope.diagnosis import CANNOT_TELL, AnalysisOptions, analyze_signal

FS, N, FR = 12000.0, 2**16, 29.95
#: The SKF 6205 of the CWRU rig (9 balls, d/D = 0.2034): multiples of the shaft rate.
BPFO, BPFI, FTF, BSF = 3.5848 * FR, 5.4152 * FR, 0.39828 * FR, 2.3568 * FR
FAULTS = {"bpfo": BPFO, "bpfi": BPFI, "ftf": FTF, "bsf": BSF}
OPTIONS = AnalysisOptions(n_harmonics=3)


def _train(rate, mod_hz=None, *, amp=1.0, noise=0.5, seed=0):
    rng = np.random.default_rng(seed)
    n = int(N / FS * rate) + 1
    times = np.arange(n) / rate + 0.005 / rate * rng.standard_normal(n)
    tt = np.arange(256) / FS
    h = sum(np.exp(-tt / tau) * np.sin(2 * np.pi * fc * tt)
            for fc, tau in ((800.0, 2e-3), (1900.0, 1.5e-3), (3700.0, 1e-3)))
    q = np.ones(n) if mod_hz is None else 1.0 + 0.8 * np.cos(2 * np.pi * mod_hz * times)
    x = np.zeros(N + tt.size)
    for ti, qi in zip(times, q):
        i = int(round(ti * FS))
        if 0 <= i < N:
            x[i:i + tt.size] += amp * qi * h
    return x[:N] + noise * rng.standard_normal(N)


def _verdict(x, faults=FAULTS):
    return analyze_signal(x, FS, fr=FR, fault_frequencies=faults, options=OPTIONS,
                          full_output=True)[1]["verdict"]


@pytest.mark.parametrize("rate, mod, family, modulation", [
    (BPFI, FR, "bpfi", "fr"),      # inner race: fr sidebands
    (BPFO, None, "bpfo", None),    # outer race: none
    (2 * BSF, FTF, "bsf2", "ftf"),  # rolling element: 2 x BSF with FTF sidebands
])
def test_clear_fault_is_high_and_alone(rate, mod, family, modulation):
    v = _verdict(_train(rate, mod))
    assert v.diagnosis.family == family and v.confidence == "high"
    assert v.diagnosis.modulation == modulation and v.diagnosis.modulation_ok
    assert v.diagnosis.harmonics == (1, 2, 3)
    assert len(v.diagnosis.bands_agreeing) >= 3
    assert abs(v.diagnosis.frequency_hz - rate) <= 2 * FS / N
    assert [d.family for d in v.detected] == [family]  # no second finding
    d = v.to_dict()
    assert d["diagnosis"] == family and d["confidence"] == "high" and d["candidates"] == []
    assert v.summary_lines()[0].endswith("above threshold]")


def test_inner_race_without_its_modulation_is_not_high():
    """BPFI lines without fr sidebands: the inner-race pattern is incomplete."""
    v = _verdict(_train(BPFI))
    assert v.diagnosis.family == "bpfi" and v.confidence == "medium"
    assert not v.diagnosis.modulation_ok
    assert "no fr sidebands (expected)" in v.evidence


def test_cage_rate_lines_alone_cannot_tell():
    """FTF lines without BSF lines: a cage fault or the cage-rate modulation of a weak
    rolling-element fault; never a confident cage diagnosis."""
    v = _verdict(_train(FTF))
    assert v.diagnosis is None and v.confidence == CANNOT_TELL
    assert v.candidates[0] == "ftf" and {"bsf", "bsf2"} <= set(v.candidates)


@pytest.mark.parametrize("amp, expect", [(0.3, "explained"), (1.0, "candidate")])
def test_three_bpfo_on_two_bpfi(amp, expect):
    """A bearing where 3 x BPFO = 2 x BPFI exactly: an inner-race train plus a weaker
    outer-race train. Weaker by 10 dB or more, its third harmonic is the inner race's second:
    explained, no second finding; as strong, the verdict cannot tell."""
    faults = dict(FAULTS, bpfo=2.0 * BPFI / 3.0)
    x = _train(BPFI, FR) + _train(2.0 * BPFI / 3.0, amp=amp, noise=0.0, seed=3)
    v = _verdict(x, faults)
    bpfo = {f.family: f for f in v.families}["bpfo"]
    assert bpfo.detected and bpfo.role == expect
    assert bpfo.explained_by == "3 BPFO = 2 BPFI"
    if expect == "explained":
        assert v.diagnosis.family == "bpfi" and v.confidence == "high"
        assert [d.family for d in v.detected] == ["bpfi"]
    else:
        assert v.diagnosis is None and v.confidence == CANNOT_TELL
        assert set(v.candidates) == {"bpfi", "bpfo"}


@pytest.mark.parametrize("seed", range(4))
def test_noise_only_no_diagnosis(seed):
    v = _verdict(np.random.default_rng(100 + seed).standard_normal(N))
    assert v.diagnosis is None and v.confidence is None and v.detected == ()
    assert v.to_dict()["diagnosis_label"] == "no fault"
