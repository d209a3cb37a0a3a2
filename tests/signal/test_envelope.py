import numpy as np
import pytest

from bearing_envelope.diagnosis import harmonic_amplitudes
from bearing_envelope.signal import amplitude_at, bandpass, envelope, envelope_spectrum, fast_kurtogram, peak_value


def am(fs=20000.0, n=40000, fc=5000.0, fm=50.0, m=0.4, a=2.0):
    t = np.arange(n) / fs
    return a * (1 + m * np.cos(2 * np.pi * fm * t)) * np.cos(2 * np.pi * fc * t)


@pytest.mark.parametrize("window", ["hann", "flattop", "boxcar"])
def test_am_carrier_envelope_line(window):
    fs, fm, m, a = 20000.0, 50.0, 0.4, 2.0
    x = am(fs=fs, fm=fm, m=m, a=a)
    f, amp = envelope_spectrum(x, fs, (3000.0, 7000.0), window=window)
    i = np.argmax(amp)
    assert f[i] == pytest.approx(fm)
    assert amp[i] == pytest.approx(a * m, rel=0.01)
    assert amp[0] < 1e-3 * a  # mean removed


def test_am_carrier_squared_envelope():
    fs, fm, m, a = 20000.0, 50.0, 0.4, 2.0
    x = am(fs=fs, fm=fm, m=m, a=a)
    f, amp = envelope_spectrum(x, fs, (3000.0, 7000.0), squared=True)
    assert amplitude_at(f, amp, fm, 1.0)[1] == pytest.approx(2 * m * a**2, rel=0.01)
    assert amplitude_at(f, amp, 2 * fm, 1.0)[1] == pytest.approx(m**2 / 2 * a**2, rel=0.01)


def test_bandpass_zero_phase_and_selective():
    fs, n = 10000.0, 20000
    t = np.arange(n) / fs
    inband = np.cos(2 * np.pi * 1000 * t)  # samples hit the crests
    x = inband + np.sin(2 * np.pi * 50 * t) + np.sin(2 * np.pi * 4000 * t)
    y = bandpass(x, fs, (700.0, 1400.0), order=4)
    core = slice(2000, -2000)
    np.testing.assert_allclose(y[core], inband[core], atol=0.02)  # no delay, no leakage
    assert peak_value(y[core]) == pytest.approx(1.0, abs=0.02)
    lp = bandpass(x, fs, (0.0, 200.0))  # low = 0: low-pass
    assert np.std(lp[core] - np.sin(2 * np.pi * 50 * t)[core]) < 0.02


def test_envelope_of_pure_tone_is_flat():
    t = np.arange(10000) / 1000.0
    e = envelope(3.0 * np.cos(2 * np.pi * 100 * t))
    np.testing.assert_allclose(e[100:-100], 3.0, rtol=1e-3)
    e2 = envelope(3.0 * np.cos(2 * np.pi * 100 * t), squared=True)
    np.testing.assert_allclose(e2[100:-100], 9.0, rtol=2e-3)


def test_envelope_at_a_slow_fft_length_with_an_offset():
    # 2**6 * 1607 samples (a large prime factor: the transform is padded to a fast length) and a
    # constant offset c: the analytic signal of c + a(t) cos(w t) is c + a(t) exp(i w t) by
    # construction, so the envelope is |c + a(t) exp(i w t)|; a padded transform of the offset
    # itself would bend it across the whole record
    fs, n, fc, fm, c = 20000.0, 64 * 1607, 5000.0, 37.0, 4.0
    t = np.arange(n) / fs
    a = 2.0 * (1 + 0.4 * np.cos(2 * np.pi * fm * t))
    e = envelope(c + a * np.cos(2 * np.pi * fc * t))
    core = slice(200, -200)
    np.testing.assert_allclose(e[core], np.abs(c + a * np.exp(2j * np.pi * fc * t))[core],
                               rtol=1e-3)


def test_fault_signal_bpfi_line_and_sidebands(fault):
    x, fs, fr, bpfi, fn = fault["x"], fault["fs"], fault["fr"], fault["bpfi"], fault["fn"]
    kg = fast_kurtogram(x, fs, 8)
    lo, hi = kg.band
    assert lo <= fn <= hi
    f, amp = envelope_spectrum(x, fs, (lo, min(hi, 0.98 * fs / 2)))
    df = f[1] - f[0]
    sel = (f > fr / 2) & (f < 3 * bpfi)
    peak = f[sel][np.argmax(amp[sel])]
    assert abs(peak - bpfi) <= df  # dominant line is BPFI within one bin
    recs = harmonic_amplitudes(f, amp, bpfi, fr=fr, n_harmonics=2, n_sidebands=1)
    byk = {(r["order"], r["sideband"]): r for r in recs}
    floor = np.median(amp[(f > 100) & (f < 1000)])
    for m in (-1, 1):
        sb = byk[(1, m)]
        assert abs(sb["frequency_hz"] - (bpfi + m * fr)) <= 2 * df
        assert sb["amplitude"] > 5 * floor  # sidebands at +-fr present
        assert sb["amplitude"] < byk[(1, 0)]["amplitude"]
    assert byk[(2, 0)]["amplitude"] > 5 * floor


def test_harmonic_amplitudes_records():
    f = np.arange(0, 1000.5, 0.5)
    amp = np.zeros_like(f)
    for fr_, a_ in ((100.0, 1.0), (90.0, 0.3), (110.0, 0.2), (200.0, 0.5)):
        amp[int(fr_ / 0.5)] = a_
    recs = harmonic_amplitudes(f, amp, 100.0, fr=10.0, n_harmonics=2, n_sidebands=1)
    got = {(r["order"], r["sideband"]): r["amplitude"] for r in recs}
    assert got == {(1, -1): 0.3, (1, 0): 1.0, (1, 1): 0.2, (2, -1): 0.0, (2, 0): 0.5, (2, 1): 0.0}
    with pytest.raises(ValueError, match="fr"):
        harmonic_amplitudes(f, amp, 100.0, fr=None, n_harmonics=2, n_sidebands=1)


@pytest.mark.parametrize(
    "band, match",
    [
        ((3000.0, 12000.0), "band: high edge 12000 Hz is at or above the Nyquist"),
        ((3000.0, 10000.0), "band: high edge 10000 Hz is at or above the Nyquist"),
        ((5000.0, 4000.0), "band: high edge 4000 Hz must be above"),
        ((-1.0, 4000.0), "band: low edge -1 Hz is negative"),
        ((np.nan, 4000.0), "finite"),
        ((11000.0, 12000.0), "low edge"),
        ("abc", "pair"),
    ],
)
def test_bad_band(band, match):
    with pytest.raises(ValueError, match=match):
        envelope_spectrum(am(), 20000.0, band)


def test_bad_signal_and_fs():
    with pytest.raises(ValueError, match="non-finite"):
        envelope_spectrum(np.r_[am()[:100], np.inf], 20000.0, (1000, 2000))
    with pytest.raises(ValueError, match="fs must be"):
        envelope_spectrum(am(), -1.0, (1000, 2000))
    with pytest.raises(ValueError, match="x is empty"):
        bandpass([], 1000.0, (10, 20))
    with pytest.raises(ValueError, match="order"):
        bandpass(am(), 20000.0, (1000, 2000), order=0)


@pytest.mark.parametrize("n_end", [0, 1, 3, 7, 11])
def test_bandpass_peak_ignores_edge_transients(n_end):
    # a steady AM carrier, the record cut at several phases of the 12 kHz carrier: the even
    # padding of the forward-backward filter puts a kink at the ends whose ringing reached
    # 1.10 x the true peak A (1 + m) before the settling samples were excluded
    from bearing_envelope.diagnosis import AnalysisOptions, analyze_signal
    from bearing_envelope.signal import settling_samples

    fs, a, m, fc, fm = 64000.0, 2.0, 0.25, 12000.0, 250.0
    t = np.arange(65536 - n_end) / fs
    x = a * (1 + m * np.cos(2 * np.pi * fm * t)) * np.cos(2 * np.pi * fc * t)
    band = {"name": "b", "strategy": "fixed", "low_hz": 8000.0, "high_hz": 16000.0}
    df = analyze_signal(
        x,
        fs,
        fr=15.625,
        bpfi=fm,
        options=AnalysisOptions(
            bands=[band], n_harmonics=1, n_sidebands=0, n_raw_harmonics=1, nlevel=None
        ),
    )
    pk = df.loc[df["quantity"] == "bandpass_peak", "amplitude"].iloc[0]
    assert pk == pytest.approx(a * (1 + m), rel=2e-3)
    k = settling_samples(fs, (8000.0, 16000.0), order=4)
    assert 5 < k < 200      # ~ a few / bandwidth: 8 kHz wide -> tens of samples


def test_settling_samples_grows_as_the_band_narrows():
    from bearing_envelope.signal import settling_samples

    wide = settling_samples(64000.0, (8000.0, 16000.0))
    narrow = settling_samples(64000.0, (11900.0, 12100.0))
    assert narrow > 20 * wide
    # the impulse response is below 1e-3 of its maximum after that many samples
    from scipy import signal as sp

    sos = sp.butter(4, [11900.0, 12100.0], btype="bandpass", fs=64000.0, output="sos")
    imp = np.zeros(4 * narrow)
    imp[0] = 1.0
    h = np.abs(sp.sosfilt(sos, imp))
    assert h[narrow:].max() <= 1e-3 * h.max() < h[narrow - 1]


def test_full_band_with_clamp():
    """(0, fs/2) is refused without clamp; with it, it is the low-pass at 0.98 fs/2, and an AM
    carrier inside reads its modulation depth (known by construction)."""
    fs = 20000.0
    x = am()
    with pytest.raises(ValueError, match="Nyquist"):
        envelope_spectrum(x, fs, (0.0, fs / 2))
    f, a = envelope_spectrum(x, fs, (0.0, fs / 2), clamp=True)
    f2, a2 = envelope_spectrum(x, fs, (0.0, 0.98 * fs / 2))
    np.testing.assert_array_equal(a, a2)
    assert a[int(round(50.0 / (f[1] - f[0])))] == pytest.approx(2.0 * 0.4, rel=1e-3)
    f3, a3 = envelope_spectrum(x, fs, (0.0, 15000.0), clamp=True, margin=0.9)
    np.testing.assert_array_equal(a3, envelope_spectrum(x, fs, (0.0, 9000.0))[1])
