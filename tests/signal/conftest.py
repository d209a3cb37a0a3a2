"""Synthetic signals with answers known by construction."""

import numpy as np
import pytest


def fault_signal(*, fs=20000.0, n=2**17, fr=15.8, bpfi=231.9, fn=6000.0, damping=1500.0,
                 jitter=0.01, am_depth=0.5, snr_db=0.0, tone_ratio=10.0, tone_hz=None, seed=0):
    """Impulses at BPFI (uniform timing jitter +-jitter of the period) ringing a decaying
    resonance at ``fn``, amplitude-modulated at ``fr``; Gaussian noise at ``snr_db`` relative to
    the impulse train's power and a low-frequency tone ``tone_ratio`` times the train's RMS."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    x = np.zeros(n)
    period = 1.0 / bpfi
    times = np.arange(0.5 * period, t[-1] - 0.01, period)
    times = times + rng.uniform(-jitter, jitter, times.size) * period
    L = int(8.0 / damping * fs)
    tt = np.arange(L) / fs
    ring = np.exp(-damping * tt) * np.sin(2 * np.pi * fn * tt)
    for t0 in times:
        i = int(round(t0 * fs))
        seg = x[i : i + L]
        seg += (1.0 + am_depth * np.cos(2 * np.pi * fr * t0)) * ring[: seg.size]
    rms = np.sqrt(np.mean(x**2))
    noise = rng.standard_normal(n) * rms * 10 ** (-snr_db / 20)
    tone_hz = fr if tone_hz is None else tone_hz
    tone = tone_ratio * rms * np.sqrt(2) * np.sin(2 * np.pi * tone_hz * t)
    return x + noise + tone


@pytest.fixture(scope="session")
def fault():
    fs, fr, bpfi, fn = 20000.0, 15.8, 231.9, 6000.0
    return dict(x=fault_signal(fs=fs, fr=fr, bpfi=bpfi, fn=fn), fs=fs, fr=fr, bpfi=bpfi, fn=fn)
