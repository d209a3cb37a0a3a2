"""The sweep configuration's schema: the file, the defaults whose home is code, validation.

The structure of ``config.yaml`` is described by ``bearing_envelope/data/config.schema.yaml`` (JSON
Schema, package data). :func:`full_schema` fills in the defaults whose home is code;
:func:`validate_mapping` rejects NaN and infinities anywhere (JSON Schema bounds do not catch
NaN), validates against the schema with a one-line message per error (the field, the value,
what is allowed; never the schema) and fills the defaults. The cross-field checks a schema
cannot express live in the typed sections (:mod:`bearing_envelope.study.sections`) and the
loader (:mod:`bearing_envelope.study.settings`).
"""

from __future__ import annotations

import copy
import difflib
import functools
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..diagnosis.options import AnalysisOptions
from ..physics.fidelity import DEFAULT_PRESET
from ..physics.transfer import sensor_defaults
from .config_read import ConfigError

__all__ = ["SCHEMA_PATH", "full_schema", "section_defaults", "validate_mapping", "MAPPING_SOURCE"]

#: What a message names as the origin of a config given as a mapping (not read from a file).
MAPPING_SOURCE = "<mapping>"

#: The JSON schema of ``config.yaml``, shipped as package data (the workflow validates against it too).
SCHEMA_PATH = Path(__file__).resolve().parent.parent / "data" / "config.schema.yaml"

#: Longest message taken from a schema error (the instance repr can be long).
_MAX_MESSAGE = 240


def _dotted(path: Sequence[Any]) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out or "(top level)"


def _check_finite(obj: Any, path: tuple = ()) -> None:
    if isinstance(obj, float) and not math.isfinite(obj):
        raise ConfigError(f"{_dotted(path)}: got {obj!r}; allowed: a finite number (NaN and "
                          f"infinity are not numbers a setting can take)")
    if isinstance(obj, Mapping):
        for k, v in obj.items():
            _check_finite(v, path + (k,))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            _check_finite(v, path + (i,))


@functools.lru_cache(maxsize=1)
def full_schema() -> dict:
    """The schema file with what has its home in code filled in: the ``fidelity`` default
    from :data:`~bearing_envelope.physics.fidelity.DEFAULT_PRESET`; the type, range and
    default of every ``analysis:`` key that sets an analysis option from
    :meth:`~bearing_envelope.diagnosis.options.AnalysisOptions.config_schema` (the file writes
    their descriptions only); the ``sensor:`` defaults from
    :func:`~bearing_envelope.physics.transfer.sensor_defaults`. The file itself holds no scene,
    fidelity, analysis-option, sensor, limits or tradeoff default (``tests/test_defaults.py``).

    Returns
    -------
    dict
        The JSON schema of a config file, with every default.
    """
    import yaml

    with open(SCHEMA_PATH, encoding="utf-8") as fh:
        schema = yaml.load(fh, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))  # libyaml: 10x faster
    props = schema["properties"]
    props["fidelity"]["default"] = DEFAULT_PRESET
    for key, fragment in AnalysisOptions.config_schema().items():
        props["analysis"]["properties"][key].update(fragment)
    sensor = props["sensor"]["properties"]
    for key, value in sensor_defaults().items():
        if key == "noise":
            for sub, v in value.items():
                sensor["noise"]["properties"][sub]["default"] = v
        else:
            sensor[key]["default"] = value
    return schema


def _schema(partial: bool) -> dict:
    schema = copy.deepcopy(full_schema())
    if partial:
        schema["required"] = []
    return schema


def _schema_message(err) -> str:
    """One line for a jsonschema error: the dotted field and what is wrong (never the schema)."""
    path = list(err.absolute_path)
    if err.validator == "additionalProperties" and isinstance(err.instance, Mapping):
        allowed = sorted((err.schema.get("properties") or {}).keys())
        unknown = sorted(str(k) for k in set(err.instance) - set(allowed))
        if unknown:
            key = unknown[0]
            hint = difflib.get_close_matches(key, allowed, n=1)
            tip = f"; did you mean {hint[0]!r}?" if hint else ""
            return (f"{_dotted(path + [key])}: unknown key{tip}; allowed keys here: "
                    f"{', '.join(allowed)}")
    if err.validator == "required":
        missing = [k for k in err.validator_value if k not in (err.instance or {})]
        if missing:
            return f"{_dotted(path + [missing[0]])}: missing; this section is required"
    msg = " ".join(err.message.split())
    if len(msg) > _MAX_MESSAGE:
        msg = msg[: _MAX_MESSAGE - 3] + "..."
    desc = err.schema.get("description") if isinstance(err.schema, Mapping) else None
    if desc and err.validator in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum",
                                  "enum", "type"):
        desc = " ".join(str(desc).split())
        msg += f" ({desc[:120]})"
    return f"{_dotted(path)}: {msg}"


def _fill_defaults(instance: Any, schema: Mapping[str, Any], root: Mapping[str, Any]) -> None:
    """Fill ``default`` values of ``properties`` into present objects, recursively.

    Mirrors ``snakemake.utils.validate(set_default=True)``, so the workflow's params (and with them
    Snakemake's rerun decisions) are the same as with Snakemake's own validation.
    """
    ref = schema.get("$ref")
    if isinstance(ref, str) and ref.startswith("#/$defs/"):
        schema = root.get("$defs", {}).get(ref.split("/")[-1], schema)
    if isinstance(instance, dict):
        for name, sub in (schema.get("properties") or {}).items():
            if "default" in sub:
                instance.setdefault(name, copy.deepcopy(sub["default"]))
            if name in instance:
                _fill_defaults(instance[name], sub, root)
    elif isinstance(instance, list) and isinstance(schema.get("items"), Mapping):
        for item in instance:
            _fill_defaults(item, schema["items"], root)


def _coerce_integers(instance: Any, schema: Mapping[str, Any], root: Mapping[str, Any]) -> Any:
    """Integral floats where the schema asks for an integer become ``int``, recursively, in
    place (JSON Schema counts ``3.0`` as an integer; ``range(3.0)`` in a job does not): the
    value every job receives is the one the check passed. Returns the (coerced) instance."""
    ref = schema.get("$ref")
    if isinstance(ref, str) and ref.startswith("#/$defs/"):
        schema = root.get("$defs", {}).get(ref.split("/")[-1], schema)
    types = schema.get("type")
    types = [types] if isinstance(types, str) else list(types or [])
    if isinstance(instance, float) and "integer" in types and "number" not in types \
            and instance.is_integer():
        return int(instance)
    if isinstance(instance, dict):
        for name, sub in (schema.get("properties") or {}).items():
            if name in instance:
                instance[name] = _coerce_integers(instance[name], sub, root)
    elif isinstance(instance, list) and isinstance(schema.get("items"), Mapping):
        for i, item in enumerate(instance):
            instance[i] = _coerce_integers(item, schema["items"], root)
    return instance


def section_defaults(section: str) -> dict[str, Any]:
    """The schema's defaults of one top-level section (``analysis``, ``diagnosability``, ...):
    the one place defaults live, read by the typed settings for keys a mapping leaves out.

    Parameters
    ----------
    section : str
        A top-level key of the schema (:func:`full_schema`).

    Returns
    -------
    dict
        Key -> default of the section's properties that have one (nested defaults filled).
    """
    schema = _schema(partial=True)
    out: dict[str, Any] = {}
    _fill_defaults(out, schema["properties"][section], schema)
    return out


def validate_mapping(config: Mapping[str, Any], *, source: str = MAPPING_SOURCE,
                     partial: bool = False) -> dict[str, Any]:
    """Finite-number check, schema validation and default filling of a config mapping.

    Parameters
    ----------
    config : mapping
        A merged config (not modified).
    source : str, keyword-only
        Where it came from, the first word of every error message.
    partial : bool, keyword-only
        Accept a config without the top-level required sections (``simulate --config`` needs
        only ``scene:``); unknown keys are refused either way.

    Returns
    -------
    dict
        A deep copy with the schema defaults filled (integral floats of integer fields as
        ``int``).

    Raises
    ------
    ConfigError
        One line: ``{source}: {dotted.field}: ...``.
    """
    import jsonschema

    if not isinstance(config, Mapping):
        raise ConfigError(f"{source}: the config must be a mapping, got {type(config).__name__}")
    config = copy.deepcopy(dict(config))
    if not partial:   # every key of these sections has a default
        for section in ("scene", "analysis"):
            config.setdefault(section, {})
    try:
        _check_finite(config)
    except ConfigError as exc:
        raise ConfigError(f"{source}: {exc}") from None
    schema = _schema(partial)
    validator = jsonschema.Draft202012Validator(schema)
    errors = list(validator.iter_errors(config))
    if errors:
        err = jsonschema.exceptions.best_match(errors)
        raise ConfigError(f"{source}: {_schema_message(err)}")
    _fill_defaults(config, schema, schema)
    _coerce_integers(config, schema, schema)
    return config
