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
    rolling-element fault; never a confident cage diagnosis. (Noise 0.4: the series stands in
    three distinct bands; at 0.5 it is seen in two distinct bands 8 dB above threshold, a
    'low' cage series, which is no finding at all.)"""
    v = _verdict(_train(FTF, noise=0.4))
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


def test_bpfi_series_on_three_bpfo_is_not_explained_away():
    """Issue 24, second pass: an inner-race train (fr sidebands) 4-5 dB weaker than an
    outer-race train on a bearing where 3 x BPFO = 2 x BPFI. BPFI's second harmonic is BPFO's
    third, but its fundamental and third harmonic stand on their own: a rival (cannot tell),
    not an explained family behind a confident outer-race verdict (the former rule dropped any
    family whose second harmonic was shared)."""
    faults = dict(FAULTS, bpfo=2.0 * BPFI / 3.0)
    x = _train(2.0 * BPFI / 3.0) + _train(BPFI, FR, amp=0.5, noise=0.0, seed=3)
    v = _verdict(x, faults)
    fams = {f.family: f for f in v.families}
    assert fams["bpfi"].explained_by == "2 BPFI = 3 BPFO" and fams["bpfi"].role == "candidate"
    assert v.diagnosis is None and v.confidence == CANNOT_TELL
    assert set(v.candidates) == {"bpfo", "bpfi"}


def _rows(family, f1, bands, margins, detected):
    """Envelope rows of one family: harmonics 1-3 (no sidebands) in each band, each line
    ``margin`` dB above a 12 dB threshold, ``detected`` as given (per band: 3 flags)."""
    out = []
    for (name, lo, hi), m, det in zip(bands, margins, detected):
        for k, d in zip((1, 2, 3), det):
            out.append({"quantity": "envelope_spectrum", "base": family, "band": name,
                        "band_low_hz": lo, "band_high_hz": hi, "order": k, "sideband": 0,
                        "frequency_hz": k * f1, "amplitude": 1.0,
                        "floor_ratio_db": 12.0 + (m if d else -3.0), "threshold_db": 12.0,
                        "detected": d})
    return out


BANDS4 = [("kurtogram", 5000.0, 5880.0), ("fs4_3fs8", 3000.0, 4500.0),
          ("bpfi_3_6", 480.0, 980.0), ("bpfi_10_13", 1600.0, 2100.0)]


@pytest.mark.parametrize("bpfi_bands, expect", [(2, "bpfi"), (1, None)])
def test_band_count_breaks_a_tie_at_the_same_level(bpfi_bands, expect):
    """Two families at the same ('low') level: BPFI found at one frequency in two bands, 2 x
    BSF in one. The family seen in more bands is the diagnosis (low); with one band each the
    verdict cannot tell."""
    import pandas as pd

    from bearing_envelope.diagnosis.faults import fault_families, fault_verdict
    fams = fault_families({"bpfi": BPFI, "bsf": BSF}, fr=FR, sidebands={"bsf": None,
                                                                        "bsf2": None})
    on, off = (True, True, False), (False, False, False)
    bpfi = [on] * bpfi_bands + [off] * (4 - bpfi_bands)
    rows = _rows("bpfi", BPFI, BANDS4, [5.0] * 4, bpfi)
    rows += _rows("bsf2", 2 * BSF, BANDS4, [5.0] * 4, [off, off, on, off])
    rows += _rows("bsf", BSF, BANDS4, [0.0] * 4, [off] * 4)
    table = pd.DataFrame(rows)
    v = fault_verdict(table, fams, pfa=0.01, n_tests=12, fr=FR, df_hz=0.1)
    levels = {f.family: f.level for f in v.families}
    assert levels["bpfi"] == "low" and levels["bsf2"] == "low"
    if expect is None:
        assert v.diagnosis is None and v.confidence == CANNOT_TELL
        assert set(v.candidates) == {"bpfi", "bsf2"}
    else:
        assert v.diagnosis.family == expect and v.confidence == "low"
        assert v.diagnosis.bands_agreeing == ("kurtogram", "fs4_3fs8")



@pytest.mark.parametrize("bpfi_margin, expect", [(16.0, "candidate"), (8.0, "explained")])
def test_shared_harmonic_rival_at_any_level(bpfi_margin, expect):
    """3 x BPFO = 2 x BPFI exactly (hand-built envelope table). BPFO in all four bands, 20 dB
    above threshold (high); BPFI in one band (low), its second harmonic on BPFO's third, its
    fundamental and third harmonic on their own. 16 dB above threshold (within RIVAL_MARGIN_DB
    = 6 dB of BPFO's margin) it rivals the diagnosis at any level: cannot tell (the former
    rule asked for medium own evidence and explained it away); 8 dB (12 dB below) it is
    explained and BPFO stands alone."""
    import pandas as pd

    from bearing_envelope.diagnosis.faults import fault_families, fault_verdict
    bpfo = 2.0 * BPFI / 3.0
    fams = fault_families({"bpfo": bpfo, "bpfi": BPFI}, fr=FR, sidebands={"bpfi": None})
    on, off = (True, True, True), (False, False, False)
    rows = _rows("bpfo", bpfo, BANDS4, [20.0] * 4, [on] * 4)
    rows += _rows("bpfi", BPFI, BANDS4, [bpfi_margin] * 4, [on, off, off, off])
    v = fault_verdict(pd.DataFrame(rows), fams, pfa=0.01, n_tests=8, fr=FR, df_hz=0.1)
    f = {x.family: x for x in v.families}
    assert f["bpfo"].level == "high" and f["bpfi"].level == "low"
    assert f["bpfi"].explained_by == "2 BPFI = 3 BPFO" and f["bpfi"].role == expect
    if expect == "candidate":
        assert v.diagnosis is None and v.confidence == CANNOT_TELL
    else:
        assert v.diagnosis.family == "bpfo" and v.confidence == "high"


@pytest.mark.parametrize("kurtogram, level", [((5000.0, 5880.0), "medium"),
                                              ((3000.0, 4000.0), "low")])
def test_overlapping_bands_count_once(kurtogram, level):
    """Issue 24, third pass: an inner-race series (harmonics 1-3, no sidebands searched) 7 dB
    above threshold in the kurtogram band, 3-4.5 kHz and 0.49-0.97 kHz. With the kurtogram band
    at 5-5.9 kHz the three bands are distinct demodulations: medium (three bands, margin below
    high's). With the kurtogram band at 3-4 kHz, inside 3-4.5 kHz, the same resonance is seen
    twice: two distinct bands at 7 dB, low (record 200's BPFI series at a 0.7 % window was
    medium this way). The former rule counted three bands in both cases."""
    import pandas as pd

    from bearing_envelope.diagnosis.faults import fault_families, fault_verdict
    fams = fault_families({"bpfi": BPFI}, fr=FR, sidebands={"bpfi": None})
    bands = [("kurtogram", *kurtogram), ("fs4_3fs8", 3000.0, 4500.0),
             ("bpfi_3_6", 486.0, 973.0)]
    on = (True, True, True)
    v = fault_verdict(pd.DataFrame(_rows("bpfi", BPFI, bands, [7.0] * 3, [on] * 3)), fams,
                      pfa=0.01, n_tests=3, fr=FR, df_hz=0.1)
    d = v.diagnosis
    assert d.family == "bpfi" and len(d.bands_agreeing) == 3
    assert d.n_distinct == (3 if level == "medium" else 2)
    assert v.confidence == level


def test_distinct_bands():
    from bearing_envelope.diagnosis.faults import distinct_bands
    assert distinct_bands([]) == 0
    assert distinct_bands([(3000, 4500), (3000, 4500)]) == 1          # the same band
    assert distinct_bands([(3000, 4000), (3000, 4500), (486, 973)]) == 2  # one inside another
    assert distinct_bands([(5000, 5880), (3000, 4500), (486, 973), (1620, 2107)]) == 4
    # 0-2 kHz holds 0.49-0.97 and most of 1.62-2.11 kHz; those two are distinct of each other
    assert distinct_bands([(0, 2000), (486, 973), (1620, 2107)]) == 2
    assert distinct_bands([(0, 1000), (900, 2000)]) == 2               # 10 % shared: distinct
    assert distinct_bands([(0, 1000), (900, 2000)], overlap=0.05) == 1


@pytest.mark.parametrize("seed", range(6))
def test_cage_train_never_confident_outer_race(seed):
    """A cage-rate impulse train holds every multiple of FTF, BPFO = 9 FTF among them: its
    BPFO 'series' is seen through overlapping bands (the kurtogram's 0-2 kHz holds both
    order-based bands). By construction there is no outer-race fault, so BPFO must never be
    diagnosed at medium or high (the former band count gave BPFO medium for seed 2: three
    bands, two of them inside the kurtogram's)."""
    v = _verdict(_train(FTF, seed=seed))
    d = v.diagnosis
    assert d is None or d.family != "bpfo" or v.confidence == "low"
    assert v.confidence not in ("high", "medium") or d is None
