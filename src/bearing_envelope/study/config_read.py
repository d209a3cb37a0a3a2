"""Reading config files: strict YAML, the one merge of files, which files a run reads.

:func:`read_yaml` reads a file with a loader that refuses duplicate keys and YAML 1.1 number
forms and reports syntax errors with their line and column; :func:`merge_configs` is the one
merge of config files (the workflow's ``config.yaml`` + ``--configfile`` files + ``--config``);
:func:`read_configs` reads and merges them. Every failure is a :class:`ConfigError` (a
``ValueError``) whose message is one line naming the file or the dotted field.
"""

from __future__ import annotations

import copy
import os
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..checks import check_input_file
from ..io.yamlsafe import MAX_DOCUMENT_BYTES, YamlLimitError, load_bounded

__all__ = ["ConfigError", "field_error", "read_yaml", "merge_configs", "read_configs",
           "config_files", "default_config_path", "DEFAULT_CONFIG_NAME"]

#: The config file ``simulate --config`` and the workflow read when none is named.
DEFAULT_CONFIG_NAME = "config.yaml"


class ConfigError(ValueError):
    """A configuration is invalid; the message is one line naming the field."""


def field_error(where: str, value: Any, allowed: str) -> ConfigError:
    """The one-line error of a bad config value.

    Parameters
    ----------
    where : str
        The dotted field (``sweep.depths_um[2]``).
    value : object
        The value given.
    allowed : str
        What the field allows.

    Returns
    -------
    ConfigError
        ``"{where}: got {value!r}; allowed: {allowed}"``.
    """
    return ConfigError(f"{where}: got {value!r}; allowed: {allowed}")


def default_config_path() -> Path | None:
    """``./config.yaml`` when it exists (the file ``simulate`` reads without ``--config``).

    Returns
    -------
    pathlib.Path or None
        The relative path :data:`DEFAULT_CONFIG_NAME` when it is a file in the working
        folder, else None.
    """
    p = Path(DEFAULT_CONFIG_NAME)
    return p if p.is_file() else None


def _unique_key_loader():
    import yaml

    class UniqueKeyLoader(yaml.SafeLoader):
        """SafeLoader that refuses a key given twice in one mapping (YAML would keep the last)."""

    def construct_mapping(loader, node, deep=False):
        loader.flatten_mapping(node)
        seen: dict[Any, int] = {}
        for key_node, _ in node.value:
            key = loader.construct_object(key_node, deep=deep)
            line = key_node.start_mark.line + 1
            try:
                first = seen.get(key)
            except TypeError:  # unhashable key: the base loader reports it
                continue
            if first is not None:
                raise ConfigError(f"{key_node.start_mark.name}, line {line}: duplicate key {key!r} "
                                  f"(first given on line {first}); allowed: each key once")
            seen[key] = line
        return yaml.SafeLoader.construct_mapping(loader, node, deep=deep)

    def construct_number(loader, node):
        text = str(node.value)
        if not _PLAIN_NUMBER.match(text):
            value = _YAML11_NUMBER[node.tag](loader, node)
            raise ConfigError(f"{node.start_mark.name}, line {node.start_mark.line + 1}: "
                              f"{text!r} is a YAML 1.1 {_number_form(text)} number (read as "
                              f"{value!r}); allowed: a plain decimal number (1.5, 90, 1e-3), "
                              f"or quote it if it is text")
        return _YAML11_NUMBER[node.tag](loader, node)

    UniqueKeyLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, construct_mapping)
    for tag in _YAML11_NUMBER:
        UniqueKeyLoader.add_constructor(tag, construct_number)
    return UniqueKeyLoader


def _yaml11_number_constructors() -> dict:
    import yaml

    return {"tag:yaml.org,2002:int": yaml.SafeLoader.construct_yaml_int,
            "tag:yaml.org,2002:float": yaml.SafeLoader.construct_yaml_float}


#: The constructors of YAML 1.1 numbers (PyYAML's SafeLoader), by tag.
_YAML11_NUMBER = _yaml11_number_constructors()

#: Numbers written as a reader expects: decimal digits with an optional sign, fraction and
#: exponent (``_`` between digits allowed), ``.inf``/``.nan`` (refused later by the finite
#: check). YAML 1.1 also reads ``1:30`` as 90 (base 60), ``010`` as 8 (octal), ``0x1f``, ``0b11``.
_PLAIN_NUMBER = re.compile(r"^[-+]?(?:(?:0|[1-9][0-9_]*)(?:\.[0-9_]*)?|\.[0-9_]+)"
                           r"(?:[eE][-+]?[0-9]+)?$|^[-+]?\.(?:inf|Inf|INF)$|^\.(?:nan|NaN|NAN)$")


def _number_form(text: str) -> str:
    """The YAML 1.1 number form of a non-plain numeric scalar (for the error message)."""
    t = text.lstrip("+-")
    if ":" in t:
        return "base-60 (sexagesimal)"
    if t.startswith(("0x", "0X")):
        return "hexadecimal"
    if t.startswith(("0b", "0B")):
        return "binary"
    return "octal" if t.startswith("0") else "non-decimal"


def read_yaml(path: str | os.PathLike) -> dict[str, Any]:
    """Read a YAML config strictly: a mapping, no duplicate keys, errors with line numbers.

    Parameters
    ----------
    path : str or os.PathLike
        The config file (size bounded by
        :data:`~bearing_envelope.io.yamlsafe.MAX_DOCUMENT_BYTES`; numbers must be plain
        decimals, not YAML 1.1 octal, hexadecimal or base-60 forms).

    Returns
    -------
    dict
        The parsed top-level mapping, not yet validated (empty for an empty file).

    Raises
    ------
    ConfigError
        File missing, a directory, unreadable, not valid YAML (``file, line L, column C: ...``),
        a duplicate key (``file, line L: duplicate key 'x' (first given on line K)``) or not a
        mapping at the top level.
    """
    import yaml

    p = os.fspath(path)
    if os.path.isdir(p):
        raise ConfigError(f"{p}: is a directory; allowed: a YAML config file")
    if not os.path.exists(p):
        raise ConfigError(f"{p}: config file not found")
    try:
        check_input_file(p, "config file", max_bytes=MAX_DOCUMENT_BYTES, allow_empty=True)
    except ValueError as exc:
        raise ConfigError(str(exc)) from None
    try:
        with open(p, encoding="utf-8") as fh:
            doc = load_bounded(fh, _unique_key_loader())  # aliases bounded (io.yamlsafe)
    except ConfigError:
        raise
    except YamlLimitError as exc:
        raise ConfigError(f"{p}: {exc}") from None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        where = f"{p}, line {mark.line + 1}, column {mark.column + 1}" if mark else p
        what = " ".join(x for x in (exc.context, exc.problem) if x)
        raise ConfigError(f"{where}: YAML syntax error: {what}") from None
    except yaml.YAMLError as exc:
        raise ConfigError(f"{p}: YAML error: {str(exc).splitlines()[0]}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{p}: cannot read the config ({exc})") from None
    if doc is None:
        doc = {}
    if not isinstance(doc, dict):
        raise ConfigError(f"{p}: the config must be a mapping of sections (sweep:, scene:, ...), "
                          f"got a {type(doc).__name__}")
    if "__use_yte__" in doc:
        raise ConfigError(
            f"{p}: __use_yte__: {doc['__use_yte__']!r}; allowed: the key absent (YTE templating "
            f"runs Python from the config file; a config here is data)")
    return doc


def merge_configs(base: Mapping[str, Any], overlay: Mapping[str, Any]) -> dict[str, Any]:
    """``overlay`` merged over ``base``: the one merge of config files (the workflow's
    ``config.yaml`` + ``--configfile`` files + ``--config``, and ``check-config``).

    Mappings merge key by key, recursively; any other value (lists included) replaces the base's,
    as Snakemake merges config files. One rule more: **a designation is a complete bearing**. An
    overlay whose ``scene.bearing`` names ``designation`` replaces the base's whole
    ``scene.bearing`` and drops the base's ``scene.operation.bpfi_override_hz`` (the override
    travels with the catalogue entry), so that a file naming a bearing is never merged with
    another bearing's keys.

    Parameters
    ----------
    base, overlay : mapping
        Parsed config files (:func:`read_yaml`).

    Returns
    -------
    dict
        A new mapping; neither argument is changed.
    """
    out = copy.deepcopy(dict(base))
    scene = overlay.get("scene")
    bearing = scene.get("bearing") if isinstance(scene, Mapping) else None
    if isinstance(bearing, Mapping) and "designation" in bearing \
            and isinstance(out.get("scene"), Mapping):
        out["scene"] = {k: v for k, v in out["scene"].items() if k != "bearing"}
        op = out["scene"].get("operation")
        if isinstance(op, Mapping):
            out["scene"]["operation"] = {k: v for k, v in op.items() if k != "bpfi_override_hz"}
    _update(out, overlay)
    return out


def _update(out: dict, overlay: Mapping[str, Any]) -> None:
    for key, value in overlay.items():
        if isinstance(value, Mapping) and isinstance(out.get(key), Mapping):
            out[key] = dict(out[key])
            _update(out[key], value)
        else:
            out[key] = copy.deepcopy(value)


def config_files(given: Sequence[str | os.PathLike] = ()) -> list[str]:
    """The files a run reads, in merge order: ``./config.yaml`` when it exists (the workflow's
    base), then ``given`` (``--configfile`` files) except ``./config.yaml`` itself.

    Parameters
    ----------
    given : sequence of path
        Further config files, later ones win.

    Returns
    -------
    list of str
        The paths in merge order, ``config.yaml`` first when it exists (each file once).
    """
    files = [DEFAULT_CONFIG_NAME] if default_config_path() is not None else []
    base = Path(DEFAULT_CONFIG_NAME).resolve()
    return files + [os.fspath(f) for f in given if not (files and Path(f).resolve() == base)]


def read_configs(files: Sequence[str | os.PathLike],
                 overrides: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Read each file once (:func:`read_yaml`) and merge them in order (:func:`merge_configs`),
    then ``overrides`` (Snakemake's ``--config key=value``).

    Parameters
    ----------
    files : sequence of path
        YAML config files, merged in order (later ones win).
    overrides : mapping, optional
        A config mapping of the same layout, merged last over every file.

    Returns
    -------
    dict
        The merged, not yet validated mapping.
    """
    merged: dict[str, Any] = {}
    for f in files:
        merged = merge_configs(merged, read_yaml(f))
    return merge_configs(merged, overrides or {})
