"""Input checks shared by the signal functions (clear errors naming the offending field).

``check_positive`` is :func:`bearing_envelope.checks.check_positive`, the one number check of
every layer, read here under the name the signal and diagnosis modules import.
"""

from __future__ import annotations

import math

import numpy as np

from ..checks import check_positive

__all__ = ["check_band", "check_fs", "check_positive", "check_signal"]


def check_fs(fs, name: str = "fs") -> float:
    """Return ``fs`` as a float, raising ``ValueError`` unless it is finite and > 0.

    Parameters
    ----------
    fs : object
        The sampling rate (Hz).
    name : str
        The argument's name in the error message.

    Returns
    -------
    float
        ``fs`` as a finite float > 0.

    Raises
    ------
    ValueError
        ``fs`` not a finite number > 0 (the message names ``name``).
    """
    try:
        v = float(fs)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number > 0 (Hz), got {fs!r}") from None
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be a finite number > 0 (Hz), got {fs!r}")
    return v


def check_signal(x, name: str = "x", *, min_length: int = 2, allow_complex: bool = False):
    """Return ``x`` as a 1-D float64 array after checking it.

    Raises ``ValueError`` naming ``name`` when the array is empty, not 1-D, shorter than
    ``min_length``, or holds NaN/inf values.

    Parameters
    ----------
    x : array_like
        The signal.
    name : str
        The argument's name in error messages.
    min_length : int
        Fewest samples allowed.
    allow_complex : bool
        Accept a complex signal (returned as complex128).

    Returns
    -------
    numpy.ndarray
        ``x`` as a 1-D float64 (or complex128) array.

    Raises
    ------
    ValueError
        Not a numeric 1-D array, complex without ``allow_complex``, empty, shorter than
        ``min_length``, or holding NaN or inf (the message names ``name``).
    """
    a = np.asarray(x)
    if a.dtype == object:
        raise ValueError(f"{name} must be a numeric 1-D array")
    if np.iscomplexobj(a) and not allow_complex:
        raise ValueError(f"{name} must be real-valued")
    a = np.asarray(a, dtype=np.complex128 if np.iscomplexobj(a) else np.float64)
    if a.ndim != 1:
        a = np.squeeze(a)
        if a.ndim != 1:
            raise ValueError(f"{name} must be 1-D, got shape {np.shape(x)}")
    if a.size == 0:
        raise ValueError(f"{name} is empty")
    if a.size < min_length:
        raise ValueError(f"{name} has {a.size} samples, at least {min_length} are needed")
    if not np.all(np.isfinite(a)):
        bad = int(np.count_nonzero(~np.isfinite(a)))
        raise ValueError(f"{name} holds {bad} non-finite value(s) (NaN or inf)")
    return a


def check_band(band, fs: float, name: str = "band") -> tuple[float, float]:
    """Check a (low, high) band in Hz against 0 < low < high < fs/2 (low may be 0).

    Parameters
    ----------
    band : sequence of two floats
        ``(low, high)`` in Hz.
    fs : float
        Sampling rate (Hz).
    name : str
        The argument's name in error messages.

    Returns
    -------
    tuple of (float, float)
        ``(low, high)`` as floats.

    Raises
    ------
    ValueError
        Not a ``(low, high)`` pair, edges not finite, a negative low edge, a high edge not above
        the low one or at or above Nyquist (the message names ``name``).
    """
    try:
        low, high = (float(band[0]), float(band[1]))
    except (TypeError, ValueError, IndexError):
        raise ValueError(f"{name} must be a (low, high) pair in Hz, got {band!r}") from None
    nyq = fs / 2.0
    if not (math.isfinite(low) and math.isfinite(high)):
        raise ValueError(f"{name} edges must be finite, got {band!r}")
    if low < 0.0:
        raise ValueError(f"{name} low edge {low} Hz is negative")
    if high <= low:
        raise ValueError(f"{name} high edge {high} Hz must be above the low edge {low} Hz")
    if high >= nyq:
        raise ValueError(
            f"{name} high edge {high:g} Hz is at or above the Nyquist frequency {nyq:g} Hz "
            f"(fs = {fs:g} Hz)"
        )
    return low, high
