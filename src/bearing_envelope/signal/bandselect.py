"""Demodulation-band selectors other than the fast kurtogram: the infogram (Antoni 2016) and the
protrugram (Barszcz & Jabłoński 2011), on a grid of bands wide enough to hold the envelope
lines of interest.

The infogram's maps are :func:`~bearing_envelope.signal.infogram.infogram`'s (the kurtogram's
filter bank); the protrugram band-passes each candidate with zero-phase Butterworth filters.

Infogram (Antoni 2016, MSSP 74, "The infogram: entropic evidence of the signature of repetitive
transients"): for each cell of the 1/3-binary tree of the fast kurtogram, the squared envelope
``SE`` of the band-passed analytic signal; its spectral negentropy in the time domain
``dI_e = < SE/<SE> ln(SE/<SE>) >`` (impulsiveness) and in the frequency domain
``dI_E = < S/<S> ln(S/<S>) >`` with ``S`` the squared magnitude of the squared-envelope spectrum
(cyclostationarity: repetition); the *average* infogram ``(dI_e + dI_E) / 2`` picks the cell.

Protrugram (Barszcz & Jabłoński 2011, MSSP 25): a band of fixed width slides over the spectrum;
for each position the kurtosis of the envelope-spectrum amplitudes (up to ``fmax_env``) measures
how much the envelope spectrum is made of a few lines; the maximum picks the centre.
"""

from __future__ import annotations

import math

import numpy as np

from .bands import NYQUIST_MARGIN
from .envelope import bandpass, envelope
from .infogram import infogram
from .kurtogram import DEFAULT_NLEVEL, max_kurtogram_level
from .validation import check_fs, check_positive, check_signal

__all__ = ["infogram_band", "protrugram_band", "tree_cells", "NO_MIN_BANDWIDTH"]

#: Narrowest band a selection may return (Hz) when none is named: no limit.
NO_MIN_BANDWIDTH = 0.0


def tree_cells(fs: float, max_level: float, min_bandwidth: float = NO_MIN_BANDWIDTH):
    """Cells ``(level, low, high)`` (Hz) of the 1/3-binary tree of the fast kurtogram up to
    ``max_level``: level ``k`` splits ``[0, fs/2]`` into ``2^k`` bands, level ``k + log2(3) - 1``
    into ``3 x 2^(k-1)``; only bands at least ``min_bandwidth`` Hz wide.

    Parameters
    ----------
    fs : float
        Sampling rate (Hz).
    max_level : float
        Deepest level of the tree (binary or 1/3 levels).
    min_bandwidth : float
        Narrowest band kept (Hz).

    Returns
    -------
    list of tuple of (float, float, float)
        ``(level, low_hz, high_hz)`` of every cell kept, by level.
    """
    fs = check_fs(fs)
    nyq = fs / 2.0
    out = []
    k = 0
    while k <= max_level:
        for level, n in ((k, 2 ** k), (k + math.log2(3) - 1, 3 * 2 ** (k - 1))):
            if level > max_level or (k == 0 and level != k) or n < 1:
                continue
            bw = nyq / n
            if bw < min_bandwidth:
                continue
            out.extend((float(level), i * bw, (i + 1) * bw) for i in range(int(n)))
        k += 1
    return out


def _clip(low: float, high: float, fs: float) -> tuple[float, float]:
    return max(low, 0.0), min(high, NYQUIST_MARGIN * fs / 2.0)


def infogram_band(x, fs: float, *, max_level: float = DEFAULT_NLEVEL,
                  min_bandwidth: float = NO_MIN_BANDWIDTH):
    """The cell of the highest average spectral negentropy (Antoni 2016), the maps of
    :func:`~bearing_envelope.signal.infogram.infogram` (the kurtogram's filter bank).

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz).
    max_level : float, default 8
        Deepest level of the tree.
    min_bandwidth : float, default 0
        Cells narrower than this (Hz) are not candidates.

    Returns
    -------
    (low, high) : tuple of float
        The band (Hz; the upper edge at most ``NYQUIST_MARGIN x fs/2``).
    info : dict
        ``level``, ``negentropy_time``, ``negentropy_freq``, ``negentropy`` (the average) of
        the chosen cell, and ``n_cells`` searched.
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=64)
    cells = tree_cells(fs, max_level, min_bandwidth)
    if not cells:
        raise ValueError(f"min_bandwidth = {min_bandwidth:g} Hz: no cell of the tree is that "
                         f"wide (fs/2 = {fs / 2:g} Hz)")
    deepest = max(level for level, _, _ in cells)
    nlevel = max(1, min(math.ceil(deepest - 1e-9), max_kurtogram_level(x.size)))
    ig = infogram(x, fs, nlevel, max_level=max_level,
                  min_bandwidth=min_bandwidth if min_bandwidth > 0 else None)
    c = ig.cells["average"]
    return _clip(*c.band, fs), {"level": c.level, "negentropy": c.value,
                                "negentropy_time": float(ig.time[c.row][c.band_index]),
                                "negentropy_freq": float(ig.spectral[c.row][c.band_index]),
                                "n_cells": len(cells)}


def protrugram_band(x, fs: float, *, bandwidth: float, step: float | None = None,
                    fmax_env: float | None = None):
    """The band of fixed ``bandwidth`` whose envelope spectrum has the largest kurtosis
    (Barszcz & Jabłoński 2011).

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz).
    bandwidth : float
        Width of the sliding band (Hz).
    step : float, optional
        Step of its centre (Hz); default ``bandwidth / 4``.
    fmax_env : float, optional
        Envelope-spectrum bins up to this frequency (Hz) enter the kurtosis; default
        ``bandwidth``.

    Returns
    -------
    (low, high) : tuple of float
        The band (Hz).
    info : dict
        ``kurtosis`` of the chosen band's envelope spectrum and ``n_bands`` searched.
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=64)
    bandwidth = check_positive(bandwidth, "bandwidth")
    step = bandwidth / 4.0 if step is None else check_positive(step, "step")
    fmax_env = bandwidth if fmax_env is None else check_positive(fmax_env, "fmax_env")
    top = NYQUIST_MARGIN * fs / 2.0
    if bandwidth >= top:
        raise ValueError(f"bandwidth = {bandwidth:g} Hz: allowed below {top:g} Hz "
                         f"(0.98 fs/2)")
    f = np.fft.rfftfreq(x.size, 1.0 / fs)
    sel = (f > 0) & (f <= fmax_env)
    best = None
    lows = np.arange(0.0, top - bandwidth + 1e-9, step)
    for low in lows:
        env = envelope(bandpass(x, fs, (low, low + bandwidth)))
        a = np.abs(np.fft.rfft(env - env.mean()))[sel]
        z = (a - a.mean()) / a.std()
        kurt = float(np.mean(z ** 4))
        if best is None or kurt > best[0]:
            best = (kurt, float(low))
    return (best[1], best[1] + bandwidth), {"kurtosis": best[0], "n_bands": int(lows.size)}
