"""The typed sections of a config: ``sweep:``, ``analysis:`` (and its bands),
``diagnosability:``, and what a simulation job needs (:class:`SimulationSetup`).

Each section's constructor runs the cross-field checks a schema cannot express (bands and
harmonics below Nyquist, ``max_level <= nlevel``, distinct sweep values ...) and raises a
one-line :class:`~bearing_envelope.study.config_read.ConfigError` naming the dotted field.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..diagnosis.options import AnalysisOptions
from ..physics.fidelity import Fidelity
from ..physics.scene import DEFECT_LOCATIONS, Scene
from ..signal.bands import resolve_band
from .case_id import CaseId, format_number
from .config_read import ConfigError, field_error
from .schema import section_defaults

__all__ = ["SweepSettings", "BandSpec", "AnalysisSettings", "DiagnosabilitySettings",
           "SimulationSetup", "MAX_VALUE_CHARS"]


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
                raise field_error(f"sweep.{key}", raw, "a non-empty list of numbers")
            out = []
            for i, v in enumerate(raw):
                if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                        or (v <= lo if lo_open else v < lo):
                    raise field_error(f"sweep.{key}[{i}]", v,
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

        Raises
        ------
        ConfigError
            Two sweep values that give the same case name.
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
        raise field_error("sweep.locations", raw, f"null or a non-empty list of {list(DEFECT_LOCATIONS)}")
    out: list[str] = []
    for i, v in enumerate(raw):
        if v not in DEFECT_LOCATIONS:
            raise field_error(f"sweep.locations[{i}]", v, f"one of {list(DEFECT_LOCATIONS)}")
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
    """The ``analysis:`` section, typed: which simulated signal is analysed, and the analysis
    options (:class:`~bearing_envelope.diagnosis.options.AnalysisOptions`, the one home of
    every option's range and default; the config loads straight into it, ``bands`` included).

    What every analysis job and :mod:`bearing_envelope.study.pipeline` function receives; it
    travels to a workflow job as itself, with :meth:`to_json` as its rerun trigger
    (:meth:`Settings.analysis_param`, :func:`job_settings`).
    """

    signal: str
    options: AnalysisOptions

    @property
    def bands(self) -> tuple[BandSpec, ...]:
        """The demodulation bands of the section (:attr:`options` ``.bands``), typed."""
        return tuple(BandSpec(**dict(b)) for b in self.options.bands)

    @classmethod
    def from_mapping(cls, m: Mapping[str, Any], *, fs: float, freqs: Mapping[str, float],
                     has_sensor: bool) -> "AnalysisSettings":
        """Build and cross-check (needs the sampling rate and base frequencies of the scene).
        Keys missing from ``m`` take the schema's defaults (AnalysisOptions').

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
            Signal, bands, harmonics, sidebands, kurtogram and detection settings, typed and
            checked against the scene's sampling rate and frequencies.

        Raises
        ------
        ConfigError
            One line naming the field (a repeated band name, a band that does not resolve
            below Nyquist, ``max_level > nlevel``, ...).
        """
        m = {**section_defaults("analysis"), **dict(m)}
        try:
            options = AnalysisOptions.from_config(m)
        except ValueError as exc:
            raise ConfigError(str(exc)) from None
        a = cls(signal=m["signal"], options=options)
        bands = a.bands
        names = [b.name for b in bands]
        for i, n in enumerate(names):
            if n in names[:i]:
                raise ConfigError(f"analysis.bands[{i}].name: {n!r} repeats "
                                  f"analysis.bands[{names.index(n)}]; allowed: unique names")
        if a.signal == "acceleration" and not has_sensor:
            raise ConfigError("analysis.signal: 'acceleration' needs a `sensor:` section (the "
                              "transfer path that makes the acceleration); allowed without it: "
                              "p_max, p_max_defect")
        _check_below_nyquist(a, fs, freqs)
        return a

    def to_mapping(self) -> dict[str, Any]:
        """The section as a plain mapping (what :meth:`from_mapping` reads back).

        Returns
        -------
        dict
            ``signal`` and every config key of :attr:`options`; ``bands`` a list of
            :meth:`BandSpec.to_mapping`.
        """
        d = {"signal": self.signal, **self.options.config_values()}
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


def _check_below_nyquist(a: AnalysisSettings, fs: float, freqs: Mapping[str, float]) -> None:
    """The checks of the section against the scene: the kurtogram's narrowest band, every band
    and K x BPFI below Nyquist (each option's own range is AnalysisOptions')."""
    opt = a.options
    if opt.min_bandwidth is not None and opt.min_bandwidth >= fs / 2:
        raise field_error("analysis.min_bandwidth_hz", opt.min_bandwidth,
                          f"null or a bandwidth below fs/2 = {fs / 2:g} Hz")
    for b in a.bands:  # the static part of the one band resolver (no signal yet)
        try:
            resolve_band(b.to_mapping(), fs, frequencies=freqs, static=True)
        except ValueError as exc:
            raise ConfigError(f"analysis.bands[{b.name}]: {exc} (scene.operation.fs_hz = "
                              f"{fs:g}, Nyquist {fs / 2:g} Hz)") from None
    if freqs["bpfi"] * opt.n_harmonics >= fs / 2:
        raise field_error("analysis.harmonics", opt.n_harmonics,
                          f"K with K x BPFI ({freqs['bpfi']:g} Hz) below Nyquist ({fs / 2:g} Hz)")


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
            Whether the map is built, its SNRs (dB), false-alarm trials per SNR and where
            its kurtogram band comes from.
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
