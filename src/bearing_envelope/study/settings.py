"""The one loader of the project: typed, frozen :class:`Settings` built once from config files.

Used by the CLI (``bearing-envelope simulate --config``) and by the workflow
(``workflow/rules/common.smk``):

1. :func:`~bearing_envelope.study.config_read.read_configs` reads each file strictly
   (:func:`~bearing_envelope.study.config_read.read_yaml`: no duplicate keys, YAML syntax errors
   with their line and column) and merges them;
2. :func:`settings_from_mapping` validates the mapping against the schema
   (:func:`~bearing_envelope.study.schema.validate_mapping`: finite numbers, one-line message per
   error, defaults filled) and builds the typed sections
   (:mod:`bearing_envelope.study.sections`), whose constructors run the cross-field checks a
   schema cannot express (every case's scene builds, bands and sensor modes below Nyquist,
   ``max_level <= nlevel`` ...).

Every failure is a :class:`~bearing_envelope.study.config_read.ConfigError` (a ``ValueError``)
whose message is one line naming the dotted field (``sweep.depths_um[2]``,
``sensor.modes[0].f_n_hz``) before any job or solve runs. Case identity lives in
:mod:`bearing_envelope.study.case_id`, job transport in :mod:`bearing_envelope.study.job_transport`.
"""

from __future__ import annotations

import dataclasses
import json
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..physics.exposure import BRIDGE_MAX_FRACTION  # the pit-bridging limit (fraction of 2b)
from ..physics.fidelity import fidelity_from
from ..physics.geometry import hertz_estimate
from ..physics.loads import scene_load_distribution
from ..physics.locations import scene_event_frequencies
from ..physics.scene import DEFAULT_SCENE, Scene
from ..physics.transfer import TransferModel
from .case_id import CaseId
from .config_read import (DEFAULT_CONFIG_NAME, ConfigError, config_files, default_config_path,
                          field_error, read_configs)
from .job_transport import CaseSetup, JobValue, TradeoffSetup
from .schema import MAPPING_SOURCE, validate_mapping
from .sections import AnalysisSettings, DiagnosabilitySettings, SimulationSetup, SweepSettings
from .tradeoff_settings import TradeoffSettings

__all__ = ["Settings", "settings_from_mapping", "load_settings", "workflow_settings",
           "DEFAULT_MAX_CASES"]

#: Cases a sweep may have when ``limits.max_cases`` is not given: the pre-run checks cost
#: about 3 CPU ms per case (``check-config`` on 1000 cases: 4.4 CPU s with imports) and
#: Snakemake's dry run about 20 ms per case; a larger sweep says so with ``limits.max_cases``.
DEFAULT_MAX_CASES = 1000


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



def settings_from_mapping(config: Mapping[str, Any], *, source: str = MAPPING_SOURCE,
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
        raise field_error("sweep.widths_um", list(sweep.widths_um),
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
                raise field_error(f"sensor.tones[{i}].{key}", getattr(tone, key),
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
    if scene_loc is None or scene_loc == DEFAULT_SCENE["defect"]["location"]:
        return sweep
    if sweep.locations is not None:
        raise field_error("sweep.locations", list(sweep.locations),
                   f"null while scene.defect.location is {scene_loc!r} (give the location in one "
                   f"place)")
    return dataclasses.replace(sweep, locations=(str(scene_loc),))


def _check_family_harmonics(analysis: AnalysisSettings, scenes, fs: float) -> None:
    """K harmonics of each swept location's fault line (and its sidebands) below Nyquist."""
    for case, sc in scenes.items():
        family, spacing = sc.defect.fault_location.family, sc.defect.fault_location.sideband
        ev = scene_event_frequencies(sc)
        opt = analysis.options
        top = opt.n_harmonics * ev[family] + opt.n_sidebands * ev[spacing]
        if top >= fs / 2:
            raise field_error("analysis.harmonics", opt.n_harmonics,
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
        raise field_error(field, w,
                   f"a width below the contact width 2a = {two_a_um:.4g} um of the most loaded "
                   f"roller at the smallest load ({f_min:g} kN"
                   f"{'' if loc is None else ', ' + loc}){also}")


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
