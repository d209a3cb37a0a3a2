"""Zero-phase band-pass, Hilbert envelope and envelope spectrum."""

from __future__ import annotations

import functools

import numpy as np
from scipy import fft as sp_fft

from .bands import NYQUIST_MARGIN, clamp_band
from .spectrum import DEFAULT_WINDOW, amplitude_spectrum
from .validation import check_fs, check_signal
from ..lazy import lazy_module

sp_signal = lazy_module("scipy.signal")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = [
    "DEFAULT_FILTER_ORDER",
    "bandpass",
    "envelope",
    "envelope_spectrum",
    "peak_value",
    "settling_samples",
]


#: Butterworth order of the zero-phase band-pass (applied forward and backward: twice the
#: attenuation), the one default of every band-pass of the package.
DEFAULT_FILTER_ORDER = 4


def bandpass(x, fs: float, band, *, order: int = DEFAULT_FILTER_ORDER):
    r"""Zero-phase Butterworth band-pass (second-order sections, forward-backward).

    Parameters
    ----------
    x : array_like, 1-D
        Real signal.
    fs : float
        Sampling frequency (Hz).
    band : (float, float)
        Edges ``(low, high)`` in Hz with ``0 <= low < high < fs/2``. ``low == 0`` gives a
        low-pass.
    order : int, default 4
        Order of the Butterworth design; :func:`scipy.signal.sosfiltfilt` applies it twice, so
        the magnitude response is :math:`|H|^2` (order ``2 * order``, -6 dB at the edges) with
        zero phase. The ends are extended by even (mirror) padding, which avoids the step that
        the default odd padding creates on an oscillating signal (and its edge transient, which
        would otherwise dominate :func:`peak_value`).

    Returns
    -------
    ndarray
        The filtered signal, same length and unit as ``x``.

    Examples
    --------
    A 1 kHz and a 5 kHz sine of unit amplitude; the 4-6 kHz band keeps the second, whose
    RMS is 1/sqrt(2) (away from the ends' transients):

    >>> import numpy as np
    >>> from bearing_envelope.signal import bandpass
    >>> fs = 20000.0
    >>> t = np.arange(2**14) / fs
    >>> x = np.sin(2 * np.pi * 1000 * t) + np.sin(2 * np.pi * 5000 * t)
    >>> y = bandpass(x, fs, (4000, 6000))
    >>> round(float(np.sqrt(np.mean(y[2000:-2000] ** 2))), 3)
    0.707
    """
    x = check_signal(x, "x", min_length=2)
    return sp_signal.sosfiltfilt(_bandpass_sos(fs, band, order), x, padtype="even")


def _bandpass_sos(fs: float, band, order) -> np.ndarray:
    """The Butterworth design of :func:`bandpass` (second-order sections), arguments checked."""
    fs = check_fs(fs)
    try:
        lo_hz, hi_hz = float(band[0]), float(band[1])
    except (TypeError, ValueError, IndexError):
        raise ValueError(f"band must be a (low, high) pair in Hz, got {band!r}") from None
    low, high, _ = clamp_band(lo_hz, hi_hz, fs, margin=1.0, clamp=False, field="band")
    if isinstance(order, bool) or int(order) != order or int(order) < 1:
        raise ValueError(f"order must be an integer >= 1, got {order!r}")
    return _butter_sos(float(low), float(high), fs, int(order)).copy()


@functools.lru_cache(maxsize=64)
def _butter_sos(low: float, high: float, fs: float, order: int) -> np.ndarray:
    """The design itself, kept for repeated bands (identify-path filters its model of one
    event some 500 times per record in the same band; the design took most of that time)."""
    if low > 0:
        sos = sp_signal.butter(order, [low, high], btype="bandpass", fs=fs, output="sos")
    else:
        sos = sp_signal.butter(order, high, btype="lowpass", fs=fs, output="sos")
    sos.setflags(write=False)
    return sos


#: Relative level below which the band-pass impulse response counts as settled
#: (:func:`settling_samples`): the edge transients of :func:`bandpass` are then < 0.1 %.
SETTLING_TOLERANCE = 1e-3


def settling_samples(fs: float, band, *, order: int = DEFAULT_FILTER_ORDER, tol: float = SETTLING_TOLERANCE) -> int:
    """Samples after which the impulse response of :func:`bandpass`'s filter stays below
    ``tol`` times its maximum: the length of the edge transients of the forward-backward
    filter at each end of a record (even padding mirrors the record about its end sample, which
    puts a kink in any oscillation that does not peak there; the filter rings on it).

    Parameters
    ----------
    fs : float
        Sampling frequency (Hz).
    band : (float, float)
        As in :func:`bandpass`.
    order : int, default 4
        Butterworth order of the band-pass (as in :func:`bandpass`).
    tol : float
        Relative settling level (dimensionless, of the response's maximum).

    Returns
    -------
    int
        Samples (``>= 1``).
    """
    sos = _bandpass_sos(fs, band, order)
    fs = float(fs)
    width = float(band[1]) - float(band[0]) if float(band[0]) > 0 else float(band[1])
    n = 64
    while True:
        # long enough for the slowest pole: grow until the tail is below tol
        imp = np.zeros(n)
        imp[0] = 1.0
        h = np.abs(sp_signal.sosfilt(sos, imp))
        above = np.flatnonzero(h > tol * h.max())
        last = int(above[-1]) + 1
        if last < n // 2 or n > 1000 * fs / max(width, 1e-9):
            return max(1, last)
        n *= 2


def envelope(x, *, squared: bool = False):
    r"""Envelope :math:`|x + i\mathcal{H}x|` (or its square) of a real signal.

    The analytic signal is :func:`scipy.signal.hilbert` of ``x - mean(x)``, zero-padded to
    the next fast FFT length (:func:`scipy.fft.next_fast_len`), truncated to ``len(x)``, plus
    the mean (whose Hilbert transform is zero). At a length with a large prime factor (the
    sweep's records: 411,392 = 2^8 x 1607) the unpadded transform runs Bluestein's algorithm,
    about 8x slower. Like the circular transform it replaces, it distorts only the first and
    last few periods of the carrier (the jump at the record's ends); the mean is removed first
    because the padding would otherwise turn a constant into a box whose Hilbert transform
    reaches across the whole record.

    Parameters
    ----------
    x : array_like, 1-D
        Real, normally band-passed, signal (unit ``U``).
    squared : bool, default False
        Return :math:`|x_a|^2` (unit ``U^2``) instead of :math:`|x_a|` (unit ``U``).

    Returns
    -------
    numpy.ndarray
        The envelope (or its square with ``squared``), same length and unit as ``x`` (squared:
        unit squared).

    Examples
    --------
    A 3 kHz carrier modulated 50 % at 50 Hz: the envelope swings from 0.5 to 1.5.

    >>> import numpy as np
    >>> from bearing_envelope.signal import envelope
    >>> t = np.arange(2**14) / 20000.0
    >>> x = (1 + 0.5 * np.cos(2 * np.pi * 50 * t)) * np.cos(2 * np.pi * 3000 * t)
    >>> e = envelope(x)[2000:-2000]
    >>> round(float(e.min()), 3), round(float(e.max()), 3)
    (0.5, 1.5)
    """
    x = check_signal(x, "x", min_length=2)
    mean = x.mean()
    z = sp_signal.hilbert(x - mean, sp_fft.next_fast_len(x.size))[:x.size]
    e2 = (z.real + mean) ** 2 + z.imag**2
    return e2 if squared else np.sqrt(e2)


def envelope_spectrum(
    x,
    fs: float,
    band,
    *,
    squared: bool = False,
    window=DEFAULT_WINDOW,
    order: int = DEFAULT_FILTER_ORDER,
    return_signal: bool = False,
    clamp: bool = False,
    margin: float = NYQUIST_MARGIN,
    fmax_hz: float | None = None,
):
    r"""Envelope spectrum of ``x`` demodulated in ``band``.

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (unit ``U``).
    fs : float
        Sampling frequency (Hz).
    band : (float, float) or None
        Demodulation band (Hz), see :func:`bandpass`; ``None`` uses ``x`` as it is (the full
        band without filtering). ``(0, fs/2)`` with ``clamp`` is the full band through a
        low-pass at ``margin * fs/2``.
    squared : bool, default False
        Use the squared envelope.
    window : str, tuple or None, default "hann"
        Window of the spectrum, see :func:`amplitude_spectrum`.
    order : int, default 4
        Butterworth order of the band-pass.
    return_signal : bool, default False
        Also return the band-passed signal and the envelope.
    clamp : bool, default False
        Lower an upper edge above ``margin * fs/2`` to it (see
        :func:`~bearing_envelope.signal.clamp_band`) instead of raising.
    margin : float, default 0.98
        Where a clamped upper edge ends, as a fraction of fs/2.
    fmax_hz : float, optional
        Return the spectrum only up to this frequency (see :func:`amplitude_spectrum`).

    Returns
    -------
    f : ndarray
        Frequencies (Hz), ``0 .. fs/2`` in steps of ``fs / len(x)``.
    amplitude : ndarray
        One-sided amplitude of the envelope's fluctuation: a component
        :math:`a\cos(2\pi f t)` of the envelope reads ``a`` (unit ``U``, or ``U^2`` when
        ``squared``). The mean is removed first, so the 0 Hz bin holds only leakage.
    filtered, env : ndarray
        Only with ``return_signal``.

    Raises
    ------
    ValueError
        ``band`` not a ``(low, high)`` pair in Hz, or out of range for ``fs``; a signal or rate
        out of range (:mod:`~.validation`).

    Notes
    -----
    :math:`y = \mathrm{BP}(x)`, :math:`e = |y + i\mathcal{H}y|` (or :math:`e^2`),
    :math:`A = \mathrm{amplitude\_spectrum}(e - \bar e)`. An AM carrier
    :math:`(1 + m\cos 2\pi f_m t)\cos 2\pi f_c t` inside the band gives a line of amplitude
    ``m`` at :math:`f_m`; with ``squared`` the line is ``2 m`` (plus :math:`m^2/2` at
    :math:`2 f_m`).

    Examples
    --------
    A 3 kHz carrier modulated 50 % at 50 Hz: the envelope spectrum of the 2-4 kHz band holds
    one line, at 50 Hz, of amplitude 0.5.

    >>> import numpy as np
    >>> from bearing_envelope.signal import envelope_spectrum
    >>> fs = 20000.0
    >>> t = np.arange(20000) / fs
    >>> x = (1 + 0.5 * np.cos(2 * np.pi * 50.0 * t)) * np.cos(2 * np.pi * 3000.0 * t)
    >>> f, a = envelope_spectrum(x, fs, (2000.0, 4000.0))
    >>> float(f[np.argmax(a)]), round(float(a.max()), 3)
    (50.0, 0.5)
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=2)
    if band is not None and clamp:
        try:
            lo_hz, hi_hz = float(band[0]), float(band[1])
        except (TypeError, ValueError, IndexError):
            raise ValueError(f"band must be a (low, high) pair in Hz, got {band!r}") from None
        band = clamp_band(lo_hz, hi_hz, fs, margin=margin, clamp=True, field="band")[:2]
    y = x if band is None else bandpass(x, fs, band, order=order)
    e = envelope(y, squared=squared)
    f, a = amplitude_spectrum(e - e.mean(), fs, window=window, fmax_hz=fmax_hz)
    if return_signal:
        return f, a, y, e
    return f, a


def peak_value(x, *, skip: int = 0):
    """Largest absolute value of a (band-passed) signal, in its unit, ignoring ``skip``
    samples at each end (the filter's edge transients, :func:`settling_samples`); at most a
    quarter of the record is skipped at each end.

    Parameters
    ----------
    x : array_like
        A real signal.
    skip : int
        Samples ignored at each end (at most a quarter of the record).

    Returns
    -------
    float
        ``max |x|`` over the samples kept.
    """
    x = check_signal(x, "x", min_length=1)
    k = min(int(skip), (x.size - 1) // 4)
    return float(np.max(np.abs(x[k: x.size - k])))


