"""The sensor's description: the structure's modes (:class:`Mode`), interfering tones
(:class:`Tone`), the noise (:class:`NoiseSpec`) and the whole transfer path
(:class:`TransferModel`, read from the ``sensor:`` section), with the section's defaults
(:func:`sensor_defaults`, their one home). The model and the signal it makes:
:mod:`bearing_envelope.physics.transfer` (which re-exports every name here) and
``docs/sensor.md``.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field, fields
from typing import Any

import numpy as np

from ..checks import check_number

__all__ = ["EXCITATION_KINDS", "Mode", "NoiseSpec", "Tone", "TransferModel", "sensor_defaults"]


#: Excitation kinds and the case signals they are taken from (first one present wins).
EXCITATION_KINDS: dict[str, tuple[str, ...]] = {
    "pressure": ("p_max_clean", "p_max"),
    "pressure_defect": ("p_max_defect_clean", "p_max_defect"),
    # the force through the contact at fixed approach (roller load minus the force the defect
    # removes): the blocked force of the contact acting on the structure (docs/sensor.md);
    # case files before format 2 have only the roller load
    "force": ("contact_force", "force", "roller_load"),
}


_DISCRETIZATIONS = ("impulse", "bilinear")


# --------------------------------------------------------------------------------------------
# validation helpers
# --------------------------------------------------------------------------------------------
def _check_keys(name: str, mapping: Any, allowed: Sequence[str]) -> Mapping:
    if not isinstance(mapping, Mapping):
        raise ValueError(f"{name} must be a mapping, got {type(mapping).__name__} {mapping!r}")
    unknown = sorted(set(mapping) - set(allowed))
    if unknown:
        raise ValueError(f"{name}: unknown key(s) {unknown}; allowed keys: {sorted(allowed)}")
    return mapping


# --------------------------------------------------------------------------------------------
# model dataclasses
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Mode:
    """One structural mode.

    Attributes
    ----------
    f_n_hz : float
        Undamped natural frequency (Hz), ``0 < f_n_hz < fs/2``.
    zeta : float
        Damping ratio (1), ``0 < zeta < 1``.
    gain : float
        Gain at resonance ``|H(j omega_n)|`` (acceleration per unit excitation, e.g.
        (m/s^2)/N for a force excitation, (m/s^2)/Pa for a pressure excitation), ``> 0``.

    Raises
    ------
    ValueError
        ``f_n_hz`` not > 0 Hz, ``zeta`` outside (0, 1), or ``gain`` not > 0.
    """

    f_n_hz: float
    zeta: float
    gain: float = 1.0

    def __post_init__(self) -> None:
        f = check_number(self.f_n_hz, "f_n_hz")
        z = check_number(self.zeta, "zeta")
        g = check_number(self.gain, "gain")
        if f <= 0.0:
            raise ValueError(f"f_n_hz must be > 0 Hz, got {self.f_n_hz!r}")
        if not 0.0 < z < 1.0:
            raise ValueError(f"zeta must be in the open range (0, 1) (underdamped), got {self.zeta!r}")
        if g <= 0.0:
            raise ValueError(f"gain must be > 0, got {self.gain!r}")
        object.__setattr__(self, "f_n_hz", f)
        object.__setattr__(self, "zeta", z)
        object.__setattr__(self, "gain", g)

    @property
    def f_d_hz(self) -> float:
        """Damped natural frequency ``f_n sqrt(1 - zeta^2)`` (Hz)."""
        return self.f_n_hz * math.sqrt(1.0 - self.zeta**2)

    def check_fs(self, fs: float, where: str = "mode") -> None:
        """Raise ValueError if ``f_n_hz`` is not below the Nyquist frequency ``fs/2``.

        Parameters
        ----------
        fs : float
            Sampling rate (Hz).
        where : str
            The mode's name in the error message.

        Raises
        ------
        ValueError
            The natural frequency at or above fs/2 (the message names ``where``).
        """
        if self.f_n_hz >= 0.5 * fs:
            raise ValueError(
                f"{where}.f_n_hz must be < fs/2 = {0.5 * fs:g} Hz, got {self.f_n_hz:g} Hz"
            )

    @classmethod
    def from_mapping(cls, m: Mapping, where: str = "mode") -> Mode:
        """A mode from its config mapping (``f_n_hz``, ``zeta``, ``gain``), checked.

        Parameters
        ----------
        m : Mapping
            ``f_n_hz``, ``zeta`` and optionally ``gain``.
        where : str
            The mapping's place in the config, for error messages.

        Returns
        -------
        Mode
            The mode.

        Raises
        ------
        ValueError
            ``f_n_hz`` or ``zeta`` missing, or a value out of range (the message names the key
            under ``where``).
        """
        m = _check_keys(where, m, ("f_n_hz", "zeta", "gain"))
        for key in ("f_n_hz", "zeta"):
            if key not in m:
                raise ValueError(f"{where}.{key} is required")
        try:
            return cls(m["f_n_hz"], m["zeta"], m.get("gain", cls.gain))
        except ValueError as exc:
            raise ValueError(f"{where}.{exc}") from None


@dataclass(frozen=True)
class Tone:
    """An interfering sinusoid (shaft harmonic, gear mesh, ...).

    Give the frequency either absolutely (``frequency_hz``) or as an ``order`` of the shaft rate
    (needs ``fr`` at synthesis), and the size either as a peak ``amplitude`` (output units, e.g.
    m/s^2) or as ``level_db`` = 10 log10(tone power / P_defect). ``phase_rad`` ``None`` draws a
    uniform random phase from the seeded generator.

    Raises
    ------
    ValueError
        Not exactly one of ``frequency_hz`` / ``order``, not exactly one of ``amplitude`` /
        ``level_db``, or a value out of range.
    """

    frequency_hz: float | None = None
    order: float | None = None
    amplitude: float | None = None
    level_db: float | None = None
    phase_rad: float | None = None

    def __post_init__(self) -> None:
        if (self.frequency_hz is None) == (self.order is None):
            raise ValueError(
                "tone needs exactly one of frequency_hz (Hz) or order (x shaft rate), got "
                f"frequency_hz={self.frequency_hz!r}, order={self.order!r}"
            )
        if (self.amplitude is None) == (self.level_db is None):
            raise ValueError(
                "tone needs exactly one of amplitude (peak, output units) or level_db "
                f"(dB re P_defect), got amplitude={self.amplitude!r}, level_db={self.level_db!r}"
            )
        for key in ("frequency_hz", "order", "amplitude"):
            v = getattr(self, key)
            if v is not None:
                v = check_number(v, key)
                if (key == "amplitude" and v < 0) or (key != "amplitude" and v <= 0):
                    bound = ">= 0" if key == "amplitude" else "> 0"
                    raise ValueError(f"{key} must be {bound}, got {getattr(self, key)!r}")
                object.__setattr__(self, key, v)
        for key in ("level_db", "phase_rad"):
            v = getattr(self, key)
            if v is not None:
                object.__setattr__(self, key, check_number(v, key))

    def frequency(self, fr: float | None) -> float:
        """Tone frequency in Hz (``order * fr`` for an order tone).

        Parameters
        ----------
        fr : float or None
            Shaft rate (Hz), needed for an order tone.

        Returns
        -------
        float
            The frequency (Hz).

        Raises
        ------
        ValueError
            A tone given by its order without the shaft rate ``fr``.
        """
        if self.frequency_hz is not None:
            return self.frequency_hz
        if fr is None:
            raise ValueError(f"tone with order={self.order:g} needs the shaft rate fr (Hz)")
        return self.order * check_number(fr, "fr")

    @classmethod
    def from_mapping(cls, m: Mapping, where: str = "tone") -> Tone:
        """A tone from its config mapping, checked.

        Parameters
        ----------
        m : Mapping
            ``frequency_hz`` or ``order``, ``amplitude`` or ``level_db``, optionally ``phase_rad``.
        where : str
            The mapping's place in the config, for error messages.

        Returns
        -------
        Tone
            The tone.

        Raises
        ------
        ValueError
            A key missing or a value out of range (the message names ``where``).
        """
        m = _check_keys(where, m, ("frequency_hz", "order", "amplitude", "level_db", "phase_rad"))
        try:
            return cls(**dict(m))
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from None


@dataclass(frozen=True)
class NoiseSpec:
    """Additive measurement noise.

    Attributes
    ----------
    snr_db : float or None
        Target SNR (dB) = 10 log10(P_defect / P_noise); ``None`` adds no noise. Range -80..200.
    exact : bool
        If True (default) the drawn noise is rescaled so that its sample variance gives the
        target SNR exactly; if False the noise has the nominal variance and the achieved SNR
        scatters by about ``4.34 sqrt(2/N)`` dB.

    Raises
    ------
    ValueError
        ``exact`` not a bool, or ``snr_db`` outside [-80, 200] dB.
    """

    snr_db: float | None = None
    exact: bool = True

    def __post_init__(self) -> None:
        if self.snr_db is not None:
            v = check_number(self.snr_db, "snr_db")
            if not -80.0 <= v <= 200.0:
                raise ValueError(f"snr_db must be in [-80, 200] dB, got {self.snr_db!r}")
            object.__setattr__(self, "snr_db", v)
        if not isinstance(self.exact, bool):
            raise ValueError(f"exact must be true or false, got {self.exact!r}")


@dataclass(frozen=True)
class TransferModel:
    """Structural modes, noise and interfering tones: the ``sensor:`` config section.

    Build it from the config with :meth:`from_mapping`. Keys (units):

    ``excitation`` (str, default ``"pressure"``): ``pressure`` (p_max - mean),
    ``pressure_defect`` (p_max_defect - mean) or ``force`` (contact force - mean);
    ``excitation_scale`` (default 1.0; e.g. m^2 to turn Pa into N); ``modes`` (list of
    ``{f_n_hz: Hz, zeta: 1, gain: output per excitation unit at resonance}``, at least one);
    ``discretization`` (``impulse`` | ``bilinear``, default ``impulse``); ``noise``
    (``{snr_db: dB or null, exact: bool}``) or the shortcut ``snr_db``; ``tones`` (list of
    ``{frequency_hz | order, amplitude | level_db, phase_rad}``); ``seed`` (int, default 0).

    Raises
    ------
    ValueError
        No mode or a mode that is not a :class:`Mode`, an unknown ``discretization`` or
        ``excitation``, ``excitation_scale`` not > 0, or ``seed`` not an integer >= 0.
    """

    modes: tuple[Mode, ...]
    noise: NoiseSpec = field(default_factory=NoiseSpec)
    tones: tuple[Tone, ...] = ()
    discretization: str = "impulse"
    excitation: str = "pressure"
    excitation_scale: float = 1.0
    seed: int = 0

    def __post_init__(self) -> None:
        modes = tuple(self.modes)
        if not modes:
            raise ValueError("modes must hold at least one mode, got []")
        for i, m in enumerate(modes):
            if not isinstance(m, Mode):
                raise ValueError(f"modes[{i}] must be a Mode, got {m!r}")
        object.__setattr__(self, "modes", modes)
        object.__setattr__(self, "tones", tuple(self.tones))
        if self.discretization not in _DISCRETIZATIONS:
            raise ValueError(
                f"discretization must be one of {_DISCRETIZATIONS}, got {self.discretization!r}"
            )
        if self.excitation not in EXCITATION_KINDS:
            raise ValueError(
                f"excitation must be one of {tuple(EXCITATION_KINDS)}, got {self.excitation!r}"
            )
        s = check_number(self.excitation_scale, "excitation_scale")
        if s <= 0:
            raise ValueError(f"excitation_scale must be > 0, got {self.excitation_scale!r}")
        object.__setattr__(self, "excitation_scale", s)
        if isinstance(self.seed, bool) or not isinstance(self.seed, (int, np.integer)) or self.seed < 0:
            raise ValueError(f"seed must be an integer >= 0, got {self.seed!r}")

    _KEYS = ("excitation", "excitation_scale", "modes", "discretization", "noise", "snr_db",
             "tones", "seed")

    @classmethod
    def from_mapping(cls, mapping: Mapping, *, fs: float | None = None) -> TransferModel:
        """Build the model from a plain mapping (the ``sensor:`` config section).

        Raises ValueError naming the offending field (``sensor.modes[0].zeta`` ...), its value and
        the allowed range. With ``fs`` (Hz) the natural frequencies are also checked against
        Nyquist.

        Parameters
        ----------
        mapping : Mapping
            The ``sensor:`` section.
        fs : float, optional
            Sampling rate (Hz) to check the modes against.

        Returns
        -------
        TransferModel
            The model.

        Raises
        ------
        ValueError
            No ``modes`` or an empty list of them, ``snr_db`` given twice (top level and under
            ``noise``), ``tones`` not a list, or a mode, tone, noise or other value out of range
            (the message names the key).
        """
        m = _check_keys("sensor", mapping, cls._KEYS)
        raw_modes = m.get("modes")
        if raw_modes is None:
            raise ValueError("sensor.modes is required (a list of {f_n_hz, zeta, gain})")
        if isinstance(raw_modes, Mapping) or not isinstance(raw_modes, Sequence) or not raw_modes:
            raise ValueError(f"sensor.modes must be a non-empty list, got {raw_modes!r}")
        modes = tuple(Mode.from_mapping(x, f"sensor.modes[{i}]") for i, x in enumerate(raw_modes))
        noise_m = m.get("noise", {}) or {}
        noise_m = dict(_check_keys("sensor.noise", noise_m, ("snr_db", "exact")))
        if "snr_db" in m:
            if "snr_db" in noise_m:
                raise ValueError("sensor: give snr_db either at the top level or under noise, not both")
            noise_m["snr_db"] = m["snr_db"]
        try:
            noise = NoiseSpec(**noise_m)
        except ValueError as exc:
            raise ValueError(f"sensor.noise.{exc}") from None
        raw_tones = m.get("tones", []) or []
        if isinstance(raw_tones, Mapping) or not isinstance(raw_tones, Sequence):
            raise ValueError(f"sensor.tones must be a list, got {raw_tones!r}")
        tones = tuple(Tone.from_mapping(x, f"sensor.tones[{i}]") for i, x in enumerate(raw_tones))
        kw: dict[str, Any] = {}
        for key in ("discretization", "excitation", "excitation_scale", "seed"):
            if key in m:
                kw[key] = m[key]
        try:
            model = cls(modes=modes, noise=noise, tones=tones, **kw)
        except ValueError as exc:
            raise ValueError(f"sensor.{exc}") from None
        if fs is not None:
            model.check_fs(fs)
        return model

    def check_fs(self, fs: float) -> None:
        """Raise ValueError if any mode is not below ``fs/2``.

        Parameters
        ----------
        fs : float
            Sampling rate (Hz).

        Raises
        ------
        ValueError
            ``fs`` not > 0 Hz, or a mode at or above fs/2.
        """
        fs = check_number(fs, "fs")
        if fs <= 0:
            raise ValueError(f"fs must be > 0 Hz, got {fs!r}")
        for i, m in enumerate(self.modes):
            m.check_fs(fs, f"sensor.modes[{i}]")

    def with_snr(self, snr_db: float | None) -> TransferModel:
        """A copy with another target SNR (dB; None = no noise).

        Parameters
        ----------
        snr_db : float or None
            The target SNR (dB), or None for no noise.

        Returns
        -------
        TransferModel
            The copy.
        """
        return TransferModel(self.modes, NoiseSpec(snr_db, self.noise.exact), self.tones,
                             self.discretization, self.excitation, self.excitation_scale, self.seed)

    def to_dict(self) -> dict[str, Any]:
        """Plain-dict form (the inverse of :meth:`from_mapping`), for provenance.

        Returns
        -------
        dict
            The ``sensor:`` mapping of this model.
        """
        d = asdict(self)
        d["modes"] = [asdict(x) for x in self.modes]
        d["tones"] = [{k: v for k, v in asdict(t).items() if v is not None} for t in self.tones]
        return d

    def to_json(self) -> str:
        """The canonical serialisation (sorted keys) a workflow job receives.

        Returns
        -------
        str
            JSON text.
        """
        return json.dumps(self.to_dict(), sort_keys=True)

    @classmethod
    def from_json(cls, text: str) -> TransferModel:
        """The model :meth:`to_json` serialised.

        Parameters
        ----------
        text : str
            JSON written by :meth:`to_json`.

        Returns
        -------
        TransferModel
            The model.
        """
        return cls.from_mapping(json.loads(text))


def sensor_defaults() -> dict[str, Any]:
    """The ``sensor:`` keys' defaults, read from :class:`TransferModel` and :class:`NoiseSpec`
    (their one home; the config loader fills the schema's sensor defaults from here).

    Returns
    -------
    dict
        ``excitation``, ``excitation_scale``, ``discretization``, ``seed`` and
        ``noise: {exact}``.
    """
    model = {f.name: f.default for f in fields(TransferModel)}
    noise = {f.name: f.default for f in fields(NoiseSpec)}
    return {**{k: model[k] for k in ("excitation", "excitation_scale", "discretization", "seed")},
            "noise": {"exact": noise["exact"]}}
