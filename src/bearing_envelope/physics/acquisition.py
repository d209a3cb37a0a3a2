"""Acquisition of a case: point samples, or anti-aliased (synthesised ``oversample`` times
faster, FIR low-pass, decimated to ``fs``); additive noise."""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from .fidelity import Fidelity, fidelity_from
from .scene import Scene
from .solves import window_spec

__all__ = ["antialias_filter", "antialias_undershoot", "auto_oversample", "acquire", "add_noise",
           "acquisition_settings", "ANTIALIAS_PASS", "ANTIALIAS_STOP", "ANTIALIAS_ATTEN_DB",
           "ACQUISITION_BLOCK"]


#: Anti-alias filter of the ``antialiased`` acquisition, as fractions of the output rate fs:
#: pass band up to ``ANTIALIAS_PASS`` (the fs/4-3fs/8 band and every BPFI band lie inside),
#: stop band from ``ANTIALIAS_STOP`` = Nyquist with at least ``ANTIALIAS_ATTEN_DB``.
ANTIALIAS_PASS = 0.40
ANTIALIAS_STOP = 0.50
ANTIALIAS_ATTEN_DB = 80.0
#: Design margin of the Kaiser window over :data:`ANTIALIAS_ATTEN_DB` (dB): the window is
#: designed for 85 dB so that the realised stop band (odd, symmetric length) keeps >= 80 dB.
ANTIALIAS_DESIGN_MARGIN_DB = 5.0

#: Output samples per block of the anti-aliased synthesis (bounds memory: the internal rate is
#: ``oversample x fs``; a block holds ``oversample x (ACQUISITION_BLOCK + filter length)`` samples).
ACQUISITION_BLOCK = 8192


def antialias_filter(oversample: int) -> np.ndarray:
    """Linear-phase FIR low-pass for decimating ``oversample x fs`` to ``fs``.

    Kaiser-window design (:func:`scipy.signal.firwin`) at the internal rate, cut-off half-way
    between :data:`ANTIALIAS_PASS` and :data:`ANTIALIAS_STOP` (0.45 fs), designed for
    ``ANTIALIAS_ATTEN_DB + ANTIALIAS_DESIGN_MARGIN_DB`` dB so that the stop band from fs/2 up is at least
    :data:`ANTIALIAS_ATTEN_DB` down (checked in the tests); pass-band ripple < 1e-4. The length
    is ``2 K oversample + 1`` (odd, symmetric: the centre tap is the zero-delay sample), unit DC
    gain.

    Parameters
    ----------
    oversample : int
        The internal rate as a multiple of fs (>= 2).

    Returns
    -------
    numpy.ndarray
        The filter's taps (odd length, symmetric, unit DC gain).
    """
    from scipy.signal import firwin, kaiser_beta, kaiserord

    n = int(oversample)
    fs_int = float(n)                      # in units of the output rate
    width = ANTIALIAS_STOP - ANTIALIAS_PASS
    numtaps, _ = kaiserord(ANTIALIAS_ATTEN_DB + ANTIALIAS_DESIGN_MARGIN_DB, width / (0.5 * fs_int))
    k = int(math.ceil((numtaps - 1) / (2.0 * n)))
    h = firwin(2 * k * n + 1, 0.5 * (ANTIALIAS_PASS + ANTIALIAS_STOP), fs=fs_int,
               window=("kaiser", kaiser_beta(ANTIALIAS_ATTEN_DB + ANTIALIAS_DESIGN_MARGIN_DB)))
    return h / h.sum()


def auto_oversample(scene: Scene, fidelity: Fidelity | str | None = None) -> int:
    """``oversample: auto``: the smallest ``N`` with the defect moving no more than the table's
    offset-node spacing per internal sample, ``N = ceil(v / (fs dx))`` with
    ``v = 2 pi (f_r - f_c) R_i`` the defect's speed relative to the cage (4.24 m/s in the default
    scene) and ``dx = min(w_x / offsets_per_width, offset_step_um)`` the largest node spacing of
    ``fidelity``'s table (:func:`_offset_nodes`; ``offset_step_um`` for a healthy race), but not
    below the window spacing. The interpolated history has no feature finer than the node
    spacing, so a denser internal rate changes nothing: measured, N = 8, 16 and 33 at
    ``standard`` agree to < 0.01 % in every amplitude (``CHANGELOG.md``, "Fidelity presets and
    their accuracy"). N = 9 (15 um defect) and 6 (100 um) at ``standard``.

    Parameters
    ----------
    scene : Scene
        The case's scene (defect width, speeds, fs).
    fidelity : Fidelity, preset name or None
        The fidelity whose table spacing bounds the travel per sample (None: ``standard``).

    Returns
    -------
    int
        ``N >= 1``.
    """
    fid = fidelity_from(fidelity)
    v = scene.defect_speed_m_s
    step = fid.offset_step_m
    if scene.defect.active:
        step = min(step, scene.defect.extent_x_m / fid.offsets_per_width)
        step = max(step, window_spec(scene, fid, 1.0, 1.0)[2])
    return max(1, int(math.ceil(v / (scene.operation.fs_hz * step) - 1e-9)))


def acquire(evaluate: Callable[[np.ndarray], dict], n_samples: int, fs: float, *,
            mode: str = "antialiased", oversample: int = 1, filtered: tuple[str, ...] | None = None,
            block: int = ACQUISITION_BLOCK,
            ranges: dict[str, list[float]] | None = None) -> dict[str, np.ndarray]:
    """Sample signals given as functions of time at ``fs``: point samples or anti-aliased.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(t) -> {name: array like t}``: the signals at times ``t`` (s); called on
        blocks, also at times slightly before 0 and after the record (filter lead-in/out).
    n_samples : int
        Output samples, at ``t_k = k / fs``.
    fs : float
        Output rate (Hz).
    mode : {"antialiased", "point"}
        ``point``: ``evaluate(t_k)``. ``antialiased``: evaluated at ``oversample x fs``, filtered
        by :func:`antialias_filter` and decimated with :func:`scipy.signal.upfirdn`, the filter
        centred on each output instant (zero phase, no delay).
    oversample : int
        Internal rate factor (``>= 1``).
    filtered : tuple of str, optional
        Names that are filtered; the others are point-sampled at ``t_k`` (default: all).
    block : int
        Output samples per block (memory bound).
    ranges : dict, optional
        Filled with ``name -> [min, max]`` of each filtered signal's internal samples (before the
        filter). The filter is linear with some negative taps, so an anti-aliased output of a
        signal that is ``>= 0`` internally can undershoot 0 near sharp features, by at most
        ``max x sum(-h[h < 0])`` (:func:`antialias_undershoot`); these ranges let a caller check
        the physics (``p >= 0``) on the internal samples and the filter bound on the output.

    Returns
    -------
    dict
        ``name -> array (n_samples,)``.
    """
    from scipy.signal import upfirdn

    if mode not in ("antialiased", "point"):
        raise ValueError(f"acquisition mode: got {mode!r}; allowed: antialiased | point")
    if isinstance(oversample, bool) or not isinstance(oversample, (int, np.integer)) or oversample < 1:
        raise ValueError(f"acquisition oversample: got {oversample!r}; allowed: an integer >= 1")
    n_samples = int(n_samples)
    if mode == "point":
        return {k: np.asarray(v, dtype=float) for k, v in evaluate(np.arange(n_samples) / fs).items()}
    n = int(oversample)
    h = antialias_filter(n)
    k_half = (h.size - 1) // (2 * n)             # filter half-length in output samples
    c = k_half * n
    out: dict[str, np.ndarray] = {}
    for m0 in range(0, n_samples, block):
        m1 = min(n_samples, m0 + block)
        j = np.arange(m0 * n - c, (m1 - 1) * n + c + 1)
        sig = evaluate(j / (n * fs))
        if not out:
            out = {k: np.empty(n_samples) for k in sig}
        for name, x in sig.items():
            x = np.asarray(x, dtype=float)
            if filtered is not None and name not in filtered:
                out[name][m0:m1] = x[c::n][: m1 - m0]
            else:
                y = upfirdn(h, x, 1, n)
                out[name][m0:m1] = y[2 * k_half: 2 * k_half + (m1 - m0)]
                if ranges is not None and x.size:
                    lo, hi = ranges.get(name, [math.inf, -math.inf])
                    ranges[name] = [min(lo, float(x.min())), max(hi, float(x.max()))]
    return out


def antialias_undershoot(oversample: int) -> float:
    """``sum(-h[h < 0])`` of :func:`antialias_filter`: an anti-aliased output of a signal with
    internal samples in ``[0, M]`` lies in ``[-u M, (1 + u) M]`` with ``u`` this value.

    Parameters
    ----------
    oversample : int
        The internal rate as a multiple of fs.

    Returns
    -------
    float
        ``u >= 0``.
    """
    h = antialias_filter(oversample)
    return float(-h[h < 0].sum())



def add_noise(x: np.ndarray, snr_db: float, seed: int) -> np.ndarray:
    """``x`` plus white Gaussian noise at ``snr_db`` (signal power = variance of ``x``), seeded.

    Parameters
    ----------
    x : numpy.ndarray
        The signal.
    snr_db : float
        Signal-to-noise ratio (dB).
    seed : int
        Seed of the noise generator.

    Returns
    -------
    numpy.ndarray
        A new array, ``x`` plus the noise.
    """
    rng = np.random.default_rng(seed)
    power = float(np.var(x))
    sigma = math.sqrt(power / 10.0 ** (snr_db / 10.0)) if power > 0 else 0.0
    return x + sigma * rng.standard_normal(x.size)


def acquisition_settings(scene: Scene, fidelity: Fidelity | str | None = None) -> dict[str, Any]:
    """The acquisition a case uses: ``mode``, resolved ``oversample`` (1 for ``point``), the
    filter's pass/stop edges (fractions of fs), its stop-band attenuation target (dB) and length.

    Parameters
    ----------
    scene : Scene
        The case's scene (its ``operation.acquisition``).
    fidelity : Fidelity, preset name or None
        The fidelity (resolves ``oversample: auto``; None: ``standard``).

    Returns
    -------
    dict
        ``{"mode": "point", "oversample": 1}``, or ``mode``, ``oversample``,
        ``oversample_setting``, ``filter``, ``pass_band_fs``, ``stop_band_fs``,
        ``stop_band_attenuation_db``, ``filter_taps``.
    """
    acq = scene.operation.acquisition
    if acq.mode == "point":
        return {"mode": "point", "oversample": 1}
    n = auto_oversample(scene, fidelity) if acq.oversample == "auto" else int(acq.oversample)
    return {"mode": acq.mode, "oversample": n, "oversample_setting": str(acq.oversample),
            "filter": "Kaiser-window FIR, linear phase, centred (zero delay), scipy.signal.upfirdn",
            "pass_band_fs": ANTIALIAS_PASS, "stop_band_fs": ANTIALIAS_STOP,
            "stop_band_attenuation_db": ANTIALIAS_ATTEN_DB,
            "filter_taps": int(antialias_filter(n).size)}
