"""Transfer path from the contact history to a synthetic accelerometer signal.

The contact simulation gives the *source* of the vibration (the contact pressure, or the contact
force, as a function of time). A sensor on the housing sees that source filtered by the structure's
resonances, plus measurement noise and other machine tones. This module builds that signal on plain
numpy arrays:

1. **Excitation** (:func:`excitation_from_history`): the chosen contact signal minus its mean,
   times a scale (e.g. an area in m^2 turns a pressure in Pa into a force in N).
2. **Structure** (:class:`Mode`, :class:`TransferModel`): a sum of second-order resonators, one per
   mode, each with natural frequency ``f_n``, damping ratio ``zeta`` and gain ``g``,

   .. math::

       H(s) = \\sum_i g_i \\frac{2\\zeta_i\\omega_i s}{s^2 + 2\\zeta_i\\omega_i s + \\omega_i^2},
       \\qquad \\omega_i = 2\\pi f_{n,i},

   so that ``|H_i(j\\omega_i)| = g_i`` (acceleration per unit excitation at resonance) and the
   response to a static load is zero (an acceleration has no DC). Each mode is discretised on its
   own as one second-order section, by impulse invariance (default: the poles map exactly,
   ``z = exp(s / fs)``, so the digital impulse response rings at ``f_d = f_n sqrt(1 - zeta^2)``
   and decays as ``exp(-zeta omega_n t)`` exactly) or by the bilinear transform prewarped at
   ``f_n``; in both cases the numerator is scaled so that the digital gain at ``f_n`` equals
   ``g``. Modes act in parallel (their outputs add).
3. **Noise** at a target SNR (:func:`synthesize_acceleration`):

   .. math:: \\mathrm{SNR} = 10 \\log_{10}(P_\\mathrm{defect} / P_\\mathrm{noise})\\ \\mathrm{dB},

   with ``P_defect`` the variance of the defect-related part of the structural response: the
   response to the excitation minus the response to a no-defect reference excitation when one is
   given, else the variance of the whole response. The noise is white Gaussian (flat to fs/2).
4. **Interfering tones** (shaft harmonics, a gear-mesh tone), added after the noise, not counted in
   the SNR.

All randomness comes from one :class:`numpy.random.Generator` seeded by ``seed``. See
``docs/sensor.md`` for the model, the config keys (``sensor:`` section) and their units.

The sensor's description (:class:`Mode`, :class:`Tone`, :class:`NoiseSpec`,
:class:`TransferModel`, the ``sensor:`` defaults) lives in :mod:`.transfer_model`; this module
makes the signal from it (excitation, structural filter, noise and tones) and re-exports it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict
from typing import Any

import numpy as np

from ..checks import check_number
from ..lazy import lazy_module
from .transfer_model import (_DISCRETIZATIONS, EXCITATION_KINDS, Mode, NoiseSpec, Tone,
                             TransferModel, sensor_defaults)

sps = lazy_module("scipy.signal")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = [
    "EXCITATION_KINDS",
    "Mode",
    "NoiseSpec",
    "Tone",
    "TransferModel",
    "sensor_defaults",
    "excitation_from_history",
    "select_excitation",
    "mode_sos",
    "impulse_response",
    "apply_structure",
    "synthesize_acceleration",
    "measure_snr_db",
    "direction_gain",
]


# --------------------------------------------------------------------------------------------
# excitation
# --------------------------------------------------------------------------------------------
def select_excitation(signals: Mapping[str, np.ndarray], kind: str = "pressure") -> tuple[str, np.ndarray]:
    """Pick the contact signal for an excitation kind.

    ``pressure`` -> ``p_max`` (Pa, max over the whole contact: the roller-load-related signal
    that the contact history always carries); ``pressure_defect`` -> ``p_max_defect``; the
    noise-free ``*_clean`` versions are preferred when the case has them (the case's own
    measurement noise is not part of the physical excitation);
    ``force`` -> the first of ``contact_force`` (roller load minus the force the defect removes
    at fixed approach: the blocked force), ``force``, ``roller_load`` (N). Returns
    ``(name, array)``; raises KeyError naming what is missing.

    Parameters
    ----------
    signals : Mapping of str to numpy.ndarray
        The case's signals by name.
    kind : str
        ``pressure``, ``pressure_defect`` or ``force``.

    Returns
    -------
    tuple of (str, numpy.ndarray)
        The signal's name and its samples.

    Raises
    ------
    ValueError
        ``kind`` is not an excitation kind.
    KeyError
        The case has none of the signals the kind needs.
    """
    if kind not in EXCITATION_KINDS:
        raise ValueError(f"excitation must be one of {tuple(EXCITATION_KINDS)}, got {kind!r}")
    for name in EXCITATION_KINDS[kind]:
        if name in signals and signals[name] is not None:
            return name, np.asarray(signals[name], dtype=float)
    raise KeyError(f"excitation {kind!r} needs one of the signals {EXCITATION_KINDS[kind]}, "
                   f"the case has {sorted(signals)}")


def excitation_from_history(x: np.ndarray, *, scale: float = 1.0) -> np.ndarray:
    """Excitation ``e(t) = scale * (x(t) - mean(x))`` from a contact signal.

    Parameters
    ----------
    x : array_like, shape (n,)
        Contact history sampled at fs: p_max (Pa) or a contact force (N).
    scale : float
        Multiplier (e.g. an effective area in m^2 to express a pressure as a force in N).

    Returns
    -------
    numpy.ndarray
        The excitation, same length as ``x``.

    Raises
    ------
    ValueError
        The excitation is not a 1-D array of >= 2 samples, or holds non-finite values.

    Notes
    -----
    The mean (the static load) produces no acceleration; removing it also avoids the start-up
    step of the filters.
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size < 2:
        raise ValueError(f"excitation must be a 1-D array with >= 2 samples, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("excitation contains non-finite values")
    return check_number(scale, "scale") * (x - x.mean())


# --------------------------------------------------------------------------------------------
# structural filter
# --------------------------------------------------------------------------------------------
def mode_sos(mode: Mode, fs: float, method: str = "impulse") -> np.ndarray:
    """Second-order section (shape (1, 6)) of one mode at sampling rate ``fs`` (Hz).

    ``impulse``: impulse invariance with the half-sample correction at t = 0,
    ``H(z) = T [sum_n h(nT) z^-n - h(0)/2]``; with ``r = exp(-zeta omega_n T)``,
    ``theta = omega_d T``, ``b1 = 2 zeta omega_n g``:
    ``A(z) = 1 - 2 r cos(theta) z^-1 + r^2 z^-2``,
    ``B(z) ~ b1/2 - (b1 zeta/sqrt(1-zeta^2)) r sin(theta) z^-1 - (b1/2) r^2 z^-2``,
    then ``B <- B - H(1) A`` so that the DC gain is exactly zero as in the analog resonator
    (this only changes the first sample of the impulse response; ``h[n], n >= 1`` stay the
    samples ``T h(nT)``).
    ``bilinear``: the analog resonator with omega_n prewarped to ``2 fs tan(omega_n T/2)``.
    Either way B is then scaled so that ``|H(exp(j omega_n T))| = g``. Poles:
    ``|z| = exp(-zeta omega_n T) < 1`` (impulse) — always stable.

    Parameters
    ----------
    mode : Mode
        The mode.
    fs : float
        Sampling rate (Hz).
    method : str
        ``impulse`` (impulse invariance) or ``bilinear`` (prewarped bilinear transform).

    Returns
    -------
    numpy.ndarray
        The section, shape (1, 6) (``scipy.signal.sosfilt`` layout).

    Raises
    ------
    ValueError
        An unknown discretization ``method``.
    """
    fs = check_number(fs, "fs")
    mode.check_fs(fs)
    T = 1.0 / fs
    wn = 2.0 * math.pi * mode.f_n_hz
    z = mode.zeta
    if method == "impulse":
        sigma = z * wn
        wd = wn * math.sqrt(1.0 - z * z)
        r = math.exp(-sigma * T)
        th = wd * T
        b1 = 2.0 * z * wn
        c = -b1 * sigma / wd  # sin coefficient of h(t) = exp(-sigma t)(b1 cos + c sin)
        b = T * np.array([b1 / 2.0, c * r * math.sin(th), -b1 / 2.0 * r * r])
        a = np.array([1.0, -2.0 * r * math.cos(th), r * r])
        # aliasing leaves a DC gain (up to 0.3 g at f_n = 0.45 fs, zeta = 0.5); remove it by
        # subtracting the constant H(1): changes only h[0], keeps h[n >= 1] impulse-invariant
        b = b - (b.sum() / a.sum()) * a
    elif method == "bilinear":
        wp = 2.0 * fs * math.tan(wn * T / 2.0)
        b, a = sps.bilinear([2.0 * z * wp, 0.0], [1.0, 2.0 * z * wp, wp * wp], fs=fs)
        b = np.r_[b, np.zeros(3 - len(b))]
        a = np.r_[a, np.zeros(3 - len(a))]
    else:
        raise ValueError(f"discretization must be one of {_DISCRETIZATIONS}, got {method!r}")
    ejw = np.exp(-1j * wn * T * np.arange(3))
    h_n = abs(np.dot(b, ejw) / np.dot(a, ejw))
    b = b * (mode.gain / h_n)
    return np.concatenate([b, a])[None, :]


def impulse_response(model: TransferModel | Sequence[Mode], fs: float, n: int) -> np.ndarray:
    """Response of the summed modes to a unit-area impulse (first sample ``fs``, others 0).

    Parameters
    ----------
    model : TransferModel or sequence of Mode
        The modes.
    fs : float
        Sampling rate (Hz).
    n : int
        Samples.

    Returns
    -------
    numpy.ndarray
        The response, ``n`` samples.
    """
    x = np.zeros(int(n))
    x[0] = fs
    return apply_structure(x, fs, model)


def apply_structure(excitation: np.ndarray, fs: float,
                    model: TransferModel | Sequence[Mode], method: str | None = None) -> np.ndarray:
    """Filter the excitation through each mode and sum: the noise-free acceleration.

    The impulse-invariant sections approximate ``y(t) = integral h(t - tau) e(tau) dtau``, so an
    input sample ``fs * A`` is an impulse of area ``A`` (see :func:`impulse_response`).

    Parameters
    ----------
    excitation : numpy.ndarray
        The excitation (:func:`excitation_from_history`; Pa for a pressure, N for a force).
    fs : float
        Sampling rate (Hz).
    model : TransferModel or sequence of Mode
        The modes.
    method : str, optional
        Discretisation of the modes (default: the model's).

    Returns
    -------
    numpy.ndarray
        The acceleration, same length as ``excitation``.
    """
    if isinstance(model, TransferModel):
        modes, method = model.modes, method or model.discretization
    else:
        modes, method = tuple(model), method or "impulse"
    x = np.asarray(excitation, dtype=float)
    y = np.zeros_like(x)
    for m in modes:
        y += sps.sosfilt(mode_sos(m, fs, method), x)
    return y


# --------------------------------------------------------------------------------------------
# synthesis
# --------------------------------------------------------------------------------------------
def direction_gain(angle_rad, sensor_rad: float, cross_axis: float) -> np.ndarray:
    """Gain of a single-axis accelerometer for a radial force acting at ``angle_rad``.

    The sensor reads the force's component along its axis (``cos`` of the angle between the
    force and the axis) through the structure's modes, and the component across it through the
    structure's cross-coupling at ``cross_axis`` times that gain; the two ring different mode
    shapes, so they add in power: ``sqrt(cos^2 d + cross_axis^2 sin^2 d)``, ``d = angle -
    sensor``. ``cross_axis = 1``: a sensor blind to direction (gain 1 everywhere); ``0``: the
    pure projection (a force across the axis is not seen).

    Parameters
    ----------
    angle_rad : array_like
        Direction of the force (rad), any convention shared with ``sensor_rad``.
    sensor_rad : float
        Direction of the sensor's axis (rad).
    cross_axis : float
        Cross-axis gain ratio, in [0, 1].

    Returns
    -------
    ndarray
        Gain in [cross_axis, 1], shape of ``angle_rad``.

    Raises
    ------
    ValueError
        A cross-axis sensitivity outside [0, 1].
    """
    k = check_number(cross_axis, "cross_axis")
    if not 0.0 <= k <= 1.0:
        raise ValueError(f"cross_axis: got {k!r}; allowed: 0 to 1")
    d = np.asarray(angle_rad, dtype=float) - float(sensor_rad)
    return np.sqrt(np.cos(d) ** 2 + k ** 2 * np.sin(d) ** 2)


def measure_snr_db(defect_part: np.ndarray, noise: np.ndarray) -> float:
    """``10 log10(var(defect_part) / var(noise))`` (dB).

    Parameters
    ----------
    defect_part : numpy.ndarray
        The signal's part due to the defect (any unit).
    noise : numpy.ndarray
        The noise added (the same unit).

    Returns
    -------
    float
        The SNR (dB).
    """
    pd = float(np.var(defect_part))
    pn = float(np.var(noise))
    if pn == 0.0:
        return math.inf
    if pd == 0.0:
        return -math.inf
    return 10.0 * math.log10(pd / pn)


def synthesize_acceleration(
    excitation: np.ndarray,
    fs: float,
    model: TransferModel,
    *,
    reference: np.ndarray | None = None,
    seed: int | None = None,
    fr: float | None = None,
    snr_db: float | None | str = "model",
) -> tuple[np.ndarray, dict[str, Any]]:
    """Synthetic accelerometer signal: structure response + noise at a target SNR + tones.

    Parameters
    ----------
    excitation : array, shape (n,)
        The excitation e(t) (see :func:`excitation_from_history`), sampled at ``fs``.
    fs : float
        Sampling rate (Hz).
    model : TransferModel
        Modes, noise and tones.
    reference : array, shape (n,), optional
        The excitation of the same case *without* the defect. If given, the defect-related part
        is ``d = H e - H e_ref``; otherwise ``d = H e`` (the whole response is counted as the
        defect's). ``P_defect = var(d)``.
    seed : int, optional
        Seed of the numpy Generator for noise and tone phases (default: ``model.seed``).
    fr : float, optional
        Shaft rate (Hz), needed by tones given as orders.
    snr_db : float, None or "model"
        Overrides ``model.noise.snr_db`` (None = no noise).

    Returns
    -------
    acc : array, shape (n,)
        ``y = H e + noise + tones`` (output units, e.g. m/s^2).
    info : dict
        Provenance: ``snr_db_target``, ``snr_db_achieved`` (10 log10(P_defect / var(noise))),
        ``p_defect``, ``p_noise``, ``p_tones``, ``defect_definition``, ``seed``, ``fs``,
        ``model`` (``TransferModel.to_dict()``), tone frequencies and phases.

    Raises
    ------
    ValueError
        ``fs`` not > 0 Hz, an excitation that is not a finite 1-D array of >= 2 samples, a
        ``seed`` not an integer >= 0, a ``reference`` of another shape, a defect-related part of
        zero power (no SNR can be set), or a tone outside (0, fs/2).
    """
    fs = check_number(fs, "fs")
    if fs <= 0:
        raise ValueError(f"fs must be > 0 Hz, got {fs!r}")
    model.check_fs(fs)
    e = np.asarray(excitation, dtype=float)
    if e.ndim != 1 or e.size < 2 or not np.all(np.isfinite(e)):
        raise ValueError(f"excitation must be a finite 1-D array with >= 2 samples, got shape {e.shape}")
    seed = model.seed if seed is None else seed
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0, got {seed!r}")
    target = model.noise.snr_db if isinstance(snr_db, str) and snr_db == "model" else snr_db
    if target is not None:
        target = NoiseSpec(target).snr_db  # validates the range
    rng = np.random.default_rng(int(seed))
    y = apply_structure(e, fs, model)
    if reference is not None:
        ref = np.asarray(reference, dtype=float)
        if ref.shape != e.shape:
            raise ValueError(f"reference must have the excitation's shape {e.shape}, got {ref.shape}")
        d = y - apply_structure(ref, fs, model)
        definition = "var(H e - H e_ref)"
    else:
        d = y
        definition = "var(H e)"
    p_defect = float(np.var(d))

    noise = np.zeros_like(y)
    if target is not None:
        if p_defect == 0.0:
            raise ValueError("the defect-related response has zero power: an SNR cannot be set "
                             "(excitation equals the reference?)")
        p_noise = p_defect / 10.0 ** (target / 10.0)
        w = rng.standard_normal(y.size)
        if model.noise.exact:
            w = (w - w.mean()) / w.std()
        noise = math.sqrt(p_noise) * w
    t = np.arange(y.size) / fs
    tones = np.zeros_like(y)
    tone_info = []
    for tone in model.tones:
        f = tone.frequency(fr)
        if not 0.0 < f < fs / 2:
            raise ValueError(f"tone frequency {f:g} Hz must be in (0, fs/2 = {fs / 2:g}) Hz")
        if tone.amplitude is not None:
            amp = tone.amplitude
        else:
            amp = math.sqrt(2.0 * p_defect * 10.0 ** (tone.level_db / 10.0))
        ph = rng.uniform(0.0, 2.0 * math.pi) if tone.phase_rad is None else tone.phase_rad
        tones += amp * np.cos(2.0 * math.pi * f * t + ph)
        tone_info.append({"frequency_hz": f, "amplitude": amp, "phase_rad": ph})
    acc = y + noise + tones
    info = {
        "snr_db_target": target,
        "snr_db_achieved": measure_snr_db(d, noise) if target is not None else math.inf,
        "p_defect": p_defect,
        "p_noise": float(np.var(noise)),
        "p_tones": float(np.var(tones)),
        "p_response": float(np.var(y)),
        "defect_definition": definition,
        "seed": int(seed),
        "fs": fs,
        "n_samples": int(y.size),
        "tones": tone_info,
        "model": model.to_dict(),
        "modes": [{**asdict(m), "f_d_hz": m.f_d_hz} for m in model.modes],
    }
    return acc, info
