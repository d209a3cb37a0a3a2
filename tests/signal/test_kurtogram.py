import math

import numpy as np
import pytest

from bearing_envelope.signal import Kurtogram, fast_kurtogram, kurtogram_levels, max_kurtogram_level
from conftest import fault_signal


def test_levels_axis():
    lev = kurtogram_levels(4)
    c = math.log2(3) - 1
    np.testing.assert_allclose(lev, [0, 1, 1 + c, 2, 2 + c, 3, 3 + c, 4])


def test_shapes_axes_and_conventions():
    fs = 1000.0
    x = np.random.default_rng(1).standard_normal(2**13)
    kg = fast_kurtogram(x, fs, 5)
    assert isinstance(kg, Kurtogram)
    assert kg.matrix.shape == (10, 96)
    assert kg.freqs[0] == pytest.approx(fs / 2 / 96 / 2) and kg.freqs[-1] < fs / 2
    np.testing.assert_allclose(kg.bandwidths, fs * 2.0 ** -(kg.levels + 1))
    for r, vals in enumerate(kg.rows):
        # number of bands of a row = (fs/2) / bandwidth
        assert vals.size == round(fs / 2 / kg.bandwidths[r])
        assert np.all(vals >= 0)  # clipped at 0
    # best cell: centre of band i is (i + 1/2) * bandwidth, and it holds the matrix maximum
    assert kg.fc == pytest.approx((kg.band_index + 0.5) * kg.bandwidth)
    assert kg.kurtosis == pytest.approx(kg.matrix.max())
    lo, hi = kg.band
    assert hi - lo == pytest.approx(kg.bandwidth)
    assert kg.window_length == round(fs / kg.bandwidth)
    assert kg.n_dropped[0] == 0 and kg.n_dropped.max() <= 16


@pytest.mark.parametrize("fn_frac", [0.06, 0.2, 0.3, 0.43])
def test_best_band_contains_resonance(fn_frac):
    fs = 40000.0
    fn = fn_frac * fs
    x = fault_signal(fs=fs, n=2**16, fn=fn, bpfi=97.0, fr=11.0, damping=800.0, snr_db=-5.0,
                     tone_ratio=5.0, seed=3)
    kg = fast_kurtogram(x, fs, 7)
    lo, hi = kg.band
    assert lo <= fn <= hi, (kg.level, kg.fc, kg.bandwidth)
    assert kg.kurtosis > 1.0


def test_fault_signal_band_contains_fn(fault):
    kg = fast_kurtogram(fault["x"], fault["fs"], 8)
    lo, hi = kg.band
    assert lo <= fault["fn"] <= hi


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_gaussian_noise_small_maximum(seed):
    x = np.random.default_rng(seed).standard_normal(2**16)
    kg = fast_kurtogram(x, 1000.0, 7)
    # statistical fluctuation of deep cells plus the bias of the edge bands (which hold DC or
    # Nyquist and are not circular): ~0.3; an impulsive band gives > 1
    assert kg.kurtosis < 0.5
    interior = np.concatenate([r[1:-1] for r in kg.rows[3:6]])
    assert interior.mean() < 0.05


def test_max_level_and_min_bandwidth_guards():
    # lightly damped resonance: narrow-band ringing -> the unguarded best cell is deep
    fs = 20000.0
    x = fault_signal(fs=fs, n=2**16, fn=5000.0, damping=60.0, bpfi=7.3, fr=3.0, snr_db=0.0,
                     tone_ratio=0.0, jitter=0.0, am_depth=0.0, seed=5)
    free = fast_kurtogram(x, fs, 8)
    assert free.level >= 5
    guarded = fast_kurtogram(x, fs, 8, max_level=3)
    assert guarded.level <= 3
    np.testing.assert_array_equal(guarded.matrix, free.matrix)  # only the search changes
    allowed = [r for r, lev in enumerate(free.levels) if lev <= 3]
    assert guarded.kurtosis == pytest.approx(max(free.rows[r].max() for r in allowed))
    bw = fast_kurtogram(x, fs, 8, min_bandwidth=1000.0)
    assert bw.bandwidth >= 1000.0
    r = free.restrict(max_level=3)
    assert (r.level, r.fc, r.kurtosis) == (guarded.level, guarded.fc, guarded.kurtosis)
    with pytest.raises(ValueError, match="exclude every level"):
        fast_kurtogram(x, fs, 4, min_bandwidth=fs)


def test_high_snr_prefers_short_transients():
    # sparse, strongly damped impulses without noise: the widest bands win (shortest
    # transients); a min_bandwidth / max_level guard does not change that, a level guard can
    fs = 20000.0
    x = fault_signal(fs=fs, n=2**15, fn=5000.0, damping=4000.0, bpfi=20.0, snr_db=60.0,
                     tone_ratio=0.0, seed=2)
    kg = fast_kurtogram(x, fs, 7)
    assert kg.level <= 2
    assert kg.kurtosis > 10


def test_demean_matters_for_large_offset():
    rng = np.random.default_rng(0)
    x = 1e3 + rng.standard_normal(2**14)
    a = fast_kurtogram(x, 1000.0, 5)
    ref = fast_kurtogram(x - x.mean(), 1000.0, 5, demean=False)
    np.testing.assert_allclose(a.matrix, ref.matrix, atol=1e-9)
    b = fast_kurtogram(x, 1000.0, 5, demean=False)
    # the offset dominates the lowest band: a near-constant sub-band reads -1, clipped to 0
    assert b.rows[1][0] == 0.0 < a.rows[1][0]


def test_max_level_rule():
    assert max_kurtogram_level(411000) == 11
    assert max_kurtogram_level(2**10) == 3


@pytest.mark.parametrize(
    "x, kwargs, match",
    [
        (np.random.default_rng(0).standard_normal(2**10), {"nlevel": 4}, r"nlevel=4 is too deep.*<= floor\(log2\(n\)\) - 7 = 3"),
        (np.ones(4096), {"nlevel": 3}, "constant"),
        (np.r_[np.zeros(4000), np.nan], {"nlevel": 3}, "non-finite"),
        (np.array([]), {"nlevel": 3}, "x is empty"),
        (np.random.default_rng(0).standard_normal(2**12), {"nlevel": 0}, "nlevel must be"),
        (np.random.default_rng(0).standard_normal(2**12), {"nlevel": 2.5}, "nlevel must be"),
        (np.random.default_rng(0).standard_normal(100), {}, "at least 256 samples"),
        (np.random.default_rng(0).standard_normal(2**12), {"nlevel": 3, "max_level": -1}, "max_level"),
        (np.random.default_rng(0).standard_normal(2**12), {"nlevel": 3, "min_bandwidth": 0}, "min_bandwidth"),
    ],
)
def test_bad_inputs(x, kwargs, match):
    with pytest.raises(ValueError, match=match):
        fast_kurtogram(x, 1000.0, **kwargs)


def test_bad_fs():
    with pytest.raises(ValueError, match="fs must be"):
        fast_kurtogram(np.random.default_rng(0).standard_normal(4096), 0.0, 3)


def test_level0_real_signal_kurtosis():
    """level0="real" is Antoni's E x^4/(E x^2)^2 - 3 of the de-meaned signal (scipy's Fisher
    kurtosis, an independent computation); the other rows do not change. (CWRU 105/130, where
    only the real level 0 wins: tests/signal/test_real_records.py.)"""
    from scipy.stats import kurtosis

    rng = np.random.default_rng(3)
    n, fs = 2**14, 10000.0
    x = 0.1 * rng.standard_normal(n)
    x[::97] += 3.0 * rng.choice([-1.0, 1.0], x[::97].size)  # sparse, white impulses
    kr = fast_kurtogram(x, fs, 5, level0="real")
    ka = fast_kurtogram(x, fs, 5)
    assert kr.rows[0][0] == pytest.approx(kurtosis(x, fisher=True), rel=1e-9)
    assert kr.rows[0][0] > ka.rows[0][0] + 5.0
    for r in range(1, len(kr.rows)):
        np.testing.assert_array_equal(kr.rows[r], ka.rows[r])
    assert kr.level == 0.0
    with pytest.raises(ValueError, match="level0"):
        fast_kurtogram(x, fs, 5, level0="complex")
