import numpy as np
import pytest

from bearing_envelope.signal import fast_kurtogram, spectral_kurtosis
from conftest import fault_signal


@pytest.mark.parametrize("seed", [0, 1])
def test_gaussian_noise_sk_near_zero(seed):
    x = np.random.default_rng(seed).standard_normal(2**16)
    f, sk, k = spectral_kurtosis(x, 1000.0, 64, return_frames=True)
    assert f.size == 33 and f[-1] == pytest.approx(500.0)
    inner = sk[1:-1]
    # bias O(1/K) (K ~ 5000 frames, correlated by the 80 % overlap) plus scatter ~0.04
    assert abs(inner.mean()) < 0.03
    assert np.abs(inner).max() < 0.25
    # at 0 Hz and fs/2 the STFT is real: a Gaussian reads ~1 there
    assert 0.6 < sk[0] < 1.4


def test_tone_gives_minus_one():
    fs, n = 1000.0, 2**14
    t = np.arange(n) / fs
    x = np.cos(2 * np.pi * 125.0 * t) + 1e-3 * np.random.default_rng(0).standard_normal(n)
    f, sk = spectral_kurtosis(x, fs, 64)
    i = np.argmin(abs(f - 125.0))
    assert sk[i] == pytest.approx(-1.0, abs=0.01)


def test_impulsive_band_and_window_from_kurtogram(fault):
    x, fs = fault["x"], fault["fs"]
    kg = fast_kurtogram(x, fs, 8)
    f, sk = spectral_kurtosis(x, fs)  # nperseg from the kurtogram
    assert f.size == max(16, kg.window_length) // 2 + 1
    f2, sk2 = spectral_kurtosis(x, fs, 32)  # window shorter than the impulse period
    inner = slice(1, -1)  # 0 Hz and fs/2 read ~1 for noise
    assert abs(f2[inner][np.argmax(sk2[inner])] - fault["fn"]) < 1500
    assert sk2[inner].max() > 1.0


@pytest.mark.parametrize(
    "kw, match",
    [({"nperseg": 2}, "nperseg"), ({"nperseg": 10**6}, "longer"), ({"nperseg": 64, "overlap": 1.0}, "overlap")],
)
def test_bad_arguments(kw, match):
    x = np.random.default_rng(0).standard_normal(4096)
    with pytest.raises(ValueError, match=match):
        spectral_kurtosis(x, 100.0, **kw)
