r"""Cycle-synchronous averages: the shape of a repeating event, read from the record itself.

A train of events repeating at a rate :math:`f` (a fault's impulses) is folded onto one period:
each sample goes to the bin of its phase :math:`(t f) \bmod 1` and each bin is averaged over
the record's cycles. Whatever repeats at :math:`f` adds coherently; noise and content at other
rates average towards their mean. The fold of a squared envelope is the *coherent* part of its
spectrum's harmonic series: its Fourier coefficient at harmonic k is the squared envelope
spectrum's line at :math:`k f` (over the record's length), so the fold's width is what sets the
harmonics' roll-off. For a Gaussian burst of r.m.s. width :math:`\sigma` (fraction of the
period) the harmonics fall as :math:`\exp(-(2\pi k \sigma)^2/2)`.

Folded at the rate of one element of a set of Z equally spaced ones (a cage's turn, ``f / Z``),
the fold shows each element's own event: how far the elements' events differ, persistently, over
the record.

The rate must be known to far better than the spectrum's resolution (a drift of ``delta f`` over
a record of ``T`` seconds smears the fold by ``delta f T`` periods): :func:`cycle_rate` refines
it by maximising the magnitude of the record's Fourier transform at the rate.
"""

from __future__ import annotations

import math

import numpy as np

from ..lazy import lazy_module
from .validation import check_fs, check_signal

sp_signal = lazy_module("scipy.signal")  # imported on first use (docs/architecture.md, lazy.py)
sp_optimize = lazy_module("scipy.optimize")

#: Half-width of the search around a nominal rate, as a fraction of it (+- 1 %).
RATE_SEARCH = 0.01

__all__ = ["RATE_SEARCH", "cycle_rate", "synchronous_average", "burst_width", "element_windows",
           "element_levels"]

#: Fraction of the burst's peak (above the floor) below which a synchronous average counts as
#: floor in :func:`burst_width`.
BURST_LEVEL = 0.1
#: Percentile of a synchronous average taken as its floor (the lower quartile: a burst spread
#: over half the cycle still leaves it on the floor).
FLOOR_PERCENTILE = 25.0
#: Cycles a record must hold for a synchronous average (and a rate refinement).
MIN_CYCLES = 8
#: Grid of the rate search, in steps of the record's resolution ``1 / T``.
RATE_GRID_STEP = 0.05
#: The rate search stops when its bracket is this small, relative to ``1 / T``.
RATE_TOLERANCE = 1e-4


def _check_rate(rate_hz, fs: float, n: int, name: str = "rate_hz") -> float:
    rate = float(rate_hz)
    if not math.isfinite(rate) or not 0.0 < rate < fs / 2:
        raise ValueError(f"{name}: got {rate_hz!r}; allowed: a rate in (0, fs/2 = {fs / 2:g}) Hz")
    if n * rate / fs < MIN_CYCLES:
        raise ValueError(f"{name}: the record holds {n * rate / fs:.1f} cycles of {rate:g} Hz; "
                         f"allowed: at least {MIN_CYCLES}")
    return rate


def _magnitude(x: np.ndarray, fs: float, f: float) -> float:
    """``|sum x[n] exp(-2 pi i f n / fs)|`` (x zero-mean)."""
    ph = np.exp(-2j * np.pi * f / fs * np.arange(x.size))
    return float(abs(np.dot(x, ph)))


def cycle_rate(x, fs: float, rate_hz: float, *, search: float = RATE_SEARCH) -> float:
    r"""The rate, near a nominal one, at which a signal repeats most strongly.

    Maximises :math:`|\sum_n (x_n - \bar x) e^{-2\pi i f n / f_s}|` over
    :math:`f \in f_0 (1 \pm s)`: on a grid of :data:`RATE_GRID_STEP` x the record's resolution
    ``fs / n`` (:func:`scipy.signal.zoom_fft`: memory of the order of the record, whatever its
    length), then by :func:`scipy.optimize.minimize_scalar` (bounded) about the best grid
    point down to :data:`RATE_TOLERANCE` x ``fs / n``.

    Parameters
    ----------
    x : array_like, 1-D
        The signal (a squared envelope, usually), sampled at ``fs``.
    fs : float
        Sampling rate (Hz).
    rate_hz : float
        Nominal rate :math:`f_0` (Hz).
    search : float, default 0.01
        Relative half-width :math:`s` of the search (0 < s < 0.5).

    Returns
    -------
    float
        The refined rate (Hz).

    Raises
    ------
    ValueError
        On a signal holding fewer than :data:`MIN_CYCLES` cycles, a rate outside (0, fs/2) or a
        search width outside (0, 0.5).
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=4)
    f0 = _check_rate(rate_hz, fs, x.size)
    if not 0.0 < float(search) < 0.5:
        raise ValueError(f"search: got {search!r}; allowed: a relative width in (0, 0.5)")
    x = x - x.mean()
    res = fs / x.size
    lo, hi = f0 * (1 - search), f0 * (1 + search)
    m = int(math.ceil((hi - lo) / (RATE_GRID_STEP * res))) + 1
    mags = np.abs(sp_signal.zoom_fft(x, [lo, hi], m=m, fs=fs, endpoint=True))
    step = (hi - lo) / (m - 1)
    peak = lo + int(np.argmax(mags)) * step
    best = sp_optimize.minimize_scalar(lambda f: -_magnitude(x, fs, f), method="bounded",
                                       bounds=(peak - step, peak + step),
                                       options={"xatol": RATE_TOLERANCE * res})
    return float(best.x)


def synchronous_average(x, fs: float, rate_hz: float, *, bins: int = 200) -> np.ndarray:
    """Mean of a signal over the cycles of a rate, by phase bin.

    Sample n goes to bin ``floor(bins * ((n / fs) rate mod 1))``; each bin holds the mean of
    its samples (every bin receives samples when ``fs / rate >= bins``).

    Parameters
    ----------
    x : array_like, 1-D
        The signal, sampled at ``fs``.
    fs : float
        Sampling rate (Hz).
    rate_hz : float
        Rate of the cycle (Hz); refine it with :func:`cycle_rate` first.
    bins : int, default 200
        Phase bins per cycle, 2 .. ``fs / rate_hz``.

    Returns
    -------
    numpy.ndarray
        The average, shape ``(bins,)``, bin j covering phases ``[j, j + 1) / bins`` of the
        cycle starting at the record's first sample.

    Raises
    ------
    ValueError
        On fewer than :data:`MIN_CYCLES` cycles, a rate outside (0, fs/2) or bins outside the
        allowed range.
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=4)
    rate = _check_rate(rate_hz, fs, x.size)
    nb = int(bins)
    if nb != bins or not 2 <= nb <= fs / rate:
        raise ValueError(f"bins: got {bins!r}; allowed: an integer 2 .. fs / rate_hz = "
                         f"{fs / rate:.1f}")
    phase = np.mod(np.arange(x.size) * (rate / fs), 1.0)
    idx = np.minimum((phase * nb).astype(np.intp), nb - 1)
    counts = np.bincount(idx, minlength=nb)
    return np.bincount(idx, weights=x, minlength=nb) / counts


def burst_width(avg, *, level: float = BURST_LEVEL) -> float:
    r"""R.m.s. width of the burst in a synchronous average, as a fraction of the cycle.

    The part of the average more than ``level`` x its peak above the floor (the average's
    lower quartile :math:`q_{25}`), :math:`w_j = a_j - q_{25}` where that exceeds
    :math:`\ell\,(\max a - q_{25})` and 0 elsewhere, is read as a distribution on
    the circle; the width is its circular standard deviation about its mean direction,
    :math:`\sigma = \sqrt{-2 \ln R} / (2\pi)` with
    :math:`R = |\sum_j w_j e^{2\pi i j/m}| / \sum_j w_j` (the r.m.s. width of a burst narrow
    against the cycle). The level keeps the floor's positive noise out: spread over the whole
    cycle, a pedestal of a few per cent of the burst's weight would double a narrow burst's
    width. For a Gaussian burst of r.m.s. width :math:`s` and the default level 0.1 the width
    is that of the Gaussian cut at :math:`\pm 2.146 s`: :math:`0.907 s`.

    Parameters
    ----------
    avg : array_like, 1-D
        A synchronous average (:func:`synchronous_average`), m >= 4 bins.
    level : float, default :data:`BURST_LEVEL`
        Fraction of the peak above the floor below which the average counts as floor, in
        (0, 1).

    Returns
    -------
    float
        The width, fraction of the cycle (divide by the rate for seconds); ``inf`` for an
        average with nothing above its floor or with no preferred phase (R = 0).
    """
    a = check_signal(avg, "avg", min_length=4)
    if not 0.0 < float(level) < 1.0:
        raise ValueError(f"level: got {level!r}; allowed: a fraction in (0, 1)")
    w = a - np.percentile(a, FLOOR_PERCENTILE)
    peak = w.max()
    if peak <= 0:
        return math.inf
    w = np.where(w > level * peak, w, 0.0)
    ph = np.exp(2j * np.pi * np.arange(a.size) / a.size)
    r = abs(np.dot(w, ph)) / w.sum()
    return math.sqrt(-2.0 * math.log(r)) / (2 * math.pi) if r > 0 else math.inf


def element_windows(avg, n_elements: int) -> list[np.ndarray]:
    """A synchronous average over a set of equally spaced elements, cut into one window each.

    The average (folded at the rate of the whole set, e.g. a cage's turn) is cut into
    ``n_elements`` equal windows (to a bin), the first starting half a window before the
    average's strongest bin, so that each window centres on one element's event; the floor
    (the average's lower quartile) is subtracted.

    Parameters
    ----------
    avg : array_like, 1-D
        A synchronous average at the set's rate, at least 2 bins per element.
    n_elements : int
        Elements in the set (>= 2), e.g. the rolling elements a cage carries.

    Returns
    -------
    list of numpy.ndarray
        The ``n_elements`` windows in the order the elements pass, first the element holding
        the average's strongest bin.
    """
    a = check_signal(avg, "avg", min_length=4)
    z = int(n_elements)
    if z != n_elements or z < 2 or a.size < 2 * z:
        raise ValueError(f"n_elements: got {n_elements!r}; allowed: an integer 2 .. "
                         f"{a.size // 2} (half the average's bins)")
    start = int(np.argmax(a)) - int(round(a.size / (2 * z)))
    a = np.roll(a, -start) - np.percentile(a, FLOOR_PERCENTILE)
    edges = np.round(np.arange(z + 1) * a.size / z).astype(int)
    return [a[edges[j]:edges[j + 1]] for j in range(z)]


def element_levels(avg, n_elements: int) -> np.ndarray:
    """Each element's event in a synchronous average over a set of equally spaced elements.

    Each window of :func:`element_windows` summed: the element's area above the floor, in the
    unit of ``avg`` x bins (the energy of its event when ``avg`` is a squared envelope). An
    area does not depend on where a narrow event falls between two bins, as a peak would.

    Parameters
    ----------
    avg : array_like, 1-D
        A synchronous average at the set's rate, at least 2 bins per element.
    n_elements : int
        Elements in the set (>= 2).

    Returns
    -------
    numpy.ndarray
        The ``n_elements`` levels in the order the elements pass, first the element holding the
        average's strongest bin (a level <= 0: the element's window holds nothing above the
        floor).
    """
    return np.array([w.sum() for w in element_windows(avg, n_elements)])
