"""The analysis options: one type, :class:`AnalysisOptions`, holding every range and default.

Each field has one :class:`OptionSpec` in :data:`OPTION_SPECS` (its kind, its range, whether
None is allowed, and its key in a config's ``analysis:`` section); :meth:`AnalysisOptions.
__post_init__` checks every field against its spec with the one checker, and the rules that
join fields (``max_level <= nlevel``) in the same place. The config schema's ``analysis:``
keys are generated from the specs (:meth:`AnalysisOptions.config_schema`), a config loads
straight into the type (:meth:`AnalysisOptions.from_config`), and a caller that names the
fields its own way (``--harmonics``, ``analysis.harmonics``) passes its names to
:func:`options_with`; nobody else writes a range.

Checks that need a record or a scene (a harmonic below Nyquist, a kurtogram as deep as a short
record allows) are made with the record (:mod:`bearing_envelope.diagnosis.records`) or the
scene (:mod:`bearing_envelope.study.sections`), not here.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..signal.bands import DEFAULT_BANDS, NYQUIST_MARGIN
from ..signal.envelope import DEFAULT_FILTER_ORDER
from ..signal.kurtogram import DEFAULT_LEVEL0, DEFAULT_NLEVEL
from ..signal.spectrum import DEFAULT_WINDOW
from .detection import DEFAULT_PFA
from .faults import DEFAULT_SEARCH_PERCENT
from .routes import ROUTES
from .speed import MEASURED_SPEED_SEARCH_PERCENT

__all__ = ["AnalysisOptions", "OptionSpec", "OPTION_SPECS", "OptionError", "options_with",
           "KURTOGRAM_MIN_ORDERS", "LEVEL0_CHOICES", "PLAIN_WINDOWS"]

#: The kurtogram band must be at least ``KURTOGRAM_MIN_ORDERS x n_harmonics x`` the highest
#: fault frequency wide (unless ``min_bandwidth`` is given): the envelope of a band ``W`` Hz
#: wide holds components up to ``W`` only, so a narrower cell (levels 6-8 at 12 kHz, 23-94 Hz)
#: cannot hold the lines searched; 2 leaves room for the sidebands on both sides of the
#: highest harmonic and for the band-pass skirts.
KURTOGRAM_MIN_ORDERS = 2.0

#: Kurtosis of the kurtogram's level 0: of the analytic signal, or of the real one (Antoni's).
LEVEL0_CHOICES = ("analytic", "real")


@dataclass(frozen=True)
class OptionSpec:
    """What one field of :class:`AnalysisOptions` allows.

    Attributes
    ----------
    kind : str
        ``int``, ``float``, ``bool``, ``choice`` (one of ``choices``), ``bands``, ``routes``,
        ``spacing`` (a mapping or None) or ``window`` (any scipy window; checked by scipy).
    low, high : float or None
        Bounds of a number (None: unbounded on that side).
    low_open, high_open : bool
        Whether the bound itself is refused.
    none : bool
        None allowed (the option switched off, or a default chosen elsewhere).
    config : str or None
        The key of the config's ``analysis:`` section that sets the field (None: none does).
    config_none : bool
        ``null`` allowed in the config (default: as ``none``).
    config_values : tuple of (value, config value) pairs
        A field written differently in the config (``interpolate``: ``amplitude``
        ``interpolated``/``peak_bin``); empty: as is.
    choices : tuple
        The values of a ``choice``.
    """

    kind: str
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    none: bool = False
    config: str | None = None
    config_none: bool | None = None
    config_values: tuple = ()
    choices: tuple = ()

    def allowed(self) -> str:
        """What the field allows, as the error messages say it.

        Returns
        -------
        str
            e.g. ``an integer 1 .. 1000``, ``a number in (0, 50)``, ``one of (...)``.
        """
        tail = " or None" if self.none else ""
        if self.kind == "int":
            return f"an integer {self.low:g} .. {self.high:g}{tail}"
        if self.kind == "float":
            lo = "-inf" if self.low is None else f"{self.low:g}"
            hi = "inf" if self.high is None else f"{self.high:g}"
            return (f"a number in {'(' if self.low_open or self.low is None else '['}{lo}, "
                    f"{hi}{')' if self.high_open or self.high is None else ']'}{tail}")
        if self.kind == "bool":
            return "True or False"
        if self.kind == "choice":
            return f"one of {self.choices}"
        if self.kind == "routes":
            return f"any of {ROUTES}"
        if self.kind == "bands":
            return "a sequence of band mappings or None"
        if self.kind == "spacing":
            return "a mapping family -> spacing name, or None"
        return "a window scipy.signal.get_window knows"

    def check(self, field: str, value):
        """The one check of a field's value: its kind and range.

        Parameters
        ----------
        field : str
            The field's name (for the message).
        value : object
            The value given.

        Returns
        -------
        object
            The value as the type keeps it (an ``int``, a ``float``, a tuple ...).

        Raises
        ------
        OptionError
            The value is not what the spec allows.
        """
        if value is None and self.none:
            return None
        ok, out = _KIND_CHECKS[self.kind](self, value)
        if not ok:
            raise OptionError(field, value, self.allowed())
        return out

    def schema(self) -> dict:
        """The JSON-schema fragment of the field's config key: type and range (no default).

        Returns
        -------
        dict
            ``type`` (with ``"null"`` when the config allows null), ``minimum`` /
            ``exclusiveMinimum`` / ``maximum`` / ``exclusiveMaximum``, or ``enum``.
        """
        if self.config_values:
            return {"type": "string", "enum": [c for _, c in self.config_values]}
        kind = {"int": "integer", "float": "number", "bool": "boolean",
                "choice": "string"}.get(self.kind)
        if kind is None:    # bands: the file's item schema
            return {}
        nullable = self.none if self.config_none is None else self.config_none
        out: dict[str, Any] = {"type": [kind, "null"] if nullable else kind}
        if self.low is not None:
            out["exclusiveMinimum" if self.low_open else "minimum"] = self.low
        if self.high is not None:
            out["exclusiveMaximum" if self.high_open else "maximum"] = self.high
        if self.choices:
            out["enum"] = list(self.choices)
        return out


def _int(spec, v):
    ok = not isinstance(v, bool) and isinstance(v, (int, np.integer)) and spec.low <= v <= spec.high
    return ok, int(v) if ok else v


def _float(spec, v):
    ok = isinstance(v, (int, float, np.floating, np.integer)) and not isinstance(v, bool)
    x = float(v) if ok else math.nan
    inside = not math.isnan(x) and (spec.low is None or (x > spec.low if spec.low_open
                                                         else x >= spec.low)) \
        and (spec.high is None or (x < spec.high if spec.high_open else x <= spec.high))
    return ok and inside and math.isfinite(x), x


def _bands(spec, v):
    if isinstance(v, (str, bytes, Mapping)) or not isinstance(v, Sequence) \
            or not all(isinstance(b, Mapping) for b in v):
        return False, v
    return True, tuple(v)


@functools.lru_cache(maxsize=64)
def _known_window(v) -> bool:
    """Whether scipy.signal.get_window makes a window of ``v`` (a name or a (name, params)
    tuple): checked where the option is set, not deep in the chain."""
    from scipy.signal import get_window  # scipy only when a window is checked

    try:
        get_window(v, 16)
    except (ValueError, TypeError, KeyError):
        return False
    return True


#: Window names accepted without importing scipy.signal (a simulate job builds the options and
#: must not load it, tests/test_lazy.py); every other name or tuple is asked of scipy. Each is
#: checked against scipy's own ``get_window`` (tests/test_records_hostile.py).
PLAIN_WINDOWS = frozenset({"hann", "hamming", "blackman", "boxcar", "bartlett", "triang",
                           "flattop", "blackmanharris", "nuttall", "cosine", "tukey"})


def _window(spec, v):
    if isinstance(v, str) and v in PLAIN_WINDOWS:
        return True, v
    try:
        return (isinstance(v, (str, tuple)) and _known_window(v)), v
    except TypeError:   # an unhashable tuple member
        return False, v


def _routes(spec, v):
    routes = (v,) if isinstance(v, str) else tuple(v) if isinstance(v, Sequence) else None
    ok = routes is not None and all(r in ROUTES for r in routes)
    return ok, routes


_KIND_CHECKS = {
    "int": _int,
    "float": _float,
    "bool": lambda s, v: (isinstance(v, (bool, np.bool_)), bool(v)),
    "choice": lambda s, v: (v in s.choices, v),
    "bands": _bands,
    "routes": _routes,
    "spacing": lambda s, v: (isinstance(v, Mapping), v),
    "window": _window,
}

_INF = None   # an unbounded side

#: Field of :class:`AnalysisOptions` -> what it allows: the one place a range of an analysis
#: option is written (the config schema's ``analysis:`` keys are generated from it). The upper
#: bounds refuse a value no analysis means; a record's own limits (a harmonic below Nyquist,
#: the kurtogram depth its length allows) are checked with the record.
OPTION_SPECS: dict[str, OptionSpec] = {
    "bands": OptionSpec("bands", none=True, config="bands"),
    "n_harmonics": OptionSpec("int", 1, 1000, config="harmonics"),
    "n_sidebands": OptionSpec("int", 0, 100, config="sidebands"),
    "n_raw_harmonics": OptionSpec("int", 1, 1000, config="raw_orders_fr"),
    "nlevel": OptionSpec("int", 1, 30, none=True, config="nlevel", config_none=False),
    "max_level": OptionSpec("float", 0.0, 30.0, none=True, config="max_level"),
    "min_bandwidth": OptionSpec("float", 0.0, _INF, low_open=True, none=True,
                                config="min_bandwidth_hz"),
    "kurtogram_min_orders": OptionSpec("float", 0.0, _INF, low_open=True, none=True),
    "filter_order": OptionSpec("int", 1, 20, config="filter_order"),
    "squared": OptionSpec("bool", config="squared_envelope"),
    "window": OptionSpec("window"),
    "tolerance_hz": OptionSpec("float", 0.0, _INF, low_open=True, none=True),
    "interpolate": OptionSpec("bool", config="amplitude",
                              config_values=((True, "interpolated"), (False, "peak_bin"))),
    "nyquist_margin": OptionSpec("float", 0.0, 1.0, low_open=True),
    "demean": OptionSpec("bool"),
    "level0": OptionSpec("choice", choices=LEVEL0_CHOICES),
    "search_percent": OptionSpec("float", 0.0, 50.0, low_open=True, high_open=True),
    "sideband_spacing": OptionSpec("spacing", none=True),
    "pfa": OptionSpec("float", 0.0, 1.0, low_open=True, high_open=True),
    "measure_speed": OptionSpec("bool"),
    "measured_speed_search_percent": OptionSpec("float", 0.0, 50.0, low_open=True,
                                                high_open=True),
    "routes": OptionSpec("routes"),
}


class OptionError(ValueError):
    """A value :class:`AnalysisOptions` refuses: the field, the value and what is allowed.

    Its message names ``AnalysisOptions.<field>``; :func:`options_with` names the field as the
    caller does (``names``). ``allowed`` may name other fields as ``{field}`` (the rule
    ``max_level <= {nlevel}``), written as the caller names them.

    Parameters
    ----------
    field : str
        The field refused (its name in :class:`AnalysisOptions`); kept as :attr:`field`.
    value : object
        The value given; kept as :attr:`value`.
    allowed : str
        What is allowed, other fields named as ``{field}``; kept as :attr:`allowed`.
    """

    def __init__(self, field: str, value, allowed: str):
        self.field, self.value, self.allowed = field, value, allowed
        shown = allowed.replace("{", "").replace("}", "")
        super().__init__(f"AnalysisOptions.{field} = {value!r}: allowed {shown}")

    def named(self, names: Mapping[str, str]) -> str:
        """The message with the fields named as the caller does.

        Parameters
        ----------
        names : mapping
            Field -> the caller's name (fields it does not name keep theirs).

        Returns
        -------
        str
            ``{name}: got {value!r}; allowed: {what}``.
        """
        what = self.allowed
        for f in OPTION_SPECS:
            what = what.replace("{" + f + "}", names.get(f, f))
        return f"{names.get(self.field, self.field)}: got {self.value!r}; allowed: {what}"


@dataclass(frozen=True)
class AnalysisOptions:
    """Settings of :func:`analyze_signal`, defaults in one place (frozen; change one with
    ``dataclasses.replace(options, n_harmonics=3)``).

    Attributes
    ----------
    bands : tuple of mapping or None, default None
        Band specifications, plain mappings as a YAML config carries them; None:
        :data:`~bearing_envelope.signal.bands.DEFAULT_BANDS` (kurtogram, fs/4-3fs/8, 3-6 x
        BPFI, 10-13 x BPFI). Keys: ``name`` (unique; default the strategy), ``strategy``
        (``kurtogram``, ``fraction``: fractions of fs, ``orders``: multiples of ``base``,
        ``fixed``: Hz), ``clamp``, ``prewhiten`` (the band of the cepstrum-pre-whitened
        signal), and for ``kurtogram`` the guards ``max_level``/``min_bandwidth``. See
        :mod:`bearing_envelope.signal.bands`.
    n_harmonics : int, default 3
        Envelope harmonics k = 1..K.
    n_sidebands : int, default 2
        Sidebands m = 1..M on each side of each harmonic (0: none), for families with a spacing.
    n_raw_harmonics : int, default 3
        Orders of fr and of each fault frequency read in the raw spectrum.

    These defaults are the sweep's and ``bearing-envelope analyze``'s (one home: the config
    schema's ``analysis`` section, the command line and the trade-off study read them here).
    nlevel : int or None, default 8
        Kurtogram depth; reduced to ``floor(log2(n)) - 7`` for short signals; None: the
        default of :func:`~bearing_envelope.signal.kurtogram.fast_kurtogram`.
    max_level, min_bandwidth : float or None
        Guards of the kurtogram's best cell (level; Hz).
    kurtogram_min_orders : float or None, default :data:`KURTOGRAM_MIN_ORDERS`
        Without ``min_bandwidth``, the kurtogram cell must be at least this many times
        ``n_harmonics x`` the highest fault frequency wide; None: no limit (the former
        choice). Only the ``kurtogram`` band strategy is affected (the simulation sweep passes
        its bands as fixed limits).
    filter_order : int, default 4
        Butterworth order of the band-pass (applied forward and backward).
    squared : bool, default False
        Squared envelope (amplitudes in ``U^2``).
    window : str or tuple, default "hann"
        Window of the raw and envelope spectra.
    tolerance_hz : float or None
        A fixed search half-width (Hz) for every line instead of ``search_percent`` and the
        narrow windows around the speed-corrected harmonics and sidebands.
    interpolate : bool, default False
        Scalloping-corrected, interpolated peaks; default the largest bin.
    nyquist_margin : float, default 0.98
        Clamped upper edges are set to ``nyquist_margin * fs/2``.
    demean : bool, default True
        De-mean before the kurtogram (the raw 0 Hz term always uses the original signal).
    level0 : {"analytic", "real"}, default "analytic"
        Kurtosis of the kurtogram's level 0 (``"real"``: Antoni's).
    search_percent : float, default 1.0
        Half-width of the search for each fundamental, percent of its nominal frequency.
    sideband_spacing : mapping or None
        ``family -> spacing name`` overriding
        :data:`~bearing_envelope.diagnosis.faults.SIDEBAND_SPACING`.
    pfa : float, default 0.01
        Record-wise false-alarm probability of the verdict: each of the F families x B bands
        tests runs at ``pfa / (F B)``.
    measure_speed : bool, default False
        Measure the shaft rate from the shaft harmonics of the raw spectrum
        (:func:`~bearing_envelope.diagnosis.speed.estimate_shaft_rate`, around ``fr``), scale
        ``fr`` and every fault frequency to it, and search each fundamental within
        ``measured_speed_search_percent`` instead of ``search_percent``. Off by default (the
        simulation sweep knows its speed exactly).
    measured_speed_search_percent : float, default 0.5
        :data:`~bearing_envelope.diagnosis.speed.MEASURED_SPEED_SEARCH_PERCENT`: what remains
        once the speed is measured is the slip of the rolling elements.
    routes : tuple of str, default ()
        Routes of :mod:`~bearing_envelope.diagnosis.routes` besides the envelope bands
        (``cpw``, ``drs_sk``, ``ees``; ``envelope`` is always one): the verdict is then
        :func:`~bearing_envelope.diagnosis.routes.combine_routes` of them (the ``analyze``
        command runs every route by default; the simulation sweep none).

    Raises
    ------
    OptionError
        A field out of its range (:data:`OPTION_SPECS`), or ``max_level`` deeper than
        ``nlevel``; the message names the field, the value and what is allowed.
    """

    bands: tuple[Mapping, ...] | None = None
    n_harmonics: int = 3
    n_sidebands: int = 2
    n_raw_harmonics: int = 3
    nlevel: int | None = DEFAULT_NLEVEL
    max_level: float | None = None
    min_bandwidth: float | None = None
    kurtogram_min_orders: float | None = KURTOGRAM_MIN_ORDERS
    filter_order: int = DEFAULT_FILTER_ORDER
    squared: bool = False
    window: str | tuple = DEFAULT_WINDOW
    tolerance_hz: float | None = None
    interpolate: bool = False
    nyquist_margin: float = NYQUIST_MARGIN
    demean: bool = True
    level0: str = DEFAULT_LEVEL0
    search_percent: float = DEFAULT_SEARCH_PERCENT
    sideband_spacing: Mapping[str, str | None] | None = None
    pfa: float = DEFAULT_PFA
    measure_speed: bool = False
    measured_speed_search_percent: float = MEASURED_SPEED_SEARCH_PERCENT
    routes: tuple[str, ...] = ()


    def __post_init__(self):
        for name, spec in OPTION_SPECS.items():
            object.__setattr__(self, name, spec.check(name, getattr(self, name)))
        if self.max_level is not None and self.nlevel is not None \
                and self.max_level > self.nlevel:
            raise OptionError("max_level", self.max_level,
                              f"None or a level <= {{nlevel}} ({self.nlevel})")

    @classmethod
    def from_config(cls, section: Mapping[str, Any], *, where: str = "analysis"
                    ) -> "AnalysisOptions":
        """The options a config's ``analysis:`` section sets (its other keys ignored; keys
        missing keep the defaults).

        Parameters
        ----------
        section : mapping
            Config key (:attr:`OptionSpec.config`) -> value, as the config writes it.
        where : str, keyword-only
            The section's dotted name, for the messages (``analysis.harmonics: got 0; ...``).

        Returns
        -------
        AnalysisOptions
            The defaults with the section's values, checked.

        Raises
        ------
        ValueError
            One line naming the config key, the value and what is allowed.
        """
        given, names = {}, {}
        for name, spec in OPTION_SPECS.items():
            if spec.config is None:
                continue
            names[name] = f"{where}.{spec.config}"
            if spec.config in section:
                value = section[spec.config]
                if spec.config_values:
                    back = {c: v for v, c in spec.config_values}
                    if value not in back:
                        raise ValueError(f"{names[name]}: got {value!r}; allowed: one of "
                                         f"{list(back)}")
                    value = back[value]
                given[name] = value
        return options_with(cls(), names=names, **given)

    def config_values(self) -> dict[str, Any]:
        """The options as a config's ``analysis:`` section writes them (what
        :meth:`from_config` reads back).

        Returns
        -------
        dict
            Config key -> value (``bands``: a list of mappings,
            :data:`~bearing_envelope.signal.bands.DEFAULT_BANDS` for None).
        """
        out = {}
        for name, spec in OPTION_SPECS.items():
            if spec.config is None:
                continue
            value = getattr(self, name)
            if spec.config_values:
                value = dict(spec.config_values)[value]
            elif spec.kind == "bands":
                value = [dict(b) for b in (DEFAULT_BANDS if value is None else value)]
            out[spec.config] = value
        return out

    @classmethod
    def config_schema(cls) -> dict[str, dict]:
        """The JSON-schema properties of the config keys that set a field: type, range and
        default, from :data:`OPTION_SPECS` and the field defaults (the config schema file
        writes only their descriptions).

        Returns
        -------
        dict
            Config key -> schema fragment.
        """
        defaults = cls().config_values()
        return {spec.config: {**spec.schema(), "default": defaults[spec.config]}
                for spec in OPTION_SPECS.values() if spec.config is not None}


def options_with(base: AnalysisOptions | None = None, *,
                 names: Mapping[str, str] | None = None, **given) -> AnalysisOptions:
    """``base`` with the ``given`` fields replaced, checked by :class:`AnalysisOptions` (the one
    place its ranges are written); an error names the field as the caller does.

    Parameters
    ----------
    base : AnalysisOptions, optional
        The options to start from (default ``AnalysisOptions()``).
    names : mapping, optional
        Field -> the caller's name for it (the command line's ``--harmonics``); the message is
        then ``{name}: got {value}; allowed: {what}``.
    **given
        Fields of :class:`AnalysisOptions`.

    Returns
    -------
    AnalysisOptions
        A new, checked options object (``base`` is not changed).

    Raises
    ------
    ValueError
        One line naming the field (as ``names`` says), the value and what is allowed.
    """
    try:
        return dataclasses.replace(base or AnalysisOptions(), **given)
    except OptionError as exc:
        if names is None or exc.field not in names:
            raise
        raise ValueError(exc.named(names)) from None
