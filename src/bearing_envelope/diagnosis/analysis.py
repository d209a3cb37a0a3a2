"""The whole diagnosis chain on one signal, as tidy records."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from ..signal.validation import check_fs, check_positive, check_signal
from ..signal.bands import DEFAULT_BANDS, NYQUIST_MARGIN, resolve_band
from ..signal.envelope import envelope_spectrum, peak_value, settling_samples
from .faults import (DEFAULT_SEARCH_PERCENT, FaultFamily, fault_families, fault_verdict,
                     search_lines)
from ..signal.kurtogram import fast_kurtogram, max_kurtogram_level
from ..signal.spectrum import amplitude_spectrum

__all__ = ["COLUMNS", "analyze_signal", "fault_frequency_map"]

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

#: Record-wise false-alarm probability of the verdict (the 1 % design of ``diagnosis``).
DEFAULT_PFA = 0.01


def fault_frequency_map(bpfi=None, fault_frequencies=None) -> dict[str, float]:
    """Named fault frequencies (Hz) from ``bpfi`` and/or ``fault_frequencies``.

    ``fault_frequencies`` may be a mapping ``name -> Hz`` or an object with attributes
    ``bpfo``, ``bpfi``, ``ftf``, ``bsf`` (:class:`bearing_envelope.physics.kinematics.FaultFrequencies`;
    its ``bsf2`` = 2 BSF joins in :func:`~bearing_envelope.diagnosis.faults.fault_families`).
    ``bpfi`` overrides the mapping's ``"bpfi"``.
    """
    out: dict[str, float] = {}
    if fault_frequencies is not None:
        if isinstance(fault_frequencies, Mapping):
            items = dict(fault_frequencies).items()
        else:
            items = [(k, getattr(fault_frequencies, k)) for k in ("bpfo", "bpfi", "ftf", "bsf")
                     if hasattr(fault_frequencies, k)]
        for k, v in items:
            out[str(k)] = check_positive(v, f"fault_frequencies[{k!r}]")
    if bpfi is not None:
        out["bpfi"] = check_positive(bpfi, "bpfi")
    if not out:
        raise ValueError("give bpfi or fault_frequencies (at least one fault frequency in Hz)")
    return out


def analyze_signal(
    x,
    fs: float,
    *,
    fr: float,
    bpfi: float | None = None,
    fault_frequencies=None,
    bands: Sequence[Mapping] | None = None,
    n_harmonics: int = 2,
    n_sidebands: int = 1,
    n_raw_harmonics: int = 1,
    nlevel: int | None = 8,
    max_level: float | None = None,
    min_bandwidth: float | None = None,
    filter_order: int = 4,
    squared: bool = False,
    window="hann",
    tolerance_hz: float | None = None,
    interpolate: bool = False,
    nyquist_margin: float = NYQUIST_MARGIN,
    demean: bool = True,
    level0: str = "analytic",
    search_percent: float = DEFAULT_SEARCH_PERCENT,
    sideband_spacing: Mapping[str, str | None] | None = None,
    pfa: float = DEFAULT_PFA,
    full_output: bool = False,
):
    r"""Run the envelope-analysis chain on one signal and return tidy records.

    Steps: raw amplitude spectrum (0 Hz, k x fr, k x fault frequency); fast kurtogram (only
    when a ``kurtogram`` band is requested); for every band: zero-phase Butterworth band-pass,
    peak of the band-passed signal, Hilbert envelope, envelope spectrum and, for every fault
    family (:mod:`bearing_envelope.diagnosis.faults`), the fundamental found within
    ``+- search_percent`` of its nominal frequency, the harmonics k = 1..K around
    ``k f_found`` and the sidebands ``+- m`` times the family's own spacing (fr for BPFI, FTF
    for BSF and 2 x BSF, none for BPFO and FTF), each with its local floor and detection; then
    a verdict per family over the bands.

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
    bands : sequence of mapping, optional
        Band specifications, plain mappings as a YAML config carries them; default
        :data:`DEFAULT_BANDS` (kurtogram, fs/4-3fs/8, 3-6 x BPFI, 10-13 x BPFI)::

            [{"name": "kurtogram", "strategy": "kurtogram"},
             {"name": "fs4_3fs8", "strategy": "fraction", "low": 0.25, "high": 0.375},
             {"name": "bpfi_3_6", "strategy": "orders", "low": 3, "high": 6, "base": "bpfi"},
             {"name": "fixed", "strategy": "fixed", "low_hz": 5000.0, "high_hz": 9000.0}]

        Keys: ``name`` (label, unique; default the strategy), ``strategy`` (``kurtogram``,
        ``fraction``: fractions of fs, ``orders``: multiples of ``base``, ``fixed``: Hz),
        ``clamp`` (clamp an upper edge at or above Nyquist instead of raising; always on for
        ``kurtogram``), and for ``kurtogram`` the guards ``max_level``/``min_bandwidth``
        (override the arguments of the same name). See :mod:`bearing_envelope.signal.bands`.
    n_harmonics : int, default 2
        Envelope harmonics k = 1..K.
    n_sidebands : int, default 1
        Sidebands m = 1..M on each side of each harmonic (0: none), for families that have a
        spacing.
    n_raw_harmonics : int, default 1
        Orders of fr and of each fault frequency read in the raw spectrum.
    nlevel : int or None, default 8
        Kurtogram depth; reduced to ``floor(log2(n)) - 7`` for short signals. ``None``: the
        default of :func:`fast_kurtogram`.
    max_level, min_bandwidth : float, optional
        Guards of the kurtogram's best cell (see :func:`fast_kurtogram`).
    filter_order : int, default 4
        Butterworth order of the band-pass (applied forward and backward).
    squared : bool, default False
        Use the squared envelope (amplitudes in ``U^2``).
    window : str or tuple, default "hann"
        Window of the raw and envelope spectra.
    tolerance_hz : float, optional
        A fixed search half-width (Hz) for every line instead of ``search_percent`` and the
        narrow windows around the speed-corrected harmonics and sidebands.
    interpolate : bool, default False
        Scalloping-corrected, interpolated peaks (see :func:`amplitude_at`); default: the
        largest bin.
    nyquist_margin : float, default 0.98
        Clamped upper edges are set to ``nyquist_margin * fs/2``.
    demean : bool, default True
        De-mean before the kurtogram (the raw 0 Hz term always uses the original signal).
    level0 : {"analytic", "real"}, default "analytic"
        Kurtosis of the kurtogram's level 0, see :func:`fast_kurtogram` (``"real"``: Antoni's).
    search_percent : float, default 1.0
        Half-width of the search for each fundamental, percent of its nominal frequency (real
        lines sit 0.2-0.7 % off when the nominal shaft speed is not the actual one).
    sideband_spacing : mapping, optional
        ``family -> spacing name`` overriding the defaults
        (:data:`bearing_envelope.diagnosis.faults.SIDEBAND_SPACING`).
    pfa : float, default 0.01
        Record-wise false-alarm probability of the verdict: each of the F families x B bands
        tests runs at ``pfa / (F B)``.
    full_output : bool, default False
        Also return a dict with the kurtogram, the bands with provenance and every spectrum
        (for plots): ``{"kurtogram", "bands": {name: {"band", "provenance", "f",
        "amplitude", "peak"}}, "raw": (f, amplitude), "frequencies", "families", "verdict",
        "fr", "fs"}`` (``verdict``: a :class:`~bearing_envelope.diagnosis.faults.Verdict`).

    Returns
    -------
    pandas.DataFrame
        One row per number, columns :data:`COLUMNS`:

        - ``band``: the band's name (``"raw"`` for the raw spectrum);
          ``band_strategy``: how it was chosen (``raw``, ``kurtogram``, ``fraction``,
          ``orders``, ``fixed``: the names of :mod:`bearing_envelope.io.vocabulary`); ``band_low_hz``, ``band_high_hz``: the band used
          (0 .. fs/2 for raw); ``clamped``: upper edge clamped below Nyquist.
        - ``quantity``: ``"raw_spectrum"`` (amplitude of the sinusoid at the target, one-sided,
          window-corrected, unit ``U``; for ``base == "dc"`` the signal mean),
          ``"envelope_spectrum"`` (amplitude of the envelope's component at the target, unit
          ``U``, or ``U^2`` if ``squared``), ``"bandpass_peak"`` (max |band-passed signal|,
          ``U``), ``"kurtogram_kurtosis"`` (kurtosis of the best cell, dimensionless,
          ``frequency_hz`` = its centre).
        - ``base``: ``"dc"``, ``"fr"`` or a fault-frequency name; ``order``: k;
          ``sideband``: signed m (0: the harmonic itself); ``target_hz``: k f + m fr;
          ``frequency_hz``: where the peak was found; ``amplitude``; ``scaling``: a short
          statement of the unit and scaling of ``amplitude``.
        - spectrum rows: ``floor`` (median amplitude over ``[0.5, 1.5] x frequency`` without
          the family's lines and the shaft harmonics), ``floor_ratio_db`` (``20 log10
          (amplitude / floor)``), ``threshold_db`` (at the per-test false-alarm probability)
          and ``detected``; NaN / NA for the other rows.

    (DataFrame, dict)
        With ``full_output``.

    Examples
    --------
    >>> import numpy as np
    >>> from bearing_envelope.diagnosis import analyze_signal
    >>> fs = 20000.0
    >>> t = np.arange(2**16) / fs
    >>> x = (1 + 0.5 * np.cos(2 * np.pi * 100.0 * t)) * np.cos(2 * np.pi * 6000.0 * t)
    >>> df = analyze_signal(x, fs, fr=25.0, bpfi=100.0, interpolate=True, bands=[
    ...     {"name": "fixed", "strategy": "fixed", "low_hz": 4000, "high_hz": 8000}])
    >>> row = df[(df.quantity == "envelope_spectrum") & (df.order == 1) & (df.sideband == 0)]
    >>> round(float(row.amplitude.iloc[0]), 2)  # 100 Hz is off-bin: interpolated
    0.5
    """
    import pandas as pd

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
    families = fault_families(faults, fr=fr, sidebands=sideband_spacing)
    freqs = {"fr": fr, **{fam.name: fam.frequency_hz for fam in families}}
    bands = list(DEFAULT_BANDS if bands is None else bands)
    names = [str(b.get("name", b.get("strategy"))) if isinstance(b, Mapping) else None
             for b in bands]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise ValueError(f"bands: duplicate band name(s) {sorted(dup)}")
    pfa = float(pfa)
    if not 0.0 < pfa < 1.0:
        raise ValueError(f"pfa must be in (0, 1), got {pfa!r}")
    n_tests = max(1, len(families) * len(bands))
    pfa_test = pfa / n_tests
    unit = "U^2" if squared else "U"
    records: list[dict] = []
    search = dict(search_percent=search_percent, tolerance_hz=tolerance_hz, pfa=pfa_test,
                  interpolate=interpolate, window=window, n=x.size)

    def rec(**kw):
        base = {c: None for c in COLUMNS}
        base.update(kw)
        records.append(base)

    # raw spectrum ---------------------------------------------------------------------------
    f_raw, a_raw = amplitude_spectrum(x, fs, window=window)
    raw_common = dict(band="raw", band_strategy="raw", band_low_hz=0.0, band_high_hz=nyq,
                      clamped=False, quantity="raw_spectrum")
    rec(**raw_common, base="dc", order=0, sideband=0, target_hz=0.0, frequency_hz=0.0,
        amplitude=float(np.mean(x)), scaling="mean of the signal (U)")
    raw_families = (FaultFamily("fr", fr, None, None, "shaft rate"),) + families
    for fam in raw_families:
        for r in search_lines(f_raw, a_raw, fam, fr=fr, n_harmonics=int(n_raw_harmonics),
                              n_sidebands=0, **search):
            rec(**raw_common, base=fam.name, scaling="one-sided sinusoid amplitude, "
                "window-corrected (U)", **r)

    # kurtogram (once, only if needed) -------------------------------------------------------
    kg = None
    if any(isinstance(b, Mapping) and b.get("strategy") == "kurtogram" for b in bands):
        nl = nlevel
        if nl is not None:
            nl = max(1, min(int(nl), max_kurtogram_level(x.size)))
        kg = fast_kurtogram(x, fs, nl, max_level=max_level, min_bandwidth=min_bandwidth,
                            demean=demean, level0=level0)

    def kg_for(ml, mb):
        if ml is None and mb is None:
            return kg
        return kg.restrict(max_level if ml is None else ml,
                           min_bandwidth if mb is None else mb)

    # bands ----------------------------------------------------------------------------------
    details: dict = {"kurtogram": kg, "bands": {}, "raw": (f_raw, a_raw), "frequencies": freqs,
                     "families": families, "fr": fr, "fs": fs, "squared": squared}
    env_scaling = (f"one-sided amplitude of the {'squared ' if squared else ''}envelope "
                   f"component, mean removed, {window} window ({unit})")
    for spec in bands:
        band, prov = resolve_band(spec, fs, kurtogram=kg_for, frequencies=freqs,
                                  margin=nyquist_margin)
        low, high = band
        common = dict(band=prov["name"], band_strategy=prov["strategy"], band_low_hz=low,
                      band_high_hz=high, clamped=bool(prov.get("clamped", False)))
        f_env, a_env, y, _ = envelope_spectrum(x, fs, band, squared=squared, window=window,
                                               order=filter_order, return_signal=True)
        pk = peak_value(y, skip=settling_samples(fs, band, order=filter_order))
        if prov["strategy"] == "kurtogram":
            rec(**common, quantity="kurtogram_kurtosis", base=None, order=None, sideband=None,
                target_hz=prov["fc_hz"], frequency_hz=prov["fc_hz"], amplitude=prov["kurtosis"],
                scaling=f"complex sub-band kurtosis (-), level {prov['level']:.3f}")
        rec(**common, quantity="bandpass_peak", base=None, order=0, sideband=0,
            target_hz=math.nan, frequency_hz=math.nan, amplitude=pk,
            scaling=f"max |band-passed signal| (U), Butterworth order {filter_order} x2, "
                    "edge transients excluded")
        found = {}
        for fam in families:
            rows = search_lines(f_env, a_env, fam, fr=fr, n_harmonics=n_harmonics,
                                n_sidebands=n_sidebands, **search)
            for r in rows:
                rec(**common, quantity="envelope_spectrum", base=fam.name, scaling=env_scaling,
                    **r)
            found[fam.name] = rows
        details["bands"][prov["name"]] = {"band": band, "provenance": prov, "f": f_env,
                                          "amplitude": a_env, "peak": pk, "lines": found}

    table = pd.DataFrame.from_records(records, columns=COLUMNS)
    table["order"] = table["order"].astype("Int64")
    table["sideband"] = table["sideband"].astype("Int64")
    table["detected"] = table["detected"].astype("boolean")
    for c in ("floor", "floor_ratio_db", "threshold_db"):
        table[c] = table[c].astype(float)
    details["verdict"] = fault_verdict(table, families, pfa=pfa, n_tests=n_tests, fr=fr,
                                       search_percent=search_percent)
    if full_output:
        return table, details
    return table
