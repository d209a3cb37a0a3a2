"""Checks of scalar arguments, shared by every layer (clear errors naming the argument).

This module sits below the layers (docs/architecture.md): it imports nothing of the package,
so ``contact``, ``physics``, ``signal`` and ``diagnosis`` all read their number checks from
here instead of each keeping its own copy.
"""

from __future__ import annotations

import math
import os
import stat

__all__ = ["check_number", "check_positive", "check_input_file"]


def _float(value, name: str) -> float:
    """``float(value)``; ``ValueError`` naming ``name`` for a bool, a string (a number spelled as
    text is a caller's mistake, not a number) or what ``float`` cannot read."""
    if isinstance(value, (bool, str, bytes)):
        raise ValueError(f"{name} must be a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None


def check_number(value, name: str) -> float:
    """Return ``value`` as a finite float.

    Raises ``ValueError`` naming ``name``: ``"{name} must be a number"`` for a bool, a string or
    what ``float`` cannot read, ``"{name} must be finite"`` for NaN or infinity.

    Parameters
    ----------
    value : object
        The value to check (a number or what ``float`` reads; not a bool or a string).
    name : str
        The field's name in the error message.

    Returns
    -------
    float
        ``value`` as a finite float.

    Raises
    ------
    ValueError
        ``value`` is not a finite number (the message names ``name``).
    """
    v = _float(value, name)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return v


def check_positive(value, name: str, *, allow_zero: bool = False, allow_none: bool = False):
    """Return ``value`` as a finite float ``> 0`` (``>= 0`` with ``allow_zero``).

    ``None`` is returned as is when ``allow_none``. Raises ``ValueError`` naming ``name``:
    ``"{name} must be a number"`` for a bool, a string or what ``float`` cannot read,
    ``"{name} must be a finite number > 0"`` (``>= 0``) for NaN, infinity or a value out of range.

    Parameters
    ----------
    value : object
        The value to check.
    name : str
        The field's name in the error message.
    allow_zero : bool
        Accept 0 (the bound is then ``>= 0``).
    allow_none : bool
        Accept ``None`` and return it.

    Returns
    -------
    float or None
        ``value`` as a finite float in range (``None`` when given and allowed).

    Raises
    ------
    ValueError
        ``value`` is not finite, or not > 0 (>= 0 with ``allow_zero``); the message names
        ``name``.
    """
    if value is None and allow_none:
        return None
    v = _float(value, name)
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise ValueError(f"{name} must be a finite number {'>= 0' if allow_zero else '> 0'}, "
                         f"got {value!r}")
    return v


def check_input_file(path, name: str, *, max_bytes: int, allow_empty: bool = False) -> str:
    """Return ``path`` (a ``str``) after checking it names a regular, non-empty file of at most
    ``max_bytes`` bytes, before anything reads it.

    A device (``/dev/zero`` reads forever), a FIFO, a directory or a file under ``/proc`` or
    ``/sys`` (their sizes are not what a read returns) is refused, as is a multi-GB file that
    would be read into memory whole.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    name : str
        What names it in the error (``scene.bearing.profile_file``).
    max_bytes : int
        Largest size accepted.
    allow_empty : bool
        Accept a file of 0 bytes.

    Returns
    -------
    str
        ``os.fspath(path)``.

    Raises
    ------
    ValueError
        One line naming ``name``, the path and what is allowed.
    """
    p = os.fspath(path)
    real = os.path.realpath(p)
    if real.startswith(("/proc/", "/sys/", "/dev/")):
        raise ValueError(f"{name}: {p!r} is a system file ({real}); allowed: a regular file")
    try:
        st = os.stat(p)
    except OSError as exc:
        raise ValueError(f"{name}: {p!r} cannot be read ({exc.strerror or exc}); allowed: an "
                         f"existing regular file") from None
    if not stat.S_ISREG(st.st_mode):
        kind = "a directory" if stat.S_ISDIR(st.st_mode) else "not a regular file (a device, " \
            "FIFO or socket)"
        raise ValueError(f"{name}: {p!r} is {kind}; allowed: a regular file")
    if st.st_size == 0 and not allow_empty:
        raise ValueError(f"{name}: {p!r} is empty; allowed: a file with data")
    if st.st_size > max_bytes:
        raise ValueError(f"{name}: {p!r} has {st.st_size:,} bytes; allowed: at most "
                         f"{max_bytes:,} bytes")
    return p
