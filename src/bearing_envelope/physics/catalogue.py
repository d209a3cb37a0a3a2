"""Bearing catalogue: the geometry of named bearings, with the source of every number.

The catalogue is package data (``bearing_envelope/data/bearings.yaml``): one entry per
designation, each field ``{value, source}`` in the units of the ``scene.bearing`` keys
(``docs/scene.md``). A config names an entry with ``scene.bearing.designation``; the entry's
values replace the default scene's bearing and any key the config gives overrides them
(:meth:`bearing_envelope.scene.Scene.from_mapping`). ``source`` says where a number comes from;
"assumed" marks a value that is not published.

Entries (issue 23): ``FAG 534176`` (the source study, equal to today's default scene),
``SKF 6205-2RS`` (CWRU drive end), ``SKF 6203`` (Paderborn), ``MFPT`` (MFPT Society test
bearing), ``Rexnord ZA-2115`` (IMS rig).
"""

from __future__ import annotations

import copy
from functools import lru_cache
from pathlib import Path
from typing import Any

import yaml

__all__ = ["CATALOGUE_PATH", "designations", "bearing_values", "bearing_sources", "entry",
           "operation_values", "OPERATION_KEYS"]

#: The catalogue file (package data).
CATALOGUE_PATH = Path(__file__).resolve().parent.parent / "data" / "bearings.yaml"

#: Entry keys that are not ``scene.bearing`` fields.
_META_KEYS = ("description",)

#: Entry keys that are ``scene.operation`` fields of the bearing (a stated BPFI): they travel
#: with the entry; an entry without one gives null (the fault frequencies from geometry).
OPERATION_KEYS = ("bpfi_override_hz",)


@lru_cache(maxsize=1)
def _load() -> dict[str, dict[str, Any]]:
    with open(CATALOGUE_PATH, encoding="utf-8") as fh:
        data = yaml.load(fh, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))  # libyaml: 10x faster
    for name, ent in data.items():
        for key, item in ent.items():
            if key in _META_KEYS:
                continue
            if not isinstance(item, dict) or set(item) != {"value", "source"}:
                raise ValueError(f"{CATALOGUE_PATH}: {name}.{key}: expected {{value, source}}")
    return data


def designations() -> tuple[str, ...]:
    """The designations in the catalogue, in file order.

    Returns
    -------
    tuple of str
        Every designation of ``data/bearings.yaml``.
    """
    return tuple(_load())


def entry(designation: str) -> dict[str, Any]:
    """The raw catalogue entry (``{field: {value, source}}`` plus ``description``).

    Parameters
    ----------
    designation : str
        A catalogue designation (its full name, e.g. ``"SKF 6205-2RS"``).

    Returns
    -------
    dict
        The entry as stored: ``{field: {"value": ..., "source": ...}, "description": ...}``.

    Raises
    ------
    ValueError
        ``scene.bearing.designation`` naming the value and the designations allowed.
    """
    cat = _load()
    if designation not in cat:
        raise ValueError(f"scene.bearing.designation: got {designation!r}; allowed: null or one of "
                         f"{list(cat)} (bearing_envelope/data/bearings.yaml)")
    return copy.deepcopy(cat[designation])


def bearing_values(designation: str) -> dict[str, Any]:
    """``scene.bearing`` values of a catalogue entry (field -> value, scene units).

    Parameters
    ----------
    designation : str
        A catalogue designation (:func:`designations`).

    Returns
    -------
    dict
        Field -> value, without the entry's operation keys (:func:`operation_values`).
    """
    return {k: v["value"] for k, v in entry(designation).items()
            if k not in _META_KEYS and k not in OPERATION_KEYS}


def operation_values(designation: str) -> dict[str, Any]:
    """``scene.operation`` values that travel with a catalogue entry.

    Parameters
    ----------
    designation : str
        A catalogue designation (:func:`designations`).

    Returns
    -------
    dict
        Every key of :data:`OPERATION_KEYS`: the entry's value, or None when it gives none.
    """
    ent = entry(designation)
    return {k: (ent[k]["value"] if k in ent else None) for k in OPERATION_KEYS}


def bearing_sources(designation: str) -> dict[str, str]:
    """The source of every value of a catalogue entry (field -> text).

    Parameters
    ----------
    designation : str
        A catalogue designation (:func:`designations`).

    Returns
    -------
    dict of str to str
        ``scene.bearing`` field -> where its value comes from (or "assumed").
    """
    return {k: v["source"] for k, v in entry(designation).items()
            if k not in _META_KEYS and k not in OPERATION_KEYS}
