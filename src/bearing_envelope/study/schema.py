"""The sweep configuration's schema: where it lives, and the static band limits and scene
frequencies the settings checks need (a leaf of :mod:`bearing_envelope.study`).

The structure of ``config.yaml`` is described by ``bearing_envelope/data/config.schema.yaml`` (JSON
Schema, package data). Loading, validation and the cross-field checks a schema cannot express
(every case's scene builds, every fixed or order band and sensor mode below Nyquist, unique band
names, finite numbers) live in :mod:`bearing_envelope.study.settings`, the one loader used by the CLI and
the workflow. All of it runs before any job, so a bad value stops the sweep at once with the field named.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

__all__ = ["band_limits_static", "scene_frequencies", "SCHEMA_PATH"]

#: The JSON schema of ``config.yaml``, shipped as package data (the workflow validates against it too).
SCHEMA_PATH = Path(__file__).resolve().parent.parent / "data" / "config.schema.yaml"


def band_limits_static(band: Mapping[str, Any], fs: float, freqs: Mapping[str, float]) -> tuple[float, float] | None:
    """Band limits (Hz) of a configured band that does not depend on the signal.

    Returns ``None`` for the ``kurtogram`` strategy (chosen per signal).

    Parameters
    ----------
    band : mapping
        One entry of ``analysis.bands``.
    fs : float
        Sampling rate (Hz).
    freqs : mapping
        Base frequencies by name (``bpfi``, ``bpfo``, ``fr``, ``ftf``, ``bsf``) in Hz.
    """
    strategy = band["strategy"]
    name = band.get("name", "?")
    if strategy == "kurtogram":
        return None

    def need(key):
        if key not in band:
            raise ValueError(f"analysis.bands[{name}].{key} is required for strategy {strategy!r}")
        return float(band[key])

    if strategy == "fraction":
        lo, hi = need("low") * fs, need("high") * fs
    elif strategy == "orders":
        base = band.get("base", "bpfi")
        if base not in freqs:
            raise ValueError(f"analysis.bands[{name}].base = {base!r}; allowed: {sorted(freqs)}")
        lo, hi = need("low") * freqs[base], need("high") * freqs[base]
    elif strategy == "fixed":
        lo, hi = need("low_hz"), need("high_hz")
    else:
        raise ValueError(
            f"analysis.bands[{name}].strategy = {strategy!r}; allowed: kurtogram, fraction, orders, fixed"
        )
    if not hi > lo:
        raise ValueError(f"analysis.bands[{name}]: upper edge {hi:g} Hz must exceed lower edge {lo:g} Hz")
    if hi >= fs / 2:
        raise ValueError(
            f"analysis.bands[{name}]: upper edge {hi:g} Hz is not below Nyquist ({fs / 2:g} Hz at "
            f"scene.operation.fs_hz = {fs:g}); allowed: high < fs/2"
        )
    return lo, hi


def scene_frequencies(scene) -> dict[str, float]:
    """Base frequencies (Hz) of a scene by name: fr, bpfi (the one used), bpfo, ftf, bsf."""
    ff = scene.frequencies()
    return {"fr": ff.fr, "bpfi": scene.bpfi_hz, "bpfo": ff.bpfo, "ftf": ff.ftf, "bsf": ff.bsf}
