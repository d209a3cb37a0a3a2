"""The sweep configuration: loading, case naming and cross-field checks.

The structure of ``config.yaml`` is described by ``bearing_envelope/data/config.schema.yaml`` (JSON
Schema, checked by ``snakemake.utils.validate`` in the workflow and by :func:`load_config`
here). :func:`check_config` adds the checks a schema cannot express: every case's scene must
build, every fixed or order band must lie below Nyquist, band names must be unique. All of it
runs before any job, so a bad value stops the sweep at once with the field named.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

__all__ = ["case_name", "check_config", "load_config", "band_limits_static", "SCHEMA_PATH"]

#: The JSON schema of ``config.yaml``, shipped as package data (the workflow validates against it too).
SCHEMA_PATH = Path(__file__).resolve().parent / "data" / "config.schema.yaml"


def _fmt(value: float) -> str:
    return f"{float(value):g}"


def case_name(load_kN: float, depth_um: float) -> str:
    """Canonical case name ``F{load_kN}kN_h{depth_um}um`` (e.g. ``F500kN_h50um``).

    Numbers are written with ``%g`` so that 500 and 500.0 give the same name.
    """
    return f"F{_fmt(load_kN)}kN_h{_fmt(depth_um)}um"


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


def check_config(config: Mapping[str, Any]) -> None:
    """Cross-field checks of a schema-valid configuration; raises ``ValueError`` naming the field.

    Builds every case's scene (load x depth) and the fidelity preset, and checks every
    signal-independent band against Nyquist. Cheap: no contact solve happens here.
    """
    from .fidelity import fidelity_from
    from .scene import Scene

    fidelity_from(config.get("fidelity", "standard"))
    scene_map = config.get("scene", {}) or {}
    sweep = config["sweep"]
    scenes = [
        Scene.from_mapping(scene_map, load_kN=f, depth_um=h)
        for f in sweep["loads_kN"]
        for h in sweep["depths_um"]
    ]
    analysis = config["analysis"]
    if analysis.get("signal", "p_max") == "acceleration" and not config.get("sensor"):
        raise ValueError("analysis.signal = 'acceleration' needs a `sensor:` section (the transfer "
                         "path that makes the acceleration); allowed without it: p_max, p_max_defect")
    names = [b["name"] for b in analysis["bands"]]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ValueError(f"analysis.bands: names must be unique; repeated: {dup}")
    scene = scenes[0]
    fs = float(scene.operation.fs_hz)
    freqs = scene_frequencies(scene)
    for band in analysis["bands"]:
        band_limits_static(band, fs, freqs)
    if freqs["bpfi"] * analysis.get("harmonics", 3) >= fs / 2:
        raise ValueError(
            f"analysis.harmonics = {analysis.get('harmonics')}: K x BPFI must stay below Nyquist ({fs / 2:g} Hz)"
        )


def scene_frequencies(scene) -> dict[str, float]:
    """Base frequencies (Hz) of a scene by name: fr, bpfi (the one used), bpfo, ftf, bsf."""
    ff = scene.frequencies()
    return {"fr": ff.fr, "bpfi": scene.bpfi_hz, "bpfo": ff.bpfo, "ftf": ff.ftf, "bsf": ff.bsf}


def load_config(path: str | Path, schema: str | Path | None = None) -> dict[str, Any]:
    """Read a YAML config, validate it against the schema (filling defaults) and check it.

    Raises
    ------
    ValueError
        With the dotted path of the offending field, its value and what is allowed.
    """
    import jsonschema
    import yaml

    with open(path, encoding="utf-8") as fh:
        config = yaml.safe_load(fh) or {}
    schema_path = Path(schema) if schema else SCHEMA_PATH
    if schema_path.exists():
        with open(schema_path, encoding="utf-8") as fh:
            schema_doc = yaml.safe_load(fh)
        validator = jsonschema.Draft202012Validator(schema_doc)
        errors = sorted(validator.iter_errors(config), key=lambda e: list(e.path))
        if errors:
            e = errors[0]
            where = ".".join(str(p) for p in e.path) or "(top level)"
            raise ValueError(f"{path}: {where}: {e.message}")
    check_config(config)
    return config


