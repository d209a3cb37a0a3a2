"""Infogram and protrugram band choice on a signal whose impulsive band is known by
construction: decaying 4 kHz bursts at 100 Hz in white noise, plus a strong stationary
sinusoid at 1.5 kHz (loud but not impulsive: a kurtosis-free, line-free distractor)."""

import numpy as np
import pytest

from bearing_envelope.signal.bandselect import infogram_band, protrugram_band, tree_cells

FS, N = 12000.0, 2**16


def _signal(seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(N) / FS
    x = 3.0 * np.sin(2 * np.pi * 1500.0 * t) + 0.3 * rng.standard_normal(N)
    tt = np.arange(96) / FS
    burst = np.exp(-tt / 2e-3) * np.sin(2 * np.pi * 4000.0 * tt)
    for i in range(0, N - tt.size, int(FS / 100.0)):
        x[i:i + tt.size] += burst
    return x


def test_tree_cells_counts():
    # levels 0, 1, 1.58, 2, 2.58: 1 + 2 + 3 + 4 + 6 bands of 6000, 3000, 2000, 1500, 1000 Hz
    cells = tree_cells(FS, 8.0, min_bandwidth=973.0)
    assert len(cells) == 16
    widths = sorted({round(h - lo) for _, lo, h in cells})
    assert widths == [1000, 1500, 2000, 3000, 6000]


def test_infogram_picks_the_impulsive_band():
    (lo, hi), info = infogram_band(_signal(), FS, min_bandwidth=973.0)
    assert lo <= 4000.0 <= hi and not lo <= 1500.0 <= hi
    assert info["n_cells"] == 16 and info["negentropy"] > 0


def test_protrugram_picks_the_impulsive_band():
    (lo, hi), info = protrugram_band(_signal(), FS, bandwidth=1000.0, fmax_env=1000.0)
    assert hi - lo == pytest.approx(1000.0)
    assert lo <= 4000.0 <= hi and not lo <= 1500.0 <= hi


def test_bad_arguments():
    with pytest.raises(ValueError, match="min_bandwidth = 7000 Hz"):
        infogram_band(_signal(), FS, min_bandwidth=7000.0)
    with pytest.raises(ValueError, match="bandwidth = 6000 Hz: allowed below"):
        protrugram_band(_signal(), FS, bandwidth=6000.0)
