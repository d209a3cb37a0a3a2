"""Fault-band metrics and a detection statistic on a one-sided spectrum.

Everything here works on a spectrum given as two arrays, frequencies ``f`` (Hz, increasing,
uniformly spaced) and amplitudes ``a`` (any linear amplitude scaling, e.g. the peak amplitude of
a sinusoid ``2|X_k|/N``), so that envelope spectra and raw spectra are handled alike.

Fault-band metrics (:func:`fault_band_metrics`)
    For each target frequency ``F`` (BPFI, BPFO, FTF, BSF, ...), each harmonic ``k F``
    (k = 1..K) and each sideband ``k F + m f_r`` (m = -M..M): the bins within a band of width
    ``w`` around the centre, the peak amplitude and its frequency, and the band power
    ``P = sum_band a_j^2 / 2 / ENBW`` (the power of a sinusoid of peak amplitude A is A^2/2;
    ``ENBW`` in bins is 1 for the rectangular window and 1.5 for Hann, so that ``P`` estimates
    the power of a line whatever the leakage). ``w`` is either relative (``bandwidth * k F``:
    the relative spread of a fault frequency under slip is the same for all its harmonics) or
    absolute (``bandwidth_hz``). ``total_band_power`` is the power over the union of all bands
    of a target (bins counted once).

Detection statistic (:func:`detection_statistic`, :func:`detect`)
    ``S = 20 log10(A_line / median(a_background))`` dB, where ``A_line`` is the largest
    amplitude within ``+- tolerance`` of the line (BPFI by default) and the background is the
    median amplitude over ``[lo, hi] x line`` with every bin near a harmonic of the line, its
    shaft-rate sidebands and the shaft harmonics removed. The median is insensitive to the few
    remaining lines. The threshold follows from the false-alarm probability on a spectrum of
    Gaussian noise: there the amplitude of each bin is Rayleigh distributed, so
    ``P(a > t * median) = 2^(-t^2)`` and the largest of ``n`` independent bins in the tolerance
    band exceeds ``t * median`` with probability ``1 - (1 - 2^(-t^2))^n``. The median is
    estimated from the ``N`` background bins, so it is itself random: :func:`threshold_db`
    averages that probability over the distribution of the sample median (order statistics:
    a Beta law) and solves it for ``pfa``; the default ``pfa = 0.01`` gives about 10-11 dB for
    5-30 bins against several hundred background bins. ``docs/sensor.md``,
    ``python -m benchmarks false_alarms`` and ``tests/test_diagnosis.py`` check it by Monte Carlo.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.optimize import brentq

from ..checks import check_positive
from ..lazy import lazy_module

pd = lazy_module("pandas")  # imported on first use (docs/architecture.md, lazy.py)
_stats = lazy_module("scipy.stats")  # imported on first use (docs/architecture.md, lazy.py)

#: Confidence of an interval on a measured rate (two-sided).
DEFAULT_CONFIDENCE = 0.95
#: Shaft-rate sidebands on each side of a line kept out of its background
#: (:func:`detection_statistic`).
EXCLUDED_SIDEBANDS = 3

__all__ = [
    "DEFAULT_CONFIDENCE",
    "EXCLUDED_SIDEBANDS",
    "BACKGROUND_BAND",
    "DEFAULT_PFA",
    "Detection",
    "fault_band_metrics",
    "threshold_db",
    "detection_statistic",
    "background_mask",
    "background_problem",
    "detect",
    "clopper_pearson",
    "false_alarm_rates",
]

#: Default false-alarm probability of :func:`detect` on a Gaussian-noise spectrum.
DEFAULT_PFA = 0.01

#: Background band of :func:`detection_statistic`, ``(lo, hi)`` in multiples of the line's
#: frequency (dimensionless): the floor is the median amplitude over ``[0.5, 1.5] x line``.
BACKGROUND_BAND = (0.5, 1.5)

_COLUMNS = [
    "spectrum", "target", "target_hz", "order", "sideband", "centre_hz", "band_low_hz",
    "band_high_hz", "n_bins", "peak_hz", "peak_amplitude", "band_power", "total_band_power",
]


def _spectrum(f, a) -> tuple[np.ndarray, np.ndarray, float]:
    f = np.asarray(f, dtype=float)
    a = np.asarray(a, dtype=float)
    if f.ndim != 1 or a.shape != f.shape or f.size < 3:
        raise ValueError(f"f and amplitude must be 1-D arrays of one length >= 3, got shapes "
                         f"{f.shape} and {a.shape}")
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(a))):
        raise ValueError("f and amplitude must be finite")
    df = np.diff(f)
    if np.any(df <= 0):
        raise ValueError("f must be strictly increasing")
    return f, a, float(np.median(df))


def _count(name: str, value, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def fault_band_metrics(
    f,
    amplitude,
    targets: Mapping[str, float],
    *,
    fr: float | None = None,
    harmonics: int = 3,
    sidebands: int = 0,
    bandwidth: float = 0.02,
    bandwidth_hz: float | None = None,
    enbw: float = 1.0,
    spectrum: str = "envelope",
) -> pd.DataFrame:
    """Peak amplitude, peak frequency and band power around fault harmonics and sidebands.

    Parameters
    ----------
    f, amplitude : array_like, shape (n,)
        One-sided spectrum: frequencies (Hz, increasing, uniform) and linear amplitudes.
    targets : mapping
        Name -> fundamental frequency (Hz), e.g. ``{"BPFI": 231.9, "BPFO": 184.2}``.
    fr : float, optional
        Shaft rate (Hz); required when ``sidebands > 0``.
    harmonics : int
        Harmonics k = 1..``harmonics`` of each target.
    sidebands : int
        Sidebands m = -``sidebands``..``sidebands`` at ``k F + m fr`` (m = 0 is the harmonic).
    bandwidth : float
        Full band width relative to the harmonic ``k F`` (default 0.02, i.e. +- 1 %).
    bandwidth_hz : float, optional
        Full band width in Hz; overrides ``bandwidth``.
    enbw : float
        Equivalent noise bandwidth of the window in bins (1 rectangular, 1.5 Hann).
    spectrum : str
        Label stored in the ``spectrum`` column (``"envelope"``, ``"raw"``, ...).

    Returns
    -------
    pandas.DataFrame
        One row per target, order, sideband with columns ``spectrum, target, target_hz, order,
        sideband, centre_hz, band_low_hz, band_high_hz, n_bins, peak_hz, peak_amplitude,
        band_power, total_band_power``. A band narrower than one bin is widened to the nearest
        bin; bands outside the spectrum give ``n_bins = 0`` and NaN metrics.

    Examples
    --------
    >>> f = np.arange(0, 1000.0, 0.5); a = np.zeros_like(f); a[f == 232.0] = 0.3
    >>> df = fault_band_metrics(f, a, {"BPFI": 232.0}, harmonics=1)
    >>> float(df.peak_amplitude[0]), float(df.peak_hz[0])
    (0.3, 232.0)
    """
    f, a, df_hz = _spectrum(f, amplitude)
    if not isinstance(targets, Mapping) or not targets:
        raise ValueError(f"targets must be a non-empty mapping name -> Hz, got {targets!r}")
    harmonics = _count("harmonics", harmonics, 1)
    sidebands = _count("sidebands", sidebands, 0)
    enbw = check_positive(enbw, "enbw")
    if bandwidth_hz is not None:
        bandwidth_hz = check_positive(bandwidth_hz, "bandwidth_hz")
    else:
        bandwidth = check_positive(bandwidth, "bandwidth")
        if bandwidth >= 1.0:
            raise ValueError(f"bandwidth (relative) must be in (0, 1), got {bandwidth!r}")
    if sidebands > 0:
        if fr is None:
            raise ValueError("fr (shaft rate, Hz) is required when sidebands > 0")
        fr = check_positive(fr, "fr")
    rows = []
    for name, F in targets.items():
        F = check_positive(F, f"targets[{name!r}]")
        union = np.zeros(f.size, dtype=bool)
        target_rows = []
        for k in range(1, harmonics + 1):
            half = 0.5 * (bandwidth_hz if bandwidth_hz is not None else bandwidth * k * F)
            for m in range(-sidebands, sidebands + 1):
                c = k * F + (m * fr if m else 0.0)
                lo, hi = c - half, c + half
                sel = (f >= lo - 1e-9 * df_hz) & (f <= hi + 1e-9 * df_hz)
                if not sel.any() and f[0] - 0.5 * df_hz <= c <= f[-1] + 0.5 * df_hz:
                    sel[int(np.argmin(np.abs(f - c)))] = True
                row = {"spectrum": spectrum, "target": str(name), "target_hz": F, "order": k,
                       "sideband": m, "centre_hz": c, "band_low_hz": lo, "band_high_hz": hi,
                       "n_bins": int(sel.sum())}
                if sel.any():
                    idx = np.flatnonzero(sel)
                    j = idx[int(np.argmax(a[idx]))]
                    row.update(peak_hz=float(f[j]), peak_amplitude=float(a[j]),
                               band_power=float(np.sum(a[idx] ** 2) / 2.0 / enbw))
                    union |= sel
                else:
                    row.update(peak_hz=math.nan, peak_amplitude=math.nan, band_power=math.nan)
                target_rows.append(row)
        total = float(np.sum(a[union] ** 2) / 2.0 / enbw) if union.any() else math.nan
        for row in target_rows:
            row["total_band_power"] = total
        rows.extend(target_rows)
    return pd.DataFrame(rows, columns=_COLUMNS)


def threshold_db(pfa: float = DEFAULT_PFA, n_bins: int = 1,
                 n_background: int | tuple[int, int] | None = None) -> float:
    """Detection threshold (dB) for a false-alarm probability on a Gaussian-noise spectrum.

    With Rayleigh-distributed bin amplitudes, ``P(a > t m) = 2^(-t^2)`` for the true median
    ``m``; the largest of ``n_bins`` independent bins exceeds ``t m`` with probability
    ``1 - (1 - 2^(-t^2))^n_bins``. With ``n_background = None`` (the median known exactly: an
    infinite background) solving for ``t`` gives ``t^2 = -log2(1 - (1 - pfa)^(1/n_bins))`` and
    the threshold ``10 log10(t^2)`` dB.

    The statistic divides by the *sample* median of ``n_background`` bins, itself random: a
    low draw of it raises every ratio, so the asymptotic threshold gives more false alarms than
    ``pfa`` (about 1.07 % for 29 bins against 843, 1.2 % against 300, 2.5 % against 50). With
    ``n_background = N`` the threshold is exact for ``N`` independent Rayleigh bins: the sample
    median ``m_hat`` of ``N`` bins has ``U = F(m_hat) ~ Beta((N+1)/2, (N+1)/2)`` (order
    statistics; exact for odd ``N``, the continuous interpolation for even ``N``), where
    ``F(a) = 1 - exp(-a^2 / 2 s^2)``, so ``P(a > t m_hat | U) = (1 - U)^(t^2)`` and

        pfa(t) = E_U[1 - (1 - (1 - U)^(t^2))^n_bins],

    computed by quadrature over the distribution of ``U`` and solved for ``t``.
    It tends to the asymptotic threshold as ``N`` grows.

    ``n_background = (N_low, N_high)`` is the threshold of the two-sided level of
    :func:`detection_statistic` (``level="two_sided"``: the mean of the medians of the
    ``N_low`` bins below the line and the ``N_high`` above it): with ``r_k = m_hat_k / m =
    sqrt(-log2(1 - U_k))`` and ``r = (r_low + r_high) / 2``, ``P(a > t m r) = 2^(-t^2 r^2)``,
    averaged over the two independent medians.

    Parameters
    ----------
    pfa : float
        False-alarm probability of the test, in (0, 1).
    n_bins : int
        Independent bins searched for the line.
    n_background : int or tuple of (int, int), optional
        Bins of the background median (a pair: the medians below and above the line, averaged);
        None: the median known exactly.

    Returns
    -------
    float
        The threshold (dB) on the line-to-background ratio.

    Examples
    --------
    >>> round(threshold_db(0.01, 1), 2), round(threshold_db(0.01, 10), 2)
    (8.22, 9.98)
    >>> round(threshold_db(0.01, 29, n_background=843), 2), round(threshold_db(0.01, 29), 2)
    (10.64, 10.61)
    >>> round(threshold_db(0.01, 29, n_background=(126, 126)), 2)
    10.73
    """
    pfa = float(pfa)
    if not 0.0 < pfa < 1.0:
        raise ValueError(f"pfa must be in the open range (0, 1), got {pfa!r}")
    n = _count("n_bins", n_bins, 1)
    q = -math.expm1(math.log1p(-pfa) / n)  # 1 - (1 - pfa)^(1/n)
    t2_inf = -math.log2(q)
    if n_background is None:
        return 10.0 * math.log10(t2_inf)
    groups = tuple(n_background) if isinstance(n_background, (tuple, list)) else (n_background,)
    if len(groups) not in (1, 2):
        raise ValueError(f"n_background must be a count or a (low, high) pair of counts, got "
                         f"{n_background!r}")
    groups = tuple(_count("n_background", g, 1) for g in groups)
    return 10.0 * math.log10(_t2_estimated_median(pfa, n, groups, t2_inf))


@lru_cache(maxsize=1024)
def _median_ratio_nodes(count: int) -> np.ndarray:
    """``r = m_hat / m`` of the sample median of ``count`` Rayleigh bins at the quadrature
    nodes (cached: a record's lines share a few background counts; treat as read-only)."""
    z = np.linspace(-_Z_MAX, _Z_MAX, _QUADRATURE_NODES)
    half = 0.5 * (count + 1)
    beta, norm = _stats.beta, _stats.norm
    u = np.where(z < 0, beta.ppf(norm.cdf(z), half, half), beta.isf(norm.sf(z), half, half))
    with np.errstate(divide="ignore"):  # U = 1: log 0 = -inf, exact
        return np.sqrt(-np.log1p(-u) / math.log(2.0))


@lru_cache(maxsize=8192)
def _t2_estimated_median(pfa: float, n: int, groups: tuple[int, ...], t2_inf: float) -> float:
    """``t^2`` with ``pfa(t) = pfa`` for a level that is the mean of the sample medians of
    ``groups`` (one or two counts) of background bins (cached: a record tests a few hundred
    distinct ``(n, groups)``, and records of one machine share many)."""
    # E_U[g(U)] = E_Z[g(B^-1(Phi(Z)))], Z standard normal: the trapezoidal rule on a smooth,
    # rapidly decaying integrand (machine precision against adaptive quadrature, also for the
    # small per-test pfa of the record-wise verdict).
    z = np.linspace(-_Z_MAX, _Z_MAX, _QUADRATURE_NODES)
    w = _stats.norm.pdf(z) * (z[1] - z[0])
    ratios = [_median_ratio_nodes(count) for count in groups]  # per group, at the nodes
    if len(ratios) == 1:
        r2, weight = ratios[0] ** 2, w
    else:
        r2 = (0.5 * (ratios[0][:, None] + ratios[1][None, :])) ** 2
        weight = w[:, None] * w[None, :]
    ln2_r2 = math.log(2.0) * r2

    def excess(log_t2):
        q = np.exp(-math.exp(log_t2) * ln2_r2)  # P(one bin > t m_hat) given the medians
        with np.errstate(divide="ignore"):
            p_fa = float(np.sum(weight * -np.expm1(n * np.log1p(-q))))
        return math.log(p_fa) - math.log(pfa)

    lo = math.log(t2_inf) - 0.05  # the estimated median raises the threshold: a sign change
    hi = lo + 0.5
    while excess(hi) > 0:
        hi += 0.5
    return math.exp(brentq(excess, lo, hi, xtol=1e-10))


#: Nodes and range of the quadrature over the sample median (trapezoidal rule in a standard
#: normal variable: relative error ~1e-14 against scipy's adaptive quadrature for 5-843
#: background bins and pfa 1e-5 to 0.01).
_QUADRATURE_NODES = 241
_Z_MAX = 12.0


@dataclass(frozen=True)
class Detection:
    """Result of :func:`detection_statistic`.

    Attributes
    ----------
    statistic_db : float
        ``20 log10(peak_amplitude / background)`` (dB).
    peak_amplitude, peak_hz : float
        Largest amplitude in the tolerance band and its frequency (Hz).
    background : float
        Background level: the median amplitude of the background bins (or the mean of the
        medians below and above the line, ``level="two_sided"``).
    n_tolerance_bins, n_background_bins : int
        Bins in the tolerance band and in the background.
    threshold_db : float
        Threshold used by :func:`detect`.
    detected : bool
        ``statistic_db > threshold_db`` and the peak is a local maximum of the spectrum (not the
        rising skirt of a neighbouring line at the edge of the tolerance band).
    """

    statistic_db: float
    peak_amplitude: float
    peak_hz: float
    background: float
    n_tolerance_bins: int
    n_background_bins: int
    threshold_db: float
    detected: bool


def detection_statistic(
    f,
    amplitude,
    line_hz: float,
    *,
    fr: float | None = None,
    tolerance: float = 0.01,
    tolerance_hz: float | None = None,
    background: tuple[float, float] = BACKGROUND_BAND,
    sidebands: int = EXCLUDED_SIDEBANDS,
    exclude_hz: Iterable[float] = (),
    threshold: float | None = None,
    pfa: float = DEFAULT_PFA,
    level: str = "median",
) -> Detection:
    """Line-to-background ratio of a fault line (BPFI by default) in dB.

    Parameters
    ----------
    f, amplitude : array_like
        One-sided spectrum (Hz, linear amplitude), envelope or raw.
    line_hz : float
        The fault frequency to look for (Hz), e.g. ``case.bpfi``.
    fr : float, optional
        Shaft rate (Hz): its harmonics and the sidebands ``k line +- m fr`` (m <= ``sidebands``)
        are excluded from the background.
    tolerance : float
        Half-width of the search band relative to ``line_hz`` (default 1 %).
    tolerance_hz : float, optional
        Half-width in Hz; overrides ``tolerance``. At least half a bin is always used.
    background : (lo, hi)
        Background band ``[lo, hi] x line_hz`` (default 0.5-1.5).
    exclude_hz : iterable of float
        Further lines (Hz) to exclude from the background (e.g. a gear-mesh tone).
    threshold : float, optional
        Threshold in dB; default :func:`threshold_db` ``(pfa, n_tolerance_bins,
        n_background_bins)`` (exact for a median estimated from the background bins).
    pfa : float
        False-alarm probability used for the default threshold.
    level : {"median", "two_sided"}
        Background level: the median of all background bins, or the mean of the medians of
        the bins below and above the line (``two_sided``: unbiased where the background varies
        linearly across the line, e.g. the falling envelope spectrum of a band a few lines
        wide; the threshold is :func:`threshold_db` ``(pfa, n, (n_low, n_high))``).

    Returns
    -------
    Detection
    """
    f, a, df_hz = _spectrum(f, amplitude)
    line = check_positive(line_hz, "line_hz")
    half = check_positive(tolerance_hz, "tolerance_hz") if tolerance_hz is not None else \
        check_positive(tolerance, "tolerance") * line
    half = max(half, 0.5 * df_hz)
    lo, hi = (float(background[0]), float(background[1])) if len(background) == 2 else (None, None)
    if lo is None or not 0.0 <= lo < 1.0 < hi:
        raise ValueError(f"background must be (lo, hi) with 0 <= lo < 1 < hi, got {background!r}")
    sidebands = _count("sidebands", sidebands, 0)
    if fr is not None:
        fr = check_positive(fr, "fr")
    if line + half > f[-1]:
        raise ValueError(f"line_hz = {line:g} Hz (+ tolerance) lies beyond the spectrum (f max = {f[-1]:g} Hz)")
    tol_sel = np.abs(f - line) <= half + 1e-9 * df_hz
    idx = np.flatnonzero(tol_sel)
    j = idx[int(np.argmax(a[idx]))]
    peak = float(a[j])

    bg = background_mask(f, line, half, (lo, hi), fr=fr, sidebands=sidebands,
                         exclude_hz=exclude_hz)
    problem = background_problem(f, bg, line, level)
    if problem is not None:
        raise ValueError(f"{problem}: widen background={background!r} or use a finer spectrum")
    if level == "median":
        value = float(np.median(a[bg]))
        counts = int(bg.sum())
    elif level == "two_sided":
        below, above = bg & (f < line), bg & (f > line)
        value = 0.5 * float(np.median(a[below]) + np.median(a[above]))
        counts = (int(below.sum()), int(above.sum()))
    else:
        raise ValueError(f"level must be 'median' or 'two_sided', got {level!r}")
    stat = 20.0 * math.log10(peak / value) if value > 0 and peak > 0 else \
        (math.inf if peak > 0 else -math.inf)
    thr = threshold_db(pfa, int(tol_sel.sum()), counts) if threshold is None else float(threshold)
    # A line must be a local maximum: a "peak" on the edge of the tolerance band that keeps
    # rising outside it is the skirt of a neighbouring line (e.g. a shaft harmonic leaking into
    # the band of a short record), not a line at line_hz.
    skirt = (j == idx[0] and j > 0 and a[j - 1] > peak) or \
        (j == idx[-1] and j + 1 < a.size and a[j + 1] > peak)
    return Detection(stat, peak, float(f[j]), value, int(tol_sel.sum()), int(bg.sum()), thr,
                     bool(stat > thr and not skirt))


def background_mask(f, line: float, half: float, background: tuple[float, float], *,
                    fr: float | None, sidebands: int, exclude_hz: Iterable[float] = ()):
    """The background bins of :func:`detection_statistic`: ``f`` within ``background x line``,
    at least ``half`` (Hz) away from every harmonic of the line and its ``fr`` sidebands,
    every ``fr`` harmonic and ``exclude_hz``.

    Parameters
    ----------
    f : numpy.ndarray
        Frequencies of the spectrum (Hz), ascending.
    line, half : float
        The line and the search half-width (Hz).
    background : (lo, hi)
        Background band in multiples of ``line``.
    fr : float or None
        Shaft rate (Hz); None: no ``fr`` lines excluded.
    sidebands : int
        Sidebands ``k line +- m fr`` excluded (m <= ``sidebands``).
    exclude_hz : iterable of float
        Further lines excluded.

    Returns
    -------
    numpy.ndarray of bool
    """
    lo, hi = background
    bg = (f >= lo * line) & (f <= hi * line) & (f > 0)
    # k line + m fr for k = 1 .. ceil(hi) + 1, |m| <= sidebands (with fr), the fr harmonics,
    # exclude_hz
    ks = np.arange(1, int(math.ceil(hi)) + 2)
    ms = np.arange(-sidebands, sidebands + 1) if fr else np.zeros(1, dtype=int)
    excl = [(ks[:, None] * line + ms[None, :] * (fr or 0.0)).ravel()]
    if fr is not None:
        excl.append(fr * np.arange(1, int(hi * line / fr) + 2))
    excl.append(np.fromiter((float(x) for x in exclude_hz), dtype=np.float64))
    excl = np.concatenate(excl)
    # f ascending: each exclusion touches the bins within half of it, found by bisection
    # (a bin's margin either side, then the exact test on those bins alone)
    pad = 2.0 * (float(f[1] - f[0]) if f.size > 1 else 0.0)
    j0s = np.searchsorted(f, excl - half - pad)
    j1s = np.searchsorted(f, excl + half + pad)
    for k in np.flatnonzero(j1s > j0s):
        j0, j1 = j0s[k], j1s[k]
        bg[j0:j1] &= np.abs(f[j0:j1] - excl[k]) > half
    return bg


def background_problem(f, bg, line: float, level: str) -> str | None:
    """Why the background ``bg`` (:func:`background_mask`) is too small for ``level`` (None
    when it is enough): fewer than 5 bins, or for ``two_sided`` fewer than 3 on a side.

    Parameters
    ----------
    f : numpy.ndarray
        Frequencies (Hz).
    bg : numpy.ndarray of bool
        The background bins.
    line : float
        The line (Hz).
    level : {"median", "two_sided"}

    Returns
    -------
    str or None
    """
    if bg.sum() < 5:
        return f"too few background bins ({int(bg.sum())}) around {line:g} Hz"
    below, above = int((bg & (f < line)).sum()), int((bg & (f > line)).sum())
    if level == "two_sided" and (below < 3 or above < 3):
        return (f"level='two_sided' needs >= 3 background bins on each side of {line:g} Hz, "
                f"got {below} and {above}")
    return None


def detect(f, amplitude, line_hz: float, **kwargs) -> tuple[float, bool]:
    """``(statistic_db, detected)`` of :func:`detection_statistic` (same keyword arguments).

    Parameters
    ----------
    f, amplitude : array_like
        The spectrum (Hz, amplitude).
    line_hz : float
        The line searched (Hz).
    **kwargs
        Passed to :func:`detection_statistic`.

    Returns
    -------
    tuple of (float, bool)
        ``(statistic_db, detected)``.
    """
    d = detection_statistic(f, amplitude, line_hz, **kwargs)
    return d.statistic_db, d.detected


def clopper_pearson(k: int, n: int, confidence: float = DEFAULT_CONFIDENCE) -> tuple[float, float]:
    """Exact (Clopper-Pearson) confidence interval of a binomial rate ``k / n``.

    ``low = B^-1(a/2; k, n - k + 1)`` and ``high = B^-1(1 - a/2; k + 1, n - k)`` with
    ``a = 1 - confidence`` and ``B^-1`` the inverse regularised incomplete beta function
    (``low = 0`` for ``k = 0``, ``high = 1`` for ``k = n``).

    Parameters
    ----------
    k : int
        Events (false alarms), ``0 <= k <= n``.
    n : int
        Trials (>= 1).
    confidence : float
        Two-sided confidence level.

    Returns
    -------
    tuple of (float, float)
        ``(low, high)``.

    Examples
    --------
    >>> lo, hi = clopper_pearson(0, 300)
    >>> lo, round(hi, 5)
    (0.0, 0.01222)
    """
    k, n = int(k), _count("n", n, 1)
    if not 0 <= k <= n:
        raise ValueError(f"k must be in [0, n = {n}], got {k}")
    a = 1.0 - float(confidence)
    if not 0.0 < a < 1.0:
        raise ValueError(f"confidence must be in (0, 1), got {confidence!r}")
    low = 0.0 if k == 0 else float(_stats.beta.ppf(a / 2, k, n - k + 1))
    high = 1.0 if k == n else float(_stats.beta.ppf(1 - a / 2, k + 1, n - k))
    return low, high


def false_alarm_rates(trials: pd.DataFrame, by=("band", "snr_db"),
                      confidence: float = DEFAULT_CONFIDENCE) -> pd.DataFrame:
    """Pool false-alarm trials (one row per healthy record tested, column ``detected``).

    Returns
    -------
    pandas.DataFrame
        One row per group of ``by`` (all rows when ``by`` is empty): ``n_trials``,
        ``n_false_alarms``, ``rate``, ``ci_low``, ``ci_high`` (Clopper-Pearson at
        ``confidence``), ``statistic_db_mean``, ``statistic_db_max``, ``threshold_db``.

    Parameters
    ----------
    trials : pandas.DataFrame
        One row per test of a healthy record (``detected``, ``statistic_db``, ``threshold_db`` and
        the ``by`` columns).
    by : sequence of str
        Columns to group by.
    confidence : float
        Confidence level of the intervals.
    """
    by = list(by)
    groups = trials.groupby(by, sort=True) if by else [((), trials)]
    rows = []
    for key, g in groups:
        key = key if isinstance(key, tuple) else (key,)
        n, k = len(g), int(g["detected"].sum())
        lo, hi = clopper_pearson(k, n, confidence)
        rows.append({**dict(zip(by, key)), "n_trials": n, "n_false_alarms": k, "rate": k / n,
                     "ci_low": lo, "ci_high": hi,
                     "statistic_db_mean": float(g["statistic_db"].mean()),
                     "statistic_db_std": float(g["statistic_db"].std(ddof=1)) if n > 1 else float("nan"),
                     "statistic_db_max": float(g["statistic_db"].max()),
                     "threshold_db": float(g["threshold_db"].median())})
    return pd.DataFrame(rows)
