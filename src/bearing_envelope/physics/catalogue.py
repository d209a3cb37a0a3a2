"""Bearing catalogue: the geometry of named bearings, with the source of every number.

The catalogue is package data (``bearing_envelope/data/bearings.yaml``): one entry per
designation, each field ``{value, source}`` in the units of the ``scene.bearing`` keys
(``docs/scene.md``). A config names an entry with ``scene.bearing.designation``; the entry's
values replace the default scene's bearing and any key the config gives overrides them
(:meth:`bearing_envelope.scene.Scene.from_mapping`). ``source`` says where a number comes from;
"assumed" marks a value that is not published.

:func:`resolve_designation` is the one resolver of a bearing's name: the designation or any
alias of it (``6205``, ``SKF 6205``, ``6205-2RS``, ``SKF 6205-2RS JEM`` all name
``SKF 6205-2RS``), the same for a config (``scene.bearing.designation``), ``analyze
--bearing``, ``identify-path --bearing`` and the rig. :func:`bearing_geometry` gives the
rolling-element geometry of a bearing named so, or checks one given by its numbers (mm or inch,
never both; a designation or the geometry, never both).

Entries (issue 23): ``FAG 534176`` (the source study, equal to today's default scene),
``SKF 6205-2RS`` (CWRU drive end), ``SKF 6203`` (Paderborn), ``MFPT`` (MFPT Society test
bearing), ``Rexnord ZA-2115`` (IMS rig).
"""

from __future__ import annotations

import copy
import math
import numbers
import re
from collections.abc import Mapping
from functools import lru_cache
from pathlib import Path
from typing import Any

import yaml

__all__ = ["CATALOGUE_PATH", "designations", "bearing_values", "bearing_sources", "entry",
           "operation_values", "OPERATION_KEYS", "resolve_designation", "known_bearings",
           "bearing_geometry", "max_rollers", "DESIGNATION_TEXT", "MM_PER_INCH",
           "GEOMETRY_KEYS"]

#: Millimetres per inch (the geometry may be given in inch).
MM_PER_INCH = 25.4

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
    return copy.deepcopy(_load()[resolve_designation(designation)])


def _key(name: str) -> str:
    return re.sub(r"[\s_]+", "-", str(name).strip().upper())


def _aliases(designation: str) -> set[str]:
    """Names a catalogue entry answers to: ``"SKF 6205-2RS"`` -> itself, ``"6205-2RS"``,
    ``"6205"`` (and ``"SKF 6205"``)."""
    out = {_key(designation)}
    words = designation.split()
    if len(words) > 1:
        out.add(_key(" ".join(words[1:])))
    m = re.search(r"\d{3,}", designation)
    if m:
        out.add(m.group(0))
        out.add(_key(designation[:m.end()]))
    return out


@lru_cache(maxsize=1)
def _alias_table() -> dict[str, str]:
    out: dict[str, str] = {}
    for d in designations():
        for a in _aliases(d):
            out.setdefault(a, d)
    return out


def known_bearings() -> dict[str, str]:
    """``alias -> catalogue designation`` of every entry (what :func:`resolve_designation`
    accepts, written in its normal form: upper case, ``-`` between words).

    Returns
    -------
    dict
        Alias (``"6205"``, ``"6205-2RS"``, ``"SKF-6205"``, ``"SKF-6205-2RS"``) -> designation.
    """
    return dict(_alias_table())


def resolve_designation(name: str, *, field: str = "scene.bearing.designation") -> str:
    """The catalogue designation a name stands for: the one resolver of bearing names.

    Case, spaces and underscores do not matter; a designation's number alone (``6205``), with
    its maker (``SKF 6205``) or with its suffix (``6205-2RS``) names it, and so does a longer
    name that starts with one of these (``SKF 6205-2RS JEM``, ``6205-2RS JEM SKF``).

    Parameters
    ----------
    name : str
        A designation or an alias of it.
    field : str, keyword-only
        How the caller names the field, for the message (``--bearing``).

    Returns
    -------
    str
        The designation as the catalogue writes it (``"SKF 6205-2RS"``).

    Raises
    ------
    ValueError
        ``{field}: got {name!r}; allowed: ...`` (the designations and aliases) for a name
        that is not a string or names no entry.

    Examples
    --------
    >>> resolve_designation("6205"), resolve_designation("skf 6205-2rs jem")
    ('SKF 6205-2RS', 'SKF 6205-2RS')
    """
    cat = _load()
    if isinstance(name, str) and name in cat:
        return name
    table = _alias_table()
    found = None
    if isinstance(name, str) and not DESIGNATION_TEXT.fullmatch(name):
        raise ValueError(f"{field}: got {name[:60]!r}{'...' if len(name) > 60 else ''}; "
                         f"allowed: a designation of ASCII letters, digits, spaces and "
                         f"- _ . / + ( ) (e.g. 6205, SKF 6205-2RS), at most 80 characters")
    if isinstance(name, str):
        _one_number(name, table, field)
        key = _key(name)
        found = table.get(key)
        words = key.split("-")
        for n in range(len(words) - 1, 0, -1):   # a longer name: its longest known start
            found = found or table.get("-".join(words[:n]))
        if found is None:   # "6205-2RS JEM SKF": its designation number
            m = re.search(r"\d{3,}", key)
            found = table.get(m.group(0)) if m else None
    if found is None:
        null = "null or " if field.startswith("scene.") else ""
        raise ValueError(f"{field}: got {name!r}; allowed: {null}one of {list(cat)} "
                         f"(bearing_envelope/data/bearings.yaml), or an alias such as 6205, "
                         f"SKF 6205, 6203")
    return found


#: What a bearing designation may be written with: ASCII letters, digits, spaces and
#: ``- _ . / + ( )``, at most 80 characters (``SKF 6205-2RS/C3``, ``NU 2310 (ECP)``); control
#: characters, ``;``, quotes and non-ASCII digits are refused, never skipped over.
DESIGNATION_TEXT = re.compile(r"[A-Za-z0-9 ._/+()\-]{1,80}")


def _one_number(name: str, table: Mapping[str, str], field: str) -> None:
    """Refuse a name that holds the numbers of two catalogue entries (``6205 6203``): it
    names no one bearing, and picking the first would be a guess."""
    hits = {table[m] for m in re.findall(r"\d{3,}", _key(name)) if m in table}
    if len(hits) > 1:
        raise ValueError(f"{field}: got {name!r}, which names {len(hits)} catalogue bearings "
                         f"({', '.join(sorted(hits))}); allowed: one designation")


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


#: The geometry :func:`bearing_geometry` returns, and the parameters of its numbers.
GEOMETRY_KEYS = ("n_rollers", "roller_diameter_mm", "pitch_diameter_mm", "contact_angle_deg")


def bearing_geometry(designation: str | None = None, *, n_rollers=None,
                     roller_diameter_mm=None, pitch_diameter_mm=None, contact_angle_deg=None,
                     roller_diameter_in=None, pitch_diameter_in=None,
                     names: Mapping[str, str] | None = None) -> dict | None:
    """The rolling-element geometry of a bearing named by designation (any alias,
    :func:`resolve_designation`) or given by its numbers, checked: the one place the rules of a
    bearing given by a user live.

    Rules: a designation or the geometry, not both; each diameter in mm or in inch, not both;
    the element count and both diameters together; diameters finite and > 0 with ``d < D``,
    ``n_rollers`` an integer that fits on the pitch circle (2 .. :func:`max_rollers`), the
    contact angle in [0, 90) degrees (default 0).

    Parameters
    ----------
    designation : str, optional
        A catalogue designation or alias (``"6205"``, ``"SKF 6205-2RS JEM"``).
    n_rollers, roller_diameter_mm, pitch_diameter_mm, contact_angle_deg : optional
        The geometry (mm, degrees), instead of a designation.
    roller_diameter_in, pitch_diameter_in : float, optional
        A diameter in inch instead of mm (converted with :data:`MM_PER_INCH`).
    names : mapping, optional
        Parameter -> how the caller names it, for the messages (``{"designation":
        "--bearing", "n_rollers": "--n-rollers", ...}``; default ``bearing`` for the
        designation, the parameter's own name for the others).

    Returns
    -------
    dict or None
        ``designation`` (the catalogue's, None for a given geometry), ``n_rollers``,
        ``roller_diameter_mm``, ``pitch_diameter_mm`` (the catalogue's, or ``(bore + OD)/2``
        where it gives none), ``contact_angle_deg`` and, for a catalogue bearing, ``source``
        (of each value); None when nothing is given.

    Raises
    ------
    ValueError
        One line naming the parameter (as ``names`` says), the value and what is allowed.

    Examples
    --------
    >>> g = bearing_geometry("6205")
    >>> g["designation"], g["n_rollers"], g["roller_diameter_mm"], g["pitch_diameter_mm"]
    ('SKF 6205-2RS', 9, 7.94, 39.04)
    """
    n = {"designation": "bearing", **dict(names or {})}
    nm = lambda p: n.get(p, p)   # noqa: E731 - the caller's name of a parameter
    d_mm = _one_unit(roller_diameter_mm, roller_diameter_in, "roller_diameter", nm)
    p_mm = _one_unit(pitch_diameter_mm, pitch_diameter_in, "pitch_diameter", nm)
    given = (n_rollers, d_mm, p_mm)
    if designation is not None:
        if any(v is not None for v in given) or contact_angle_deg is not None:
            raise ValueError(f"{nm('designation')}: give the bearing by designation or by its "
                             f"geometry ({nm('n_rollers')}, {nm('roller_diameter_mm')}, "
                             f"{nm('pitch_diameter_mm')}), not both")
        return _catalogue_geometry(resolve_designation(designation, field=nm("designation")))
    if all(v is None for v in given):
        return None
    if any(v is None for v in given):
        raise ValueError(f"bearing geometry: give {nm('n_rollers')}, {nm('roller_diameter_mm')} "
                         f"and {nm('pitch_diameter_mm')} together")
    return _checked_geometry(n_rollers, d_mm, p_mm, contact_angle_deg or 0.0, nm)


def _one_unit(mm, inch, what: str, nm) -> float | None:
    """A diameter given in mm or in inch (not both), in mm."""
    if mm is not None and inch is not None:
        raise ValueError(f"{nm(what + '_in')}: give the {what.replace('_', ' ')} once, in mm "
                         f"({nm(what + '_mm')}) or in inch")
    if inch is None:
        return mm
    if not _finite(inch) or inch <= 0:
        raise ValueError(f"{nm(what + '_in')}: got {inch!r}; allowed: a finite diameter > 0")
    return inch * MM_PER_INCH


def _finite(v) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)


def _checked_geometry(z, d_mm, p_mm, alpha, nm) -> dict:
    if isinstance(z, bool) or not isinstance(z, numbers.Integral) or z < 1:
        raise ValueError(f"{nm('n_rollers')}: got {z!r}; allowed: an integer >= 1")
    for key, v in (("roller_diameter_mm", d_mm), ("pitch_diameter_mm", p_mm)):
        if not _finite(v) or v <= 0:
            raise ValueError(f"{nm(key)}: got {v!r}; allowed: a finite diameter > 0")
    if d_mm >= p_mm:
        raise ValueError(f"{nm('roller_diameter_mm')}: got {d_mm:g} mm; allowed: below the "
                         f"pitch diameter ({p_mm:g} mm)")
    z_max = max_rollers(d_mm, p_mm)
    if not 2 <= z <= z_max:
        raise ValueError(f"{nm('n_rollers')}: got {z}; allowed: 2 .. {z_max} (rollers of "
                         f"{d_mm:g} mm fit on a pitch circle of {p_mm:g} mm only while "
                         f"D sin(pi/Z) >= d)")
    if not _finite(alpha) or not 0 <= alpha < 90:
        raise ValueError(f"{nm('contact_angle_deg')}: got {alpha!r}; allowed: 0 <= angle < 90")
    return {"designation": None, "n_rollers": int(z), "roller_diameter_mm": float(d_mm),
            "pitch_diameter_mm": float(p_mm), "contact_angle_deg": float(alpha)}


def max_rollers(roller_diameter_mm: float, pitch_diameter_mm: float) -> int:
    """The most rolling elements of diameter d that fit side by side on a pitch circle of
    diameter D: the largest Z with D sin(pi / Z) >= d (neighbours' centres D sin(pi/Z) apart).

    Parameters
    ----------
    roller_diameter_mm : float
        Roller (ball) diameter d, mm; ``0 < d < D``.
    pitch_diameter_mm : float
        Pitch diameter D, mm.

    Returns
    -------
    int
        ``floor(pi / arcsin(d / D))`` (at least 2).

    Examples
    --------
    >>> max_rollers(7.94, 39.04)   # the CWRU 6205 holds 9 balls
    15
    """
    return max(2, int(math.pi / math.asin(roller_diameter_mm / pitch_diameter_mm) + 1e-9))


def _catalogue_geometry(designation: str) -> dict:
    v, src = bearing_values(designation), bearing_sources(designation)
    pitch = v["pitch_diameter_mm"]
    if pitch is None:
        pitch = 0.5 * (v["bore_mm"] + v["outside_diameter_mm"])
    return {"designation": designation, "n_rollers": int(v["rollers_per_row"]),
            "roller_diameter_mm": float(v["roller_diameter_mm"]),
            "pitch_diameter_mm": float(pitch),
            "contact_angle_deg": float(v.get("contact_angle_deg") or 0.0),
            "source": {k: src[k] for k in ("rollers_per_row", "roller_diameter_mm",
                                           "pitch_diameter_mm", "contact_angle_deg")
                       if k in src}}
