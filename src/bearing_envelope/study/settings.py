"""Typed, frozen settings built once from the schema-validated configuration.

One loader, used by the CLI (``bearing-envelope simulate --config``) and by the workflow
(``workflow/rules/common.smk``):

1. :func:`read_yaml` reads the file with a loader that refuses duplicate keys and reports YAML
   syntax errors with their line and column;
2. :func:`settings_from_mapping` rejects NaN and infinities anywhere (JSON Schema bounds do not
   catch NaN), validates against the schema shipped as package data
   (:data:`bearing_envelope.study.schema.SCHEMA_PATH`) with a one-line message per error (the field,
   the value, what is allowed; never the schema), fills the schema defaults, and builds the typed
   settings, whose constructors run the cross-field checks a schema cannot express (every case's
   scene builds, bands and sensor modes below Nyquist, ``max_level <= nlevel`` ...).

Every failure is a :class:`ConfigError` (a ``ValueError``) whose message is one line naming the
dotted field (``sweep.depths_um[2]``, ``sensor.modes[0].f_n_hz``) before any job or solve runs.

:class:`CaseId` is the one formatter and parser of case names: ``F{load_kN}kN_h{depth_um}um``
plus ``_w{width_um}um`` when the sweep sets widths and ``_ir``/``_or``/``_re`` (the defect
location, :data:`LOCATION_CODES`) when the sweep sets locations or the scene's is not the inner
race. Numbers are written exactly (the shortest
decimal that reads back to the same float, never ``%g``), so every name parses back to the
values it was made from and two different sweep values never share a name.
"""

from __future__ import annotations

import copy
import dataclasses
import difflib
import functools
import json
import math
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..checks import check_input_file
from ..diagnosis.analysis import AnalysisOptions
from ..io.yamlsafe import MAX_DOCUMENT_BYTES, YamlLimitError, load_bounded
from ..physics.exposure import BRIDGE_MAX_FRACTION  # the pit-bridging limit (fraction of 2b)
from ..physics.fidelity import DEFAULT_PRESET, Fidelity, fidelity_from
from ..physics.geometry import hertz_estimate
from ..physics.loads import scene_load_distribution
from ..physics.locations import LOCATION_FAMILIES, scene_event_frequencies
from ..physics.scene import DEFECT_LOCATIONS, Scene
from ..physics.transfer import TransferModel
from ..signal.bands import DEFAULT_BANDS, resolve_band
from .schema import SCHEMA_PATH
from .tradeoff_settings import TradeoffSettings

__all__ = [
    "ConfigError", "CaseId", "format_number", "CASE_NAME_REGEX", "LOCATION_CODES",
    "BandSpec", "AnalysisSettings", "SweepSettings", "DiagnosabilitySettings", "Settings",
    "SimulationSetup", "section_defaults", "JobValue", "CaseSetup", "TradeoffSetup",
    "JobSettings", "JOB_PARAMS", "job_settings",
    "read_yaml", "settings_from_mapping", "load_settings", "workflow_settings",
    "default_config_path", "merge_configs", "read_configs", "config_files", "analysis_defaults",
    "DEFAULT_CONFIG_NAME", "DEFAULT_MAX_CASES", "full_schema",
]

#: The config file ``simulate --config`` and the workflow read when none is named.
DEFAULT_CONFIG_NAME = "config.yaml"

#: Cases a sweep may have when ``limits.max_cases`` is not given: the pre-run checks cost
#: about 3 CPU ms per case (``check-config`` on 1000 cases: 4.4 CPU s with imports) and
#: Snakemake's dry run about 20 ms per case; a larger sweep says so with ``limits.max_cases``.
DEFAULT_MAX_CASES = 1000

#: Longest message taken from a schema error (the instance repr can be long).
_MAX_MESSAGE = 240


class ConfigError(ValueError):
    """A configuration is invalid; the message is one line naming the field."""


# --------------------------------------------------------------------------------------------
# case names


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

#: Short code of each defect location in case names (``_ir``, ``_or``, ``_re``).
LOCATION_CODES = {"inner_race": "ir", "outer_race": "or", "rolling_element": "re"}
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
            s += f"_{LOCATION_CODES[self.location]}"
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
        if width is None or depth == 0 or float(width) == 2.0 * depth:
            width = None
        location = defect.get("location")
        if location == DEFECT_LOCATIONS[0]:
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


# --------------------------------------------------------------------------------------------
# typed sections


def _err(where: str, value: Any, allowed: str) -> ConfigError:
    return ConfigError(f"{where}: got {value!r}; allowed: {allowed}")


#: Longest exact text of one sweep value in a case name (:func:`format_number`), characters:
#: ``1e-300`` is 302 digits long. Checked as the sweep is read, before any case is built.
MAX_VALUE_CHARS = 24


@dataclass(frozen=True)
class SweepSettings:
    """The ``sweep:`` section: loads (kN), depths (um), optional widths (um) and locations.

    Without ``widths_um`` every depth keeps the study's width w = 2 h (27 cases, names without a
    width). With ``widths_um`` each defect depth is combined with each width (names carry
    ``_w{width}um``); the healthy race (depth 0) stays one case per load, without a width.
    With ``locations`` (``inner_race``, ``outer_race``, ``rolling_element``) every case is
    repeated per location, healthy races included (the healthy contact differs: the inner race's,
    the outer race's, or the element's two), and names carry ``_ir``, ``_or`` or ``_re``; the
    settings set a one-location axis themselves when the scene's location is not the inner race,
    so that those names say where the defect is too.
    """

    loads_kN: tuple[float, ...]
    depths_um: tuple[float, ...]
    widths_um: tuple[float, ...] | None = None
    locations: tuple[str, ...] | None = None

    @classmethod
    def from_mapping(cls, m: Mapping[str, Any]) -> "SweepSettings":
        """Check and type the ``sweep:`` section.

        Parameters
        ----------
        m : mapping
            ``loads_kN`` (numbers > 0), ``depths_um`` (numbers >= 0), optionally ``widths_um``
            (numbers > 0) and ``locations``; each a non-empty list of distinct values.

        Returns
        -------
        SweepSettings
            The values as floats (``-0.0`` as ``0.0``), in the order given.

        Raises
        ------
        ConfigError
            One line naming the entry (``sweep.depths_um[2]``), the value and what is allowed;
            also a value whose exact text (:func:`format_number`) is longer than
            :data:`MAX_VALUE_CHARS`.
        """
        def values(key, lo, lo_open):
            raw = m.get(key)
            if not isinstance(raw, Sequence) or isinstance(raw, str) or not raw:
                raise _err(f"sweep.{key}", raw, "a non-empty list of numbers")
            out = []
            for i, v in enumerate(raw):
                if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                        or (v <= lo if lo_open else v < lo):
                    raise _err(f"sweep.{key}[{i}]", v,
                               f"a finite number {'>' if lo_open else '>='} {lo:g}")
                f = float(v) + 0.0
                text = format_number(f)
                if len(text) > MAX_VALUE_CHARS:
                    raise ConfigError(f"sweep.{key}[{i}]: got {v!r} ({len(text)} digits in a "
                                      f"case name); allowed: a value written with at most "
                                      f"{MAX_VALUE_CHARS} characters (e.g. 0.5, 12.25)")
                if f in out:
                    j = out.index(f)
                    raise ConfigError(f"sweep.{key}[{i}]: {v!r} repeats sweep.{key}[{j}] "
                                      f"({raw[j]!r}); allowed: distinct values")
                out.append(f)
            return tuple(out)

        widths = None if m.get("widths_um") is None else values("widths_um", 0.0, True)
        locations = _locations(m.get("locations"))
        return cls(values("loads_kN", 0.0, True), values("depths_um", 0.0, False), widths,
                   locations)

    @property
    def n_cases(self) -> int:
        """How many cases :meth:`cases` makes, counted without making them."""
        healthy = sum(1 for h in self.depths_um if h == 0)
        per_load = healthy + (len(self.depths_um) - healthy) * len(self.widths_um or (None,))
        return len(self.locations or (None,)) * len(self.loads_kN) * per_load

    def cases(self) -> list[CaseId]:
        """Every case: locations outermost (when set), then loads, depths, widths innermost.

        Returns
        -------
        list of CaseId
            :attr:`n_cases` cases; the healthy race (depth 0) once per load and location,
            without a width.
        """
        out = []
        for loc in (self.locations or (None,)):
            for f in self.loads_kN:
                for h in self.depths_um:
                    if self.widths_um is None:
                        out.append(CaseId(f, h, None, loc))
                    elif h == 0:
                        out.append(CaseId(f, 0.0, None, loc))
                    else:
                        out.extend(CaseId(f, h, w, loc) for w in self.widths_um)
        names = [c.name for c in out]
        if len(set(names)) != len(names):  # cannot happen with exact names; kept as a guard
            dup = sorted({n for n in names if names.count(n) > 1})
            raise ConfigError(f"sweep: values collapse into the same case name(s) {dup}")
        return out


def _locations(raw: Any) -> tuple[str, ...] | None:
    """``sweep.locations``: None, or a non-empty list of distinct defect locations."""
    if raw is None:
        return None
    if not isinstance(raw, Sequence) or isinstance(raw, str) or not raw:
        raise _err("sweep.locations", raw, f"null or a non-empty list of {list(DEFECT_LOCATIONS)}")
    out: list[str] = []
    for i, v in enumerate(raw):
        if v not in DEFECT_LOCATIONS:
            raise _err(f"sweep.locations[{i}]", v, f"one of {list(DEFECT_LOCATIONS)}")
        if v in out:
            raise ConfigError(f"sweep.locations[{i}]: {v!r} repeats sweep.locations"
                              f"[{out.index(v)}]; allowed: distinct values")
        out.append(v)
    return tuple(out)


@dataclass(frozen=True)
class BandSpec:
    """One demodulation band of ``analysis.bands`` (meaning of the fields: the schema)."""

    name: str
    strategy: str
    low: float | None = None
    high: float | None = None
    base: str | None = None
    low_hz: float | None = None
    high_hz: float | None = None
    clamp: bool | None = None

    def to_mapping(self) -> dict[str, Any]:
        """The band as ``analysis.bands`` writes it (the resolver's input).

        Returns
        -------
        dict
            The fields that are set (None fields left out).
        """
        return {k: v for k, v in dataclasses.asdict(self).items() if v is not None}


@dataclass(frozen=True)
class AnalysisSettings:
    """The ``analysis:`` section, typed; every field is required here because its default lives
    in the schema alone (:func:`section_defaults` fills a partial mapping from it).

    What every analysis job and :mod:`bearing_envelope.study.pipeline` function receives; it
    travels to a workflow job as itself, with :meth:`to_json` as its rerun trigger
    (:meth:`Settings.analysis_param`, :func:`job_settings`).
    """

    bands: tuple[BandSpec, ...]
    signal: str
    nlevel: int
    max_level: float | None
    min_bandwidth_hz: float | None
    filter_order: int
    squared_envelope: bool
    harmonics: int
    sidebands: int
    raw_orders_fr: int
    amplitude: str                   # spectral-line estimator: interpolated | peak_bin

    @classmethod
    def from_mapping(cls, m: Mapping[str, Any], *, fs: float, freqs: Mapping[str, float],
                     has_sensor: bool) -> "AnalysisSettings":
        """Build and cross-check (needs the sampling rate and base frequencies of the scene).
        Keys missing from ``m`` take the schema's defaults.

        Parameters
        ----------
        m : mapping
            The ``analysis:`` section (schema-validated).
        fs : float, keyword-only
            The scene's sampling rate, Hz (bands, bandwidths and harmonics below Nyquist).
        freqs : mapping, keyword-only
            The scene's base frequencies, Hz (``fr``, ``bpfi``, ...;
            :func:`~bearing_envelope.physics.locations.scene_event_frequencies`), for the
            ``orders`` bands and the harmonics.
        has_sensor : bool, keyword-only
            Whether the config has a ``sensor:`` section (needed by ``signal: acceleration``).

        Returns
        -------
        AnalysisSettings

        Raises
        ------
        ConfigError
            One line naming the field (a repeated band name, a band that does not resolve
            below Nyquist, ``max_level > nlevel``, ...).
        """
        m = {**section_defaults("analysis"), **dict(m)}
        kw = {f.name: m[f.name] for f in dataclasses.fields(cls) if f.name != "bands"}
        bands = tuple(BandSpec(**dict(b)) for b in m["bands"])
        a = cls(bands=bands, **kw)
        names = [b.name for b in bands]
        for i, n in enumerate(names):
            if n in names[:i]:
                raise ConfigError(f"analysis.bands[{i}].name: {n!r} repeats "
                                  f"analysis.bands[{names.index(n)}]; allowed: unique names")
        if a.signal == "acceleration" and not has_sensor:
            raise ConfigError("analysis.signal: 'acceleration' needs a `sensor:` section (the "
                              "transfer path that makes the acceleration); allowed without it: "
                              "p_max, p_max_defect")
        if a.max_level is not None and a.max_level > a.nlevel:
            raise _err("analysis.max_level", a.max_level,
                       f"null or a level <= analysis.nlevel ({a.nlevel})")
        if a.min_bandwidth_hz is not None and a.min_bandwidth_hz >= fs / 2:
            raise _err("analysis.min_bandwidth_hz", a.min_bandwidth_hz,
                       f"null or a bandwidth below fs/2 = {fs / 2:g} Hz")
        for b in bands:  # the static part of the one band resolver (no signal yet)
            try:
                resolve_band(b.to_mapping(), fs, frequencies=freqs, static=True)
            except ValueError as exc:
                raise ConfigError(f"analysis.bands[{b.name}]: {exc} (scene.operation.fs_hz = "
                                  f"{fs:g}, Nyquist {fs / 2:g} Hz)") from None
        if freqs["bpfi"] * a.harmonics >= fs / 2:
            raise _err("analysis.harmonics", a.harmonics,
                       f"K with K x BPFI ({freqs['bpfi']:g} Hz) below Nyquist ({fs / 2:g} Hz)")
        return a

    def to_mapping(self) -> dict[str, Any]:
        """The section as a plain mapping (what :meth:`from_mapping` reads back).

        Returns
        -------
        dict
            Every field; ``bands`` a list of :meth:`BandSpec.to_mapping`.
        """
        d = dataclasses.asdict(self)
        d["bands"] = [b.to_mapping() for b in self.bands]
        return d

    def to_json(self) -> str:
        """The canonical serialisation (sorted keys) a workflow job receives as a param.

        Returns
        -------
        str
            JSON of :meth:`to_mapping`.
        """
        return json.dumps(self.to_mapping(), sort_keys=True)

    @property
    def needs_kurtogram(self) -> bool:
        """Whether any band is chosen by the kurtogram."""
        return any(b.strategy == "kurtogram" for b in self.bands)


@dataclass(frozen=True)
class DiagnosabilitySettings:
    """The ``diagnosability:`` section: whether the map is in the default target, and its SNRs
    (defaults: the schema)."""

    enabled: bool
    snr_db: tuple[float, ...]
    false_alarm_trials: int
    kurtogram_from: str

    @classmethod
    def from_mapping(cls, m: Mapping[str, Any] | None) -> "DiagnosabilitySettings":
        """Type the ``diagnosability:`` section.

        Parameters
        ----------
        m : mapping or None
            The section (schema-validated); missing keys take the schema's defaults.

        Returns
        -------
        DiagnosabilitySettings
        """
        m = {**section_defaults("diagnosability"), **dict(m or {})}
        return cls(bool(m["enabled"]), tuple(float(x) for x in m["snr_db"]),
                   int(m["false_alarm_trials"]), str(m["kurtogram_from"]))


@dataclass(frozen=True)
class SimulationSetup:
    """What a simulation job needs besides its case: the ``scene:`` section (validated, defaults
    filled) and the resolved :class:`~bearing_envelope.physics.fidelity.Fidelity`.

    Its :meth:`to_json` is the simulate jobs' rerun trigger (a change of either reruns exactly
    the simulations); the job receives its case's :class:`CaseSetup` with it
    (:meth:`Settings.simulation_param`).
    """

    scene_mapping: dict
    fidelity: Fidelity

    def to_json(self) -> str:
        """The canonical serialisation: the simulate jobs' rerun trigger, the text of their
        ``simulation`` param (:meth:`Settings.simulation_param`).

        Returns
        -------
        str
            JSON ``{"scene": scene mapping, "fidelity": every Fidelity field}``, sorted keys.
        """
        return json.dumps({"scene": self.scene_mapping, "fidelity": self.fidelity.to_dict()},
                          sort_keys=True)

    def scene(self, case: "CaseId") -> Scene:
        """The validated scene of one case.

        Parameters
        ----------
        case : CaseId
            The case (load, depth, width, location).

        Returns
        -------
        Scene
            Built now from :attr:`scene_mapping` (:meth:`CaseId.scene`).
        """
        return case.scene(self.scene_mapping)


@dataclass(frozen=True)
class Settings:
    """The whole configuration, validated and typed.

    Attributes
    ----------
    source : str
        Where it came from (a file path, or ``"<mapping>"``).
    config : dict
        The validated mapping with the schema defaults filled (what the workflow passes to jobs).
    sweep : SweepSettings or None
        ``None`` only for a partial config (``simulate --config`` with just ``scene:``).
    fidelity : bearing_envelope.physics.fidelity.Fidelity
    scene_mapping : dict
        The ``scene:`` section (build a case's scene with :meth:`scene`).
    analysis : AnalysisSettings or None
    sensor : bearing_envelope.physics.transfer.TransferModel or None
    diagnosability : DiagnosabilitySettings
    tradeoff : bearing_envelope.study.tradeoff_settings.TradeoffSettings
        The ``tradeoff:`` section, checked and typed once (its defaults where it is missing);
        :func:`bearing_envelope.study.tradeoff.study_from_config` runs it unchecked.
    scenes : dict
        ``CaseId -> Scene`` of every sweep case, built (and validated) once by the loader;
        :meth:`scene` reads them.
    """

    source: str
    config: dict
    sweep: SweepSettings | None
    fidelity: Any
    scene_mapping: dict
    analysis: AnalysisSettings | None
    sensor: Any
    diagnosability: DiagnosabilitySettings
    tradeoff: TradeoffSettings | None = None
    scenes: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def cases(self) -> list[CaseId]:
        return [] if self.sweep is None else self.sweep.cases()

    @property
    def simulation(self) -> SimulationSetup:
        """The scene section and fidelity a simulation job receives."""
        return SimulationSetup(self.scene_mapping, self.fidelity)

    def scene(self, case: CaseId):
        """The validated scene of one case: built once, when the settings were (a sweep case),
        else now.

        Parameters
        ----------
        case : CaseId
            A case of the sweep, or any other case of this scene section.

        Returns
        -------
        Scene
            The loader's scene of a sweep case (the same object each call), else a new one.
        """
        sc = self.scenes.get(case)
        return sc if sc is not None else case.scene(self.scene_mapping)

    # what the workflow hands its jobs (one ``params`` entry each; :func:`job_settings` reads)

    def simulation_param(self, case: CaseId) -> "JobValue":
        """A simulate job's ``simulation`` param: the scene section and fidelity's JSON (its
        rerun trigger) carrying the case's :class:`CaseSetup` (its scene as the loader built it).

        Parameters
        ----------
        case : CaseId
            The job's case.

        Returns
        -------
        JobValue
        """
        return JobValue(self.simulation.to_json(), CaseSetup(case, self.scene(case), self.fidelity))

    def analysis_param(self) -> "JobValue":
        """An analysis job's ``analysis`` param: :meth:`AnalysisSettings.to_json` carrying the
        settings.

        Returns
        -------
        JobValue
        """
        return JobValue(self.analysis.to_json(), self.analysis)

    def sensor_param(self) -> "JobValue":
        """A sensor job's ``sensor`` param: the transfer model's JSON carrying the model
        (``"{}"`` carrying None without a ``sensor:`` section).

        Returns
        -------
        JobValue
        """
        if self.sensor is None:
            return JobValue("{}", None)
        return JobValue(self.sensor.to_json(), self.sensor)

    def tradeoff_param(self) -> "JobValue":
        """The trade-off job's ``tradeoff`` param: its section, the scene and the analysis as
        one canonical JSON, carrying a :class:`TradeoffSetup`.

        Returns
        -------
        JobValue
        """
        text = json.dumps({"tradeoff": self.tradeoff.section, "scene": self.scene_mapping,
                           "analysis": self.analysis.to_mapping()}, sort_keys=True)
        return JobValue(text, TradeoffSetup(self.tradeoff, self.scene_mapping, self.analysis))


# --------------------------------------------------------------------------------------------
# handing typed values to workflow jobs


class JobValue(str):
    """A validated value on its way to a workflow job: its canonical JSON text, carrying the
    value itself (:attr:`value`).

    Snakemake decides that a job must rerun by comparing its ``params`` with the last run's, and
    compares only plain values (a ``str`` by its text; a typed object is not compared at all),
    so a typed value travels as this text. Snakemake pickles a job's params into its script,
    so :attr:`value` arrives as the loader built it: :func:`job_settings` reads it without
    parsing or checking anything again.
    """

    value: Any

    def __new__(cls, text: str, value: Any) -> "JobValue":
        obj = super().__new__(cls, text)
        obj.value = value
        return obj

    def __reduce__(self):
        return (JobValue, (str(self), self.value))


@dataclass(frozen=True)
class CaseSetup:
    """What a simulate job runs: its case, the case's scene (built and validated by the loader)
    and the fidelity."""

    case: CaseId
    scene: Scene
    fidelity: Fidelity


@dataclass(frozen=True)
class TradeoffSetup:
    """What the trade-off job runs: the ``tradeoff:`` section (typed), the ``scene:`` section
    and the analysis settings."""

    settings: TradeoffSettings
    scene_mapping: dict
    analysis: AnalysisSettings


@dataclass(frozen=True)
class JobSettings:
    """The typed values a workflow job received (None: its rule hands none)."""

    simulation: CaseSetup | None = None
    analysis: AnalysisSettings | None = None
    sensor: TransferModel | None = None
    tradeoff: TradeoffSetup | None = None


#: The params :func:`job_settings` reads: name -> the type of its value.
JOB_PARAMS: dict[str, tuple[type, ...]] = {
    "simulation": (CaseSetup,), "analysis": (AnalysisSettings,),
    "sensor": (TransferModel, type(None)), "tradeoff": (TradeoffSetup,)}


def job_settings(snakemake) -> JobSettings:
    """The one loader of a workflow job: the typed values its rule handed it as params
    (:class:`JobValue`: ``Settings.simulation_param`` / ``analysis_param`` / ``sensor_param``
    / ``tradeoff_param``), as the workflow's loader built and validated them; nothing is parsed
    or checked again.

    Parameters
    ----------
    snakemake : object
        The ``snakemake`` object of a script job (its ``params``).

    Returns
    -------
    JobSettings

    Raises
    ------
    TypeError
        A param of :data:`JOB_PARAMS` that is not a :class:`JobValue` of the right type (a
        rule handing plain text).
    """
    params = snakemake.params
    values = {}
    for name, kinds in JOB_PARAMS.items():
        if not hasattr(params, name):
            continue
        p = getattr(params, name)
        if not isinstance(p, JobValue) or not isinstance(p.value, kinds):
            got = type(p.value if isinstance(p, JobValue) else p).__name__
            raise TypeError(f"params.{name}: got a {got}; allowed: a JobValue of "
                            f"{' | '.join(k.__name__ for k in kinds)} "
                            f"(Settings.{name}_param)")
        values[name] = p.value
    return JobSettings(**values)


# --------------------------------------------------------------------------------------------
# reading and validation


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


#: ``analysis:`` keys whose default is a field of
#: :class:`~bearing_envelope.diagnosis.analysis.AnalysisOptions`, the one home of the analysis
#: defaults (the sweep and ``analyze`` share it): config key -> option field.
ANALYSIS_OPTION_FIELDS = {
    "nlevel": "nlevel", "max_level": "max_level", "min_bandwidth_hz": "min_bandwidth",
    "filter_order": "filter_order", "squared_envelope": "squared", "harmonics": "n_harmonics",
    "sidebands": "n_sidebands", "raw_orders_fr": "n_raw_harmonics",
}


def analysis_defaults() -> dict[str, Any]:
    """The ``analysis:`` defaults the schema is filled with, read from
    :class:`~bearing_envelope.diagnosis.analysis.AnalysisOptions` (``amplitude``:
    ``interpolated`` when its ``interpolate`` is true, else ``peak_bin``; ``bands``: its bands,
    :data:`~bearing_envelope.signal.bands.DEFAULT_BANDS` when None).

    Returns
    -------
    dict
        Config key -> default value.
    """
    opt = AnalysisOptions()
    out = {key: getattr(opt, name) for key, name in ANALYSIS_OPTION_FIELDS.items()}
    out["amplitude"] = "interpolated" if opt.interpolate else "peak_bin"
    out["bands"] = [dict(b) for b in (opt.bands or DEFAULT_BANDS)]
    return out


@functools.lru_cache(maxsize=1)
def full_schema() -> dict:
    """The schema file with the defaults whose home is code filled in: ``fidelity`` from
    :data:`~bearing_envelope.physics.fidelity.DEFAULT_PRESET`, the analysis keys from
    :func:`analysis_defaults`. The file itself holds no scene, fidelity, analysis-option,
    limits or tradeoff default (``tests/test_defaults.py``).

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
    for key, value in analysis_defaults().items():
        props["analysis"]["properties"][key]["default"] = value
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


def validate_mapping(config: Mapping[str, Any], *, source: str = "<mapping>",
                     partial: bool = False) -> dict[str, Any]:
    """Finite-number check, schema validation and default filling of a config mapping.

    Returns a deep copy with the schema defaults filled. ``partial=True`` accepts a config without
    the top-level required sections (``simulate --config`` needs only ``scene:``); unknown keys
    are refused either way.
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


def settings_from_mapping(config: Mapping[str, Any], *, source: str = "<mapping>",
                          partial: bool = False) -> Settings:
    """Validate a config mapping and build the typed :class:`Settings` (no contact solve).

    Parameters
    ----------
    config : mapping
        A merged config (:func:`read_configs`); not modified.
    source : str, keyword-only
        Where it came from, the first word of every error message.
    partial : bool, keyword-only
        Accept a config without the top-level required sections (``simulate --config`` needs
        only ``scene:``).

    Returns
    -------
    Settings
        Every section typed and cross-checked, the scene of every sweep case built once.

    Raises
    ------
    ConfigError
        One line: ``{source}: {dotted.field}: got {value}; allowed: ...``.
    """
    cfg = validate_mapping(config, source=source, partial=partial)
    try:
        return _build(cfg, source, partial)
    except ConfigError as exc:
        raise ConfigError(f"{source}: {exc}") from None
    except ValueError as exc:  # the dataclass constructors name their fields
        msg = " ".join(str(exc).split())
        raise ConfigError(f"{source}: {msg}") from None


#: Roller load (kN) at which a partial config's scene (``simulate --config`` with only ``scene:``)
#: is built to read its sampling rate and fault frequencies, which do not depend on the load.
PARTIAL_SCENE_LOAD_KN = 500.0


def _build(cfg: dict, source: str, partial: bool) -> Settings:
    fidelity = fidelity_from(cfg["fidelity"])  # the schema fills its default
    scene_map = cfg.get("scene") or {}
    sweep = SweepSettings.from_mapping(cfg["sweep"]) if "sweep" in cfg else None
    if sweep is not None and sweep.widths_um is not None \
            and ((scene_map.get("defect") or {}).get("width_um")) is not None:
        raise _err("sweep.widths_um", list(sweep.widths_um),
                   "null while scene.defect.width_um is set (give the width in one place)")
    if sweep is not None:
        sweep = _location_axis(sweep, scene_map)
        _check_case_count(sweep, cfg)
        scenes = {}
        for case in sweep.cases():
            where = f"case {case.name}: "
            try:
                scenes[case] = case.scene(scene_map)
            except ValueError as exc:
                raise ConfigError(where + str(exc)) from None
        if sweep.widths_um is not None:
            _check_widths(sweep, scenes, scene_load_distribution, hertz_estimate)
        elif (scene_map.get("defect") or {}).get("width_um") is not None:
            _check_widths(sweep, scenes, scene_load_distribution, hertz_estimate,
                          {"scene.defect.width_um": float(scene_map["defect"]["width_um"])})
        scene0 = next(iter(scenes.values()))
    else:
        scene0 = Scene.from_mapping(scene_map, load_kN=PARTIAL_SCENE_LOAD_KN, depth_um=0.0)
    fs = float(scene0.operation.fs_hz)
    freqs = scene_event_frequencies(scene0)
    sensor = None
    if cfg.get("sensor"):
        sensor = TransferModel.from_mapping(cfg["sensor"], fs=fs)
        for i, tone in enumerate(sensor.tones):
            f = tone.frequency(freqs["fr"])
            if f >= fs / 2:
                key = "frequency_hz" if tone.frequency_hz is not None else "order"
                raise _err(f"sensor.tones[{i}].{key}", getattr(tone, key),
                           f"a tone below fs/2 = {fs / 2:g} Hz (this one is at {f:g} Hz)")
    analysis = None
    if "analysis" in cfg:
        analysis = AnalysisSettings.from_mapping(cfg["analysis"], fs=fs, freqs=freqs,
                                                 has_sensor=sensor is not None)
        if analysis.signal == "acceleration":
            s = cfg["sensor"]
            if "snr_db" not in s and "snr_db" not in (s.get("noise") or {}):
                raise ConfigError("sensor.snr_db: missing; analysis.signal = 'acceleration' needs "
                                  "the noise level of the accelerometer signal (dB; null for a "
                                  "noise-free signal)")
    if analysis is not None and sweep is not None and sweep.locations is not None:
        _check_family_harmonics(analysis, scenes, fs)
    diag = DiagnosabilitySettings.from_mapping(cfg.get("diagnosability"))
    return Settings(source=source, config=cfg, sweep=sweep, fidelity=fidelity,
                    scene_mapping=scene_map, analysis=analysis, sensor=sensor,
                    diagnosability=diag,
                    tradeoff=TradeoffSettings.from_mapping(cfg.get("tradeoff")),
                    scenes=scenes if sweep is not None else {})


def _check_case_count(sweep: SweepSettings, cfg: Mapping[str, Any]) -> None:
    """Refuse a sweep of more than ``limits.max_cases`` cases before any case is built (the
    checks cost about 3 ms per case, Snakemake's DAG more)."""
    limit = (cfg.get("limits") or {}).get("max_cases") or DEFAULT_MAX_CASES
    n = sweep.n_cases
    if n > limit:
        axes = " x ".join(f"{len(v)} {k}" for k, v in (
            ("locations", sweep.locations), ("loads_kN", sweep.loads_kN),
            ("depths_um", sweep.depths_um), ("widths_um", sweep.widths_um)) if v)
        raise ConfigError(f"sweep: {n:,} cases ({axes}); allowed: at most {limit:,} "
                          f"(limits.max_cases; raise it for a larger sweep)")


def _location_axis(sweep: SweepSettings, scene_map: Mapping[str, Any]) -> SweepSettings:
    """The sweep with its location axis: ``sweep.locations`` as given (refused next to a scene
    location other than the inner race: one place for it), else the scene's location when it
    is not the inner race (names then say ``_or`` / ``_re``), else none (names as before)."""
    scene_loc = (scene_map.get("defect") or {}).get("location")
    if scene_loc is None or scene_loc == DEFECT_LOCATIONS[0]:
        return sweep
    if sweep.locations is not None:
        raise _err("sweep.locations", list(sweep.locations),
                   f"null while scene.defect.location is {scene_loc!r} (give the location in one "
                   f"place)")
    return dataclasses.replace(sweep, locations=(str(scene_loc),))


def _check_family_harmonics(analysis: AnalysisSettings, scenes, fs: float) -> None:
    """K harmonics of each swept location's fault line (and its sidebands) below Nyquist."""
    for case, sc in scenes.items():
        family, spacing = LOCATION_FAMILIES[sc.defect.location]
        ev = scene_event_frequencies(sc)
        top = analysis.harmonics * ev[family] + analysis.sidebands * ev[spacing]
        if top >= fs / 2:
            raise _err("analysis.harmonics", analysis.harmonics,
                       f"K with K x {family} + M x {spacing} ({top:g} Hz, case {case.name}) "
                       f"below Nyquist ({fs / 2:g} Hz)")




def _check_widths(sweep: SweepSettings, scenes, load_distribution, hertz_estimate,
                  widths: Mapping[str, float] | None = None) -> None:
    """Each width must be narrower than the contact (2 a, Hertz) of the most loaded roller at the
    smallest load, so that the defect lies inside the contact band it crosses; a ball may also
    bridge a wider pit whose axial extent is at most :data:`BRIDGE_MAX_FRACTION` x 2b.
    ``widths``: field name -> width (um); default the sweep's ``widths_um``."""
    f_min = min(sweep.loads_kN)
    if widths is None:
        widths = {f"sweep.widths_um[{i}]": w for i, w in enumerate(sweep.widths_um)}
    cand = [c for c in scenes if c.load_kN == f_min
            and (c.width_um is not None or scenes[c].defect.active)]
    if not cand:      # no defect in the sweep: the width is never used
        return
    # one case per location (the contact differs: inner, outer race); the narrowest counts
    per_loc = {c.location: c for c in reversed(cand)}
    ellipse = {loc: hertz_estimate(scenes[c], load_distribution(scenes[c]).q_max)
               for loc, c in per_loc.items()}
    loc = min(ellipse, key=lambda k: ellipse[k].a)
    sc = scenes[per_loc[loc]]
    # the narrowest contact sets 2a, the shortest 2b (each may be another location's)
    two_a_um, two_b_um = 2e6 * ellipse[loc].a, 2e6 * min(e.b for e in ellipse.values())
    d = sc.defect
    for field, w in widths.items():
        if d.orientation != "axial" or w < two_a_um:
            continue
        axial_um = w if d.shape == "cylinder" else 1e6 * d.extent_y_m
        bridge_um = BRIDGE_MAX_FRACTION * two_b_um
        if sc.bearing.kind == "ball" and axial_um <= bridge_um:
            continue     # the ball bridges the pit (benchmarks/wide_pit.py)
        also = (f", or for a ball a pit whose axial extent is at most {BRIDGE_MAX_FRACTION:g} x "
                f"2b = {bridge_um:.4g} um" if sc.bearing.kind == "ball" else "")
        raise _err(field, w,
                   f"a width below the contact width 2a = {two_a_um:.4g} um of the most loaded "
                   f"roller at the smallest load ({f_min:g} kN"
                   f"{'' if loc is None else ', ' + loc}){also}")


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
    overrides : mapping, optional

    Returns
    -------
    dict
        The merged, not yet validated mapping.
    """
    merged: dict[str, Any] = {}
    for f in files:
        merged = merge_configs(merged, read_yaml(f))
    return merge_configs(merged, overrides or {})


def load_settings(path: str | os.PathLike | Sequence[str | os.PathLike] | None = None, *,
                  partial: bool = False, overrides: Mapping[str, Any] | None = None) -> Settings:
    """Read, merge, validate and type config files: the one loader of the project.

    Parameters
    ----------
    path : path, sequence of paths or None
        One file, or files merged in order (:func:`merge_configs`); None: ``./config.yaml``.
    partial : bool
        Accept a config without the top-level required sections (``simulate --config`` needs
        only ``scene:``).
    overrides : mapping, optional
        Merged last (Snakemake's ``--config``).

    Returns
    -------
    Settings

    Raises
    ------
    ConfigError
        One line naming the file(s), the field, the value and what is allowed.
    """
    if path is None:
        path = default_config_path()
        if path is None:
            raise ConfigError(f"no config given and no ./{DEFAULT_CONFIG_NAME} in {os.getcwd()}")
    files = [os.fspath(path)] if isinstance(path, (str, os.PathLike)) else \
        [os.fspath(p) for p in path]
    if not files:
        raise ConfigError(f"no config file given and no ./{DEFAULT_CONFIG_NAME} in {os.getcwd()}")
    source = " + ".join(files)
    return settings_from_mapping(read_configs(files, overrides), source=source, partial=partial)


def workflow_settings(files: Sequence[str | os.PathLike] = (),
                      overrides: Mapping[str, Any] | None = None) -> Settings:
    """The workflow's loader (``workflow/rules/common.smk`` calls exactly this): ``./config.yaml``
    and the ``--configfile`` files (:func:`config_files`), each parsed once, merged by
    :func:`merge_configs`, ``--config`` values last; validated and typed once.

    Parameters
    ----------
    files : sequence of path
        ``workflow.overwrite_configfiles`` (the ``--configfile`` files).
    overrides : mapping, optional
        ``workflow.config_settings.config`` (the ``--config`` values).

    Returns
    -------
    Settings
    """
    return load_settings(config_files(files), overrides=overrides)
