"""Discrete/random separation (DRS, Antoni & Randall 2004) and the squared envelope spectra of
the separated or pre-whitened signal.

**DRS** (Antoni & Randall 2004, MSSP 18, "Unsupervised noise cancellation for vibration
signals: part II - a novel frequency-domain algorithm"): a discrete (periodic) component stays
coherent with itself after a delay ``D``, a random component whose correlation is shorter than
``D`` does not. With Welch averages over segments of ``nperseg`` samples (``D >= nperseg``: a
segment and its delayed twin share no sample, else the random part is coherent with itself
through the shared samples),

    ``G(f) = |S_{x x_D}(f)| / sqrt(S_{xx}(f) S_{x_D x_D}(f))``

(``x_D`` the signal delayed by ``D``) is the fraction of the power at ``f`` that is discrete:
1 on a line, ~0 between the lines. This module applies ``G`` as a zero-phase gain to the
whole record's spectrum (``G`` interpolated linearly from the segment grid to the record's
bins; between the lines ``G`` is the estimator's bias, about ``sqrt(pi / (4 K))`` for ``K``
segments, 0.12 for a 10 s record at 12 kHz): ``discrete = IFFT(G X)``,
``random = x - discrete``. The paper builds a filter from the complex
cross-spectrum and applies it to the delayed signal; the magnitude form used here is that
filter's gain without its delay, so the separated parts stay aligned with ``x``.

**Cepstrum pre-whitening** (Sawalhi & Randall; Borghesani et al. 2013):
:func:`~bearing_envelope.signal.spectrum.prewhiten`. :func:`prewhitened_ses` is Smith &
Randall's (2015) "method 2": the squared envelope spectrum of the full band of the whitened
signal.
"""

from __future__ import annotations

import numpy as np
from scipy import fft as sp_fft

from .envelope import envelope_spectrum
from .spectrum import DEFAULT_WINDOW, prewhiten
from .validation import check_fs, check_positive, check_signal
from ..lazy import lazy_module

sp_signal = lazy_module("scipy.signal")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = ["DRS_NPERSEG", "discrete_random_separation", "drs_gain",
           "prewhitened_ses"]

#: Welch segment of the DRS (samples): its resolution ``fs / nperseg`` must separate the shaft
#: harmonics (29 Hz at 1730 rpm) with bins to spare: 2.9 Hz at 12 kHz, 10 bins between them.
DRS_NPERSEG = 4096


def drs_gain(x, fs: float, *, delay_s: float | None = None, nperseg: int = DRS_NPERSEG):
    """The DRS gain ``G(f) = |S_{x x_D}| / sqrt(S_{xx} S_{x_D x_D})`` on the Welch grid.

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (any unit), longer than ``2 nperseg`` + the delay.
    fs : float
        Sampling frequency (Hz).
    delay_s : float, optional
        Delay ``D`` (s); default ``nperseg / fs`` (the shortest delay at which a segment and
        its delayed twin share no sample). Longer than the correlation of the random part
        (the decay of a structural resonance after an impulse, a few ms), shorter than the time
        over which a discrete component drifts in phase.
    nperseg : int, default :data:`DRS_NPERSEG`
        Welch segment (samples, Hann window, half overlap).

    Returns
    -------
    f : ndarray
        Frequencies (Hz), ``0 .. fs/2`` in steps of ``fs / nperseg``.
    gain : ndarray
        ``G(f)`` clipped to ``[0, 1]``.
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=16)
    nper = int(nperseg)
    d = nper if delay_s is None else int(round(check_positive(delay_s, "delay_s") * fs))
    if nper < 16 or x.size - d < 2 * nper:
        raise ValueError(f"x has {x.size} samples: the DRS needs at least 2 x nperseg "
                         f"({nper}) + the delay ({d} samples)")
    a, b = x[d:], x[:-d]
    f, sab = sp_signal.csd(a, b, fs=fs, nperseg=nper, window="hann")
    _, saa = sp_signal.welch(a, fs=fs, nperseg=nper, window="hann")
    _, sbb = sp_signal.welch(b, fs=fs, nperseg=nper, window="hann")
    den = np.sqrt(saa * sbb)
    g = np.divide(np.abs(sab), den, out=np.zeros_like(den), where=den > 0)
    return f, np.clip(g, 0.0, 1.0)


def discrete_random_separation(x, fs: float, *, delay_s: float | None = None,
                               nperseg: int = DRS_NPERSEG):
    """Split a signal into its discrete (periodic) and random parts (DRS).

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (unit ``U``).
    fs : float
        Sampling frequency (Hz).
    delay_s, nperseg
        See :func:`drs_gain`.

    Returns
    -------
    discrete, random : ndarray
        ``discrete + random == x`` (unit ``U``); the mean goes to ``discrete``.
    """
    x = check_signal(x, "x", min_length=16)
    fg, g = drs_gain(x, fs, delay_s=delay_s, nperseg=nperseg)
    spec = sp_fft.rfft(x)
    f = sp_fft.rfftfreq(x.size, 1.0 / check_fs(fs))
    gain = np.interp(f, fg, g)
    gain[0] = 1.0
    discrete = sp_fft.irfft(spec * gain, n=x.size)
    return discrete, x - discrete


def prewhitened_ses(x, fs: float, *, window=DEFAULT_WINDOW):
    """Squared envelope spectrum of the cepstrum-pre-whitened signal, full band (Smith &
    Randall 2015, method 2).

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz).
    window : str or tuple, default "hann"
        Window of the spectrum.

    Returns
    -------
    f, amplitude : ndarray
        The spectrum (Hz; dimensionless: the whitened signal's squared envelope).
    """
    fs = check_fs(fs)
    return envelope_spectrum(prewhiten(x), fs, None, squared=True, window=window)
