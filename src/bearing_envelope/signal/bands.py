"""Demodulation-band strategies: kurtogram, fractions of fs, orders of a base frequency, fixed.

Every strategy returns ``(low, high)`` in Hz and a provenance dict. A band specification is a
plain mapping (the form a YAML config carries)::

    {"name": "kurtogram", "strategy": "kurtogram"}                      # best kurtogram cell
    {"name": "fs4_3fs8",  "strategy": "fraction", "low": 0.25, "high": 0.375}   # x fs
    {"name": "bpfi_3_6",  "strategy": "orders", "low": 3, "high": 6, "base": "bpfi"}
    {"name": "fixed",     "strategy": "fixed", "low_hz": 5000.0, "high_hz": 9000.0}

Optional keys: ``name`` (defaults to the strategy), ``clamp`` (bool: clamp an upper edge at
or above Nyquist instead of raising; always on for ``kurtogram``), ``prewhiten`` (bool: the
band is taken from the cepstrum-pre-whitened signal, :func:`~bearing_envelope.signal.
spectrum.prewhiten`; recorded in the provenance), and for ``kurtogram``
``max_level`` / ``min_bandwidth`` (guards, see :func:`fast_kurtogram`). ``base`` is a key of
the frequencies given to :func:`resolve_band` (``"fr"``, ``"bpfi"``, ...) or a number in Hz.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping

from .validation import check_fs, check_positive

#: The ``fraction`` strategy's band when its edges are not given: fs/4 - 3 fs/8 (fractions of fs).
FRACTION_BAND_LOW = 0.25
FRACTION_BAND_HIGH = 0.375

__all__ = [
    "FRACTION_BAND_LOW",
    "FRACTION_BAND_HIGH",
    "DEFAULT_BANDS",
    "NYQUIST_MARGIN",
    "band_fixed",
    "band_fraction",
    "band_from_kurtogram",
    "band_orders",
    "clamp_band",
    "resolve_band",
]

#: Clamped upper edges are set to ``NYQUIST_MARGIN * fs / 2``.
NYQUIST_MARGIN = 0.98

#: The bands of the source study (a fixed band needs user values, so it is not a default).
DEFAULT_BANDS = (
    {"name": "kurtogram", "strategy": "kurtogram"},
    {"name": "fs4_3fs8", "strategy": "fraction", "low": FRACTION_BAND_LOW,
     "high": FRACTION_BAND_HIGH},
    {"name": "bpfi_3_6", "strategy": "orders", "low": 3, "high": 6, "base": "bpfi"},
    {"name": "bpfi_10_13", "strategy": "orders", "low": 10, "high": 13, "base": "bpfi"},
)

_KEYS = {
    "kurtogram": {"name", "strategy", "clamp", "prewhiten", "max_level", "min_bandwidth"},
    "fraction": {"name", "strategy", "clamp", "prewhiten", "low", "high"},
    "orders": {"name", "strategy", "clamp", "prewhiten", "low", "high", "base"},
    "fixed": {"name", "strategy", "clamp", "prewhiten", "low_hz", "high_hz"},
}


def clamp_band(low: float, high: float, fs: float, *, margin: float = NYQUIST_MARGIN, clamp=True,
               field: str = "band"):
    """Check ``0 <= low < high`` and handle an upper edge at or above ``margin * fs/2``.

    Returns ``(low, high, info)`` with ``info = {"clamped": bool, "requested_high_hz": high}``.
    With ``clamp`` the upper edge is lowered to ``margin * fs / 2``; without it a
    ``ValueError`` naming ``field`` is raised when ``high >= fs / 2``.

    Parameters
    ----------
    low, high : float
        Band edges (Hz).
    fs : float
        Sampling rate (Hz).
    margin : float
        Fraction of Nyquist the upper edge is lowered to when clamped.
    clamp : bool
        Lower an upper edge at or above ``margin * fs / 2`` (else refuse one at or above ``fs / 2``).
    field : str
        The band's name in error messages.

    Returns
    -------
    tuple of (float, float, dict)
        ``(low, high, info)``; ``info = {"clamped": bool, "requested_high_hz": high}``.

    Raises
    ------
    ValueError
        Edges not finite, a negative low edge, a high edge not above the low one, a low edge at
        or above Nyquist, or a high edge above it without ``clamp`` (the message names
        ``field``).
    """
    fs = check_fs(fs)
    nyq = fs / 2.0
    if not all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in (low, high)):
        raise ValueError(f"{field}: band edges must be numbers (Hz), got ({low!r}, {high!r})")
    low, high = float(low), float(high)
    if not (math.isfinite(low) and math.isfinite(high)):
        raise ValueError(f"{field}: band edges must be finite, got ({low}, {high})")
    if low < 0:
        raise ValueError(f"{field}: low edge {low:g} Hz is negative")
    if high <= low:
        raise ValueError(f"{field}: high edge {high:g} Hz must be above the low edge {low:g} Hz")
    if low >= nyq * margin:
        raise ValueError(
            f"{field}: low edge {low:g} Hz is at or above the Nyquist frequency {nyq:g} Hz "
            f"(x {margin})"
        )
    info = {"clamped": False, "requested_high_hz": high}
    if not clamp and high >= nyq:
        raise ValueError(
            f"{field}: high edge {high:g} Hz is at or above the Nyquist frequency "
            f"{nyq:g} Hz (fs = {fs:g} Hz); lower it or set clamp"
        )
    if clamp and high > margin * nyq:
        high = margin * nyq
        info["clamped"] = True
    return low, high, info


def band_from_kurtogram(kurtogram, *, margin: float = NYQUIST_MARGIN):
    """Band of the best kurtogram cell, ``fc -+ bandwidth/2``, upper edge clamped below Nyquist.

    Parameters
    ----------
    kurtogram : Kurtogram
        Result of :func:`fast_kurtogram`.
    margin : float, default 0.98
        An upper edge above ``margin * fs/2`` is lowered to it (the topmost kurtogram band ends
        exactly at Nyquist, where no band-pass filter can end); ``clamped`` records it. When the
        clamp would keep less than half the cell (a deep cell next to Nyquist), the band keeps
        the cell's bandwidth and ends at the clamp; ``shifted_from_low_hz`` records the cell's
        own lower edge.

    Returns
    -------
    (low, high) : tuple of float
        Band edges (Hz).
    provenance : dict
        ``strategy``, ``level``, ``fc_hz``, ``bandwidth_hz``, ``kurtosis``, ``clamped``,
        ``requested_high_hz``.
    """
    kg = kurtogram
    low, high = kg.band
    top = margin * kg.fs / 2.0
    shifted = None
    if min(high, top) - low < 0.5 * kg.bandwidth:
        # A deep cell at the very top of the spectrum: clamping its upper edge would leave less
        # than half of it (or nothing). Keep its bandwidth and end it at the clamp instead.
        shifted = low
        low = max(0.0, top - kg.bandwidth)
    low, high, info = clamp_band(low, high, kg.fs, margin=margin, clamp=True, field="kurtogram")
    if shifted is not None:
        info["shifted_from_low_hz"] = shifted
    prov = {
        "strategy": "kurtogram",
        "level": kg.level,
        "fc_hz": kg.fc,
        "bandwidth_hz": kg.bandwidth,
        "kurtosis": kg.kurtosis,
        **info,
    }
    return (low, high), prov


def band_fraction(fs: float, low: float = FRACTION_BAND_LOW, high: float = FRACTION_BAND_HIGH, *,
                  clamp: bool = False,
                  margin: float = NYQUIST_MARGIN):
    """Band ``[low fs, high fs]`` (default fs/4 - 3 fs/8); fractions in ``[0, 0.5]``.

    Parameters
    ----------
    fs : float
        Sampling rate (Hz).
    low, high : float
        Band edges as fractions of ``fs``, in ``[0, 0.5]``.
    clamp : bool
        Lower an upper edge at or above ``margin * fs / 2`` (see :func:`clamp_band`).
    margin : float
        Fraction of Nyquist for the clamp.

    Returns
    -------
    tuple of (float, float, dict)
        ``(low_hz, high_hz, info)`` as :func:`clamp_band`.

    Raises
    ------
    ValueError
        A fraction of fs that is negative or not a number.
    """
    fs = check_fs(fs)
    lo_f, hi_f = float(low), float(high)
    for nm, v in (("low", lo_f), ("high", hi_f)):
        if not math.isfinite(v) or v < 0:
            raise ValueError(f"fraction band: {nm}={v!r} must be a fraction of fs >= 0")
    l_hz, h_hz, info = clamp_band(lo_f * fs, hi_f * fs, fs, margin=margin, clamp=clamp,
                                  field="fraction band")
    return (l_hz, h_hz), {"strategy": "fraction", "low_fraction": lo_f, "high_fraction": hi_f,
                          **info}


def band_orders(base_hz: float, low: float, high: float, fs: float, *, base_name: str = "base",
                clamp: bool = False, margin: float = NYQUIST_MARGIN):
    """Band ``[low, high] x base_hz`` (e.g. 3-6 x BPFI, 10-13 x BPFI).

    Parameters
    ----------
    base_hz : float
        The base frequency (Hz), e.g. BPFI.
    low, high : float
        Band edges as multiples of ``base_hz``.
    fs : float
        Sampling rate (Hz).
    base_name : str
        The base's name in error messages.
    clamp : bool
        Lower an upper edge at or above ``margin * fs / 2`` (see :func:`clamp_band`).
    margin : float
        Fraction of Nyquist for the clamp.

    Returns
    -------
    tuple of (float, float, dict)
        ``(low_hz, high_hz, info)`` as :func:`clamp_band`.
    """
    fs = check_fs(fs)
    base_hz = check_positive(base_hz, f"orders band: base {base_name!r}")
    l_hz, h_hz, info = clamp_band(float(low) * base_hz, float(high) * base_hz, fs, margin=margin,
                                  clamp=clamp, field=f"orders band ({low} - {high} x {base_name})")
    return (l_hz, h_hz), {"strategy": "orders", "low_order": float(low),
                          "high_order": float(high), "base": base_name, "base_hz": base_hz,
                          **info}


def band_fixed(low_hz: float, high_hz: float, fs: float, *, clamp: bool = False,
               margin: float = NYQUIST_MARGIN):
    """A band given in Hz, the same for every case.

    Parameters
    ----------
    low_hz, high_hz : float
        Band edges (Hz).
    fs : float
        Sampling rate (Hz).
    clamp : bool
        Lower an upper edge at or above ``margin * fs / 2`` (see :func:`clamp_band`).
    margin : float
        Fraction of Nyquist for the clamp.

    Returns
    -------
    tuple of (float, float, dict)
        ``(low_hz, high_hz, info)`` as :func:`clamp_band`.
    """
    l_hz, h_hz, info = clamp_band(low_hz, high_hz, fs, margin=margin, clamp=clamp,
                                  field="fixed band")
    return (l_hz, h_hz), {"strategy": "fixed", **info}


def _need(spec, key, name):
    if key not in spec:
        raise ValueError(f"band {name!r} ({spec.get('strategy')}): missing key {key!r}")
    return spec[key]


def resolve_band(spec: Mapping, fs: float, *, kurtogram=None, frequencies: Mapping | None = None,
                 margin: float = NYQUIST_MARGIN, static: bool = False):
    """Turn one band specification (a mapping, see the module docstring) into a band.

    The one band resolver: the configuration check calls it with ``static=True`` before any
    signal exists (every strategy but ``kurtogram`` is then resolved and checked in full; the
    kurtogram band is only checked for its keys and returns ``(None, None)``), the analysis
    calls it per signal.

    Parameters
    ----------
    spec : mapping
        ``{"name": ..., "strategy": "kurtogram" | "fraction" | "orders" | "fixed", ...}``.
    fs : float
        Sampling frequency (Hz).
    kurtogram : Kurtogram or callable, optional
        Needed by the ``kurtogram`` strategy: a :class:`Kurtogram`, or a callable
        ``f(max_level, min_bandwidth) -> Kurtogram`` when the spec carries guards.
    frequencies : mapping, optional
        Named base frequencies for ``orders`` (e.g. ``{"fr": 15.8, "bpfi": 231.9}``).
    margin : float
        Nyquist margin for clamping, see :func:`clamp_band`.
    static : bool
        Check the specification without a signal (see above).

    Returns
    -------
    (low, high) : tuple of float
        Band edges (Hz).
    provenance : dict
        ``name``, ``strategy`` and the strategy's own fields (see the ``band_*`` functions).

    Raises
    ------
    ValueError
        A specification that is not a mapping, an unknown strategy or key, a ``kurtogram`` band
        without a kurtogram, an ``orders`` base that is not a known frequency, or edges out of
        range.
    """
    if not isinstance(spec, Mapping):
        raise ValueError(f"a band specification must be a mapping, got {spec!r}")
    strategy = spec.get("strategy")
    if strategy not in _KEYS:
        raise ValueError(
            f"band {spec.get('name')!r}: strategy must be one of {sorted(_KEYS)}, got {strategy!r}"
        )
    name = str(spec.get("name", strategy))
    unknown = set(spec) - _KEYS[strategy]
    if unknown:
        raise ValueError(f"band {name!r} ({strategy}): unknown key(s) {sorted(unknown)}")
    clamp = bool(spec.get("clamp", False))
    if strategy == "kurtogram":
        if static:
            return (None, None), {"name": name, "strategy": strategy}
        if kurtogram is None:
            raise ValueError(f"band {name!r}: the kurtogram strategy needs a kurtogram")
        kg = kurtogram
        if callable(kurtogram):
            kg = kurtogram(spec.get("max_level"), spec.get("min_bandwidth"))
        band, prov = band_from_kurtogram(kg, margin=margin)
    elif strategy == "fraction":
        band, prov = band_fraction(fs, spec.get("low", FRACTION_BAND_LOW),
                                   spec.get("high", FRACTION_BAND_HIGH),
                                   clamp=clamp, margin=margin)
    elif strategy == "orders":
        base = _need(spec, "base", name)
        if isinstance(base, str):
            freqs = dict(frequencies or {})
            if base not in freqs:
                raise ValueError(
                    f"band {name!r}: base {base!r} is not a known frequency "
                    f"(known: {sorted(freqs)})"
                )
            base_hz, base_name = freqs[base], base
        else:
            base_hz, base_name = float(base), f"{float(base):g} Hz"
        band, prov = band_orders(base_hz, _need(spec, "low", name), _need(spec, "high", name),
                                 fs, base_name=base_name, clamp=clamp, margin=margin)
    else:
        band, prov = band_fixed(_need(spec, "low_hz", name), _need(spec, "high_hz", name), fs,
                                clamp=clamp, margin=margin)
    prov = {"name": name, **prov}
    if spec.get("prewhiten"):
        prov["prewhiten"] = True
    return band, prov
