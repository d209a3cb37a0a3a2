r"""The infogram (Antoni 2016): entropic evidence of impulsiveness and of repetition in every cell
of the fast kurtogram's 1/3-binary tree.

J. Antoni, "The infogram: entropic evidence of the signature of repetitive transients",
Mechanical Systems and Signal Processing 74 (2016) 73-94. Written from the paper's equations.

For a cell of centre ``f`` and bandwidth ``Df``, ``x(n; f, Df)`` is the complex sub-band signal
of the fast kurtogram's filter bank (:mod:`~bearing_envelope.signal.kurtogram`, the same
filters and the same bands; the whole band, level 0, is the analytic signal). Its **squared
envelope** is ``SE(n) = |x(n; f, Df)|^2`` and its **squared envelope spectrum** is
``SES(alpha) = |DFT_n[w(n) (SE(n) - <SE>)]|^2`` at the cyclic frequencies
``0 < alpha <= alpha_max``, ``w`` a Hann window (the paper takes the plain DFT: there a line
between two bins leaks over many bins, and a cell's negentropy then depends on where its lines
fall on the bin grid: on the tests' record, dropping a few samples changed the winning cell).
The spectral **negentropy** of a non-negative sequence ``p`` is

.. math:: \Delta I(p) = \left\langle \frac{p}{\langle p \rangle}
   \ln \frac{p}{\langle p \rangle} \right\rangle

(``0 ln 0 = 0``): the entropy of the flat sequence (``ln N``) minus the entropy of ``p``
normalised to a distribution; 0 when ``p`` is constant, large when ``p`` is concentrated on a
few values. The infogram has three maps:

- **time** ``dI_e(f, Df) = Delta I(SE)``: large where the band's energy arrives in a few
  impulses (what the kurtogram measures too: one isolated shock scores as high as a train);
- **spectral** ``dI_E(f, Df) = Delta I(SES)``: large where the squared envelope repeats, its
  spectrum made of a few cyclic lines (a single shock has a flat SES and scores low);
- **average** ``dI_1/2 = (dI_e + dI_E) / 2``.

Reference values (stationary Gaussian noise): the squared envelope of a complex Gaussian
sub-band signal is exponentially distributed, so ``E[dI_e] = 1 - gamma = 0.4228`` (Euler's
gamma) in every cell, whatever its width, except the cells at 0 Hz and fs/2: there the band
of a real signal holds its own mirror image, is not circular, and reads more (up to
``2 - gamma - ln 2 = 0.73``, a real Gaussian's value); the SES bins of such noise are exponentially
distributed about the spectrum of ``SE`` (flat for ``alpha`` well inside the band's width), so
``dI_E`` is about ``1 - gamma`` too when ``alpha_max`` is a small fraction of the bandwidth.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import fft as sp_fft

from .kurtogram import _best_cell, _check_nlevel, _filter_bank, kurtogram_levels
from .validation import check_fs, check_positive, check_signal
from ..lazy import lazy_module

sp_signal = lazy_module("scipy.signal")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = ["INFOGRAM_MAPS", "Infogram", "InfogramCell", "infogram", "infogram_depth",
           "negentropy"]

#: The maps of an :class:`Infogram`: impulsiveness, repetition and their average.
INFOGRAM_MAPS = ("time", "spectral", "average")
#: Fewest cyclic-frequency bins a cell's SES must hold to be searched (fewer: its spectral
#: negentropy is noise).
MIN_SES_BINS = 8


def negentropy(p, axis: int = -1):
    """Spectral negentropy ``< p/<p> ln(p/<p>) >`` of a non-negative sequence.

    Parameters
    ----------
    p : array_like
        Non-negative values (a squared envelope, a squared envelope spectrum).
    axis : int, default -1
        Axis along which the mean is taken.

    Returns
    -------
    ndarray or float
        ``>= 0``; 0 for a constant sequence (and for an all-zero one), ``ln N`` for a sequence
        of ``N`` values with one non-zero.
    """
    p = np.asarray(p, dtype=np.float64)
    m = p.mean(axis=axis, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(m > 0, p / m, 0.0)
        v = np.where(r > 0, r * np.log(np.where(r > 0, r, 1.0)), 0.0)
    return v.mean(axis=axis)


@dataclass(frozen=True)
class InfogramCell:
    """The best cell of one map of an :class:`Infogram`.

    Attributes
    ----------
    kind : str
        The map (:data:`INFOGRAM_MAPS`).
    level, fc, bandwidth : float
        Level of the tree, centre frequency (Hz) and bandwidth (Hz).
    value : float
        The map's negentropy there.
    row, band_index : int
        Position in ``Infogram.levels`` and in that row.
    """

    kind: str
    level: float
    fc: float
    bandwidth: float
    value: float
    row: int
    band_index: int

    @property
    def band(self) -> tuple[float, float]:
        """Edges ``(fc - bandwidth/2, fc + bandwidth/2)`` (Hz)."""
        return (self.fc - self.bandwidth / 2.0, self.fc + self.bandwidth / 2.0)


@dataclass(frozen=True)
class Infogram:
    """Result of :func:`infogram`: the three maps over the kurtogram's tree and their best cells.

    Attributes
    ----------
    time, spectral : list of ndarray
        Per row of the tree, the time (impulsiveness) and spectral (repetition) negentropy of
        each band; band ``i`` of row ``r`` spans ``[i, i + 1] * bandwidths[r]`` Hz. A row whose
        SES holds fewer than :data:`MIN_SES_BINS` cyclic bins gets NaN in ``spectral`` (and is
        never a best cell of the spectral or average map).
    levels, bandwidths : ndarray
        Level and bandwidth (Hz) of each row (as :class:`~bearing_envelope.signal.kurtogram.
        Kurtogram`).
    n_samples : ndarray of int
        Samples of each row's squared envelopes (filter transients dropped).
    fs, alpha_max_hz : float
        Sampling frequency and the highest cyclic frequency of the SES (Hz; each row reads to
        its own Nyquist frequency, ``bandwidth``, at most).
    nlevel : int
        Binary levels of the tree.
    cells : dict
        ``map -> InfogramCell``, the best cell of each map under the guards of :func:`infogram`.
    """

    time: list
    spectral: list
    levels: np.ndarray
    bandwidths: np.ndarray
    n_samples: np.ndarray
    fs: float
    alpha_max_hz: float
    nlevel: int
    cells: dict

    def rows(self, kind: str) -> list:
        """Per-row values of one map.

        Parameters
        ----------
        kind : {"time", "spectral", "average"}
            The map: time (impulsiveness) or spectral (repetition) negentropy, or their mean.

        Returns
        -------
        list of ndarray
            One array per row of the tree (dimensionless negentropies), band ``i`` of row
            ``r`` spanning ``[i, i + 1] * bandwidths[r]`` Hz; NaN where a row's SES is too short.

        Raises
        ------
        ValueError
            ``kind`` is not a map of :data:`INFOGRAM_MAPS`.
        """
        if kind == "time":
            return self.time
        if kind == "spectral":
            return self.spectral
        if kind == "average":
            return [0.5 * (t + s) for t, s in zip(self.time, self.spectral)]
        raise ValueError(f"kind = {kind!r}: allowed {INFOGRAM_MAPS}")

    def matrix(self, kind: str) -> np.ndarray:
        """One map laid out like ``Kurtogram.matrix`` (each band repeated over its columns).

        Parameters
        ----------
        kind : {"time", "spectral", "average"}
            The map, as in :meth:`rows`.

        Returns
        -------
        ndarray, shape (2 * nlevel, 3 * 2**nlevel)
            The negentropies (dimensionless), row ``r`` of the tree on row ``r``, frequency
            from 0 to fs/2 along the columns.
        """
        ncol = 3 * 2 ** self.nlevel
        return np.vstack([np.repeat(v, ncol // v.size) for v in self.rows(kind)])

    def best(self, kind: str = "spectral", *, max_level: float | None = None,
             min_bandwidth: float | None = None, above_dc: bool = False) -> InfogramCell:
        """The cell of the largest value of one map, searched where ``level <= max_level`` and
        ``bandwidth >= min_bandwidth``.

        Parameters
        ----------
        kind : {"time", "spectral", "average"}, default "spectral"
            The map searched, as in :meth:`rows`.
        max_level : float, optional
            Deepest level searched.
        min_bandwidth : float, optional
            Narrowest cell searched (Hz).
        above_dc : bool, default False
            Leave out the cells that start at 0 Hz: there a real signal's band holds the
            mirror image of each low-frequency tone, and a tone ``f0`` beating with its image
            makes the squared envelope repeat at ``2 f0`` without any impulse.

        Returns
        -------
        InfogramCell
            Ties go to the lower level, then the lower frequency.

        Raises
        ------
        ValueError
            ``kind`` unknown, or no cell allowed by ``max_level`` / ``min_bandwidth`` holds enough
            SES bins.
        """
        rows = [np.nan_to_num(v, nan=-np.inf) for v in self.rows(kind)]
        if above_dc:
            for v in rows:
                v[0] = -np.inf
        r, i, v = _best_cell(rows, self.levels, self.bandwidths, max_level, min_bandwidth)
        if not math.isfinite(v):
            raise ValueError(f"kind = {kind!r}: no cell allowed by max_level = {max_level} / "
                             f"min_bandwidth = {min_bandwidth} holds {MIN_SES_BINS} SES bins "
                             f"below alpha_max_hz = {self.alpha_max_hz:g} Hz")
        bw = float(self.bandwidths[r])
        return InfogramCell(kind, float(self.levels[r]), (i + 0.5) * bw, bw, float(v), r, i)


def infogram_depth(fs: float, min_bandwidth: float, n: int) -> int:
    """The fewest binary levels whose tree holds every cell at least ``min_bandwidth`` wide.

    Parameters
    ----------
    fs : float
        Sampling frequency (Hz).
    min_bandwidth : float
        Narrowest cell wanted (Hz).
    n : int
        Samples of the signal (the depth is capped by the kurtogram's rule,
        ``floor(log2(n)) - 7``).

    Returns
    -------
    int
        ``nlevel`` (>= 1) for :func:`infogram`.
    """
    fs = check_fs(fs)
    min_bandwidth = check_positive(min_bandwidth, "min_bandwidth")
    deepest = math.log2(fs / (2.0 * min_bandwidth))  # level of a cell min_bandwidth wide
    k = math.floor(deepest + 1e-9)
    need = k + 1 if deepest - k >= math.log2(3.0) - 1.0 - 1e-9 else k
    return int(max(1, min(need, _check_nlevel(None, n))))


def _fast_len_below(n: int) -> int:
    """The largest length ``<= n`` that is a product of 2, 3 and 5 (a fast FFT length)."""
    m = int(n)
    while m > 1 and sp_fft.next_fast_len(m, real=True) != m:
        m -= 1
    return m


def _row_maps(yr, yi, drop: int, alpha_max: float, bandwidth: float):
    """Time and spectral negentropy of every band of one row (bands along axis 0; the row's
    signals run at ``2 bandwidth``, its SES bin ``k`` at ``k 2 bandwidth / n``); the SES reads
    the first samples of a fast FFT length (at most a few per cent fewer)."""
    se = yr[:, drop:] ** 2 + yi[:, drop:] ** 2
    n = _fast_len_below(se.shape[1])
    k_alpha = min(int(math.floor(alpha_max * n / (2.0 * bandwidth) + 1e-9)), n // 2)
    s = (se[:, :n] - se[:, :n].mean(axis=1, keepdims=True)) * sp_signal.windows.hann(n, sym=False)
    ses = np.abs(sp_fft.rfft(s, axis=1)[:, 1:k_alpha + 1]) ** 2
    spectral = negentropy(ses) if ses.shape[1] >= MIN_SES_BINS else np.full(se.shape[0], np.nan)
    return negentropy(se), spectral, se.shape[1]


def infogram(x, fs: float, nlevel: int | None = None, *, alpha_max_hz: float | None = None,
             max_level: float | None = None, min_bandwidth: float | None = None) -> Infogram:
    r"""The infogram of a signal (Antoni 2016) over the fast kurtogram's 1/3-binary tree.

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (any unit); its mean is removed.
    fs : float
        Sampling frequency (Hz).
    nlevel : int, optional
        Binary levels of the tree (as :func:`~bearing_envelope.signal.kurtogram.
        fast_kurtogram`; default ``min(8, floor(log2(n)) - 7)``; :func:`infogram_depth`
        gives the shallowest tree holding the cells a ``min_bandwidth`` allows).
    alpha_max_hz : float, optional
        Highest cyclic frequency of the SES (Hz): the repetition sought lies below it, and
        a bound well inside the narrowest cell's width keeps the SES of noise flat. Default:
        every cell's SES to its Nyquist frequency (the paper).
    max_level, min_bandwidth : float, optional
        Guards of the best cells (as the kurtogram's); the maps cover every cell.

    Returns
    -------
    Infogram
        The three maps and, in ``cells``, the best cell of each.

    Raises
    ------
    ValueError
        As :func:`~bearing_envelope.signal.kurtogram.fast_kurtogram` (short, constant or
        non-finite signal, ``nlevel`` too deep), or when the guards leave no cell.

    Notes
    -----
    Each row's complex sub-band signals come from the kurtogram's filter bank (same
    prototypes, same transients dropped); level 0 is the analytic signal of ``x``. The SES is
    the squared magnitude of the DFT of the mean-removed, Hann-windowed squared envelope
    (its first samples of a fast FFT length), bins ``0 < alpha <= alpha_max_hz`` at the row's
    resolution ``2 bandwidth / n_samples``.

    Examples
    --------
    >>> import numpy as np
    >>> from bearing_envelope.signal.infogram import infogram
    >>> rng = np.random.default_rng(0)
    >>> fs = 20000.0
    >>> x = rng.standard_normal(2**15)
    >>> ring = np.exp(-np.arange(64) / 8.0) * np.sin(2 * np.pi * 0.3 * np.arange(64))
    >>> for i in range(100, x.size - 64, 200):  # impulses every 10 ms ringing at 6 kHz
    ...     x[i:i + 64] += 5.0 * ring
    >>> ig = infogram(x, fs, 4)
    >>> lo, hi = ig.cells["spectral"].band
    >>> bool(lo <= 6000.0 <= hi)
    True
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=2)
    nlevel = _check_nlevel(nlevel, x.size)
    alpha_max = (fs / 2.0 if alpha_max_hz is None
                 else check_positive(alpha_max_hz, "alpha_max_hz"))
    if np.ptp(x) == 0.0:
        raise ValueError("x is constant: its infogram is undefined")
    x = x - x.mean()
    levels = kurtogram_levels(nlevel)
    bandwidths = fs * 2.0 ** -(levels + 1.0)
    time, spectral = [None] * len(levels), [None] * len(levels)
    nsamp = np.zeros(len(levels), dtype=int)

    def visit(row, yr, yi, drop):
        time[row], spectral[row], nsamp[row] = _row_maps(yr, yi, drop, alpha_max,
                                                         bandwidths[row])

    # level 0: the analytic signal (FFT Hilbert transform at a fast length, zero-padded)
    nfft = sp_fft.next_fast_len(x.size, real=True)
    spec = sp_fft.rfft(x, nfft)
    spec *= -1j
    spec[0] = 0.0
    if nfft % 2 == 0:
        spec[-1] = 0.0
    visit(0, x[None, :], sp_fft.irfft(spec, nfft)[None, :x.size], 0)
    _filter_bank(x, nlevel, len(levels), visit=visit)
    ig = Infogram(time, spectral, levels, bandwidths, nsamp, fs, alpha_max, nlevel, {})
    ig.cells.update({k: ig.best(k, max_level=max_level, min_bandwidth=min_bandwidth)
                     for k in INFOGRAM_MAPS})
    return ig
