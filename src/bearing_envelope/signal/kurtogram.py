"""Fast kurtogram (Antoni 2007): kurtosis of complex sub-band signals on a 1/3-binary tree.

The filter bank is written from the equations of the paper; the inner loops run in numba.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace

import numpy as np
from numba import njit
from scipy import fft as sp_fft

from .validation import check_fs, check_positive, check_signal
from ..lazy import lazy_module

sp_signal = lazy_module("scipy.signal")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = ["Kurtogram", "fast_kurtogram", "kurtogram_levels", "max_kurtogram_level"]

#: Length of the binary-split prototype low-pass (Antoni 2007: 16th order).
BINARY_TAPS = 17
#: Cut-off of the binary prototype, as a fraction of its Nyquist frequency (published: 0.4).
BINARY_CUTOFF = 0.4
#: Length of the ternary-split prototype low-pass (3/2 x 16th order).
TERNARY_TAPS = 25
#: Cut-off of the ternary prototype, as a fraction of its Nyquist frequency (2/3 x 0.4).
TERNARY_CUTOFF = 2.0 / 3.0 * 0.4
#: log2 of the minimum number of samples per band of the deepest binary level (published
#: rule ``nlevel <= log2(n) - 7``).
_DEEPEST_LOG2 = 7
#: Minimum number of samples of the deepest binary level (published rule nlevel <= log2(n) - 7).
MIN_DEEPEST_SAMPLES = 2**_DEEPEST_LOG2
#: Binary levels computed when ``nlevel`` is not given (the published default), if the signal
#: is long enough.
DEFAULT_NLEVEL = 8
#: The kurtogram's level 0 when not named: the analytic signal (``"real"``: the real input).
DEFAULT_LEVEL0 = "analytic"
#: Centre of the band of the real input, ``[0, 1/2]`` cycles/sample.
_REAL_INPUT_CENTRE = 0.25
#: Shift (cycles/sample, at the parent's rate) from a node's centre to the centres of its
#: binary halves (1/4 of its band of width 1/2) and of its outer ternary thirds (1/3 of it).
_BINARY_SHIFT = 0.125
_TERNARY_SHIFT = 1.0 / 6.0



@dataclass(frozen=True)
class Kurtogram:
    """Result of :func:`fast_kurtogram`.

    Attributes
    ----------
    matrix : ndarray, shape (2 * nlevel, 3 * 2**nlevel)
        Kurtosis of every cell, each band's value repeated over the columns it spans so that
        every row shares the frequency axis ``freqs`` (the layout of Antoni's plots).
    levels : ndarray, shape (2 * nlevel,)
        Level of each row: 0, 1, 1.585, 2, 2.585, ..., nlevel - 0.415, nlevel
        (the one-third levels are ``k + log2(3) - 1``).
    freqs : ndarray, shape (3 * 2**nlevel,)
        Centre frequency (Hz) of each column of ``matrix``.
    bandwidths : ndarray, shape (2 * nlevel,)
        Bandwidth of each row's bands, ``fs * 2**-(level + 1)`` (Hz).
    rows : list of ndarray
        The kurtosis of each band of each row without repetition; band ``i`` of row ``r``
        spans ``[i, i + 1] * bandwidths[r]`` Hz.
    level, fc, bandwidth, kurtosis : float
        The best cell: its level, centre frequency (Hz), bandwidth (Hz) and kurtosis.
    row, band_index : int
        Position of the best cell in ``levels`` and ``rows[row]``.
    fs : float
        Sampling frequency (Hz).
    nlevel : int
        Number of binary levels.
    n_dropped : ndarray of int
        Samples dropped at the start of each row's sub-band signals (filter transients), counted
        at that row's decimated rate.
    n_samples : ndarray of int
        Samples used for the kurtosis of each band of each row.
    max_level, min_bandwidth : float or None
        The guards applied to the search for the best cell.
    """

    matrix: np.ndarray
    levels: np.ndarray
    freqs: np.ndarray
    bandwidths: np.ndarray
    rows: list
    level: float
    fc: float
    bandwidth: float
    kurtosis: float
    row: int
    band_index: int
    fs: float
    nlevel: int
    n_dropped: np.ndarray
    n_samples: np.ndarray
    max_level: float | None = None
    min_bandwidth: float | None = None
    info: dict = field(default_factory=dict)

    @property
    def band(self) -> tuple[float, float]:
        """Edges ``(fc - bandwidth/2, fc + bandwidth/2)`` of the best cell (Hz)."""
        return (self.fc - self.bandwidth / 2.0, self.fc + self.bandwidth / 2.0)

    def restrict(self, max_level: float | None = None, min_bandwidth: float | None = None):
        """The same kurtogram with the best cell searched only where ``level <= max_level`` and
        ``bandwidth >= min_bandwidth`` (Hz); ``None`` keeps no limit.

        Parameters
        ----------
        max_level : float, optional
            Deepest level searched for the best cell.
        min_bandwidth : float, optional
            Narrowest band searched (Hz).

        Returns
        -------
        Kurtogram
            A copy whose best cell (level, centre, bandwidth, kurtosis) is the restricted search's.
        """
        if max_level is not None:
            max_level = float(max_level)
        min_bandwidth = check_positive(min_bandwidth, "min_bandwidth", allow_none=True)
        r, i, k = _best_cell(self.rows, self.levels, self.bandwidths, max_level, min_bandwidth)
        bw = float(self.bandwidths[r])
        return replace(self, level=float(self.levels[r]), fc=(i + 0.5) * bw, bandwidth=bw,
                       kurtosis=k, row=r, band_index=i, max_level=max_level,
                       min_bandwidth=min_bandwidth)

    @property
    def window_length(self) -> int:
        """STFT window length matching the best cell: ``round(fs / bandwidth) = 2**(level+1)``."""
        return int(round(2.0 ** (self.level + 1.0)))


def kurtogram_levels(nlevel: int) -> np.ndarray:
    """Levels of the rows of a kurtogram with ``nlevel`` binary levels.

    Returns ``[0, 1, 1 + c, 2, 2 + c, ..., nlevel - 1 + c, nlevel]`` with
    ``c = log2(3) - 1 ~= 0.585``, i.e. ``2 * nlevel`` values.

    Parameters
    ----------
    nlevel : int
        Number of binary levels (>= 1).

    Returns
    -------
    numpy.ndarray
        The ``2 * nlevel`` row levels.
    """
    nlevel = int(nlevel)
    # the ternary rows are splits of binary level k - 1 -> level (k - 1) + log2(3) = k + 0.585
    out = [0.0]
    for k in range(1, nlevel + 1):
        out.append(float(k))
        if k < nlevel:
            out.append(k + math.log2(3.0) - 1.0)
    return np.asarray(out)


def max_kurtogram_level(n: int) -> int:
    """Largest ``nlevel`` allowed for ``n`` samples: ``floor(log2(n)) - 7`` (>= 128 samples
    per sub-band at the deepest binary level, the rule of the published code).

    Parameters
    ----------
    n : int
        Number of samples of the signal.

    Returns
    -------
    int
        The largest ``nlevel`` :func:`fast_kurtogram` accepts for ``n`` samples.
    """
    return int(math.floor(math.log2(max(int(n), 1)))) - _DEEPEST_LOG2


#: Outputs per block of the filter-bank kernel; ``dec * _BLOCK`` is a multiple of the phasor
#: period 24 for dec = 2 and 3, so one phasor table serves every block.
_BLOCK = 960
#: Every demodulation frequency (cycles/sample) is a multiple of 1/24.
_PERIOD = 24


@njit(cache=True, fastmath=True)
def _demodulate(xr, xi, p, has_imag, cos_c, sin_c, dec, tbase, n_poly, phr, phi):  # pragma: no cover - jit
    """Polyphase buffers of one block of node ``p`` shifted by ``-f_c``: ``phr[d, jj] + i
    phi[d, jj] = x[t] exp(-2j pi f_c t)`` at ``t = tbase + dec*jj + d`` (zero before the start),
    ``cos_c``/``sin_c`` the child's phasor table (see :func:`_bank_step`)."""
    for d in range(dec):
        for jj in range(n_poly):
            trel = dec * jj + d
            t = tbase + trel
            if t < 0:
                phr[d, jj] = 0.0
                phi[d, jj] = 0.0
            else:
                a = xr[p, t]
                cc = cos_c[trel]
                ss = sin_c[trel]
                if has_imag:
                    b = xi[p, t]
                    phr[d, jj] = a * cc + b * ss
                    phi[d, jj] = b * cc - a * ss
                else:
                    phr[d, jj] = a * cc
                    phi[d, jj] = -a * ss


@njit(cache=True, fastmath=True)
def _bank_step(xr, xi, has_imag, tabc, tabs, w, dec, drop, store):  # pragma: no cover - jit
    """Split every node of a level into ``C`` children, block by block.

    Child ``c`` of node ``p`` (row ``p * C + c``) is ``y[m] = sum_n w[n] z[dec*m + dec-1 - n]``
    with ``z[t] = x[t] * exp(-2j*pi*f_c*t)``; ``tabc``/``tabs`` hold ``cos``/``sin`` of
    ``2 pi f_c t`` for ``t = t_rel - dec*Q`` (period 24). The demodulated input of one block
    is written to small polyphase buffers (cache-resident) and filtered four taps at a time.
    Returns the children (if ``store``) and the sums of ``|y|^2`` and ``|y|^4`` over
    ``m >= drop``. ``w`` has a multiple of 4 taps (zero-padded).
    """
    n_nodes, m_in = xr.shape
    n_child = tabc.shape[0]
    m_out = m_in // dec
    n_taps = w.shape[0]
    q_hist = (n_taps + dec - 1) // dec
    n_task = n_nodes * n_child
    if store:
        yr = np.empty((n_task, m_out))
        yi = np.empty((n_task, m_out))
    else:
        yr = np.empty((1, 1))
        yi = np.empty((1, 1))
    s2 = np.zeros(n_task)
    s4 = np.zeros(n_task)
    blk = _BLOCK
    phr = np.zeros((dec, q_hist + blk))
    phi = np.zeros((dec, q_hist + blk))
    accr = np.empty(blk)
    acci = np.empty(blk)
    for p in range(n_nodes):
        for m0 in range(0, m_out, blk):
            m1 = min(m0 + blk, m_out)
            nb = m1 - m0
            tbase = dec * (m0 - q_hist)
            for c in range(n_child):
                _demodulate(xr, xi, p, has_imag, tabc[c], tabs[c], dec, tbase, q_hist + nb, phr, phi)
                for m in range(nb):
                    accr[m] = 0.0
                    acci[m] = 0.0
                for g in range(0, n_taps, 4):
                    q0 = g // dec
                    d0 = dec - 1 - (g - q0 * dec)
                    q1 = (g + 1) // dec
                    d1 = dec - 1 - (g + 1 - q1 * dec)
                    q2 = (g + 2) // dec
                    d2 = dec - 1 - (g + 2 - q2 * dec)
                    q3 = (g + 3) // dec
                    d3 = dec - 1 - (g + 3 - q3 * dec)
                    w0 = w[g]
                    w1 = w[g + 1]
                    w2 = w[g + 2]
                    w3 = w[g + 3]
                    r0 = phr[d0, q_hist - q0 :]
                    r1 = phr[d1, q_hist - q1 :]
                    r2 = phr[d2, q_hist - q2 :]
                    r3 = phr[d3, q_hist - q3 :]
                    i0 = phi[d0, q_hist - q0 :]
                    i1 = phi[d1, q_hist - q1 :]
                    i2 = phi[d2, q_hist - q2 :]
                    i3 = phi[d3, q_hist - q3 :]
                    for m in range(nb):
                        accr[m] += w0 * r0[m] + w1 * r1[m] + w2 * r2[m] + w3 * r3[m]
                        acci[m] += w0 * i0[m] + w1 * i1[m] + w2 * i2[m] + w3 * i3[m]
                task = p * n_child + c
                a2s = 0.0
                a4s = 0.0
                for m in range(max(drop - m0, 0), nb):
                    a2 = accr[m] * accr[m] + acci[m] * acci[m]
                    a2s += a2
                    a4s += a2 * a2
                s2[task] += a2s
                s4[task] += a4s
                if store:
                    for m in range(nb):
                        yr[task, m0 + m] = accr[m]
                        yi[task, m0 + m] = acci[m]
    return yr, yi, s2, s4


def _prototypes():
    """Binary and ternary prototype low-pass filters (Hamming-windowed sinc, published
    lengths and cut-offs), zero-padded to a multiple of 4 taps for the kernel."""
    out = []
    for taps, cut in ((BINARY_TAPS, BINARY_CUTOFF), (TERNARY_TAPS, TERNARY_CUTOFF)):
        w = sp_signal.firwin(taps, cut)
        out.append(np.concatenate([w, np.zeros(-taps % 4)]))
    return out[0], out[1]


@functools.lru_cache(maxsize=16)
def _tables(freqs, dec, n_taps):
    """cos/sin of ``2 pi f t`` for the kernel's block-relative time ``t = t_rel - dec*Q``
    (cached: treat as read-only)."""
    q_hist = (n_taps + dec - 1) // dec
    t = np.arange(dec * (_BLOCK + q_hist)) - dec * q_hist
    f = np.asarray(freqs, dtype=np.float64)
    # exact phases: reduce t f modulo 1 with integers
    k = np.round(f * _PERIOD).astype(np.int64)
    ang = 2.0 * np.pi * (np.mod(np.outer(k, t), _PERIOD) / _PERIOD)
    return np.cos(ang), np.sin(ang)


def _best_cell(rows, levels, bandwidths, max_level, min_bandwidth):
    allowed = np.ones(len(levels), dtype=bool)
    if max_level is not None:
        allowed &= levels <= max_level + 1e-9
    if min_bandwidth is not None:
        allowed &= bandwidths >= min_bandwidth * (1.0 - 1e-12)
    if not allowed.any():
        raise ValueError(
            f"max_level={max_level} / min_bandwidth={min_bandwidth} exclude every level of the "
            f"kurtogram (levels {levels[0]:g}..{levels[-1]:g}, bandwidths "
            f"{bandwidths[-1]:g}..{bandwidths[0]:g} Hz)"
        )
    best_r, best_i, best_k = -1, -1, -np.inf
    for r in np.flatnonzero(allowed):
        i = int(np.argmax(rows[r]))
        if rows[r][i] > best_k:
            best_r, best_i, best_k = int(r), i, float(rows[r][i])
    return best_r, best_i, best_k


def _kurt_from_sums(s2, s4, n):
    s2 = np.asarray(s2, dtype=np.float64)
    s4 = np.asarray(s4, dtype=np.float64)
    k = np.zeros_like(s2)
    ok = s2 > np.finfo(np.float64).tiny * max(n, 1)
    k[ok] = n * s4[ok] / (s2[ok] * s2[ok]) - 2.0
    return np.maximum(k, 0.0)


def _drop_after(drop_in: int, taps: int, dec: int) -> int:
    # output m is transient while dec*m + dec-1 - (taps-1) < drop_in  (input samples)
    return max(0, int(math.ceil((taps - dec + drop_in) / dec)))


def fast_kurtogram(
    x,
    fs: float,
    nlevel: int | None = None,
    *,
    max_level: float | None = None,
    min_bandwidth: float | None = None,
    demean: bool = True,
    level0: str = DEFAULT_LEVEL0,
) -> Kurtogram:
    r"""Fast kurtogram of a signal (Antoni 2007, 1/3-binary filter-bank tree).

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (any unit).
    fs : float
        Sampling frequency (Hz), > 0.
    nlevel : int, optional
        Number of binary levels (>= 1). The deepest binary level keeps ``n / 2**nlevel``
        samples per band, which must be at least 128: ``nlevel <= floor(log2(n)) - 7``.
        Default: ``min(8, floor(log2(n)) - 7)``.
    max_level : float, optional
        Only cells with ``level <= max_level`` may be the best cell (guard against deep,
        few-sample cells that win by chance). The matrix is still computed to ``nlevel``.
    min_bandwidth : float, optional
        Only cells with ``bandwidth >= min_bandwidth`` (Hz) may be the best cell.
    demean : bool, default True
        Subtract the mean of ``x`` first. Without it a large mean leaks into the lowest bands
        through the side lobes of the filters.
    level0 : {"analytic", "real"}, default "analytic"
        Kurtosis of level 0 (the whole band): ``"analytic"`` takes it on the analytic signal of
        ``x``, :math:`E|x_a|^4/(E|x_a|^2)^2 - 2`, like every other cell; ``"real"`` takes it on
        the real signal, :math:`E x^4/(E x^2)^2 - 3`, as Antoni's published code does. A
        sparse impulse train of a broad-band resonance reads higher on the real signal (the
        analytic envelope smooths the carrier's oscillation away), so with ``"real"`` level 0
        can win where it wins in the reference (CWRU records 105 and 130).

    Returns
    -------
    Kurtogram
        Matrix, level and frequency axes and the best cell (see :class:`Kurtogram`).

    Raises
    ------
    ValueError
        If ``x`` is empty, non-finite or constant, ``fs <= 0``, ``nlevel`` is too deep for the
        signal length, or the guards exclude every cell.

    See Also
    --------
    spectral_kurtosis : STFT-based spectral kurtosis.

    Notes
    -----
    **Levels and bands.** Level ``l`` splits ``[0, fs/2]`` into bands of width
    :math:`B_l = f_s 2^{-(l+1)}`. Binary levels are ``k = 0, 1, ..., nlevel``; the one-third
    levels ``k + \log_2 3 - 1`` (1.585, 2.585, ...) split each band of binary level ``k - 1``
    into three. Band ``i`` of a row spans :math:`[i B_l, (i+1) B_l]` and its centre frequency is
    the middle of that interval, :math:`f_c = (i + 1/2) B_l`. These are the nominal edges; the
    analysis filters overlap their neighbours (see below).

    **Filter bank.** Each node holds a complex sub-band signal sampled at twice (binary) or
    three times (ternary) its bandwidth, its band centred on 0 Hz. A binary split shifts the
    lower and upper half of the node's band to 0 Hz (multiplication by
    :math:`e^{\mp 2\pi i t/8}`), low-pass filters with the prototype
    :math:`w_2` and keeps every second sample,

    .. math:: c_{\pm}[m] = \sum_{n=0}^{16} w_2[n]\, z_{\pm}[2m + 1 - n],

    a ternary split does the same with shifts :math:`0, \pm 1/6` and the prototype
    :math:`w_3`, keeping every third sample (:math:`c[m] = \sum_n w_3[n] z[3m + 2 - n]`).
    The prototypes are the published ones: Hamming-windowed sinc low-pass filters of 17 taps,
    cut-off 0.4 of their Nyquist frequency, and of 25 taps, cut-off :math:`0.4 \cdot 2/3`.
    This equals Antoni's quasi-analytic filters :math:`h(n) = w_2(n) e^{i\pi n/4}` etc. up to
    a unit-modulus factor per sample, which does not change :math:`|c|`. Level 0 (the whole
    band) uses the analytic signal of ``x`` (FFT Hilbert transform), or with
    ``level0="real"`` the real signal and :math:`E x^4/(E x^2)^2 - 3`.

    **Kurtosis.** For every band, on the complex sub-band signal :math:`c`,

    .. math:: K = \frac{\langle |c|^4 \rangle}{\langle |c|^2 \rangle^2} - 2,

    clipped at 0 as in the published algorithm (a complex Gaussian gives 0, a pure tone -1).
    The sub-band signals are not de-meaned again (the published code does; after ``demean``
    the difference is negligible).

    **Transients.** The filters start from rest; the first samples of every node are dropped
    from its kurtosis: :math:`T' = \lceil (L - D + T)/D \rceil` samples at the node's rate for
    a parent with transient :math:`T`, a filter of :math:`L` taps and decimation :math:`D`
    (16 samples at deep binary levels; ``n_dropped`` lists them).

    **Best cell.** The largest value over the allowed rows (``max_level``,
    ``min_bandwidth``); ties go to the lower level, then the lower frequency.

    References
    ----------
    .. [1] J. Antoni, "Fast computation of the kurtogram for the detection of transient faults",
       Mechanical Systems and Signal Processing 21 (2007) 108-124.

    Examples
    --------
    >>> import numpy as np
    >>> from bearing_envelope.signal import fast_kurtogram
    >>> rng = np.random.default_rng(0)
    >>> fs = 20000.0
    >>> x = rng.standard_normal(2**15)
    >>> ring = np.exp(-np.arange(64) / 8.0) * np.sin(2 * np.pi * 0.3 * np.arange(64))
    >>> for i in range(100, x.size - 64, 1500):  # impulses ringing at 0.3 fs = 6 kHz
    ...     x[i:i + 64] += 20.0 * ring
    >>> kg = fast_kurtogram(x, fs, 6)
    >>> kg.matrix.shape
    (12, 192)
    >>> bool(kg.band[0] <= 6000.0 <= kg.band[1])
    True
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=2)
    nlevel = _check_nlevel(nlevel, x.size)
    if max_level is not None:
        max_level = float(max_level)
        if not math.isfinite(max_level) or max_level < 0:
            raise ValueError(f"max_level must be a finite number >= 0, got {max_level!r}")
    min_bandwidth = check_positive(min_bandwidth, "min_bandwidth", allow_none=True)
    if np.ptp(x) == 0.0:
        raise ValueError("x is constant: its kurtogram is undefined")
    if level0 not in ("analytic", "real"):
        raise ValueError(f"level0 must be 'analytic' or 'real', got {level0!r}")
    if demean:
        x = x - x.mean()

    levels = kurtogram_levels(nlevel)
    bandwidths = fs * 2.0 ** -(levels + 1.0)
    rows, dropped, nsamp = _filter_bank(x, nlevel, len(levels))
    rows[0] = _level0_kurtosis(x, level0)
    nsamp[0] = x.size

    ncol = 3 * 2**nlevel
    matrix = np.empty((len(levels), ncol))
    for r, vals in enumerate(rows):
        matrix[r] = np.repeat(vals, ncol // vals.size)
    freqs = fs / 2.0 * (np.arange(ncol) + 0.5) / ncol

    best_r, best_i, best_k = _best_cell(rows, levels, bandwidths, max_level, min_bandwidth)
    bw = float(bandwidths[best_r])
    return Kurtogram(
        matrix=matrix,
        levels=levels,
        freqs=freqs,
        bandwidths=bandwidths,
        rows=rows,
        level=float(levels[best_r]),
        fc=(best_i + 0.5) * bw,
        bandwidth=bw,
        kurtosis=best_k,
        row=best_r,
        band_index=best_i,
        fs=fs,
        nlevel=nlevel,
        n_dropped=dropped,
        n_samples=nsamp,
        max_level=max_level,
        min_bandwidth=min_bandwidth,
        info={"demean": bool(demean), "level0": level0, "binary_taps": BINARY_TAPS,
              "ternary_taps": TERNARY_TAPS},
    )


def _check_nlevel(nlevel, n: int) -> int:
    """``nlevel`` checked against the signal length ``n`` (default :data:`DEFAULT_NLEVEL`, capped
    by :func:`max_kurtogram_level`)."""
    nmax = max_kurtogram_level(n)
    if nlevel is None:
        nlevel = min(DEFAULT_NLEVEL, nmax)
        if nlevel < 1:
            raise ValueError(
                f"x has {n} samples: the fast kurtogram needs at least "
                f"{2 * MIN_DEEPEST_SAMPLES} samples (nlevel >= 1 with >= {MIN_DEEPEST_SAMPLES} per band)"
            )
    if isinstance(nlevel, bool) or int(nlevel) != nlevel or int(nlevel) < 1:
        raise ValueError(f"nlevel must be an integer >= 1, got {nlevel!r}")
    nlevel = int(nlevel)
    if nlevel > nmax:
        raise ValueError(
            f"nlevel={nlevel} is too deep for a signal of {n} samples: need "
            f"nlevel <= floor(log2(n)) - {_DEEPEST_LOG2} = {nmax} (at least {MIN_DEEPEST_SAMPLES} samples "
            f"per sub-band at the deepest level)"
        )
    return nlevel


def _level0_kurtosis(x: np.ndarray, level0: str) -> np.ndarray:
    """Kurtosis of the whole band (row 0), one value.

    ``"analytic"``: ``|analytic signal|^2 = x^2 + (Hx)^2``, ``Hx`` by FFT in single precision
    (the kurtosis needs ~6 digits; this halves the cost of the largest transform); ``"real"``:
    ``E x^4 / (E x^2)^2 - 3`` on ``x`` itself (Antoni's published code).
    """
    n = x.size
    scale = 1.0 / np.std(x)
    xs = x * scale
    if level0 == "real":
        x2 = xs * xs
        # _kurt_from_sums gives max(n s4 / s2^2 - 2, 0); the real kurtosis subtracts 3
        return np.maximum(_kurt_from_sums([x2.sum()], [np.dot(x2, x2)], n) - 1.0, 0.0)
    nfft = sp_fft.next_fast_len(n, real=True)
    spec = sp_fft.rfft(xs.astype(np.float32), nfft)  # one transform: one thread (threads: 1)
    spec *= np.complex64(-1j)  # Hilbert transform: -i sign(f); DC and Nyquist set to 0
    spec[0] = 0.0
    if nfft % 2 == 0:
        spec[-1] = 0.0
    hx = sp_fft.irfft(spec, nfft)[:n].astype(np.float64)
    a2 = xs * xs + hx * hx
    return _kurt_from_sums([a2.sum()], [np.dot(a2, a2)], n)


def _filter_bank(x: np.ndarray, nlevel: int, n_rows: int, visit=None):
    """The 1/3-binary tree below level 0: ``(rows, n_dropped, n_samples)`` (row 0 left empty).

    Binary level ``k`` is split in two (row ``2k + 1``, level ``k + 1``) and, above the deepest
    level, in three (row ``2k + 2``, level ``k + 1.585``: a leaf, moments only).
    ``visit(row, yr, yi, drop)``, when given, receives every row's complex sub-band signals
    (``yr + i yi``, one band per row of the arrays, in frequency order; the first ``drop``
    samples are filter transients), the leaves' included.
    """
    w2, w3 = _prototypes()
    rows: list[np.ndarray] = [None] * n_rows  # type: ignore[list-item]
    dropped = np.zeros(n_rows, dtype=int)
    nsamp = np.zeros(n_rows, dtype=int)
    xr = x[None, :]
    xi = np.zeros((1, 1))
    centre = _REAL_INPUT_CENTRE
    drop = 0
    for k in range(nlevel):
        m_in = xr.shape[1]
        # ternary split of binary level k -> row of level k + 1.585 (leaves: moments only)
        r3 = 2 * k + 2
        if r3 < n_rows:  # the split of the deepest binary level is not part of the map
            d3 = _drop_after(drop, TERNARY_TAPS, 3)
            cb, sb = _tables((centre - _TERNARY_SHIFT, centre, centre + _TERNARY_SHIFT), 3, w3.size)
            y3r, y3i, s2, s4 = _bank_step(xr, xi, k > 0, cb, sb, w3, 3, d3, visit is not None)
            if visit is not None:
                visit(r3, y3r, y3i, d3)
            cnt = m_in // 3 - d3
            rows[r3] = _kurt_from_sums(s2, s4, cnt)
            dropped[r3] = d3
            nsamp[r3] = cnt
        # binary split -> level k + 1
        d2 = _drop_after(drop, BINARY_TAPS, 2)
        cb, sb = _tables((centre - _BINARY_SHIFT, centre + _BINARY_SHIFT), 2, w2.size)
        store = k + 1 < nlevel or visit is not None
        yr, yi, s2, s4 = _bank_step(xr, xi, k > 0, cb, sb, w2, 2, d2, store)
        cnt = m_in // 2 - d2
        r2 = 2 * k + 1
        if visit is not None:
            visit(r2, yr, yi, d2)
        rows[r2] = _kurt_from_sums(s2, s4, cnt)
        dropped[r2] = d2
        nsamp[r2] = cnt
        xr, xi = yr, yi
        centre = 0.0  # every sub-band signal is centred on 0 Hz
        drop = d2
    return rows, dropped, nsamp
