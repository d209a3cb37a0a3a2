"""The analysis of one measured recording as a library call: :func:`analyze_record`.

Every decision between "a record and what is known about it" and the analysis chain
(:func:`~bearing_envelope.diagnosis.analysis.analyze_signal`) is taken here, the same for the
command line (``bearing-envelope analyze``) and for a notebook:

- the sampling frequency and the shaft rate: the caller's, else the record's own;
- the fault frequencies and where each comes from (:func:`fault_sources`): the bearing (a
  catalogue designation or alias,
  :func:`~bearing_envelope.physics.catalogue.bearing_geometry`, or its geometry), then ``bpfi`` and
  ``faults`` (overriding the bearing's value of the same name), then a case file's BPFI;
- the kurtogram depth for the record's length (:func:`record_nlevel`);
- the band list with an optional fixed band (:func:`record_bands`);
- the checks that refuse, never clip: a record no spectrum can be read from
  (:func:`check_record`), frequencies at or above Nyquist or below the resolution
  (:func:`check_frequencies`), harmonic orders fs/2 cannot hold (:func:`check_orders`).

The result is a :class:`RecordAnalysis` (``.verdict``, ``.lines``, ``.to_frame()``,
``.to_dict()``). Reading a file is the io layer's (:func:`bearing_envelope.io.records.
read_record`): this module takes an array or a record already read (a mapping with ``"x"``),
or a path together with a ``reader``; :mod:`bearing_envelope.io.analysis` binds the reader.
Many records at once, in parallel: :func:`bearing_envelope.diagnosis.batch.analyze_records`.

Messages name the parameters of this module; a caller with other names (the command line's
options) passes ``names`` (parameter -> its own name) and the messages use those.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any, NamedTuple

import numpy as np

from ..physics.catalogue import bearing_geometry
from ..physics.kinematics import bearing_rates, spin_events
from ..signal.bands import DEFAULT_BANDS
from ..signal.kurtogram import max_kurtogram_level
from .analysis import AnalysisOptions, analyze_signal
from .routes import DEFAULT_ROUTES
from .detection import fault_band_metrics
from .faults import Verdict
from ..lazy import lazy_module

pd = lazy_module("pandas")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = ["MIN_BINS", "RECORD_OPTIONS", "RecordAnalysis", "RecordFailure", "Source",
           "analyze_record", "fault_sources",
           "record_nlevel", "record_bands", "check_fixed_band", "check_record",
           "check_frequencies", "check_orders"]

#: A frequency must lie at least this many bins (fs / n) above 0 Hz: the floor around a line
#: is measured over [0.5, 1.5] x its frequency.
MIN_BINS = 10

#: The options of a measured recording: the shared defaults of :class:`AnalysisOptions` (the
#: sweep's), with the shaft rate measured from the record (a nominal speed is off by a fraction
#: of a percent on a real machine; the sweep knows its speed exactly and keeps it off) and
#: every route of :mod:`~bearing_envelope.diagnosis.routes` in the verdict (the sweep runs
#: none).
RECORD_OPTIONS = AnalysisOptions(measure_speed=True, routes=DEFAULT_ROUTES)


class Source(NamedTuple):
    """A fault frequency and where it comes from."""

    hz: float
    origin: str  # the name that gave it, as the caller calls it (``--bpfi``, ``faults``, ...)
    param: str  # the parameter of :func:`analyze_record` (``bearing``, ``bpfi``, ...)


def _namer(names: Mapping[str, str] | None) -> Callable[[str], str]:
    names = dict(names or {})
    return lambda param: names.get(param, param)


# ------------------------------------------------------------------------------ bearings
def _geometry(bearing, n) -> dict | None:
    """A designation -> its catalogue geometry; a mapping -> itself; None -> None."""
    if bearing is None or isinstance(bearing, Mapping):
        return None if bearing is None else dict(bearing)
    return bearing_geometry(bearing, names={"designation": n("bearing")})


# ------------------------------------------------------------------------------- checks
def check_record(x: np.ndarray, where: str) -> None:
    """Refuse a record no spectrum can be read from: empty, non-finite values, constant.

    Parameters
    ----------
    x : ndarray
        The samples.
    where : str
        What the record is, for the message (``file: PATH``).

    Raises
    ------
    ValueError
        An empty signal, non-finite samples, fewer than 16 samples or a constant signal (the
        message names the record).
    """
    if x.size == 0:
        raise ValueError(f"{where} holds an empty signal")
    bad = int(np.count_nonzero(~np.isfinite(x)))
    if bad:
        raise ValueError(f"{where} holds {bad} non-finite value(s) (NaN or inf) in "
                         f"{x.size} samples; clean or cut the record first")
    if x.size < 16:
        raise ValueError(f"{where} holds {x.size} samples; at least 16 are needed")
    if np.ptp(x) == 0.0:
        raise ValueError(f"{where} holds a constant signal ({x[0]:g}): no spectrum line, "
                         f"no envelope")


def _label(name: str, s: Source, n) -> str:
    """The message prefix of a frequency: its parameter alone for the shaft rate and ``bpfi``,
    else ``origin (name = Hz)``."""
    if s.param in ("shaft_hz", "bpfi"):
        return s.origin
    return f"{s.origin} ({name} = {s.hz:g} Hz)"


def check_frequencies(sources: Mapping[str, Source], fs: float, n_samples: int,
                      names: Mapping[str, str] | None = None) -> None:
    """Each frequency below Nyquist and resolvable (:data:`MIN_BINS` bins of fs/n above 0).

    Parameters
    ----------
    sources : mapping
        Name -> :class:`Source` (the shaft rate under ``"fr"``).
    fs : float
        Sampling frequency, Hz.
    n_samples : int
        Length of the record.
    names : mapping, optional
        Parameter -> the caller's name of it, for the messages.

    Raises
    ------
    ValueError
        A rate at or above Nyquist, or below the record's resolution (the message names it).
    """
    n = _namer(names)
    nyq, df = fs / 2.0, fs / n_samples
    for name, s in sources.items():
        label = _label(name, s, n)
        if s.hz >= nyq:
            raise ValueError(f"{label}: {s.hz:g} Hz is at or above the Nyquist frequency "
                             f"{nyq:g} Hz (fs = {fs:g} Hz)")
        if s.hz < MIN_BINS * df:
            raise ValueError(f"{label}: {s.hz:g} Hz is below the resolution of this record "
                             f"(at least {MIN_BINS} bins of fs/n = {df:.4g} Hz, i.e. "
                             f"{MIN_BINS * df:.4g} Hz; a longer record resolves it)")


def check_orders(options: AnalysisOptions, sources: Mapping[str, Source], fr: float,
                 fs: float, names: Mapping[str, str] | None = None) -> None:
    """``n_harmonics`` and ``n_raw_harmonics`` within what fs/2 holds for the highest fault
    frequency (with the search margin), ``n_sidebands`` above 0 Hz: refused, never clipped.

    Parameters
    ----------
    options : AnalysisOptions
        The orders and the search half-width.
    sources : mapping
        Fault name -> :class:`Source`.
    fr, fs : float
        Shaft rate and sampling frequency, Hz.
    names : mapping, optional
        Parameter -> the caller's name of it, for the messages.

    Raises
    ------
    ValueError
        Harmonics whose top order (with the search margin) passes fs/2, or sidebands whose
        lowest line falls to 0 Hz; the message gives the range allowed for this record.
    """
    n = _namer(names)
    nyq = fs / 2.0
    top_name, top_src = max(sources.items(), key=lambda kv: kv[1].hz)
    top = top_src.hz
    margin = (1.0 + options.search_percent / 100.0) * 1.002  # search window + harmonic tol.
    for param, k, f in (("n_harmonics", options.n_harmonics, top),
                        ("n_raw_harmonics", options.n_raw_harmonics, max(top, fr))):
        kmax = int(nyq / (f * margin))
        if k > kmax:
            raise ValueError(f"{n(param)}: got {k}; allowed: 1 .. {max(kmax, 1)} for this "
                             f"record ({max(kmax, 1)} x "
                             f"{top_name.upper() if f == top else 'fr'} {f:g} Hz with the "
                             f"search margin stays below fs/2 = {nyq:g} Hz)")
    m = options.n_sidebands
    if m and "bpfi" in sources and m * fr >= sources["bpfi"].hz:
        mmax = max(int(sources["bpfi"].hz / fr - 1e-9), 0)
        raise ValueError(f"{n('n_sidebands')}: got {m}; allowed: 0 .. {mmax} (the lower "
                         f"sideband BPFI - M x fr must stay above 0 Hz)")


# ----------------------------------------------------------------------------- decisions
def record_nlevel(nlevel: int | None, n_samples: int, *, follow: bool = False,
                  names: Mapping[str, str] | None = None) -> int:
    """Kurtogram depth for ``n_samples``.

    Parameters
    ----------
    nlevel : int or None
        The depth asked for; None: :class:`AnalysisOptions`' default.
    n_samples : int
        Length of the record.
    follow : bool, default False
        The depth is a default, not a request: reduce it to what the length allows instead of
        refusing it.
    names : mapping, optional
        Parameter -> the caller's name of it, for the message.

    Returns
    -------
    int
        ``nlevel``, or the deepest level the length allows when ``follow`` (at least 1).

    Raises
    ------
    ValueError
        ``nlevel`` deeper than the record allows (128 samples per band at the deepest level).
    """
    nmax = max_kurtogram_level(n_samples)
    if nlevel is None:
        nlevel, follow = AnalysisOptions.nlevel, True
    if follow:
        return max(1, min(int(nlevel), nmax))
    if nlevel > nmax:
        raise ValueError(f"{_namer(names)('nlevel')}: got {nlevel}; allowed: 1 .. "
                         f"{max(nmax, 1)} for {n_samples} samples (at least 128 samples per "
                         f"band at the deepest level)")
    return int(nlevel)


def check_fixed_band(fixed_band, names: Mapping[str, str] | None = None) -> tuple[float, float]:
    """A fixed band's edges, finite and ordered (before any record is read).

    Parameters
    ----------
    fixed_band : (float, float)
        ``(low_hz, high_hz)``.
    names : mapping, optional
        Parameter -> the caller's name of it, for the message.

    Returns
    -------
    (float, float)
        ``0 <= low_hz < high_hz``.

    Raises
    ------
    ValueError
        Not ``0 <= low_hz < high_hz``.
    """
    lo, hi = (float(v) for v in fixed_band)
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi):
        raise ValueError(f"{_namer(names)('fixed_band')}: got {lo!r} {hi!r}; allowed: 0 <= "
                         f"LOW_HZ < HIGH_HZ")
    return lo, hi


def record_bands(bands, fixed_band, fs: float, *, clamp: bool = False,
                 names: Mapping[str, str] | None = None):
    """The band list for a record at ``fs``: ``bands`` (None: the defaults) plus an optional
    fixed band checked against its Nyquist frequency.

    Parameters
    ----------
    bands : sequence of mapping or None
        Band specifications (:class:`AnalysisOptions` ``bands``).
    fixed_band : (float, float) or None
        ``(low_hz, high_hz)`` added as a band named ``fixed``; low 0 gives a low-pass, a high
        edge at or above fs/2 is clamped to 0.98 fs/2 (recorded) when ``clamp`` or exactly
        fs/2.
    fs : float
        Sampling frequency, Hz.
    clamp : bool, default False
        Clamp a high edge above Nyquist instead of refusing it.
    names : mapping, optional
        Parameter -> the caller's name of it, for the message.

    Returns
    -------
    tuple of mapping or None
        None when neither is given (the defaults of :func:`analyze_signal`).

    Raises
    ------
    ValueError
        The fixed band's low edge at or above Nyquist, or its high edge above it without
        ``clamp``.
    """
    if fixed_band is None:
        return bands
    n = _namer(names)
    lo, hi = check_fixed_band(fixed_band, names)
    nyq = fs / 2.0
    if lo >= nyq:
        raise ValueError(f"{n('fixed_band')}: LOW_HZ {lo:g} is at or above the Nyquist "
                         f"frequency {nyq:g} Hz (fs = {fs:g} Hz)")
    if hi > nyq and not clamp:
        raise ValueError(f"{n('fixed_band')}: HIGH_HZ {hi:g} is above the Nyquist frequency "
                         f"{nyq:g} Hz (fs = {fs:g} Hz); lower it or add {n('clamp')}")
    out = list(DEFAULT_BANDS if bands is None else bands)
    out.append({"name": "fixed", "strategy": "fixed", "low_hz": lo, "high_hz": hi,
                "clamp": bool(clamp or hi >= nyq)})
    return tuple(out)


def fault_sources(shaft_hz: float, *, bearing=None, bpfi: float | None = None,
                  faults: Mapping[str, float] | None = None,
                  record_bpfi: float | None = None,
                  names: Mapping[str, str] | None = None) -> dict[str, Source]:
    """The fault frequencies of a record (Hz) and where each comes from.

    Parameters
    ----------
    shaft_hz : float
        Shaft rate, Hz (the bearing's frequencies are proportional to it).
    bearing : str or mapping, optional
        A catalogue designation or alias (:func:`~bearing_envelope.physics.catalogue.
        bearing_geometry`) or a geometry ``{"n_rollers",
        "roller_diameter_mm", "pitch_diameter_mm", "contact_angle_deg"}`` (optionally
        ``"designation"``): its BPFO, BPFI, BSF and FTF.
    bpfi : float, optional
        Inner-race fault frequency, Hz (overrides the bearing's).
    faults : mapping, optional
        Name -> Hz (overrides the bearing's value of the same name; other names are families
        without sidebands).
    record_bpfi : float, optional
        The record's own BPFI (a case file's), used unless ``bpfi``/``faults``/the bearing
        give one.
    names : mapping, optional
        Parameter -> the caller's name of it, for the origins and messages.

    Returns
    -------
    dict
        Name -> :class:`Source`; a ``bsf`` brings ``bsf2`` = 2 x BSF.

    Raises
    ------
    ValueError
        A bearing, fault or BPFI that does not resolve (the message names the option), or no
        fault frequency known at all.
    """
    n = _namer(names)
    out: dict[str, Source] = {}
    geometry = _geometry(bearing, n)
    if geometry is not None:
        label = f"{n('bearing')} {geometry['designation']}" if geometry.get("designation") \
            else (f"bearing geometry ({n('n_rollers')}, {n('roller_diameter_mm')}, "
                  f"{n('pitch_diameter_mm')})")
        try:
            rates = bearing_rates(shaft_hz, geometry["n_rollers"],
                                  geometry["roller_diameter_mm"],
                                  geometry["pitch_diameter_mm"],
                                  geometry.get("contact_angle_deg") or 0.0)
        except ValueError as exc:
            raise ValueError(f"{label}: {exc}") from None
        for name in ("bpfo", "bpfi", "bsf", "ftf"):   # bsf2 joins after the overrides
            out[name] = Source(rates[name], label, "bearing")
    if bpfi is not None:
        out["bpfi"] = Source(float(bpfi), n("bpfi"), "bpfi")
    for name, hz in (faults or {}).items():
        out[str(name)] = Source(float(hz), n("faults"), "faults")
    if "bpfi" not in out and record_bpfi is not None:
        out["bpfi"] = Source(float(record_bpfi), n("record"), "record")
    if not out:
        raise ValueError(f"bpfi: pass {n('bpfi')}, {n('faults')} or {n('bearing')} (a "
                         f"designation or the geometry): no fault frequency is known")
    if "bsf" in out and "bsf2" not in out:
        out["bsf2"] = Source(spin_events(out["bsf"].hz), out["bsf"].origin, out["bsf"].param)
    return out


def _rate(given, from_record, param: str, what: str, n) -> float:
    """fs or the shaft rate: the caller's, else the record's (checked > 0)."""
    v = given if given is not None else from_record
    if v is None:
        if param == "fs":
            raise ValueError(f"fs: the {what} does not give the sampling frequency; pass "
                             f"{n('fs')}")
        raise ValueError(f"{n('shaft_hz')}: the {what} does not give the shaft rate; pass it "
                         f"(Hz)")
    ok = isinstance(v, (int, float, np.number)) and not isinstance(v, bool) \
        and math.isfinite(v) and v > 0
    if not ok:
        kind = "sampling frequency" if param == "fs" else "shaft rate"
        if given is not None:
            raise ValueError(f"{n(param)}: got {v!r}; allowed: a {kind} > 0 (Hz)")
        short = "fs" if param == "fs" else "fr"
        raise ValueError(f"{n(param)}: the {what} gives {short} = {v!r}; pass a {kind} > 0 "
                         f"with {n(param)}")
    return float(v)


# -------------------------------------------------------------------------------- result
@dataclass(frozen=True)
class RecordAnalysis:
    """The analysis of one record (:func:`analyze_record`).

    Attributes
    ----------
    file : str or None
        The file read (None for an array).
    name : str or None
        A short name (figure names; the file's stem by default).
    source : str
        What was read (``npz:x``, ``mat:X105_DE_time``, ``array``, ...).
    n_samples : int
        Length of the record.
    fs : float
        Sampling frequency, Hz.
    shaft_hz : float
        The shaft rate given (nominal), Hz; the measured one is ``details["fr"]``.
    bearing : str or None
        The catalogue designation of the bearing, if one was named.
    sources : dict
        Fault name -> :class:`Source` (Hz and where it came from).
    nlevel : int
        Kurtogram depth used.
    options : AnalysisOptions
        The options the chain ran with (bands and depth resolved for this record).
    lines : pandas.DataFrame
        Every line, one row per number: :func:`analyze_signal`'s table (columns
        :data:`~bearing_envelope.diagnosis.analysis.COLUMNS`).
    details : dict
        :func:`analyze_signal`'s ``full_output`` (kurtogram, bands, spectra, families,
        verdict, speed); :meth:`compact` drops the spectra.
    rows : tuple of dict
        The rows of the verdict table (:meth:`to_frame`), one per fault family.
    signal : ndarray or None
        The samples (None once compact).
    figure : str or None
        The analyst figure written for it, if any.
    defect_size : dict or None
        The diagnosed defect's length from its entry-exit spacing, or why there is none
        (:func:`~bearing_envelope.diagnosis.defect_size.size_document`; None: not asked).
    """

    file: str | None
    name: str | None
    source: str
    n_samples: int
    fs: float
    shaft_hz: float
    bearing: str | None
    sources: dict
    nlevel: int
    options: AnalysisOptions
    lines: pd.DataFrame = field(repr=False)
    details: dict = field(repr=False)
    rows: tuple = field(repr=False, default=())
    signal: np.ndarray | None = field(repr=False, default=None)
    figure: str | None = None
    defect_size: dict | None = None

    ok = True  # a failed record is a RecordFailure

    @property
    def verdict(self) -> Verdict:
        """The record's verdict (:class:`~bearing_envelope.diagnosis.faults.Verdict`)."""
        return self.details["verdict"]

    @property
    def kurtogram(self):
        """The kurtogram (None when no band asked for it)."""
        return self.details["kurtogram"]

    @property
    def bands(self) -> dict:
        """Band name -> ``{"band": (low, high), "provenance": {...}, ...}``."""
        return self.details["bands"]

    @property
    def frequencies(self) -> dict:
        """``fr`` and every fault frequency searched (measured-speed values), Hz."""
        return self.details["frequencies"]

    @property
    def families(self):
        """The fault families searched."""
        return self.details["families"]

    def summary_lines(self) -> list[str]:
        """The verdict in words (:meth:`Verdict.summary_lines`).

        Returns
        -------
        list of str
            The verdict line, then one line per other family worth naming.
        """
        return self.verdict.summary_lines()

    def to_frame(self) -> pd.DataFrame:
        """The verdict table of this record: one row per fault family (:func:`record_rows`).

        Returns
        -------
        pandas.DataFrame
            The rows of :func:`record_rows` (the record, its verdict, the family and its lines).
        """
        return pd.DataFrame.from_records(list(self.rows))

    def to_dict(self, lines: pd.DataFrame | None = None) -> dict:
        """The machine-readable result: frequencies, bands, every line, verdict (JSON-safe).

        Parameters
        ----------
        lines : DataFrame, optional
            The line table to list (default :attr:`lines`; the command line lists it in the
            tidy vocabulary).

        Returns
        -------
        dict
            JSON types only: ``file``, ``source``, ``n_samples``, ``fs_hz``, ``fr_hz``,
            ``bearing``, ``families`` (name, ``frequency_hz``, sideband), ``search_percent``,
            ``kurtogram`` (level, ``fc_hz``, ``bandwidth_hz``, kurtosis), ``bands`` (name,
            ``low_hz``, ``high_hz``, strategy), ``lines`` (one dict per line; NaN as None) and
            ``verdict`` (:meth:`Verdict.to_dict`); ``defect_size`` when estimated.
        """
        table = self.lines if lines is None else lines
        kg = self.kurtogram
        rows = [{k: _clean(v) for k, v in rec.items()}
                for rec in table.drop(columns=["scaling"]).to_dict(orient="records")]
        return {
            "file": self.file, "source": self.source, "n_samples": self.n_samples,
            "fs_hz": self.fs, "fr_hz": self.shaft_hz, "bearing": self.bearing,
            "families": [{"name": f.name, "frequency_hz": f.frequency_hz,
                          "sideband": f.sideband_name, "sideband_hz": f.sideband_hz,
                          "label": f.label} for f in self.families],
            "search_percent": self.options.search_percent,
            "kurtogram": None if kg is None else {
                "level": float(kg.level), "fc_hz": float(kg.fc),
                "bandwidth_hz": float(kg.bandwidth), "kurtosis": float(kg.kurtosis),
                "level0": self.options.level0},
            "bands": [{"name": nm, "low_hz": float(b["band"][0]), "high_hz": float(b["band"][1]),
                       "strategy": b["provenance"]["strategy"],
                       "clamped": bool(b["provenance"].get("clamped", False))}
                      for nm, b in self.bands.items()],
            "lines": rows,
            "verdict": self.verdict.to_dict(),
            **({} if self.defect_size is None else {"defect_size": self.defect_size}),
        }

    def compact(self) -> "RecordAnalysis":
        """The same result without the samples and the spectra (what a batch keeps): the
        verdict, the lines, the bands' limits and provenance, the kurtogram stay.

        Returns
        -------
        RecordAnalysis
            The copy.
        """
        bands = {nm: {k: v for k, v in b.items() if k not in ("f", "amplitude")}
                 for nm, b in self.bands.items()}
        details = {k: v for k, v in self.details.items() if k != "raw"}
        details["bands"] = bands
        return replace(self, details=details, signal=None)


@dataclass(frozen=True)
class RecordFailure:
    """A record that could not be read or analysed, with its one-line reason."""

    file: str | None
    name: str | None
    error: str

    ok = False

    @property
    def rows(self) -> tuple:
        """One verdict-table row: the record and its reason."""
        f = self.file or self.name or ""
        return ({"file": self.file, "record": os.path.splitext(os.path.basename(f))[0],
                 "status": "error", "error": self.error},)

    def summary_lines(self) -> list[str]:
        """No verdict: an empty list.

        Returns
        -------
        list of str
            ``[]``.
        """
        return []

    def to_frame(self) -> pd.DataFrame:
        """The one-row verdict table of the failure.

        Returns
        -------
        pandas.DataFrame
            One row: the file, ``status`` error and the reason.
        """
        return pd.DataFrame.from_records(list(self.rows))

    def to_dict(self, lines=None) -> dict:
        """``{"file", "error"}``.

        Parameters
        ----------
        lines : optional
            Ignored (the signature of :meth:`RecordAnalysis.to_dict`).

        Returns
        -------
        dict
            ``{"file": ..., "error": ...}``.
        """
        return {"file": self.file, "error": self.error}


def _clean(v):
    if isinstance(v, (np.floating, float)):
        return None if not math.isfinite(float(v)) else float(v)
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, np.bool_):
        return bool(v)
    if v is None or v is pd.NA:
        return None
    return v


# ---------------------------------------------------------------------------- the record
def _as_record(signal, reader, file) -> tuple[dict, str | None]:
    """``({"x", "fs", "fr", "bpfi", "source"}, file)`` of an array, a read record or a path."""
    if isinstance(signal, (str, os.PathLike)):
        if reader is None:
            raise ValueError(f"file: {os.fspath(signal)}: a path needs a reader "
                             "(bearing_envelope.io.analysis.analyze_file reads files)")
        return dict(reader(os.fspath(signal))), os.fspath(signal)
    if isinstance(signal, Mapping):
        if "x" not in signal:
            raise ValueError("signal: a read record is a mapping with 'x' (the samples); got "
                             f"keys {sorted(signal)}")
        return dict(signal), file if file is not None else signal.get("file")
    return {"x": signal, "source": "array"}, file


def _samples(x, where: str) -> np.ndarray:
    a = np.asarray(x)
    if a.dtype.kind not in "iuf" or a.ndim != 1:
        raise ValueError(f"{where}: got {a.dtype} samples of shape {a.shape}; allowed: a 1-D "
                         "array of real numbers")
    return a.astype(np.float64, copy=False)


def analyze_record(signal, fs: float | None = None, *, shaft_hz: float | None = None,
                   bearing=None, bpfi: float | None = None,
                   faults: Mapping[str, float] | None = None,
                   options: AnalysisOptions | None = None, fixed_band=None,
                   clamp: bool = False, file: str | None = None, name: str | None = None,
                   reader: Callable[[str], Mapping] | None = None,
                   names: Mapping[str, str] | None = None) -> RecordAnalysis:
    """Analyse one vibration record: every fault family's lines, a verdict.

    Parameters
    ----------
    signal : array_like, mapping or path
        The samples (1-D), a record already read (a mapping with ``"x"`` and optionally
        ``"fs"``, ``"fr"``, ``"bpfi"``, ``"source"``, as
        :func:`bearing_envelope.io.records.read_record` returns), or a path read with
        ``reader``.
    fs : float, optional
        Sampling frequency, Hz; default the record's.
    shaft_hz : float, optional
        Shaft rate, Hz (nominal; measured from the record with ``options.measure_speed``);
        default the record's.
    bearing : str or mapping, optional
        A catalogue designation (``"6205"``) or a geometry (:func:`fault_sources`).
    bpfi : float, optional
        Inner-race fault frequency, Hz.
    faults : mapping, optional
        Further fault frequencies ``name -> Hz`` (``bpfo``, ``bpfi``, ``bsf``, ``ftf`` get
        their sidebands; other names none).
    options : AnalysisOptions, optional
        Default :data:`RECORD_OPTIONS` (the shared defaults, speed measured). A ``nlevel``
        other than the default is a request, refused when the record is too short for it.
    fixed_band : (float, float), optional
        A fixed band added to ``options.bands`` (:func:`record_bands`).
    clamp : bool, default False
        Clamp ``fixed_band``'s upper edge above Nyquist instead of refusing it.
    file, name : str, optional
        The record's file and short name, for the result and the messages.
    reader : callable, optional
        ``reader(path) -> record mapping``, to accept a path.
    names : mapping, optional
        Parameter -> the caller's name of it in messages (``{"n_harmonics": "--harmonics"}``).

    Returns
    -------
    RecordAnalysis
        ``.verdict``, ``.lines``, ``.to_frame()``, ``.to_dict()``.

    Raises
    ------
    ValueError
        One line naming the parameter (or the file) and what is allowed, before the chain.

    Examples
    --------
    A synthetic inner-race fault of a 6205 at 29.95 Hz: impacts at BPFI (162.19 Hz) ringing
    at 3 kHz, modulated once per shaft turn, in noise.

    >>> import numpy as np
    >>> from bearing_envelope.diagnosis.records import analyze_record
    >>> fs, fr, bpfi = 12000.0, 29.95, 162.19
    >>> t = np.arange(2**15) / fs
    >>> rng = np.random.default_rng(0)
    >>> tau = (t % (1 / bpfi))
    >>> x = ((1 + 0.5 * np.cos(2 * np.pi * fr * t)) * np.exp(-tau / 2e-3)
    ...      * np.sin(2 * np.pi * 3000 * tau) + 0.3 * rng.standard_normal(t.size))
    >>> res = analyze_record(x, fs, shaft_hz=fr, bearing="6205")
    >>> res.verdict.diagnosis.family
    'bpfi'
    >>> table = res.to_frame().set_index("family")
    >>> bool(table.loc["bpfi", "detected"]), bool(table.loc["bpfo", "detected"])
    (True, False)
    """
    n = _namer(names)
    opt = RECORD_OPTIONS if options is None else options
    if not isinstance(opt, AnalysisOptions):
        raise ValueError(f"options = {opt!r}: allowed an AnalysisOptions or None")
    rec, file = _as_record(signal, reader, file)
    where = f"file: {file}" if file is not None else "signal"
    x = _samples(rec["x"], where)
    check_record(x, where)
    what = "file" if file is not None else "signal"
    fs = _rate(fs, rec.get("fs"), "fs", what, n)
    fr = _rate(shaft_hz, rec.get("fr"), "shaft_hz", what, n)
    nlevel = record_nlevel(opt.nlevel, x.size, follow=opt.nlevel == AnalysisOptions.nlevel,
                           names=names)
    sources = fault_sources(fr, bearing=bearing, bpfi=bpfi, faults=faults,
                            record_bpfi=rec.get("bpfi"), names=names)
    check_frequencies({"fr": Source(fr, n("shaft_hz"), "shaft_hz"), **sources}, fs, x.size,
                      names)
    check_orders(opt, sources, fr, fs, names)
    if opt.min_bandwidth is not None and opt.min_bandwidth > fs / 2.0:
        raise ValueError(f"{n('min_bandwidth')}: got {opt.min_bandwidth:g} Hz; allowed: at "
                         f"most fs/2 = {fs / 2.0:g} Hz (the kurtogram's widest band)")
    bands_given = opt.bands is not None
    opt = replace(opt, nlevel=nlevel, bands=record_bands(opt.bands, fixed_band, fs,
                                                         clamp=clamp, names=names))
    if opt.bands is not None and not opt.bands:   # no band: no envelope, no verdict
        raise ValueError(f"{n('bands')}: got an empty list; allowed: at least one band (or "
                         f"an empty list with {n('fixed_band')})")
    table, det = _run_chain(x, fs, fr, sources, opt, where,
                            n("bands") if bands_given else "bands")
    geometry = _geometry(bearing, n)
    res = RecordAnalysis(
        file=file, name=name, source=str(rec.get("source", "array")), n_samples=int(x.size),
        fs=fs, shaft_hz=fr, bearing=None if geometry is None else geometry.get("designation"),
        sources=sources, nlevel=nlevel, options=opt, lines=table, details=det, signal=x)
    return replace(res, rows=tuple(record_rows(res)))


def _run_chain(x, fs, fr, sources, opt, where, bands_name):
    """:func:`analyze_signal`; its own refusals name the record (and the bands) too."""
    try:
        return analyze_signal(x, fs, fr=fr, fault_frequencies={k: s.hz for k, s in
                                                                sources.items()},
                              options=opt, full_output=True)
    except (ValueError, KeyError) as exc:
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else str(exc)
        raise ValueError(f"{where}: {bands_name}: {msg}" if "band" in str(msg)
                         else f"{where}: {msg}") from None


# ------------------------------------------------------------------------- verdict table
def record_rows(res: RecordAnalysis) -> list[dict]:
    """Rows of the verdict table for one analysed record: one per fault family.

    Columns: the record (``file, record, status, error, source, n_samples, fs_hz, fr_hz,
    bearing``), the record's verdict (``verdict`` = its summary line, ``record_*`` = every
    scalar of ``Verdict.to_dict()``), the family (``family, nominal_hz, diagnosis`` and every
    scalar of its ``FamilyVerdict``, lists joined by ``;``, and ``margin_db``), its lines in
    the band of its verdict (``h{k}_hz, h{k}_amplitude, h{k}_db, h{k}_detected``) and the
    fault-band metrics there (:func:`bearing_envelope.diagnosis.detection.fault_band_metrics`:
    ``h{k}_band_peak, h{k}_band_peak_hz, h{k}_band_power, total_band_power``).

    Parameters
    ----------
    res : RecordAnalysis
        With its spectra (before :meth:`RecordAnalysis.compact`).

    Returns
    -------
    list of dict
        One row per fault family, the columns above.
    """
    vd = res.verdict.to_dict()
    f = res.file if res.file is not None else (res.name or "")
    head = {"file": res.file, "record": os.path.splitext(os.path.basename(f))[0],
            "status": "ok", "error": None, "source": res.source, "n_samples": res.n_samples,
            "fs_hz": res.fs, "fr_hz": res.shaft_hz, "bearing": res.bearing,
            "verdict": (vd.get("summary") or [None])[0]}
    for k, v in vd.items():
        if k not in ("families", "summary", "statistic") and _flat(v):
            head[f"record_{k}"] = _joined(v)
    fams = {fam.name: fam for fam in res.families}
    rows = []
    for fv in vd["families"]:
        name = fv["family"]
        row = dict(head, family=name, nominal_hz=fams[name].frequency_hz,
                   diagnosis=name == vd.get("diagnosis"))
        for k, v in fv.items():
            if k != "family" and _flat(v):
                row[k] = _joined(v)
        sr, th = fv.get("floor_ratio_db"), fv.get("threshold_db")
        row["margin_db"] = sr - th if sr is not None and th is not None else None
        row.update(_line_columns(res.lines, name, fv.get("band"), res.options.n_harmonics))
        row.update(_band_metrics(res, fams[name], fv.get("band")))
        rows.append(row)
    return rows


def _scalar(v) -> bool:
    return v is None or isinstance(v, (str, bool, int, float))


def _flat(v) -> bool:
    """A scalar, or a list of scalars (a table cell joined by ``;``)."""
    return _scalar(v) or (isinstance(v, (list, tuple)) and all(_scalar(u) for u in v))


def _joined(v):
    return ";".join(map(str, v)) if isinstance(v, (list, tuple)) else v


def _line_columns(table, family: str, band, n_harmonics: int) -> dict:
    out = {}
    sel = table[(table["band"] == band) & (table["base"] == family)
                & (table["sideband"] == 0)
                & table["quantity"].astype(str).str.startswith("envelope")] \
        if band is not None else table.iloc[0:0]
    by_k = {int(r["order"]): r for _, r in sel.iterrows()}
    for k in range(1, n_harmonics + 1):
        r = by_k.get(k)
        out[f"h{k}_hz"] = None if r is None else float(r["frequency_hz"])
        out[f"h{k}_amplitude"] = None if r is None else float(r["amplitude"])
        out[f"h{k}_db"] = None if r is None else float(r["floor_ratio_db"])
        out[f"h{k}_detected"] = None if r is None or r["detected"] is None or \
            str(r["detected"]) == "<NA>" else bool(r["detected"])
    return out


def _band_metrics(res: RecordAnalysis, fam, band) -> dict:
    opt = res.options
    k_max = opt.n_harmonics
    out: dict[str, Any] = {f"h{k}_{c}": None for k in range(1, k_max + 1)
                           for c in ("band_peak", "band_peak_hz", "band_power")}
    out["total_band_power"] = None
    b = res.bands.get(band) if band is not None else None
    if b is None:
        return out
    m = fault_band_metrics(b["f"], b["amplitude"], {fam.name: fam.frequency_hz},
                           harmonics=k_max, sidebands=0,
                           bandwidth=2.0 * opt.search_percent / 100.0,
                           enbw=1.5 if opt.window == "hann" else 1.0)
    for _, r in m.iterrows():
        k = int(r["order"])
        out[f"h{k}_band_peak"] = _num(r["peak_amplitude"])
        out[f"h{k}_band_peak_hz"] = _num(r["peak_hz"])
        out[f"h{k}_band_power"] = _num(r["band_power"])
        out["total_band_power"] = _num(r["total_band_power"])
    return out


def _num(v):
    v = float(v)
    return v if math.isfinite(v) else None
