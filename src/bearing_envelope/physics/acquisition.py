"""Acquisition of a case: point samples, or anti-aliased (synthesised ``oversample`` times
faster, FIR low-pass, decimated to ``fs``); additive noise."""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from .fidelity import Fidelity
from .kernels import HAVE_NUMBA, decimate_kernel
from .scene import DEFAULT_SCENE, Scene
from .solves import window_spec

__all__ = ["antialias_filter", "antialias_undershoot", "kaiser_beta", "kaiser_lowpass", "decimate_centred", "auto_oversample", "acquire", "add_noise",
           "acquisition_settings", "signal_bounds", "clip_to_bounds",
           "ANTIALIAS_PASS", "ANTIALIAS_STOP", "ANTIALIAS_ATTEN_DB",
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


def kaiser_beta(atten_db: float) -> float:
    """The Kaiser window's ``beta`` for a stop band ``atten_db`` dB down (Kaiser 1974; Oppenheim &
    Schafer, eq. 7.62; the same numbers as :func:`scipy.signal.kaiser_beta`).

    Parameters
    ----------
    atten_db : float
        Stop-band attenuation (dB, > 0).

    Returns
    -------
    float
        ``0.1102 (A - 8.7)`` above 50 dB, ``0.5842 (A - 21)^0.4 + 0.07886 (A - 21)`` from 21 to
        50 dB, 0 below.
    """
    a = float(atten_db)
    if a > 50:
        return 0.1102 * (a - 8.7)
    if a > 21:
        return 0.5842 * (a - 21) ** 0.4 + 0.07886 * (a - 21)
    return 0.0


def kaiser_lowpass(numtaps: int, cutoff: float, beta: float) -> np.ndarray:
    """Windowed-sinc FIR low-pass: the ideal response up to ``cutoff`` (a fraction of Nyquist)
    times a symmetric Kaiser window, scaled to unit DC gain (the window method; the same taps as
    ``scipy.signal.firwin(numtaps, cutoff, window=("kaiser", beta))`` to the last bit, which
    ``tests/test_history.py`` checks: the ``simulate`` job then needs no ``scipy.signal``, 0.5 CPU s
    to import).

    Parameters
    ----------
    numtaps : int
        Filter length (odd: a symmetric filter with a centre tap).
    cutoff : float
        Cut-off frequency as a fraction of Nyquist, in (0, 1).
    beta : float
        Kaiser window parameter (:func:`kaiser_beta`).

    Returns
    -------
    numpy.ndarray
        The taps, ``numtaps`` long, summing to 1.
    """
    from scipy.special import i0

    m = np.arange(0, numtaps, dtype=np.float64) - 0.5 * (numtaps - 1)
    h = cutoff * np.sinc(cutoff * m)
    alpha = (numtaps - 1) / 2.0
    n = np.arange(0, numtaps, dtype=np.float64)
    h *= i0(beta * np.sqrt(1 - ((n - alpha) / alpha) ** 2.0)) / i0(np.float64(beta))
    h /= np.sum(h)
    return h


def antialias_filter(oversample: int) -> np.ndarray:
    """Linear-phase FIR low-pass for decimating ``oversample x fs`` to ``fs``.

    Kaiser-window design (:func:`kaiser_lowpass`; length from Kaiser's formula) at the internal rate, cut-off half-way
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
    n = int(oversample)
    fs_int = float(n)                      # in units of the output rate
    width = ANTIALIAS_STOP - ANTIALIAS_PASS
    atten = ANTIALIAS_ATTEN_DB + ANTIALIAS_DESIGN_MARGIN_DB
    # Kaiser's length estimate (scipy.signal.kaiserord), transition width a fraction of Nyquist
    numtaps = int(math.ceil((atten - 7.95) / 2.285 / (np.pi * (width / (0.5 * fs_int))) + 1))
    k = int(math.ceil((numtaps - 1) / (2.0 * n)))
    h = kaiser_lowpass(2 * k * n + 1, 0.5 * (ANTIALIAS_PASS + ANTIALIAS_STOP) / (0.5 * fs_int),
                       kaiser_beta(atten))
    return h / h.sum()


def decimate_centred(h: np.ndarray, x: np.ndarray, n: int, count: int, *,
                     use_numba: bool = True) -> np.ndarray:
    """``count`` outputs of the FIR ``h`` (odd length ``2c + 1``) on ``x``, every ``n``-th,
    centred: ``y[i] = sum_j h[j] x[c + i n + c - j]``, i.e. output ``i`` is the filter centred on
    ``x[c + i n]``. ``x`` must hold ``(count - 1) n + 2c + 1`` samples (every output complete).

    The sum runs from the last tap to the first, the order of :func:`scipy.signal.upfirdn`
    (``upfirdn(h, x, 1, n)[2c/n:][:count]``), so the outputs equal it to the last bit (checked in
    ``tests/test_history.py``); one vector operation per tap over all outputs.

    Parameters
    ----------
    h : numpy.ndarray
        Taps, odd length.
    x : numpy.ndarray
        Input samples at the internal rate.
    n : int
        Decimation factor (>= 1).
    count : int
        Number of outputs.
    use_numba : bool, default True
        The numba loop (:func:`~.kernels.decimate_kernel`, the same sums: 30 % less CPU than
        numpy's per-tap passes) where numba is available.

    Returns
    -------
    numpy.ndarray
        ``(count,)`` outputs.
    """
    c = (h.size - 1) // 2
    if x.size != (count - 1) * n + 2 * c + 1:
        raise ValueError(f"decimate_centred: x has {x.size} samples; allowed: "
                         f"(count - 1) n + 2c + 1 = {(count - 1) * n + 2 * c + 1}")
    if use_numba and HAVE_NUMBA:
        out = np.empty(count)
        decimate_kernel(np.ascontiguousarray(h, dtype=float), np.ascontiguousarray(x, dtype=float),
                        int(n), out)
        return out
    acc = np.zeros(count)
    tmp = np.empty(count)
    span = (count - 1) * n + 1
    for j in range(h.size - 1, -1, -1):
        np.multiply(x[2 * c - j: 2 * c - j + span: n], h[j], out=tmp)
        acc += tmp
    return acc


def auto_oversample(scene: Scene, fidelity: Fidelity) -> int:
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
    fidelity : Fidelity
        The case's fidelity (converted once, at the edge: the loader, the CLI or ``simulate``).
        The fidelity whose table spacing bounds the travel per sample (None: ``standard``).

    Returns
    -------
    int
        ``N >= 1``.
    """
    fid = fidelity
    v = scene.defect_speed_m_s
    step = fid.offset_step_m
    if scene.defect.active:
        step = min(step, scene.defect.extent_x_m / fid.offsets_per_width)
        step = max(step, window_spec(scene, fid, 1.0, 1.0)[2])
    return max(1, int(math.ceil(v / (scene.operation.fs_hz * step) - 1e-9)))


def acquire(evaluate: Callable[[np.ndarray], dict], n_samples: int, fs: float, *,
            mode: str = DEFAULT_SCENE["operation"]["acquisition"]["mode"], oversample: int = 1,
            filtered: tuple[str, ...] | None = None,
            block: int = ACQUISITION_BLOCK,
            ranges: dict[str, list[float]] | None = None,
            bounds: dict[str, tuple[float, float]] | None = None,
            clipped: dict[str, dict] | None = None) -> dict[str, np.ndarray]:
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
        by :func:`antialias_filter` and decimated (:func:`decimate_centred`), the filter
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
    bounds : dict, optional
        ``name -> (lo, hi)``: the physical range of a filtered signal (:func:`signal_bounds`).
        The filter's ringing on a feature the physics clips (a pressure capped at the hardness,
        a contact that unloads to 0) overshoots that range; each output is clipped back into
        it after the filter (:func:`clip_to_bounds`).
    clipped : dict, optional
        Filled with ``name -> {"samples": count, "max_excess": largest distance clipped}`` for
        every bounded signal (counts 0 included), so the clipping is reported, never silent.

    Returns
    -------
    dict
        ``name -> array (n_samples,)``.
    """
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
                y = decimate_centred(h, x, n, m1 - m0)
                if bounds is not None and name in bounds:
                    y = clip_to_bounds(y, bounds[name], clipped, name)
                out[name][m0:m1] = y
                if ranges is not None and x.size:
                    lo, hi = ranges.get(name, [math.inf, -math.inf])
                    ranges[name] = [min(lo, float(x.min())), max(hi, float(x.max()))]
    return out


def signal_bounds(scene: Scene) -> dict[str, tuple[float, float]]:
    """The physical range of each filtered contact signal a case records.

    A contact pressure lies in ``[0, H]`` (``H`` the hardness bound of every solve,
    ``material.hardness_GPa``; no upper bound for an elastic surface); the contact force and
    area are ``>= 0``. ``removed_force``, ``approach`` and ``approach_change`` have no bound
    the physics fixes, and are not clipped.

    Parameters
    ----------
    scene : Scene
        The case's scene (its hardness).

    Returns
    -------
    dict
        ``name -> (lo, hi)`` in the signal's SI unit (Pa, N, m^2).
    """
    cap = scene.material.hardness_pa
    p = (0.0, math.inf if cap is None else float(cap))
    return {"p_max": p, "p_max_defect": p, "contact_force": (0.0, math.inf),
            "contact_area": (0.0, math.inf)}


def clip_to_bounds(y: np.ndarray, bound: tuple[float, float], clipped: dict | None = None,
                   name: str = "") -> np.ndarray:
    """``y`` clipped into ``bound``, the count and the largest excess added to ``clipped``.

    The anti-alias filter is linear with negative taps: on a peak the physics flattens at ``H``
    or a load that falls to 0 its output rings past the bound by up to
    :func:`antialias_undershoot` times the peak (0.6 % over ``H``, 1.6 % of ``H`` below 0 on
    the CWRU pits at ``standard``). A recorded pressure must stay a pressure, so the filtered
    samples are clipped (filter, then clip: no filter without negative taps keeps an 80 dB
    stop band from 0.5 fs with a pass band to 0.4 fs). The change at a clipped sample is at
    most that ringing; the count says how many samples carry it.

    Parameters
    ----------
    y : numpy.ndarray
        Filtered samples.
    bound : tuple of float
        ``(lo, hi)``, ``lo <= hi`` (either may be infinite).
    clipped : dict, optional
        ``name -> {"samples": int, "max_excess": float}``, accumulated over calls.
    name : str
        The signal's key in ``clipped``.

    Returns
    -------
    numpy.ndarray
        ``numpy.clip(y, lo, hi)`` (``y`` itself when nothing lies outside).
    """
    lo, hi = float(bound[0]), float(bound[1])
    excess = np.maximum(lo - y, y - hi)
    outside = excess > 0
    k = int(np.count_nonzero(outside))
    if clipped is not None:
        rec = clipped.setdefault(name, {"samples": 0, "max_excess": 0.0})
        rec["samples"] += k
        if k:
            rec["max_excess"] = max(rec["max_excess"], float(excess[outside].max()))
    return np.clip(y, lo, hi) if k else y


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


def acquisition_settings(scene: Scene, fidelity: Fidelity) -> dict[str, Any]:
    """The acquisition a case uses: ``mode``, resolved ``oversample`` (1 for ``point``), the
    filter's pass/stop edges (fractions of fs), its stop-band attenuation target (dB) and length.

    Parameters
    ----------
    scene : Scene
        The case's scene (its ``operation.acquisition``).
    fidelity : Fidelity
        The case's fidelity (converted once, at the edge: the loader, the CLI or ``simulate``).
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
            "filter": "Kaiser-window FIR, linear phase, centred (zero delay), decimated",
            "pass_band_fs": ANTIALIAS_PASS, "stop_band_fs": ANTIALIAS_STOP,
            "stop_band_attenuation_db": ANTIALIAS_ATTEN_DB,
            "filter_taps": int(antialias_filter(n).size)}
