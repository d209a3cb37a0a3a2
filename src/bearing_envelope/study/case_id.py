"""Case identity: :class:`CaseId`, the one formatter and parser of case names.

A case name is ``F{load_kN}kN_h{depth_um}um`` plus ``_w{width_um}um`` when the sweep sets widths
and ``_ir``/``_or``/``_re`` (the defect location, :data:`LOCATION_CODES`) when the sweep sets
locations or the scene's is not the inner race. Numbers are written exactly (the shortest
decimal that reads back to the same float, never ``%g``), so every name parses back to the
values it was made from and two different sweep values never share a name.
"""

from __future__ import annotations

import copy
import dataclasses
import json
import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..physics.locations import LOCATIONS, get_location
from ..physics.scene import DEFAULT_SCENE, Scene, default_width_um

__all__ = ["CaseId", "format_number", "CASE_NAME_REGEX", "LOCATION_CODES"]


def format_number(value: float) -> str:
    """Exact decimal text of a float: the shortest positional string that reads back to it.

    ``50.0 -> '50'``, ``333.3333 -> '333.3333'``, ``50.0000001 -> '50.0000001'`` (never ``%g``,
    which writes 333.333 for 333.3333). ``float(format_number(v)) == v`` for every finite ``v``.

    Parameters
    ----------
    value : float
        A finite number (``-0.0`` is written ``0``).

    Returns
    -------
    str
        Positional decimal text, no exponent, no trailing zeros or point.

    Raises
    ------
    ValueError
        ``value`` is NaN or infinite.
    """
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"case values must be finite, got {value!r}")
    return np.format_float_positional(v + 0.0, unique=True, trim="-")


_NUM = r"[0-9]+(?:\.[0-9]+)?"

#: Short code of each defect location in case names (``_ir``, ``_or``, ``_re``): the ``code`` of
#: every registered location (:data:`bearing_envelope.physics.locations.LOCATIONS`).
LOCATION_CODES = {name: loc.code for name, loc in LOCATIONS.items()}
_LOCATION_OF_CODE = {v: k for k, v in LOCATION_CODES.items()}
_LOC = "|".join(LOCATION_CODES.values())

#: Regular expression of a canonical case name (also the workflow's wildcard constraint).
CASE_NAME_REGEX = rf"F{_NUM}kN_h{_NUM}um(?:_w{_NUM}um)?(?:_(?:{_LOC}))?"
_CASE_RE = re.compile(
    rf"^F(?P<load>{_NUM})kN_h(?P<depth>{_NUM})um(?:_w(?P<width>{_NUM})um)?"
    rf"(?:_(?P<loc>{_LOC}))?$")


@dataclass(frozen=True, order=True)
class CaseId:
    """One case of the sweep: load (kN), defect depth (um) and, when the sweep sets them, width
    (um) and defect location.

    ``width_um = None`` means the scene's width (``scene.defect.width_um``; null there = 2 x
    depth, the study's rule); ``location = None`` the scene's location (``defect.location``; the
    inner race by default). :attr:`name` is the one formatter of case names and :meth:`parse`
    the one parser; ``CaseId.parse(c.name) == c`` exactly.

    Examples
    --------
    >>> CaseId(500, 50).name
    'F500kN_h50um'
    >>> CaseId.parse("F333.3333kN_h30um_w200um")
    CaseId(load_kN=333.3333, depth_um=30.0, width_um=200.0, location=None)
    >>> CaseId(1, 279.4, 177.8, "outer_race").name
    'F1kN_h279.4um_w177.8um_or'
    """

    load_kN: float
    depth_um: float
    width_um: float | None = None
    location: str | None = None

    def __post_init__(self) -> None:
        if self.location is not None and self.location not in LOCATION_CODES:
            raise ValueError(f"CaseId.location: got {self.location!r}; allowed: None or one of "
                             f"{list(LOCATION_CODES)}")
        for key in ("load_kN", "depth_um", "width_um"):
            v = getattr(self, key)
            if v is None and key == "width_um":
                continue
            if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) \
                    or not math.isfinite(float(v)) or float(v) < 0:
                raise ValueError(f"CaseId.{key}: got {v!r}; allowed: a finite number >= 0")
            object.__setattr__(self, key, float(v) + 0.0)

    @property
    def name(self) -> str:
        """Canonical name ``F{load}kN_h{depth}um[_w{width}um][_{ir|or|re}]`` (numbers exact)."""
        s = f"F{format_number(self.load_kN)}kN_h{format_number(self.depth_um)}um"
        if self.width_um is not None:
            s += f"_w{format_number(self.width_um)}um"
        if self.location is not None:
            s += f"_{get_location(self.location).code}"
        return s

    def __str__(self) -> str:
        return self.name

    @classmethod
    def parse(cls, name: str | os.PathLike) -> "CaseId":
        """Parse a case name (or a path whose file stem is one: ``results/cases/F500kN_h50um.h5``).

        Parameters
        ----------
        name : str or os.PathLike
            A case name, or a path whose last component is one, optionally ending in ``.h5``,
            ``.csv``, ``.json`` or ``.npz``.

        Returns
        -------
        CaseId
            The case whose :attr:`name` is that name.

        Raises
        ------
        ValueError
            If the name does not match :data:`CASE_NAME_REGEX`, or is not canonical (e.g.
            ``F500.0kN_h50um``: the canonical name is ``F500kN_h50um``), so that one case never
            has two names.
        """
        text = os.fspath(name)
        stem = Path(text).name
        for ext in (".h5", ".csv", ".json", ".npz"):
            if stem.endswith(ext):
                stem = stem[: -len(ext)]
                break
        m = _CASE_RE.match(stem)
        if not m:
            raise ValueError(f"case name {text!r} does not match "
                             f"'F{{load_kN}}kN_h{{depth_um}}um[_w{{width_um}}um][_{{{_LOC}}}]'")
        case = cls(float(m["load"]), float(m["depth"]),
                   None if m["width"] is None else float(m["width"]),
                   None if m["loc"] is None else _LOCATION_OF_CODE[m["loc"]])
        if case.name != stem:
            raise ValueError(f"case name {text!r} is not canonical; the canonical name of this "
                             f"case is {case.name!r}")
        return case

    def attrs(self) -> dict[str, str]:
        """The case-file attributes that record this case: ``case`` (its name, for people) and
        ``case_json`` (the typed fields, what :meth:`from_case` reads back).

        Returns
        -------
        dict of str to str
            ``{"case": name, "case_json": JSON of load_kN, depth_um, width_um, location}``
            (sorted keys).
        """
        return {"case": self.name, "case_json": json.dumps(dataclasses.asdict(self),
                                                           sort_keys=True)}

    @classmethod
    def from_case(cls, case) -> "CaseId":
        """The id of a read case file (:class:`bearing_envelope.io.Case`).

        Uses the typed ``case_json`` attribute the writers store (:meth:`attrs`; never the name);
        for older files, load and depth (and the width when it is not the default 2 x depth, the
        location when it is not the inner race).

        Parameters
        ----------
        case : bearing_envelope.io.Case
            A read case file (or an object with ``attrs``, ``scene``, ``load_kN`` and
            ``depth_um``).

        Returns
        -------
        CaseId
            The case's id (``width_um`` and ``location`` None where the file's are the
            defaults).
        """
        attrs = getattr(case, "attrs", {}) or {}
        if attrs.get("case_json"):
            return cls(**json.loads(str(attrs["case_json"])))
        defect = (getattr(case, "scene", None) or {}).get("defect") or {}
        width = defect.get("width_um")
        depth = float(case.depth_um)
        if width is None or depth == 0 or float(width) == default_width_um(depth):
            width = None
        location = defect.get("location")
        if location == DEFAULT_SCENE["defect"]["location"]:
            location = None
        return cls(float(case.load_kN), depth, width, location)

    def scene_mapping(self, scene: Mapping[str, Any] | None) -> dict[str, Any]:
        """The ``scene:`` mapping of this case (a copy; ``defect.width_um`` and
        ``defect.location`` set when given).

        Parameters
        ----------
        scene : mapping or None
            The config's ``scene:`` section (not modified; None = empty).

        Returns
        -------
        dict
            A deep copy of ``scene`` with this case's width (um) and location in ``defect``.
        """
        m = copy.deepcopy(dict(scene or {}))
        if self.width_um is not None or self.location is not None:
            m["defect"] = dict(m.get("defect") or {})
        if self.width_um is not None:
            m["defect"]["width_um"] = self.width_um
        if self.location is not None:
            m["defect"]["location"] = self.location
        return m

    @property
    def healthy(self) -> "CaseId":
        """The healthy race (depth 0, no width) of this case's load and location."""
        return CaseId(self.load_kN, 0.0, None, self.location)

    def scene(self, scene: Mapping[str, Any] | None = None):
        """Build and validate this case's :class:`bearing_envelope.physics.scene.Scene`.

        Parameters
        ----------
        scene : mapping, optional
            The config's ``scene:`` section (:meth:`scene_mapping`); None: the default scene.

        Returns
        -------
        Scene
            At this case's load (kN) and defect depth (um).

        Raises
        ------
        ValueError
            A scene value out of range (the message names the field).
        """
        return Scene.from_mapping(self.scene_mapping(scene), load_kN=self.load_kN,
                                  depth_um=self.depth_um)

