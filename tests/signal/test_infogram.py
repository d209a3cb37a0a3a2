"""The infogram (signal.infogram) on records whose answer is known by construction.

- Periodic impulses (every 1/97 s) ring a resonance at 7.3 kHz (band B); one large isolated
  impulse rings a resonance at 2.8 kHz (band A); white noise under both. The isolated shock
  makes band A the most impulsive (the kurtogram and the time negentropy pick it); only band
  B repeats (the spectral negentropy picks it: a single shock has a flat SES).
- White noise: the squared envelope of a circular complex Gaussian band is exponentially
  distributed, so every cell's negentropy estimates E[u ln u] = 1 - gamma (u ~ Exp(1)), with
  variance (Gamma''(3) - (1 - gamma)^2) / n_eff (moments of the exponential law, from scipy's
  digamma/polygamma, not from the code under test). Statistic: the z-score of every cell
  against that; cells touching 0 Hz or fs/2 hold a band's mirror image (a real signal there is
  not circular) and are bounded by the value of a real Gaussian, E[u ln u] for u ~ chi2(1),
  2 - gamma - ln 2.
"""

import math

import numpy as np
import pytest
from scipy import special

from bearing_envelope.signal import fast_kurtogram
from bearing_envelope.signal.infogram import (INFOGRAM_MAPS, infogram, infogram_depth,
                                              negentropy)

FS, N, NLEVEL = 20000.0, 2**16, 6
F_A, F_B = 2800.0, 7300.0
EULER = float(np.euler_gamma)
#: E[u ln u] and its standard deviation for u ~ Exp(1): psi(2) and Gamma''(3) - psi(2)^2
MEAN_EXP = float(special.digamma(2.0))
SD_EXP = math.sqrt(2.0 * (special.digamma(3.0) ** 2 + special.polygamma(1, 3.0))
                   - MEAN_EXP ** 2)


def _ring(f0, tau=1e-3, n=200):
    t = np.arange(n) / FS
    return np.exp(-t / tau) * np.sin(2 * np.pi * f0 * t)


def _two_bands(seed=1):
    x = np.random.default_rng(seed).standard_normal(N)
    rb = 2.0 * _ring(F_B)
    for i in range(50, N - rb.size, int(FS / 97.0)):
        x[i:i + rb.size] += rb
    x[30000:30200] += 60.0 * _ring(F_A)
    return x


def _near(cell_band, f0, ring_half_width=320.0):
    lo, hi = cell_band
    return lo - ring_half_width <= f0 <= hi + ring_half_width


def test_reference_values_of_the_negentropy():
    assert MEAN_EXP == pytest.approx(1.0 - EULER)
    assert negentropy(np.full(50, 3.0)) == 0.0
    assert negentropy(np.zeros(8)) == 0.0
    spike = np.zeros(1000)
    spike[17] = 5.0
    assert negentropy(spike) == pytest.approx(math.log(1000.0))
    u = np.random.default_rng(0).exponential(1.0, 200_000)
    assert negentropy(u) == pytest.approx(1.0 - EULER, abs=5 * SD_EXP / math.sqrt(u.size))
    rows = negentropy(np.vstack([np.ones(10), spike[:10] + 1e-300]), axis=1)
    assert rows.shape == (2,) and rows[0] == 0.0


def test_spectral_infogram_picks_the_repetitive_band_kurtogram_the_isolated_shock():
    x = _two_bands()
    kg = fast_kurtogram(x, FS, NLEVEL)
    ig = infogram(x, FS, NLEVEL)
    assert _near(kg.band, F_A) and not _near(kg.band, F_B)
    assert _near(ig.cells["time"].band, F_A) and not _near(ig.cells["time"].band, F_B)
    spec = ig.cells["spectral"]
    assert _near(spec.band, F_B) and not _near(spec.band, F_A)
    # by a wide margin over every cell holding A (its SES: the smooth spectrum of one decay)
    a_best = max(v[i] for v, bw in zip(ig.spectral, ig.bandwidths)
                 for i in range(v.size) if _near(((i) * bw, (i + 1) * bw), F_A, 0.0)
                 and not _near(((i) * bw, (i + 1) * bw), F_B))
    assert spec.value > 2.0 * a_best


def test_white_noise_no_cell_stands_out():
    x = np.random.default_rng(5).standard_normal(N)
    alpha_max = 150.0
    ig = infogram(x, FS, NLEVEL, alpha_max_hz=alpha_max)
    for r, bw in enumerate(ig.bandwidths):
        n_cells = ig.time[r].size
        n_se = ig.n_samples[r]
        # a row's signal runs at twice its bandwidth: about n / 2 independent samples
        z_time = (ig.time[r] - MEAN_EXP) / (SD_EXP / math.sqrt(n_se / 2.0))
        inner = np.arange(n_cells)[1:-1] if r > 0 else np.arange(0)
        assert np.all(np.abs(z_time[inner]) < 5.0), (r, z_time)
        assert np.all(ig.time[r] < 2.0 - EULER - math.log(2.0)), (r, ig.time[r])
        if alpha_max <= bw / 4.0:  # the SES of noise is flat up to alpha_max
            k = int(alpha_max * n_se / (2.0 * bw))
            # Hann-windowed bins: about k / 2 independent values
            z_spec = (ig.spectral[r] - MEAN_EXP) / (SD_EXP / math.sqrt(k / 2.0))
            assert np.all(np.abs(z_spec) < 5.0), (r, z_spec)


def test_maps_share_the_kurtogram_tree():
    x = _two_bands()
    ig = infogram(x, FS, 3, min_bandwidth=1000.0)
    kg = fast_kurtogram(x, FS, 3)
    np.testing.assert_allclose(ig.levels, kg.levels)
    np.testing.assert_allclose(ig.bandwidths, kg.bandwidths)
    assert [v.size for v in ig.time] == [v.size for v in kg.rows]
    for kind in INFOGRAM_MAPS:
        assert ig.matrix(kind).shape == kg.matrix.shape
        assert ig.cells[kind].bandwidth >= 1000.0
    avg = ig.rows("average")
    c = ig.cells["average"]
    assert c.value == pytest.approx(0.5 * (ig.time[c.row][c.band_index]
                                           + ig.spectral[c.row][c.band_index]))
    assert c.value == pytest.approx(max(float(np.max(v)) for v, bw in zip(avg, ig.bandwidths)
                                        if bw >= 1000.0))


def test_depth_for_the_narrowest_cell():
    # 12 kHz: levels 0, 1, 1.585, 2, 2.585, 3 are 6000, 3000, 2000, 1500, 1000, 750 Hz wide
    assert infogram_depth(12000.0, 972.0, 121991) == 3  # 1000 Hz cells: level 2.585
    assert infogram_depth(12000.0, 1500.0, 121991) == 2
    assert infogram_depth(12000.0, 1.0, 121991) == 8  # capped by the default depth
    assert infogram_depth(12000.0, 1.0, 4096) == 5  # and by the record's length


def test_bad_input():
    with pytest.raises(ValueError, match="constant"):
        infogram(np.ones(4096), FS, 2)
    with pytest.raises(ValueError, match="alpha_max_hz"):
        infogram(_two_bands()[:4096], FS, 2, alpha_max_hz=-1.0)
    with pytest.raises(ValueError, match="kind = 'x'"):
        infogram(_two_bands()[:4096], FS, 2).rows("x")
    with pytest.raises(ValueError, match="SES bins"):
        infogram(_two_bands()[:4096], FS, 2, alpha_max_hz=1.0).best("spectral")


def test_a_tone_beats_with_its_mirror_in_the_cells_at_0_hz():
    # a real 300 Hz tone: the complex band signal of a cell starting at 0 Hz holds it and its
    # image at -300 Hz, whose beat makes the squared envelope repeat at 600 Hz
    t = np.arange(N) / FS
    x = np.random.default_rng(3).standard_normal(N) + 5.0 * np.sin(2 * np.pi * 300.0 * t)
    ig = infogram(x, FS, NLEVEL, alpha_max_hz=1000.0)
    assert ig.best("spectral", min_bandwidth=1250.0).band[0] == 0.0
    assert ig.best("spectral", min_bandwidth=1250.0).value > 2.0
    clear = ig.best("spectral", min_bandwidth=1250.0, above_dc=True)
    assert clear.band[0] > 0.0 and clear.value < 1.0
