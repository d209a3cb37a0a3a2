"""The whole diagnosis chain on one signal, as tidy records."""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from ..signal.validation import check_fs, check_positive, check_signal
from ..signal.bands import DEFAULT_BANDS, resolve_band
from ..signal.envelope import envelope_spectrum, peak_value, settling_samples
from .faults import FaultFamily, fault_families, fault_verdict, search_lines
from ..signal.kurtogram import fast_kurtogram, max_kurtogram_level
from ..signal.spectrum import TOLERANCE_MIN_BINS, amplitude_spectrum, prewhiten
from .options import AnalysisOptions
from .routes import apply_routes, combine_routes, run_routes
from .speed import estimate_shaft_rate
from ..lazy import lazy_module

pd = lazy_module("pandas")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = ["COLUMNS", "analyze_signal", "fault_frequency_map", "check_fault_name",
           "RESERVED_LINE_NAMES"]

#: Columns of the table returned by :func:`analyze_signal`, in order.
COLUMNS = [
    "band",
    "band_strategy",
    "band_low_hz",
    "band_high_hz",
    "clamped",
    "quantity",
    "base",
    "order",
    "sideband",
    "target_hz",
    "frequency_hz",
    "amplitude",
    "scaling",
    "floor",
    "floor_ratio_db",
    "threshold_db",
    "detected",
]

#: Line names that are not fault families: the shaft rate and the 0 Hz term of every spectrum.
RESERVED_LINE_NAMES = ("fr", "dc")


def check_fault_name(name: str, where: str) -> str:
    """Refuse a fault-family name the spectra already use (:data:`RESERVED_LINE_NAMES`).

    Parameters
    ----------
    name : str
        The family's name (``bpfo``, ``gear``, ...).
    where : str
        How the caller names the entry, for the message (``--fault fr``).

    Returns
    -------
    str
        ``name``.

    Raises
    ------
    ValueError
        ``name`` is ``fr`` or ``dc``.
    """
    if name in RESERVED_LINE_NAMES:
        raise ValueError(f"{where}: {name!r} is reserved (fr: the shaft rate, given as such; "
                         f"dc: the 0 Hz term); allowed: any other name")
    return name


def fault_frequency_map(bpfi=None, fault_frequencies=None) -> dict[str, float]:
    """Named fault frequencies (Hz) from ``bpfi`` and/or ``fault_frequencies``.

    ``fault_frequencies`` may be a mapping ``name -> Hz`` or an object with attributes
    ``bpfo``, ``bpfi``, ``ftf``, ``bsf``, ``bsf2``
    (:class:`bearing_envelope.physics.kinematics.FaultFrequencies`, every rate of
    :func:`~bearing_envelope.physics.kinematics.bearing_rates`).
    ``bpfi`` overrides the mapping's ``"bpfi"``.

    Parameters
    ----------
    bpfi : float, optional
        Ball-pass frequency of the inner race, Hz (> 0).
    fault_frequencies : mapping or FaultFrequencies, optional
        Named fault frequencies, Hz (each > 0).

    Returns
    -------
    dict of str to float
        Name -> frequency, Hz; neither argument given raises ``ValueError``.

    Raises
    ------
    ValueError
        Neither ``bpfi`` nor ``fault_frequencies`` given.
    """
    out: dict[str, float] = {}
    if fault_frequencies is not None:
        if isinstance(fault_frequencies, Mapping):
            items = dict(fault_frequencies).items()
        else:
            items = [(k, getattr(fault_frequencies, k))
                     for k in ("bpfo", "bpfi", "ftf", "bsf", "bsf2")
                     if hasattr(fault_frequencies, k)]
        for k, v in items:
            check_fault_name(str(k), f"fault_frequencies[{k!r}]")
            out[str(k)] = check_positive(v, f"fault_frequencies[{k!r}]")
    if bpfi is not None:
        out["bpfi"] = check_positive(bpfi, "bpfi")
    if not out:
        raise ValueError("give bpfi or fault_frequencies (at least one fault frequency in Hz)")
    return out


def analyze_signal(x, fs: float, *, fr: float, bpfi: float | None = None,
                   fault_frequencies=None, options: AnalysisOptions | None = None,
                   full_output: bool = False):
    r"""Run the envelope-analysis chain on one signal and return tidy records.

    Steps: raw amplitude spectrum (0 Hz, k x fr, k x fault frequency); fast kurtogram (only
    when a ``kurtogram`` band is requested); for every band: zero-phase Butterworth band-pass,
    peak of the band-passed signal, Hilbert envelope, envelope spectrum and, for every fault
    family (:mod:`bearing_envelope.diagnosis.faults`), the fundamental found within
    ``+- search_percent`` of its nominal frequency, the harmonics k = 1..K around
    ``k f_found`` and the sidebands ``+- m`` times the family's own spacing (fr for BPFI, FTF
    for BSF and 2 x BSF, none for BPFO and FTF), each with its local floor and detection; then
    a verdict over the bands with its confidence (:func:`~bearing_envelope.diagnosis.faults.
    fault_verdict`).

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (unit ``U``: Pa for the pressure histories, m/s^2 for an accelerometer).
    fs : float
        Sampling frequency (Hz).
    fr : float
        Shaft rate (Hz): raw-spectrum orders and sideband spacing.
    bpfi : float, optional
        Inner-race fault frequency (Hz). Shorthand for ``fault_frequencies={"bpfi": bpfi}``.
    fault_frequencies : mapping or FaultFrequencies, optional
        Named fault frequencies (Hz); each is a fault family (a ``bsf`` brings ``bsf2`` =
        2 x BSF), and an ``orders`` band's ``base`` refers to them (or to ``"fr"``). Each must
        lie below fs/2. A line too close to 0 Hz for a floor around it (a short record) gets
        NaN ``floor`` and NA ``detected``.
    options : AnalysisOptions, optional
        Bands, harmonics, kurtogram, filter, search and false-alarm settings; default
        ``AnalysisOptions()``.
    full_output : bool, default False
        Also return a dict with the kurtogram, the bands with provenance and every spectrum
        (for plots): ``{"kurtogram", "bands": {name: {"band", "provenance", "f",
        "amplitude", "peak", "lines"}}, "raw": (f, amplitude), "frequencies", "families",
        "verdict", "fr", "fs", "squared", "options", "speed"}`` (and ``"routes"``:
        ``route -> RouteResult`` with ``options.routes``) (``speed``: the
        :class:`~bearing_envelope.diagnosis.speed.ShaftRate` with ``measure_speed``, else None;
        ``fr`` and ``frequencies`` are then the measured-speed values) (``verdict``: a
        :class:`~bearing_envelope.diagnosis.faults.Verdict`).

    Returns
    -------
    pandas.DataFrame
        One row per number, columns :data:`COLUMNS`:

        - ``band``: the band's name (``"raw"`` for the raw spectrum); ``band_strategy``: how
          it was chosen (``raw``, ``kurtogram``, ``fraction``, ``orders``, ``fixed``);
          ``band_low_hz``, ``band_high_hz``: the band used (0 .. fs/2 for raw); ``clamped``.
        - ``quantity``: ``"raw_spectrum"`` (amplitude of the sinusoid at the target, one-sided,
          window-corrected, ``U``; for ``base == "dc"`` the signal mean),
          ``"envelope_spectrum"`` (``U``, or ``U^2`` if ``squared``), ``"bandpass_peak"`` (max
          |band-passed signal|, ``U``), ``"kurtogram_kurtosis"`` (kurtosis of the best cell,
          dimensionless, ``frequency_hz`` = its centre).
        - ``base``: ``"dc"``, ``"fr"`` or a fault-frequency name; ``order``: k; ``sideband``:
          signed m; ``target_hz``; ``frequency_hz``: where the peak was found; ``amplitude``;
          ``scaling``: the unit and scaling of ``amplitude``.
        - spectrum rows: ``floor`` (median amplitude over the background band without the
          family's lines and the shaft harmonics), ``floor_ratio_db``, ``threshold_db`` (at
          the per-test false-alarm probability) and ``detected``; NaN / NA for the other rows.

    (DataFrame, dict)
        With ``full_output``.

    Raises
    ------
    ValueError
        ``options`` is neither an :class:`AnalysisOptions` nor None; a signal, rate or fault
        frequency out of range (the message names it).

    Examples
    --------
    >>> import numpy as np
    >>> from bearing_envelope.diagnosis import AnalysisOptions, analyze_signal
    >>> fs = 20000.0
    >>> t = np.arange(2**16) / fs
    >>> x = (1 + 0.5 * np.cos(2 * np.pi * 100.0 * t)) * np.cos(2 * np.pi * 6000.0 * t)
    >>> opts = AnalysisOptions(interpolate=True, bands=[
    ...     {"name": "fixed", "strategy": "fixed", "low_hz": 4000, "high_hz": 8000}])
    >>> df = analyze_signal(x, fs, fr=25.0, bpfi=100.0, options=opts)
    >>> row = df[(df.quantity == "envelope_spectrum") & (df.order == 1) & (df.sideband == 0)]
    >>> round(float(row.amplitude.iloc[0]), 2)  # 100 Hz is off-bin: interpolated
    0.5
    """
    opt = AnalysisOptions() if options is None else options
    if not isinstance(opt, AnalysisOptions):
        raise ValueError(f"options = {opt!r}: allowed an AnalysisOptions or None")
    raw = {}  # the raw spectrum, computed once for the speed and the raw rows
    speed, fr, bpfi, fault_frequencies = _measured_speed(x, fs, fr, bpfi, fault_frequencies,
                                                         opt, raw)
    fs, x, fr, families, bands = _check_inputs(x, fs, fr, bpfi, fault_frequencies, opt)
    n_tests = max(1, len(families) * len(bands))
    ctx = {"records": [], "search": dict(
        search_percent=(opt.measured_speed_search_percent
                        if speed is not None and speed.measured else opt.search_percent), tolerance_hz=opt.tolerance_hz, pfa=opt.pfa / n_tests,
        interpolate=opt.interpolate, window=opt.window, n=x.size,
        min_search_bins=(TOLERANCE_MIN_BINS if speed is not None and speed.measured else 0.0))}
    f_raw, a_raw = _raw_rows(ctx, x, fs, fr, families, opt, raw.get("spectrum"))
    kg = _kurtogram(x, fs, families, bands, opt)
    details = {"kurtogram": kg, "bands": {}, "raw": (f_raw, a_raw), "options": opt,
               "frequencies": {"fr": fr, **{f.name: f.frequency_hz for f in families}},
               "families": families, "fr": fr, "fs": fs, "squared": opt.squared,
               "speed": speed}
    _band_rows(ctx, details, x, bands, opt)
    table = _table(ctx["records"])
    details["verdict"] = fault_verdict(table, families, pfa=opt.pfa, n_tests=n_tests, fr=fr,
                                       df_hz=fs / x.size)
    if opt.routes:
        routes = ("envelope",) + tuple(r for r in opt.routes if r != "envelope")
        details["routes"] = run_routes(x, fs, details, routes)
        details["verdict"] = apply_routes(details["verdict"], combine_routes(details["routes"]),
                                          details["routes"])
    return (table, details) if full_output else table


def _measured_speed(x, fs, fr, bpfi, fault_frequencies, opt, raw):
    """``(speed, fr, bpfi, fault_frequencies)``: with ``opt.measure_speed`` the measured
    :class:`~bearing_envelope.diagnosis.speed.ShaftRate` and the shaft rate and fault
    frequencies scaled to it (every kinematic frequency is proportional to the shaft rate);
    else ``None`` and the inputs unchanged. The raw spectrum it reads goes to
    ``raw["spectrum"]``."""
    if not opt.measure_speed:
        return None, fr, bpfi, fault_frequencies
    x = check_signal(x, "x", min_length=16)
    fs = check_fs(fs)
    raw["spectrum"] = amplitude_spectrum(x, fs, window=opt.window)
    speed = estimate_shaft_rate(x, fs, check_positive(fr, "fr"), window=opt.window,
                                spectrum=raw["spectrum"])
    scaled = {k: v * speed.ratio for k, v in fault_frequency_map(bpfi, fault_frequencies).items()}
    return speed, speed.hz, None, scaled


def _check_inputs(x, fs, fr, bpfi, fault_frequencies, opt):
    """Validated ``fs, x, fr``, the fault families and the band list."""
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=16)
    fr = check_positive(fr, "fr")
    faults = fault_frequency_map(bpfi, fault_frequencies)
    nyq = fs / 2.0
    for name, hz in {"fr": fr, **faults}.items():
        what = "fr" if name == "fr" else f"fault frequency {name!r}"
        if hz >= nyq:
            raise ValueError(f"{what} = {hz:g} Hz is at or above the Nyquist frequency "
                             f"{nyq:g} Hz (fs = {fs:g} Hz)")
    families = fault_families(faults, fr=fr, sidebands=opt.sideband_spacing)
    bands = list(DEFAULT_BANDS if opt.bands is None else opt.bands)
    names = [str(b.get("name", b.get("strategy"))) if isinstance(b, Mapping) else None
             for b in bands]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise ValueError(f"bands: duplicate band name(s) {sorted(dup)}")
    return fs, x, fr, families, bands


def _record(ctx, **kw):
    base = {c: None for c in COLUMNS}
    base.update(kw)
    ctx["records"].append(base)


def _raw_rows(ctx, x, fs, fr, families, opt, spectrum=None):
    """The raw spectrum's rows (0 Hz, k x fr, k x each fault frequency); returns it
    (``spectrum``: already computed)."""
    f_raw, a_raw = amplitude_spectrum(x, fs, window=opt.window) if spectrum is None else spectrum
    common = dict(band="raw", band_strategy="raw", band_low_hz=0.0, band_high_hz=fs / 2.0,
                  clamped=False, quantity="raw_spectrum")
    _record(ctx, **common, base="dc", order=0, sideband=0, target_hz=0.0, frequency_hz=0.0,
            amplitude=float(np.mean(x)), scaling="mean of the signal (U)")
    for fam in (FaultFamily("fr", fr, None, None, "shaft rate"),) + tuple(families):
        for r in search_lines(f_raw, a_raw, fam, fr=fr, n_harmonics=opt.n_raw_harmonics,
                              n_sidebands=0, **ctx["search"]):
            _record(ctx, **common, base=fam.name, scaling="one-sided sinusoid amplitude, "
                    "window-corrected (U)", **r)
    return f_raw, a_raw


def _kurtogram(x, fs, families, bands, opt):
    """The fast kurtogram (None when no band asks for it), its cells limited to bands that
    can hold the lines searched (:data:`KURTOGRAM_MIN_ORDERS`) unless ``min_bandwidth``."""
    if not any(isinstance(b, Mapping) and b.get("strategy") == "kurtogram" for b in bands):
        return None
    nl = opt.nlevel
    if nl is not None:
        nl = max(1, min(int(nl), max_kurtogram_level(x.size)))
    min_bw = opt.min_bandwidth
    if min_bw is None and opt.kurtogram_min_orders is not None:
        min_bw = (opt.kurtogram_min_orders * opt.n_harmonics
                  * max(fam.frequency_hz for fam in families))
        min_bw = min(min_bw, fs / 2.0)  # level 0 (the whole band) stays allowed
    return fast_kurtogram(x, fs, nl, max_level=opt.max_level, min_bandwidth=min_bw,
                          demean=opt.demean, level0=opt.level0)


def _band_rows(ctx, details, x, bands, opt):
    """Per band: the band-passed peak, the envelope spectrum and every family's lines."""
    fs, kg = details["fs"], details["kurtogram"]

    def kg_for(ml, mb):
        if ml is None and mb is None:
            return kg
        return kg.restrict(opt.max_level if ml is None else ml,
                           kg.min_bandwidth if mb is None else mb)

    unit = "U^2" if opt.squared else "U"
    env_scaling = (f"one-sided amplitude of the {'squared ' if opt.squared else ''}envelope "
                   f"component, mean removed, {opt.window} window ({unit})")
    x_white = None
    for spec in bands:
        band, prov = resolve_band(spec, fs, kurtogram=kg_for, frequencies=details["frequencies"],
                                  margin=opt.nyquist_margin)
        common = dict(band=prov["name"], band_strategy=prov["strategy"], band_low_hz=band[0],
                      band_high_hz=band[1], clamped=bool(prov.get("clamped", False)))
        if prov.get("prewhiten") and x_white is None:
            x_white = prewhiten(x)
        f_env, a_env, y, _ = envelope_spectrum(x_white if prov.get("prewhiten") else x, fs, band,
                                               squared=opt.squared, window=opt.window,
                                               order=opt.filter_order, return_signal=True)
        pk = peak_value(y, skip=settling_samples(fs, band, order=opt.filter_order))
        if prov["strategy"] == "kurtogram":
            _record(ctx, **common, quantity="kurtogram_kurtosis", base=None, order=None,
                    sideband=None, target_hz=prov["fc_hz"], frequency_hz=prov["fc_hz"],
                    amplitude=prov["kurtosis"],
                    scaling=f"complex sub-band kurtosis (-), level {prov['level']:.3f}")
        _record(ctx, **common, quantity="bandpass_peak", base=None, order=0, sideband=0,
                target_hz=math.nan, frequency_hz=math.nan, amplitude=pk,
                scaling=f"max |band-passed signal| (U), Butterworth order {opt.filter_order} "
                        "x2, edge transients excluded")
        found = {}
        for fam in details["families"]:
            rows = search_lines(f_env, a_env, fam, fr=details["fr"], n_harmonics=opt.n_harmonics,
                                n_sidebands=opt.n_sidebands, **ctx["search"])
            for r in rows:
                _record(ctx, **common, quantity="envelope_spectrum", base=fam.name,
                        scaling=env_scaling, **r)
            found[fam.name] = rows
        details["bands"][prov["name"]] = {"band": band, "provenance": prov, "f": f_env,
                                          "amplitude": a_env, "peak": pk, "lines": found}


def _table(records):
    """The tidy table with its column types."""
    table = pd.DataFrame.from_records(records, columns=COLUMNS)
    table["order"] = table["order"].astype("Int64")
    table["sideband"] = table["sideband"].astype("Int64")
    table["detected"] = table["detected"].astype("boolean")
    for c in ("floor", "floor_ratio_db", "threshold_db"):
        table[c] = table[c].astype(float)
    return table
