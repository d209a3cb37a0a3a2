r"""Second-order cyclostationary evidence: the spectral coherence from the cyclic modulation
spectrum and the enhanced envelope spectrum (EES).

**Cyclic modulation spectrum** (CMS; Antoni, Xin & Hamzaoui 2017, MSSP 92, "Fast computation
of the spectral correlation", its first step): the short-time Fourier transform ``X(k, f)``
(Hann window of ``nwin`` samples, hop ``R``), the power ``P(k, f) = |X(k, f)|^2`` of each
narrow band over time, and the Fourier transform of ``P`` over the frames ``k``:

.. math:: \mathrm{CMS}(\alpha, f) = \frac{2 \left|\sum_k v_k P(k, f) e^{-i 2\pi \alpha k R / f_s}
   \right|}{\sum_k v_k}

(``v`` a Hann window over the frames, the factor 2 makes a power modulation
``(1 + m \cos 2\pi\alpha t)`` read ``m`` like :func:`~bearing_envelope.signal.amplitude_spectrum`).
The spectral **coherence** is the CMS divided by the band's mean power ``CMS(0, f)`` and by the
window's response at ``alpha``, ``R_w(\alpha) = |\sum_n w_n^2 e^{-i 2\pi\alpha n / f_s}| /
\sum_n w_n^2`` (a modulation at ``alpha`` reaches the power of a band through pairs of
frequencies ``alpha`` apart, both inside the window's passband): the coherence does not depend
on how loud each band is. The cyclic frequencies run to ``fs / (2 R)``; the CMS approximates
the spectral correlation for ``alpha`` well inside the window's bandwidth (``nwin`` short), the
correction of the fast spectral correlation for larger ``alpha`` is not needed here.

**Enhanced envelope spectrum** (Antoni 2017; Abboud et al.): the coherence averaged over the
spectral frequencies of a band, ``EES(\alpha) = \langle |\gamma(\alpha, f)| \rangle_f``: every
narrow band contributes the repetition it carries, whitened, so a weak resonance excited by
the fault counts as much as a loud band without it.
"""

from __future__ import annotations

import numpy as np
from scipy import fft as sp_fft

from .validation import check_fs, check_positive, check_signal
from ..lazy import lazy_module

sp_signal = lazy_module("scipy.signal")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = ["CMS_NWIN", "enhanced_envelope_spectrum", "spectral_coherence"]

#: STFT window of the CMS (samples): short, so that the window's passband (+-2 bins of a Hann
#: window, +-1500 Hz at 12 kHz) spans the cyclic frequencies sought (a few hundred Hz).
CMS_NWIN = 32


def _hop(fs: float, alpha_max_hz: float, nwin: int) -> int:
    """The largest hop (samples, <= nwin / 2) whose frame rate keeps ``alpha_max_hz`` below
    its Nyquist frequency with a 25 % margin."""
    hop = int(fs / (2.5 * alpha_max_hz))
    if hop < 1:
        raise ValueError(f"alpha_max_hz = {alpha_max_hz:g} Hz: allowed below fs / 2.5 = "
                         f"{fs / 2.5:g} Hz")
    return max(1, min(hop, nwin // 2))


def spectral_coherence(x, fs: float, *, alpha_max_hz: float, nwin: int = CMS_NWIN):
    """Spectral coherence ``|gamma(alpha, f)|`` from the cyclic modulation spectrum.

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz).
    alpha_max_hz : float
        Highest cyclic frequency needed (Hz); sets the hop ``R`` (frame rate >= 2.5 x it).
    nwin : int, default :data:`CMS_NWIN`
        STFT window (samples, Hann).

    Returns
    -------
    alpha : ndarray
        Cyclic frequencies (Hz), ``0 .. fs / (2R)``, step ``fs / (K R)`` (K frames: about
        ``fs / len(x)``).
    f : ndarray
        Spectral frequencies (Hz) of the STFT bins, ``0 .. fs/2`` in steps of ``fs / nwin``.
    coherence : ndarray, shape (len(alpha), len(f))
        ``|gamma(alpha, f)|`` (dimensionless; a power modulation of depth m reads m).

    Raises
    ------
    ValueError
        ``nwin`` outside 8 .. ``len(x) / 8``.
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=16)
    alpha_max = check_positive(alpha_max_hz, "alpha_max_hz")
    nwin = int(nwin)
    if nwin < 8 or nwin > x.size // 8:
        raise ValueError(f"nwin = {nwin}: allowed 8 .. len(x) / 8 = {x.size // 8}")
    hop = _hop(fs, alpha_max, nwin)
    w = sp_signal.windows.hann(nwin, sym=False)
    # the frames wholly inside the record, transformed in one call (scipy's ShortTimeFFT
    # loops over the frames in Python: 20x slower at a hop of a few samples)
    frames = np.lib.stride_tricks.sliding_window_view(x - x.mean(), nwin)[::hop]
    p = (np.abs(sp_fft.rfft(frames * w, axis=1)) ** 2).T  # (f, frames)
    f = sp_fft.rfftfreq(nwin, 1.0 / fs)
    v = sp_signal.windows.hann(p.shape[1], sym=False)
    cms = 2.0 * np.abs(sp_fft.rfft(p * v, axis=1)) / v.sum()
    mean = (p * v).sum(axis=1) / v.sum()
    alpha = sp_fft.rfftfreq(p.shape[1], hop / fs)
    n = np.arange(nwin)
    rw = np.abs(np.exp(-2j * np.pi * np.outer(alpha, n) / fs) @ (w ** 2)) / np.sum(w ** 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        coh = cms.T / mean[None, :] / rw[:, None]
    coh[:, mean <= 0] = 0.0
    return alpha, f, coh


def enhanced_envelope_spectrum(x, fs: float, *, alpha_max_hz: float, band=None,
                               nwin: int = CMS_NWIN):
    """Enhanced envelope spectrum: the spectral coherence averaged over a band.

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz).
    alpha_max_hz : float
        Highest cyclic frequency needed (Hz).
    band : (float, float), optional
        Spectral band (Hz) whose STFT bins are averaged; default every bin strictly between 0
        and fs/2 (their windows straddle neither edge of the spectrum).
    nwin : int, default :data:`CMS_NWIN`
        STFT window (samples).

    Returns
    -------
    alpha, ees : ndarray
        Cyclic frequencies (Hz) and the averaged coherence (dimensionless).

    Raises
    ------
    ValueError
        A band that holds no STFT bin.
    """
    alpha, f, coh = spectral_coherence(x, fs, alpha_max_hz=alpha_max_hz, nwin=nwin)
    if band is None:
        sel = (f > 0) & (f < f[-1])
    else:
        lo, hi = float(band[0]), float(band[1])
        sel = (f >= lo) & (f <= hi) & (f > 0) & (f < f[-1])
    if not sel.any():
        raise ValueError(f"band = {band!r}: no STFT bin (step {f[1]:g} Hz) lies inside it")
    return alpha, coh[:, sel].mean(axis=1)
