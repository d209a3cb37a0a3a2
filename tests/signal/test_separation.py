"""Discrete/random separation, cepstrum pre-whitened SES and the enhanced envelope spectrum on
signals whose answer is known by construction."""

import numpy as np
import pytest

from bearing_envelope.signal.cyclostationary import (enhanced_envelope_spectrum,
                                                     spectral_coherence)
from bearing_envelope.signal.separation import (discrete_random_separation, drs_gain,
                                                prewhitened_ses)

FS, N = 12000.0, 2**17


def _t():
    return np.arange(N) / FS


def test_drs_splits_sines_from_noise():
    # two sines (a shaft harmonic and a mesh-like tone) + unit white noise: the discrete part
    # is the sines, the random part the noise (DRS gain ~1 on the lines, its bias between)
    rng = np.random.default_rng(1)
    s = 3.0 * np.sin(2 * np.pi * 29.5 * _t()) + 2.0 * np.sin(2 * np.pi * 1234.5 * _t() + 0.3)
    noise = rng.standard_normal(N)
    d, r = discrete_random_separation(s + noise, FS)
    assert np.allclose(d + r, s + noise)
    assert np.std(d - s) < 0.2          # the noise left in the discrete part: the gain's bias
    assert np.std(r - noise) < 0.2      # the sines left in the random part: < 10 % of 1
    f, g = drs_gain(s + noise, FS)
    assert g[np.argmin(abs(f - 1234.5))] > 0.95
    assert np.median(g) < 0.2


def test_drs_needs_a_long_enough_record():
    with pytest.raises(ValueError, match="nperseg"):
        drs_gain(np.ones(5000), FS)


def test_prewhitened_ses_finds_a_train_under_a_loud_tone():
    # decaying 3 kHz bursts at 97 Hz with a 0.5 % random jitter of their spacing (the slip of
    # a bearing: cyclostationary, not periodic, so whitening keeps them), 30 dB under a 1 kHz
    # tone: the pre-whitened SES holds the 97 Hz line and its harmonic far above its median
    rng = np.random.default_rng(2)
    x = 30.0 * np.sin(2 * np.pi * 1000.0 * _t()) + 0.05 * rng.standard_normal(N)
    tt = np.arange(60) / FS
    burst = np.exp(-tt / 1e-3) * np.sin(2 * np.pi * 3000.0 * tt)
    rate = 97.0
    starts = np.cumsum(FS / rate * (1 + 0.005 * rng.standard_normal(2000))).astype(int)
    for i in starts[starts < N - tt.size]:
        x[i:i + tt.size] += burst
    f, a = prewhitened_ses(x, FS)
    for k in (1, 2):
        sel = abs(f - k * rate) < 0.01 * k * rate
        bg = (f > 0.5 * k * rate) & (f < 1.5 * k * rate)
        assert 20 * np.log10(a[sel].max() / np.median(a[bg])) > 20.0


def test_ees_reads_the_depth_of_a_power_modulation():
    # white noise whose power is modulated (1 + 0.5 cos 2 pi 100 t): every band carries the
    # modulation, the coherence reads 0.5 at 100 Hz (on a bin) and ~0 elsewhere
    rng = np.random.default_rng(3)
    fm = FS / N * round(100.0 * N / FS)
    x = rng.standard_normal(N) * np.sqrt(1 + 0.5 * np.cos(2 * np.pi * fm * _t()))
    alpha, e = enhanced_envelope_spectrum(x, FS, alpha_max_hz=400.0)
    i = np.argmin(abs(alpha - fm))
    assert e[i - 1:i + 2].max() == pytest.approx(0.5, abs=0.05)
    assert np.median(e[(alpha > 50) & (alpha < 400)]) < 0.05
    a2, f, coh = spectral_coherence(x, FS, alpha_max_hz=400.0)
    assert coh.shape == (a2.size, f.size) and a2[-1] >= 400.0


def test_ees_band_and_bad_input():
    x = np.random.default_rng(4).standard_normal(4096)
    with pytest.raises(ValueError, match="no STFT bin"):
        enhanced_envelope_spectrum(x, FS, alpha_max_hz=300.0, band=(10.0, 20.0))
    with pytest.raises(ValueError, match="alpha_max_hz"):
        spectral_coherence(x, FS, alpha_max_hz=FS)
