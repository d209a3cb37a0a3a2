import numpy as np
import pytest

from bearing_envelope.diagnosis import raw_terms
from bearing_envelope.signal import amplitude_at, amplitude_spectrum


@pytest.mark.parametrize("window", ["hann", "boxcar", "flattop", ("tukey", 0.25), "hamming"])
def test_sine_amplitude_exact_on_bin(window):
    fs, n = 1000.0, 4000
    t = np.arange(n) / fs
    x = 3.0 + 2.5 * np.cos(2 * np.pi * 50.0 * t + 0.3)
    f, a = amplitude_spectrum(x, fs, window=window)
    assert f[1] == pytest.approx(fs / n)
    assert a[200] == pytest.approx(2.5, rel=1e-9)
    assert a[0] == pytest.approx(3.0, rel=1e-9)


@pytest.mark.parametrize("window", ["hann", "boxcar"])
def test_spectrum_up_to_fmax_at_a_slow_length(window):
    # 2**5 * 1607 samples: the first bins come from the zoom transform, not the FFT; lines on
    # bins 40 and 150 (of 25,712) read their amplitudes, a constant its value, and the bins
    # are the full spectrum's
    fs, n = 8000.0, 32 * 1607
    t = np.arange(n) / fs
    x = 0.7 + 2.0 * np.cos(2 * np.pi * 40 * fs / n * t + 0.4) + 0.5 * np.sin(2 * np.pi * 150 * fs / n * t)
    f, a = amplitude_spectrum(x, fs, window=window, fmax_hz=200 * fs / n)
    assert f.size == 202 and f[-1] == pytest.approx(201 * fs / n)
    assert a[0] == pytest.approx(0.7, rel=1e-9)
    assert a[40] == pytest.approx(2.0, rel=1e-9) and a[150] == pytest.approx(0.5, rel=1e-9)
    f_all, a_all = amplitude_spectrum(x, fs, window=window)
    np.testing.assert_allclose(f, f_all[:202])
    np.testing.assert_allclose(a, a_all[:202], rtol=0, atol=1e-9)


@pytest.mark.parametrize("fmax", [0.0, -1.0, float("nan"), "1"])
def test_bad_fmax(fmax):
    with pytest.raises(ValueError, match="fmax_hz"):
        amplitude_spectrum(np.ones(64), 8.0, fmax_hz=fmax)


def test_nyquist_and_dc_bins_not_doubled():
    fs, n = 8.0, 64
    x = np.cos(np.pi * np.arange(n))  # exactly at fs/2, amplitude 1
    f, a = amplitude_spectrum(x, fs, window=None)
    assert f[-1] == 4.0 and a[-1] == pytest.approx(1.0)


@pytest.mark.parametrize("window", ["hann", "boxcar", "hamming", "blackmanharris"])
def test_off_bin_interpolation_corrects_scalloping(window):
    fs, n = 1000.0, 1000
    t = np.arange(n) / fs
    x = 1.7 * np.sin(2 * np.pi * 123.4 * t)  # 0.4 bin off
    f, a = amplitude_spectrum(x, fs, window=window)
    f0, a0 = amplitude_at(f, a, 123.4, 2.0)
    assert a0 < 1.7 * 0.99  # scalloping loss without interpolation
    f1, a1 = amplitude_at(f, a, 123.4, 2.0, interpolate=True, window=window, n=n)
    assert f1 == pytest.approx(123.4, abs=0.1)
    assert a1 == pytest.approx(1.7, rel=0.01)


def test_amplitude_at_picks_largest_bin_within_tolerance():
    f = np.arange(11.0)
    a = np.array([0, 1, 5, 1, 0, 0, 9, 0, 0, 0, 0.0])
    assert amplitude_at(f, a, 3.0, 1.0) == (2.0, 5.0)
    assert amplitude_at(f, a, 3.0, 3.0) == (6.0, 9.0)
    assert amplitude_at(f, a, 3.2, 0.0) == (3.0, 1.0)
    with pytest.raises(ValueError, match="beyond"):
        amplitude_at(f, a, 20.0, 1.0)
    with pytest.raises(ValueError, match="tolerance"):
        amplitude_at(f, a, 2.0, -1.0)


def test_raw_terms_dc_fr_bpfi():
    fs, n, fr, bpfi = 2000.0, 20000, 10.0, 53.0
    t = np.arange(n) / fs
    x = 5.0 + 2.0 * np.cos(2 * np.pi * fr * t) + 0.5 * np.cos(2 * np.pi * bpfi * t)
    r = {(d["base"], d["order"]): d for d in raw_terms(x, fs, fr=fr, bpfi=bpfi, n_harmonics=1)}
    assert r[("dc", 0)]["amplitude"] == pytest.approx(5.0)
    assert r[("fr", 1)]["amplitude"] == pytest.approx(2.0, rel=1e-6)
    assert r[("bpfi", 1)]["amplitude"] == pytest.approx(0.5, rel=1e-6)


@pytest.mark.parametrize(
    "x, fs, match",
    [
        (np.array([]), 1.0, "x is empty"),
        (np.array([1.0, np.nan, 2.0]), 1.0, "non-finite"),
        (np.ones(10), 0.0, "fs must be"),
        (np.ones(10), -5.0, "fs must be"),
        (np.ones(10), np.inf, "fs must be"),
        (np.ones((3, 4)), 1.0, "1-D"),
    ],
)
def test_bad_inputs(x, fs, match):
    with pytest.raises(ValueError, match=match):
        amplitude_spectrum(x, fs)


def test_raw_terms_follow_a_speed_error():
    """Lines 0.6 % below their nominal frequencies (the nominal speed is not the actual one)
    are found by the +-1 % search; the fixed +-0.2 % one reads a sidelobe."""
    fs, n, fr, bpfi, s = 2000.0, 40000, 10.0, 53.0, 0.994
    t = np.arange(n) / fs
    x = 2.0 * np.cos(2 * np.pi * s * fr * t) + 0.5 * np.cos(2 * np.pi * s * bpfi * t) \
        + 0.2 * np.cos(2 * np.pi * 2 * s * bpfi * t)
    r = {(d["base"], d["order"]): d for d in raw_terms(x, fs, fr=fr, bpfi=bpfi, n_harmonics=2)}
    df = fs / n
    for key, hz, amp in ((("fr", 1), s * fr, 2.0), (("bpfi", 1), s * bpfi, 0.5),
                         (("bpfi", 2), 2 * s * bpfi, 0.2)):
        assert abs(r[key]["frequency_hz"] - hz) <= df / 2
        assert r[key]["amplitude"] == pytest.approx(amp, rel=0.16)  # Hann scalloping <= 1.4 dB
    old = {(d["base"], d["order"]): d for d in raw_terms(x, fs, fr=fr, bpfi=bpfi,
                                                         n_harmonics=1, tolerance=0.002 * bpfi)}
    assert old[("bpfi", 1)]["amplitude"] < 0.05


def test_prewhiten_flat_magnitude_same_phase():
    """Cepstrum pre-whitening (issue 24): every bin of the result has magnitude 1 (0 Hz: the
    mean is removed) and the phase of the input, checked with numpy's FFT."""
    from bearing_envelope.signal.spectrum import prewhiten

    rng = np.random.default_rng(1)
    x = np.cumsum(rng.standard_normal(1000)) + 5.0 * np.sin(np.arange(1000) * 0.3)
    y = prewhiten(x)
    Y, X = np.fft.rfft(y), np.fft.rfft(x - x.mean())
    assert y.shape == x.shape
    assert np.allclose(np.abs(Y[1:]), 1.0, atol=1e-9) and abs(Y[0]) < 1e-9
    assert np.allclose(np.angle(Y[1:] * np.conj(X[1:])), 0.0, atol=1e-7)
