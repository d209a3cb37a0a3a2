"""One-sided amplitude spectra and amplitudes at target frequencies."""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy import fft as sp_fft
from scipy.optimize import minimize_scalar

from ..checks import check_positive
from .validation import check_fs, check_signal
from ..lazy import lazy_module

sp_signal = lazy_module("scipy.signal")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = ["DEFAULT_WINDOW", "TOLERANCE_FRACTION", "TOLERANCE_MAX_SPACING", "TOLERANCE_MIN_BINS",
           "amplitude_spectrum", "amplitude_at", "default_tolerance", "prewhiten"]

#: The analysis window of every spectrum (Hann: an amplitude-correct peak with an equivalent
#: noise bandwidth of 1.5 bins), unless a caller names another.
DEFAULT_WINDOW = "hann"


def _window(window, n: int) -> np.ndarray:
    """The window as an array of ``n`` values (named windows are cached, read-only)."""
    if isinstance(window, np.ndarray):
        w = np.asarray(window, dtype=np.float64)
        if w.shape != (n,):
            raise ValueError(f"window array has shape {w.shape}, expected ({n},)")
        return w
    if window is None:
        window = "boxcar"
    if isinstance(window, list):
        window = tuple(window)
    try:
        return _named_window(window, int(n))
    except TypeError:  # unhashable spec
        return sp_signal.get_window(window, n, fftbins=True)


@functools.lru_cache(maxsize=32)
def _named_window(window, n: int) -> np.ndarray:
    w = sp_signal.get_window(window, n, fftbins=True)
    w.setflags(write=False)
    return w


def amplitude_spectrum(x, fs: float, *, window=DEFAULT_WINDOW, detrend: bool = False, workers=None,
                       fmax_hz: float | None = None):
    r"""One-sided amplitude spectrum with amplitude-correct scaling.

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (any unit ``U``).
    fs : float
        Sampling frequency (Hz), > 0.
    window : str, tuple or ndarray, default "hann"
        Window, as accepted by :func:`scipy.signal.get_window` (periodic form), or an array of
        ``len(x)`` values. ``None`` or ``"boxcar"`` for none.
    detrend : bool, default False
        Subtract the mean before the transform (the 0 Hz line then holds only window leakage).
    workers : int, optional
        Passed to :func:`scipy.fft.rfft`.
    fmax_hz : float, optional
        Only the bins up to this frequency (and the next one) are returned; the same bins as
        the full spectrum. When they are a small part of it and ``n`` has a large prime factor
        (the FFT then runs Bluestein's algorithm), they are computed by a chirp-z zoom
        transform (:class:`scipy.signal.ZoomFFT`): about 3x faster, equal to 1e-9 relative.

    Returns
    -------
    f : ndarray
        Frequencies ``k fs / n`` (Hz), ``k = 0 .. n//2`` (or up to ``fmax_hz``).
    amplitude : ndarray
        Amplitude in ``U``: a sinusoid :math:`a\cos(2\pi f_k t + \phi)` centred on bin ``k``
        reads ``a``; a constant ``c`` reads ``c`` at 0 Hz.

    Notes
    -----
    With window :math:`w` and :math:`X_k = \sum_n w_n x_n e^{-2\pi i k n/N}`,

    .. math:: A_0 = \frac{|X_0|}{\sum_n w_n}, \quad
              A_k = \frac{2 |X_k|}{\sum_n w_n}\ (0 < k < N/2), \quad
              A_{N/2} = \frac{|X_{N/2}|}{\sum_n w_n}.

    This is the coherent-gain (amplitude) correction. Between bins the reading drops by the
    window's scalloping loss (up to 3.9 dB for the rectangular window, 1.4 dB for Hann,
    < 0.02 dB for "flattop"); :func:`amplitude_at` can correct it by interpolation.

    Examples
    --------
    >>> import numpy as np
    >>> fs, n = 1000.0, 1000
    >>> t = np.arange(n) / fs
    >>> f, a = amplitude_spectrum(2.0 * np.sin(2 * np.pi * 50.0 * t), fs)
    >>> round(float(a[50]), 6)
    2.0
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=2)
    n = x.size
    if detrend:
        x = x - x.mean()
    w = _window(window, n)
    spec = _one_sided(x * w, _n_bins(n, fs, fmax_hz), workers)
    amp = np.abs(spec) * (2.0 / w.sum())
    amp[0] *= 0.5
    if n % 2 == 0 and amp.size == n // 2 + 1:
        amp[-1] *= 0.5
    f = np.arange(amp.size) * (fs / n)
    return f, amp


def _n_bins(n: int, fs: float, fmax_hz: float | None) -> int:
    """Bins ``0 .. k`` of a length-``n`` spectrum with ``k fs / n`` just above ``fmax_hz``."""
    full = n // 2 + 1
    if fmax_hz is None:
        return full
    fmax_hz = check_positive(fmax_hz, "fmax_hz")
    return min(full, int(math.floor(fmax_hz * n / fs)) + 2)


#: The zoom transform is used below this fraction of the one-sided bins (its cost is about that
#: of one fast transform of length n + m, against Bluestein's two of length >= 2n).
ZOOM_MAX_FRACTION = 0.125


def _one_sided(y: np.ndarray, m: int, workers=None) -> np.ndarray:
    """The first ``m`` bins of ``rfft(y)``: by :class:`scipy.signal.ZoomFFT` when they are few
    and ``len(y)`` is not a fast FFT length, else by the real FFT."""
    n = y.size
    if m <= ZOOM_MAX_FRACTION * (n // 2 + 1) and sp_fft.next_fast_len(n, real=True) != n:
        return _zoom(n, m)(y)
    return sp_fft.rfft(y, workers=workers)[:m]


@functools.lru_cache(maxsize=8)
def _zoom(n: int, m: int):
    """Chirp-z transform onto bins ``k / n``, ``k = 0 .. m-1`` (cached: its chirps take as long
    to build as one transform)."""
    return sp_signal.ZoomFFT(n, [0.0, (m - 1) / n], m=m, fs=1.0, endpoint=True)


#: Named windows are evaluated at this length for the response between bins: their normalised
#: response at a given offset in bins is independent of the length to O((nu/m)^2) ~ 1e-7.
_RESPONSE_LENGTH = 4096


def _window_response(window, n: int, delta: np.ndarray) -> np.ndarray:
    """|W(delta)| / W(0) of the length-n window at offsets of ``delta`` bins."""
    if not isinstance(window, np.ndarray) and n > _RESPONSE_LENGTH:
        n = _RESPONSE_LENGTH
    w = _window(window, n)
    k = np.arange(n)
    e = np.exp(-2j * np.pi * np.outer(np.atleast_1d(delta), k) / n)
    return np.abs(e @ w) / w.sum()


def _fit_offset(a3, window, n):
    """Offset ``delta`` (bins, |delta| <= 0.5) of a sinusoid from the peak bin of three
    amplitudes ``a3 = (a[i-1], a[i], a[i+1])``, fitting the window's own response
    ``R(j - delta)``, j = -1, 0, 1, to their log-ratios; returns ``(delta, R(-delta))``."""
    a3 = np.maximum(np.asarray(a3, dtype=np.float64), 1e-300)
    obs = np.log(a3[[0, 2]] / a3[1])

    def resp(d):
        return np.maximum(_window_response(window, n, np.array([-1.0 - d, -d, 1.0 - d])), 1e-300)

    def cost(d):
        r = resp(d)
        model = np.log(r[[0, 2]] / r[1])
        return float(np.sum((model - obs) ** 2))

    res = minimize_scalar(cost, bounds=(-0.5, 0.5), method="bounded",
                          options={"xatol": 1e-6})
    d = float(res.x)
    return d, float(resp(d)[1])


def amplitude_at(
    f,
    amplitude,
    target: float,
    tolerance: float,
    *,
    interpolate: bool = False,
    window=DEFAULT_WINDOW,
    n: int | None = None,
) -> tuple[float, float]:
    r"""Largest spectral line within ``target +- tolerance``.

    Parameters
    ----------
    f, amplitude : ndarray
        A spectrum from :func:`amplitude_spectrum` or :func:`envelope_spectrum` (uniform ``f``).
    target : float
        Frequency looked for (Hz), >= 0.
    tolerance : float
        Half-width of the search window (Hz), >= 0. The bin nearest ``target`` is always
        searched, so 0 means "the nearest bin".
    interpolate : bool, default False
        Refine the peak: the offset :math:`\delta` (bins, within +-0.5) of a sinusoid from
        the peak bin is fitted so that the window's own normalised response
        :math:`R(\nu) = |W(\nu)|/W(0)` at :math:`j - \delta` (j = -1, 0, 1) matches the
        log-ratios of the three bins; the frequency is :math:`f_i + \delta\,\Delta f` and the
        amplitude :math:`A_i / R(-\delta)` (scalloping correction). Exact for an isolated
        sinusoid with any window (the negative-frequency image is neglected). Needs ``window`` and ``n`` (the
        length of the transformed signal, default ``2 (len(f) - 1)``).
    window : str, tuple or ndarray, default "hann"
        The window used for the spectrum (only for ``interpolate``).
    n : int, optional
        Length of the signal behind the spectrum (only for ``interpolate``).

    Returns
    -------
    frequency : float
        Frequency of the peak (Hz): the bin's frequency, or the interpolated one.
    amplitude : float
        The peak amplitude, in the unit of ``amplitude`` (scalloping-corrected if
        ``interpolate``).

    Raises
    ------
    ValueError
        If ``target`` is beyond the spectrum or the arguments are invalid.
    """
    f = np.asarray(f, dtype=np.float64)
    amplitude = np.asarray(amplitude, dtype=np.float64)
    if f.size < 2 or f.shape != amplitude.shape:
        raise ValueError("f and amplitude must be 1-D arrays of the same length >= 2")
    target = float(target)
    tolerance = float(tolerance)
    if not math.isfinite(target) or target < 0:
        raise ValueError(f"target must be a finite frequency >= 0 Hz, got {target!r}")
    if not math.isfinite(tolerance) or tolerance < 0:
        raise ValueError(f"tolerance must be a finite number >= 0 Hz, got {tolerance!r}")
    df = f[1] - f[0]
    if target > f[-1] + 0.5 * df:
        raise ValueError(f"target {target:g} Hz is beyond the spectrum (up to {f[-1]:g} Hz)")
    i0 = int(round(target / df))
    lo = max(0, min(i0, int(math.ceil((target - tolerance) / df - 1e-9))))
    hi = min(f.size - 1, max(i0, int(math.floor((target + tolerance) / df + 1e-9))))
    i = lo + int(np.argmax(amplitude[lo : hi + 1]))
    freq, amp = float(f[i]), float(amplitude[i])
    if interpolate and 0 < i < f.size - 1:
        nn = int(n) if n is not None else 2 * (f.size - 1)
        delta, resp = _fit_offset(amplitude[i - 1 : i + 2], window, nn)
        freq = float(f[i] + delta * df)
        amp = amp / resp if resp > 0 else amp
    return freq, amp


#: Default search half-width of a line, relative to its frequency (dimensionless): 0.2 %
#: covers the residual speed uncertainty of a harmonic searched around k x a found line.
TOLERANCE_FRACTION = 0.002
#: ... and at least this many bins (the bin of the found line is uncertain by half a bin).
TOLERANCE_MIN_BINS = 2.0
#: ... and at most this fraction of the sideband spacing (Hz / Hz), so that neighbouring
#: sidebands never share a search window.
TOLERANCE_MAX_SPACING = 0.25


def default_tolerance(target: float, df: float, fr: float | None = None) -> float:
    """Default search half-width (Hz): ``max(TOLERANCE_MIN_BINS df, TOLERANCE_FRACTION
    target)`` = ``max(2 df, 0.002 target)``, at most ``TOLERANCE_MAX_SPACING fr`` = ``fr / 4``
    (``fr``: the sideband spacing, Hz; ``df``: the bin spacing, Hz).

    Parameters
    ----------
    target : float
        The line's frequency (Hz).
    df : float
        Bin spacing of the spectrum (Hz).
    fr : float, optional
        Sideband spacing (Hz), bounding the half-width.

    Returns
    -------
    float
        The search half-width (Hz).
    """
    tol = max(TOLERANCE_MIN_BINS * df, TOLERANCE_FRACTION * abs(target))
    if fr is not None:
        tol = min(tol, TOLERANCE_MAX_SPACING * fr)
    return max(tol, 0.0)


def prewhiten(x) -> np.ndarray:
    r"""Cepstrum pre-whitening (Borghesani et al. 2013, MSSP 36): the signal with a flat
    amplitude spectrum and its phase kept.

    Setting the real cepstrum to zero at every quefrency (the 0 quefrency included) divides
    each Fourier coefficient by its magnitude: :math:`x_w = \mathcal{F}^{-1}[X / |X|]`. The
    discrete lines (shaft harmonics, gear mesh) and the resonances are flattened together, so
    the impulses of a fault stand out in any band of :math:`x_w`, and its (squared) envelope
    spectrum shows their repetition rate without a band search.

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (any unit), at least 16 samples.

    Returns
    -------
    ndarray
        The whitened signal, same length, dimensionless: each bin of its spectrum has
        magnitude 1, except 0 Hz (and bins of zero magnitude), which are 0.
    """
    x = check_signal(x, "x", min_length=16)
    spec = sp_fft.rfft(x - x.mean())
    mag = np.abs(spec)
    spec = np.divide(spec, mag, out=np.zeros_like(spec), where=mag > 0)
    spec[0] = 0.0  # the mean is removed: 0 Hz holds only rounding
    return sp_fft.irfft(spec, n=x.size)
