"""Fault families, the line search that survives a speed error, and the per-record verdict.

A **fault family** is a characteristic bearing frequency (BPFO, BPFI, BSF, 2 x BSF, FTF, or a
user-named line) with its harmonics and its own sideband spacing: the shaft rate for BPFI (the
inner-race defect turns with the shaft through the load zone), the cage rate FTF for BSF (the
ball turns with the cage through the load zone), none for BPFO (the outer-race defect is fixed)
and none for FTF itself.

**Line search.** The nominal frequencies follow from the nominal shaft rate, while the actual
speed differs from it by a fraction of a percent (and slip adds to it for the rolling
elements): real lines sit 0.2-0.7 % away from their nominal value (CWRU 105: BPFI nominal
162.19 Hz, line at 161.70 Hz). So the fundamental of each family is searched within
``f_nom * (1 +- p / 100)`` (``search_percent = p``, default :data:`DEFAULT_SEARCH_PERCENT` = 1 %),
giving ``f_1``. Everything else follows the line that was found, with the speed ratio
``s = f_1 / f_nom``: harmonic k is searched around ``k f_1``, and its sidebands around
``k f_1 +- m s f_sb`` (the sideband spacing ``f_sb`` scales with the speed too), both within
the narrow :func:`~bearing_envelope.signal.spectrum.default_tolerance`
(``max(2 df, 0.002 f)``, at most a quarter of the spacing), which covers the remaining
uncertainty (``k df / 2`` from the bin of ``f_1``). A line reported is the largest bin of its
window: a plain arg-max that anyone can recompute.

**Floor and detection.** Each line is scored by :func:`bearing_envelope.diagnosis.detection.
detection_statistic`: ``floor`` is the median amplitude over ``[0.5, 1.5] x`` the line's
frequency with every harmonic and sideband of the family and every shaft harmonic removed
(the local spectral floor), ``floor_ratio_db = 20 log10(amplitude / floor)``, and the line is
``detected`` when the ratio exceeds ``threshold_db`` (:func:`bearing_envelope.diagnosis.detection.
threshold_db`: the false-alarm design on a Rayleigh-distributed noise spectrum, for the number
of bins searched) and it is a local maximum.

**Verdict.** A fault is a repetitive impulse train, so its envelope holds a harmonic series:
a family is detected in a band when its fundamental *and* its second harmonic (at ``2 f_1``;
only the fundamental when a single harmonic is asked for) are detected there, in a band that
can hold them (at least :data:`HOLD_ORDERS` x its fundamental wide). Testing F families in B
bands makes ``F x B`` tests; each line is tested at ``pfa / (F x B)`` (Bonferroni), so that on
a record without any fault line the probability of any false "detected" in the verdict is at
most ``pfa`` (default 1 %), whatever the dependence between the bands.

**Confidence** (:func:`evidence_level`): what an analyst checks before acting. ``high``: the
family found at one frequency (one shaft speed) in at least :data:`HIGH_MIN_BANDS` distinct
bands (:func:`distinct_bands`: bands sharing more than :data:`DISTINCT_BAND_OVERLAP` of the
narrower one's width demodulate the same resonance and count once), every harmonic searched
present, the modulation its fault shows (fr sidebands for an inner
race turning through the load zone, FTF sidebands for a rolling element carried by the cage,
none needed for a fixed outer-race defect), and a margin of :data:`HIGH_MIN_MARGIN_DB` over the
threshold; ``medium``: that many bands without the rest, or :data:`MEDIUM_MIN_BANDS` bands with
a margin of :data:`MEDIUM_MIN_MARGIN_DB`; ``low``: any other detection. Real envelope spectra
are crowded (shaft harmonics, the fault's own sidebands, kinematic coincidences: BPFO = Z x FTF,
3 BPFO = 2 BPFI on the 6205), so a weaker family is **explained** by a stronger one when its
fundamental falls on ``k f +- m`` spacings of it or on a shaft harmonic, when it is the cage
period of its train (FTF = BPFO / Z), or when one of its harmonics is a line of it (then it
counts only with its own evidence, without that harmonic). The **diagnosis** is the strongest
family; an unexplained family with ``medium`` evidence or better is a **second finding**; one
with evidence as strong as the diagnosis's makes the verdict :data:`CANNOT_TELL` (as strong:
the same level found in as many agreeing bands, :data:`BAND_TIE_BREAK`; a family sharing a
harmonic with the diagnosis, on its own lines without the shared one: the same level, or a
fundamental within :data:`RIVAL_MARGIN_DB` of the diagnosis's margin), and so do cage-rate
lines alone (a cage fault or a rolling element's modulation). The levels' measured
meaning on real records: ``benchmarks/cwru_dev.py`` and ``docs/benchmarks.md`` (issue 24).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from ..physics.kinematics import spin_events
from ..signal.spectrum import DEFAULT_WINDOW, amplitude_at, default_tolerance
from .detection import BACKGROUND_BAND, DEFAULT_PFA, detection_statistic

__all__ = [
    "CANNOT_TELL",
    "CONFIDENCE_LEVELS",
    "DEFAULT_SEARCH_PERCENT",
    "FAMILY_LABELS",
    "SIDEBAND_SPACING",
    "FaultFamily",
    "FamilyVerdict",
    "Verdict",
    "distinct_bands",
    "evidence_level",
    "fault_families",
    "fault_verdict",
    "search_lines",
]

#: Default half-width (percent of the nominal frequency) of the search for a fundamental.
DEFAULT_SEARCH_PERCENT = 1.0

#: What a detected family means.
FAMILY_LABELS = {
    "bpfo": "outer race fault",
    "bpfi": "inner race fault",
    "bsf": "rolling element fault",
    "bsf2": "rolling element fault",
    "ftf": "cage fault",
}

#: Sideband spacing of each known family: the name of another frequency, or None.
SIDEBAND_SPACING = {"bpfi": "fr", "bsf": "ftf", "bsf2": "ftf", "bpfo": None, "ftf": None}

_DISPLAY = {"bpfo": "BPFO", "bpfi": "BPFI", "bsf": "BSF", "bsf2": "2xBSF", "ftf": "FTF",
            "fr": "fr"}


def display_name(name: str) -> str:
    """``"bpfi" -> "BPFI"``, ``"bsf2" -> "2xBSF"``; other names unchanged."""
    return _DISPLAY.get(name, name)


@dataclass(frozen=True)
class FaultFamily:
    """One fault family.

    Attributes
    ----------
    name : str
        Key of the frequency (``bpfo``, ``bpfi``, ``bsf``, ``bsf2``, ``ftf`` or a user name).
    frequency_hz : float
        Nominal fundamental (Hz).
    sideband_name : str or None
        Name of the sideband spacing (``"fr"``, ``"ftf"``) or None for no sidebands.
    sideband_hz : float or None
        The nominal spacing (Hz).
    label : str
        What a detection means (``"inner race fault"``; a user family: ``"<name> line"``).
    """

    name: str
    frequency_hz: float
    sideband_name: str | None
    sideband_hz: float | None
    label: str


def fault_families(frequencies: Mapping[str, float], *, fr: float,
                   sidebands: Mapping[str, str | None] | None = None) -> tuple[FaultFamily, ...]:
    """Fault families of the named frequencies (Hz), with their sideband spacing.

    Parameters
    ----------
    frequencies : mapping
        ``name -> Hz`` of the fault lines (``bpfo``, ``bpfi``, ``bsf``, ``bsf2``, ``ftf``, or
        any other name). A ``bsf`` without ``bsf2`` adds ``bsf2 = 2 bsf`` (a spall on a rolling
        element strikes both races once per spin revolution).
    fr : float
        Shaft rate (Hz), the spacing named ``"fr"``.
    sidebands : mapping, optional
        ``name -> spacing name`` (``"fr"``, another family's name, or None), overriding
        :data:`SIDEBAND_SPACING`. Families not listed anywhere get no sidebands. A spacing
        whose frequency is unknown (``bsf`` without ``ftf``) gives no sidebands. A spacing may
        also be a pair ``(name, Hz)``: a spacing that is not itself a searched family (the
        sweep's rolling-element cases: ``{"bsf2": ("ftf", f_c)}``).

    Returns
    -------
    tuple of FaultFamily
        In the order given (``bsf2`` right after ``bsf``).
    """
    freqs = {str(k): float(v) for k, v in frequencies.items()}
    if "bsf" in freqs and "bsf2" not in freqs:
        items = []
        for k, v in freqs.items():
            items.append((k, v))
            if k == "bsf":
                items.append(("bsf2", spin_events(v)))
        freqs = dict(items)
    spacing_map = {**SIDEBAND_SPACING, **dict(sidebands or {})}
    known = {"fr": float(fr), **freqs}
    out = []
    for name, hz in freqs.items():
        sb = spacing_map.get(name)
        if isinstance(sb, tuple):
            sb, sb_hz = str(sb[0]), float(sb[1])
        else:
            sb_hz = known.get(sb) if sb is not None else None
        if sb_hz is None:
            sb = None
        out.append(FaultFamily(name, hz, sb, sb_hz, FAMILY_LABELS.get(name, f"{name} line")))
    return tuple(out)


def _score(f, a, line_hz, half, *, fr, exclude, pfa):
    """Detection of one line (``diagnosis.detection_statistic``); None when the spectrum is
    too short for a background around it."""
    # only the background band [lo, hi] x line (+ the search window and the local-maximum
    # check's neighbours) enters the statistic: pass that slice, not the whole spectrum
    lo, hi = BACKGROUND_BAND
    df = f[1] - f[0]
    i0 = max(0, int(math.floor((lo * line_hz - half) / df)) - 2)
    i1 = min(f.size, int(math.ceil((hi * line_hz + half) / df)) + 3)
    try:
        return detection_statistic(f[i0:i1], a[i0:i1], line_hz, fr=fr, tolerance_hz=half,
                                   sidebands=0, exclude_hz=exclude, pfa=pfa)
    except ValueError:
        return None


def search_lines(
    f,
    amplitude,
    family: FaultFamily,
    *,
    fr: float | None = None,
    n_harmonics: int,
    n_sidebands: int,
    search_percent: float = DEFAULT_SEARCH_PERCENT,
    tolerance_hz: float | None = None,
    pfa: float = DEFAULT_PFA,
    interpolate: bool = False,
    window=DEFAULT_WINDOW,
    n: int | None = None,
    min_search_bins: float = 0.0,
) -> list[dict]:
    r"""Fundamental, harmonics and sidebands of one fault family in a spectrum.

    Parameters
    ----------
    f, amplitude : ndarray
        A one-sided spectrum (uniform ``f`` from 0 Hz), e.g. from
        :func:`~bearing_envelope.signal.envelope_spectrum`.
    family : FaultFamily
        The family (see :func:`fault_families`).
    fr : float, optional
        Shaft rate (Hz): its harmonics are kept out of the floor.
    n_harmonics : int
        Harmonics k = 1..K (the analysis's: ``AnalysisOptions.n_harmonics``).
    n_sidebands : int
        Sidebands m = 1..M per side (only for a family with a sideband spacing).
    search_percent : float, default 1.0
        Half-width of the fundamental's search, percent of its nominal frequency.
    tolerance_hz : float, optional
        A fixed half-width (Hz) for every line instead (the fundamental searched around its
        nominal frequency, everything else around the speed-corrected targets).
    pfa : float, default 0.01
        False-alarm probability of each line's detection threshold.
    interpolate, window, n
        Refine the reported frequency and amplitude of each peak bin, see
        :func:`~bearing_envelope.signal.amplitude_at` (the floor ratio stays the bin's).
    min_search_bins : float, default 0
        The fundamental's search half-width is at least this many bins (the resolution floor
        the harmonics' :func:`~bearing_envelope.signal.spectrum.default_tolerance` has: a line
        between two bins shows in either; 0.5 % of a 12 Hz cage rate is less than one bin of
        a 10 s record).

    Returns
    -------
    list of dict
        One record per line with ``order`` (k), ``sideband`` (signed m), ``target_hz`` (the
        nominal fundamental for k = 1, m = 0; else ``k f_1 + m s f_sb``), ``frequency_hz`` and
        ``amplitude`` (the largest bin of the window, or interpolated), ``floor`` (local
        median), ``floor_ratio_db``, ``threshold_db``, ``detected`` (NaN / None where the
        spectrum holds no background around the line). Lines beyond the spectrum are skipped;
        if the fundamental is, the list is empty.

    Notes
    -----
    With :math:`f_1` the largest bin within :math:`f_{nom}(1 \pm p/100)` and
    :math:`s = f_1 / f_{nom}`, harmonic k is the largest bin within
    :math:`k f_1 \pm \max(2\Delta f, 0.002\,k f_1)`, sideband m of it within
    :math:`k f_1 + m s f_{sb} \pm` the same (at most :math:`f_{sb}/4`).
    """
    f = np.asarray(f, dtype=np.float64)
    a = np.asarray(amplitude, dtype=np.float64)
    n_harmonics = int(n_harmonics)
    n_sidebands = int(n_sidebands) if family.sideband_hz else 0
    if n_harmonics < 1:
        raise ValueError(f"n_harmonics must be >= 1, got {n_harmonics}")
    if n_sidebands < 0:
        raise ValueError(f"n_sidebands must be >= 0, got {n_sidebands}")
    p = float(search_percent)
    if not math.isfinite(p) or not 0.0 < p < 50.0:
        raise ValueError(f"search_percent must be in (0, 50), got {search_percent!r}")
    df = float(f[1] - f[0])
    fmax = float(f[-1])
    F = float(family.frequency_hz)
    spacing = float(family.sideband_hz) if n_sidebands else 0.0

    def exclusions(f1, sp):
        # every line of the family inside the background band of the highest harmonic
        jmax = int(math.ceil(BACKGROUND_BAND[1] * (n_harmonics + 1))) + 1
        out = [j * f1 for j in range(1, jmax + 1)]
        out += [j * f1 + m * sp for j in range(1, jmax + 1) for m in
                range(-n_sidebands, n_sidebands + 1) if m and sp]
        return out

    def line(order, sideband, target, centre, half, excl):
        if centre + half > fmax or centre - half < 0:
            return None
        det = _score(f, a, centre, half, fr=fr, exclude=excl, pfa=pfa)
        if det is not None:
            ff, aa = det.peak_hz, det.peak_amplitude
        else:
            ff, aa = amplitude_at(f, a, centre, half)
        rec = {"order": order, "sideband": sideband, "target_hz": target, "frequency_hz": ff,
               "amplitude": aa,
               "floor": math.nan if det is None else det.background,
               "floor_ratio_db": math.nan if det is None else det.statistic_db,
               "threshold_db": math.nan if det is None else det.threshold_db,
               "detected": None if det is None else bool(det.detected)}
        if interpolate:
            rec["frequency_hz"], rec["amplitude"] = amplitude_at(f, a, ff, 0.0, interpolate=True,
                                                                 window=window, n=n)
        return rec, ff

    half1 = (float(tolerance_hz) if tolerance_hz is not None
             else max(p / 100.0 * F, float(min_search_bins) * df))
    first = line(1, 0, F, F, half1, exclusions(F, spacing))
    if first is None:
        return []
    rec1, f1 = first
    s = f1 / F
    sp = s * spacing
    excl = exclusions(f1, sp)
    out = []
    for k in range(1, n_harmonics + 1):
        if k == 1:
            rec_k, fk = rec1, f1
        else:
            c = k * f1
            half = float(tolerance_hz) if tolerance_hz is not None else default_tolerance(c, df)
            got = line(k, 0, c, c, half, excl)
            if got is None:
                break
            rec_k, fk = got
        recs = [rec_k]
        for m in range(1, n_sidebands + 1):
            for sign in (-1, 1):
                c = k * f1 + sign * m * sp
                half = (float(tolerance_hz) if tolerance_hz is not None
                        else default_tolerance(c, df, sp))
                got = line(k, sign * m, c, c, half, excl)
                if got is not None:
                    recs.append(got[0])
        out.extend(sorted(recs, key=lambda r: r["sideband"]))
    return out


# --------------------------------------------------------------------------- the verdict
#: A band can hold a family when it is at least ``HOLD_ORDERS`` times the family's fundamental
#: wide: the envelope of a band ``W`` Hz wide has components up to ``W`` only, and a family
#: needs its fundamental and second harmonic.
HOLD_ORDERS = 2

#: Bands agree on a family when the fundamental they found lies within ``AGREE_PERCENT`` % (or
#: two bins) of the best band's: one shaft speed, one line, in every band.
AGREE_PERCENT = 0.2

#: Two demodulation bands are one piece of evidence when they share more than this fraction of
#: the narrower one's width (issue 24, third pass): the kurtogram's band often lies inside a
#: fixed band (3-4 kHz in 3-4.5 kHz), and the same resonance seen through two overlapping
#: filters gives the same envelope lines twice. Bands are counted as the largest set of the
#: agreeing bands no two of which overlap more than this (:func:`distinct_bands`).
DISTINCT_BAND_OVERLAP = 0.5

#: ``high``: detected, at one frequency, in at least this many distinct bands that can hold the
#: family (``medium`` with fewer harmonics, no modulation or a lower margin).
HIGH_MIN_BANDS = 3
#: ``high``: the fundamental at least this far above its threshold (dB) in the best band.
HIGH_MIN_MARGIN_DB = 10.0
#: ``medium`` from fewer bands: detected, at one frequency, in at least this many distinct
#: bands ...
MEDIUM_MIN_BANDS = 2
#: ... with the fundamental at least this far above its threshold (dB).
MEDIUM_MIN_MARGIN_DB = 15.0

#: A family sharing a harmonic with the diagnosis (3 BPFO = 2 BPFI) whose fundamental is within
#: this many dB of the diagnosis's margin is a rival: the verdict cannot tell them apart.
RIVAL_MARGIN_DB = 6.0

#: Orders k <= EXPLAIN_MAX_ORDER and sidebands |m| <= EXPLAIN_MAX_SIDEBAND of a stronger family
#: that explain a weaker family's fundamental.
EXPLAIN_MAX_ORDER = 6
EXPLAIN_MAX_SIDEBAND = 3
#: A cage-rate (FTF) family whose fundamental divides a stronger family's by an integer up to
#: this is the cage period of that train (BPFO = Z x FTF): not a cage fault.
CAGE_MAX_DIVISOR = 20

#: The family whose detection means a cage fault: it needs ``high`` evidence of its own.
CAGE_FAMILY = "ftf"

#: Confidence levels, strongest first; ``CANNOT_TELL`` where the evidence conflicts.
CONFIDENCE_LEVELS = ("high", "medium", "low")
CANNOT_TELL = "cannot tell"

_RANK = {"high": 3, "medium": 2, "low": 1, None: 0}


@dataclass(frozen=True)
class FamilyVerdict:
    """The decision on one fault family over all bands of a record.

    Attributes
    ----------
    family, label : str
        Family name and what a detection means.
    detected : bool
        Fundamental and second harmonic detected in at least one band that can hold them.
    band : str or None
        The band with the highest statistic among those where the family is detected (else
        among all bands); None when no band could hold the line.
    band_low_hz, band_high_hz : float
        Its limits (Hz).
    frequency_hz, amplitude : float
        The fundamental found there (Hz, unit of the spectrum).
    floor_ratio_db, threshold_db : float
        Its statistic ``20 log10(amplitude / floor)`` and the threshold (dB).
    harmonics : tuple of int
        Orders k detected in that band.
    sideband_name : str or None
        The family's sideband spacing (``"fr"``, ``"ftf"``) when at least one of its sidebands
        is detected in that band.
    bands_detected : tuple of str
        Every band where the family is detected.
    explained_by : str or None
        For a detected family whose fundamental falls on a line of a stronger family, on a
        shaft harmonic, divides a stronger family's fundamental (cage rate) or shares a
        harmonic with it: that line (``"BPFI - 5 fr"``, ``"3 fr"``, ``"BPFO / 9"``,
        ``"3 BPFO = 2 BPFI"``).
    bands_agreeing : tuple of str
        The bands of ``bands_detected`` whose fundamental agrees with the best band's
        (:data:`AGREE_PERCENT`).
    n_bands_held : int
        Bands wide enough to hold the family (:data:`HOLD_ORDERS`).
    n_orders : int
        Harmonics searched in the best band.
    modulation : str or None
        The modulation a fault of this family shows (``"fr"`` inner race, ``"ftf"`` rolling
        element, None: none expected).
    lines : tuple of (int, int, float)
        ``(order, sideband, frequency_hz)`` of every line detected in the best band.
    level : str or None
        The family's evidence on its own: ``high``, ``medium``, ``low`` (see
        :func:`evidence_level`), None when not detected.
    n_distinct : int or None
        How many of :attr:`bands_agreeing` are distinct demodulation bands
        (:func:`distinct_bands`, :data:`DISTINCT_BAND_OVERLAP`); None: unknown (then all
        agreeing bands count).
    role : str or None
        ``"diagnosis"``, ``"candidate"`` (cannot tell between candidates), ``"second finding"``,
        ``"explained"``, ``"weak"`` (detected, below the bar of a second finding), None.
    """

    family: str
    label: str
    detected: bool
    band: str | None
    band_low_hz: float
    band_high_hz: float
    frequency_hz: float
    amplitude: float
    floor_ratio_db: float
    threshold_db: float
    harmonics: tuple[int, ...]
    sideband_name: str | None
    bands_detected: tuple[str, ...]
    explained_by: str | None = None
    bands_agreeing: tuple[str, ...] = ()
    n_bands_held: int = 0
    n_orders: int = 0
    modulation: str | None = None
    lines: tuple[tuple[int, int, float], ...] = ()
    level: str | None = None
    role: str | None = None
    n_distinct: int | None = None

    @property
    def n_bands(self) -> int:
        """The agreeing bands counted as evidence: :attr:`n_distinct` (distinct demodulation
        bands, :func:`distinct_bands`) when known, else ``len(bands_agreeing)``."""
        return len(self.bands_agreeing) if self.n_distinct is None else int(self.n_distinct)

    @property
    def margin_db(self) -> float:
        """``floor_ratio_db - threshold_db`` (dB)."""
        return self.floor_ratio_db - self.threshold_db

    @property
    def modulation_ok(self) -> bool:
        """The expected modulation is seen (always true for a family that expects none)."""
        return self.modulation is None or self.sideband_name == self.modulation

    def evidence(self) -> list[str]:
        """The evidence behind :attr:`level`, one short phrase each.

        Returns
        -------
        list of str
            Bands agreeing, harmonics found, modulation, margin above threshold (dB).
        """
        out = [f"detected at one frequency in {len(self.bands_agreeing)} of "
               f"{self.n_bands_held} bands that can hold it"
               + (f" ({self.n_bands} distinct)" if self.n_bands != len(self.bands_agreeing)
                  else "")]
        if self.harmonics:
            out.append(f"harmonics {_ranges(self.harmonics)} of {self.n_orders}")
        if self.modulation is None:
            out.append("no modulation expected")
        elif self.modulation_ok:
            out.append(f"{display_name(self.modulation)} sidebands as expected")
        else:
            out.append(f"no {display_name(self.modulation)} sidebands (expected)")
        out.append(f"{self.margin_db:.1f} dB above threshold")
        return out

    def summary(self) -> str:
        """One line, e.g. ``inner race fault: BPFI 161.7 Hz, harmonics 1-3, fr sidebands,
        37.1 dB above floor (threshold 12.0 dB), in band kurtogram (0-5880 Hz)``.

        Returns
        -------
        str
            The line; for a family not detected, its best line against the threshold; for one
            not searched, ``not searched``.
        """
        name = display_name(self.family)
        if self.band is None:
            return f"{name}: not searched (no band could hold it)"
        if not self.detected:
            return (f"no {self.label} line: {name} best {self.floor_ratio_db:.1f} dB above floor "
                    f"at {self.frequency_hz:.2f} Hz in band {self.band}, threshold "
                    f"{self.threshold_db:.1f} dB, harmonics detected "
                    f"{_ranges(self.harmonics) if self.harmonics else 'none'}")
        parts = [f"{self.label}: {name} {self.frequency_hz:.1f} Hz"]
        if self.harmonics:
            parts.append(f"harmonics {_ranges(self.harmonics)}")
        if self.sideband_name:
            parts.append(f"{display_name(self.sideband_name)} sidebands")
        parts.append(f"{self.floor_ratio_db:.1f} dB above floor (threshold "
                     f"{self.threshold_db:.1f} dB)")
        parts.append(f"in band {self.band} ({self.band_low_hz:.0f}-{self.band_high_hz:.0f} Hz)")
        if len(self.bands_detected) > 1:
            parts.append(f"detected in {len(self.bands_detected)} bands")
        if self.explained_by:
            parts.append(f"falls on {self.explained_by}")
        return ", ".join(parts)


def _ranges(ks: Sequence[int]) -> str:
    ks = sorted(ks)
    groups, start, prev = [], ks[0], ks[0]
    for k in ks[1:]:
        if k == prev + 1:
            prev = k
            continue
        groups.append((start, prev))
        start = prev = k
    groups.append((start, prev))
    return ", ".join(f"{a}" if a == b else f"{a}-{b}" for a, b in groups)


def evidence_level(v: FamilyVerdict) -> str | None:
    """The evidence of one detected family on its own: ``high``, ``medium``, ``low`` or None.

    ``high``: detected at one frequency in >= :data:`HIGH_MIN_BANDS` distinct bands
    (:func:`distinct_bands`: overlapping bands count once), every harmonic
    searched detected in the best band, the expected modulation seen (fr sidebands for an inner
    race, FTF sidebands for a rolling element, none needed for an outer race) and the
    fundamental >= :data:`HIGH_MIN_MARGIN_DB` dB above its threshold. ``medium``: >=
    :data:`HIGH_MIN_BANDS` agreeing bands without the rest, or >= :data:`MEDIUM_MIN_BANDS`
    with the fundamental >= :data:`MEDIUM_MIN_MARGIN_DB` dB above its threshold. ``low``: any
    other detection (one band, or two with weak lines).

    Parameters
    ----------
    v : FamilyVerdict
        One family's verdict.

    Returns
    -------
    str or None
        ``"high"``, ``"medium"`` or ``"low"``; ``None`` when the family was not detected.
    """
    if not v.detected:
        return None
    nb = v.n_bands
    full = v.n_orders > 0 and len(v.harmonics) >= v.n_orders
    if (nb >= HIGH_MIN_BANDS and full and v.modulation_ok
            and v.margin_db >= HIGH_MIN_MARGIN_DB):
        return "high"
    if nb >= HIGH_MIN_BANDS or (nb >= MEDIUM_MIN_BANDS and v.margin_db >= MEDIUM_MIN_MARGIN_DB):
        return "medium"
    return "low"


@dataclass(frozen=True)
class Verdict:
    """Per-record verdict of :func:`fault_verdict`.

    Attributes
    ----------
    families : tuple of FamilyVerdict
        One per fault family, in the order of the table (each with its ``level`` and ``role``).
    pfa : float
        Record-wise false-alarm probability (any family in any band).
    n_tests : int
        Family x band tests; each line is tested at ``pfa_test = pfa / n_tests``.
    pfa_test : float
        The per-test false-alarm probability behind every ``threshold_db``.
    confidence : str or None
        ``high``, ``medium``, ``low`` (the diagnosis's :func:`evidence_level`) or
        :data:`CANNOT_TELL` (two candidates with evidence of the same level); None when no
        family is detected.
    candidates : tuple of str
        The families between which the verdict cannot tell (else empty).
    statistic : str
        Statement of the statistic, the threshold and the decision rule.
    routes : tuple of str
        With the routes of :mod:`~bearing_envelope.diagnosis.routes`: which route found
        what, one phrase per route (else empty).
    decided_by : str or None
        With the routes: ``"envelope"``, ``"envelope, high needs a second route"`` or
        ``"routes"`` (:func:`~bearing_envelope.diagnosis.routes.combine_routes`).
    """

    families: tuple[FamilyVerdict, ...]
    pfa: float
    n_tests: int
    pfa_test: float
    confidence: str | None = None
    candidates: tuple[str, ...] = ()
    statistic: str = field(default=(
        "S = 20 log10(peak / floor), floor = median amplitude over [0.5, 1.5] x line without "
        "the family's lines and the shaft harmonics; a line is detected if S > "
        "threshold_db(pfa / n_tests, bins searched) (diagnosis.threshold_db, Rayleigh noise) "
        "and it is a local maximum; a family is detected in a band if its fundamental and "
        "its second harmonic are; confidence from the bands that agree, the harmonics, the "
        "expected modulation and the margin (faults.evidence_level)"))
    routes: tuple[str, ...] = ()
    decided_by: str | None = None

    def _role(self, role: str) -> tuple[FamilyVerdict, ...]:
        return tuple(v for v in self.families if v.role == role)

    @property
    def detected(self) -> tuple[FamilyVerdict, ...]:
        """The diagnosis (or the candidates) and the second findings, strongest first."""
        return self._role("diagnosis") + self._role("candidate") + self._role("second finding")

    @property
    def diagnosis(self) -> FamilyVerdict | None:
        """The diagnosed family, or None (no fault detected, or :data:`CANNOT_TELL`)."""
        d = self._role("diagnosis")
        return d[0] if d else None

    @property
    def evidence(self) -> list[str]:
        """The evidence that set :attr:`confidence`."""
        d = self.diagnosis
        if d is not None:
            return d.evidence()
        if self.candidates:
            return [f"{display_name(v.family)} and the others reach '{v.level}' evidence"
                    for v in self._role("candidate")[:1]]
        return []

    def summary_lines(self) -> list[str]:
        """The diagnosis line with its confidence, then ``second finding`` and ``explained``
        lines; or one ``no bearing fault detected`` / ``cannot tell`` line.

        Returns
        -------
        list of str
            The lines; ``decided by`` and one line per route last (when routes ran).
        """
        d = self.diagnosis
        if d is None and not self.candidates:
            best = max((v for v in self.families if v.band is not None),
                       key=lambda v: v.margin_db, default=None)
            tail = "" if best is None else (
                f" (closest: {display_name(best.family)} {best.floor_ratio_db:.1f} dB against "
                f"{best.threshold_db:.1f} dB in band {best.band}, harmonics detected "
                f"{_ranges(best.harmonics) if best.harmonics else 'none'})")
            return [f"no bearing fault detected at a record-wise false-alarm probability of "
                    f"{self.pfa:g}{tail}"] + self._route_lines()
        if d is None:
            names = " or ".join(display_name(c) for c in self.candidates)
            lines = [f"cannot tell: {names} ({self.confidence} evidence each)"]
            lines += [f"candidate: {v.summary()}" for v in self._role("candidate")]
        else:
            lines = [f"{d.summary()} [confidence {self.confidence}: "
                     f"{'; '.join(d.evidence())}]"]
        lines += [f"second finding ({v.level}): {v.summary()}"
                  for v in self._role("second finding")]
        lines += [f"explained: {v.summary()}" for v in self._role("explained")]
        lines += [f"weak, not a finding: {v.summary()}" for v in self._role("weak")]
        return lines + self._route_lines()

    def _route_lines(self) -> list[str]:
        """``decided by ...`` and one line per route (empty without the routes)."""
        if not self.routes:
            return []
        return [f"decided by: {self.decided_by}"] + [f"route {r}" for r in self.routes]

    def to_dict(self) -> dict:
        """Plain JSON-able form.

        Returns
        -------
        dict
            ``diagnosis``, ``diagnosis_label``, ``confidence``, ``candidates``, ``evidence``,
            ``second_findings``, ``pfa``, ``n_tests``, ``pfa_test``, ``statistic``, ``summary``,
            ``families`` (one dict per family, non-finite floats as ``None``), ``routes``,
            ``decided_by``.
        """
        fams = []
        for v in self.families:
            d = {k: getattr(v, k) for k in v.__dataclass_fields__}
            for k in ("harmonics", "bands_detected", "bands_agreeing"):
                d[k] = list(d[k])
            d["lines"] = [list(x) for x in v.lines]
            d["evidence"] = v.evidence() if v.detected else []
            for k, x in d.items():
                if isinstance(x, float) and not math.isfinite(x):
                    d[k] = None
            fams.append(d)
        diag = self.diagnosis
        label = ("no fault" if diag is None and not self.candidates else
                 CANNOT_TELL if diag is None else diag.label)
        return {"diagnosis": None if diag is None else diag.family,
                "diagnosis_label": label, "confidence": self.confidence,
                "candidates": list(self.candidates), "evidence": self.evidence,
                "second_findings": [v.family for v in self._role("second finding")],
                "pfa": self.pfa, "n_tests": self.n_tests, "pfa_test": self.pfa_test,
                "statistic": self.statistic, "summary": self.summary_lines(), "families": fams,
                "routes": list(self.routes), "decided_by": self.decided_by}


def _tolerance(f0: float, df_hz: float) -> float:
    """Half-width (Hz) within which two found lines are the same line: ``max(2 df,
    AGREE_PERCENT % of f0)``."""
    return max(2.0 * df_hz, AGREE_PERCENT / 100.0 * abs(f0))


def _comb_line(f0: float, sv: FamilyVerdict, sfam: FaultFamily, tol: float) -> str | None:
    """The line ``k f +- m sp`` of a stronger family (k <= EXPLAIN_MAX_ORDER, |m| <=
    EXPLAIN_MAX_SIDEBAND, its spacing scaled by its speed ratio; k = 0 gives the spacing's own
    harmonics, e.g. FTF for a rolling element) within ``tol`` of ``f0``, or None."""
    s = sv.frequency_hz / sfam.frequency_hz
    sp = s * sfam.sideband_hz if sfam.sideband_hz else 0.0
    ms = range(-EXPLAIN_MAX_SIDEBAND, EXPLAIN_MAX_SIDEBAND + 1) if sp else (0,)
    for k in range(0, EXPLAIN_MAX_ORDER + 1):
        for m in ms:
            if (k == 0 and m <= 0) or abs(f0 - abs(k * sv.frequency_hz + m * sp)) > tol:
                continue
            name = display_name(sv.family)
            if k == 0:
                return f"{m} {display_name(sfam.sideband_name)}" if m > 1 else \
                    display_name(sfam.sideband_name)
            head = name if k == 1 else f"{k} {name}"
            if m == 0:
                return head
            return f"{head} {'+' if m > 0 else '-'} {abs(m)} {display_name(sfam.sideband_name)}"
    return None


def _shared_harmonic(v: FamilyVerdict, sv: FamilyVerdict, df_hz: float) -> str | None:
    """A harmonic k >= 2 of ``v`` found on a detected line of ``sv`` (``"3 BPFO = 2 BPFI"``)."""
    for k, m, f in v.lines:
        if m != 0 or k < 2:
            continue
        for ks, ms, fs_ in sv.lines:
            if abs(f - fs_) <= _tolerance(f, df_hz):
                rhs = display_name(sv.family) if ks == 1 else f"{ks} {display_name(sv.family)}"
                if ms:
                    rhs += f" {'+' if ms > 0 else '-'} {abs(ms)} sb"
                return f"{k} {display_name(v.family)} = {rhs}"
    return None


def _explanation(v: FamilyVerdict, stronger: Sequence[tuple[FamilyVerdict, FaultFamily]],
                 fr: float, df_hz: float) -> tuple[str | None, str | None]:
    """Why ``v``'s lines need no fault of their own: ``(line, kind)`` with kind ``"comb"`` (its
    fundamental on a line of a stronger family or on a shaft harmonic), ``"cage"`` (the cage
    period of a stronger family's train: its fundamental an integer fraction of theirs) or
    ``"shared"`` (a harmonic on a stronger family's line, ``3 BPFO = 2 BPFI``); else
    ``(None, None)``."""
    f0 = v.frequency_hz
    tol = _tolerance(f0, df_hz)
    for sv, sfam in stronger:
        why = _comb_line(f0, sv, sfam, tol)
        if why:
            return why, "comb"
    k = round(f0 / fr)
    if k >= 1 and abs(f0 - k * fr) <= tol:
        return f"{k} fr", "comb"
    if v.family == CAGE_FAMILY:
        for sv, _ in stronger:
            n = round(sv.frequency_hz / f0)
            if 2 <= n <= CAGE_MAX_DIVISOR and abs(sv.frequency_hz / n - f0) <= tol:
                return f"{display_name(sv.family)} / {n}", "cage"
    for sv, _ in stronger:
        why = _shared_harmonic(v, sv, df_hz)
        if why:
            return why, "shared"
    return None, None


def distinct_bands(limits: Sequence[tuple[float, float]],
                   overlap: float | None = None) -> int:
    """How many of the bands ``[(low, high), ...]`` (Hz) are distinct evidence: the size of the
    largest subset in which no two bands share more than ``overlap`` (default
    :data:`DISTINCT_BAND_OVERLAP`) of the narrower one's width. A band inside another (the
    kurtogram's 3-4 kHz inside 3-4.5 kHz) counts once with it; disjoint bands count each.
    Exact for up to 12 bands (every subset), greedy (narrowest first) beyond.

    Parameters
    ----------
    limits : sequence of (float, float)
        Band limits ``(low, high)``, Hz.
    overlap : float, optional
        Fraction of the narrower band's width two bands may share and stay distinct.

    Returns
    -------
    int
        Number of distinct bands (0 for none).
    """
    frac = DISTINCT_BAND_OVERLAP if overlap is None else float(overlap)
    bands = [(float(lo), float(hi)) for lo, hi in limits]

    def same(a, b):
        shared = min(a[1], b[1]) - max(a[0], b[0])
        narrow = min(a[1] - a[0], b[1] - b[0])
        return shared > frac * narrow if narrow > 0 else shared >= 0

    n = len(bands)
    if n <= 12:
        from itertools import combinations
        for k in range(n, 0, -1):
            for sub in combinations(bands, k):
                if all(not same(a, b) for a, b in combinations(sub, 2)):
                    return k
        return 0
    kept: list[tuple[float, float]] = []
    for b in sorted(bands, key=lambda x: x[1] - x[0]):
        if all(not same(b, c) for c in kept):
            kept.append(b)
    return len(kept)


def _columns(rows, keep=None) -> dict:
    """The columns :func:`_family_verdict` reads, as numpy arrays (rows ``keep`` only)."""
    cols = {"band": rows["band"].to_numpy(dtype=object),
            "detected": rows["detected"].fillna(False).astype(bool).to_numpy()}
    for c in ("band_low_hz", "band_high_hz", "order", "sideband", "frequency_hz", "amplitude",
              "floor_ratio_db", "threshold_db"):
        cols[c] = rows[c].to_numpy(dtype=float)
    return cols if keep is None else {k: v[keep] for k, v in cols.items()}


def _ok_bands(c: Mapping, held: Sequence) -> list:
    """Bands (in order) where the fundamental is detected, and the second harmonic too when the
    band holds one."""
    out = []
    h = c["sideband"] == 0
    for band in held:
        g = c["band"] == band
        k1 = bool((c["detected"] & g & h & (c["order"] == 1)).any())
        has2 = bool((g & h & (c["order"] == 2)).any())
        k2 = bool((c["detected"] & g & h & (c["order"] == 2)).any())
        if k1 and (k2 or not has2):
            out.append(band)
    return out


def _family_verdict(fam: FaultFamily, rows, df_hz: float) -> FamilyVerdict:
    """One family's detection over the bands that can hold it (envelope rows of the table)."""
    width = rows["band_high_hz"].to_numpy(dtype=float) - rows["band_low_hz"].to_numpy(dtype=float)
    c = _columns(rows, width >= HOLD_ORDERS * fam.frequency_hz)
    held = list(dict.fromkeys(c["band"]))
    fund = np.flatnonzero((c["order"] == 1) & (c["sideband"] == 0)
                          & np.isfinite(c["floor_ratio_db"]))
    modulation = SIDEBAND_SPACING.get(fam.name) if fam.sideband_hz else None
    if fund.size == 0:
        return FamilyVerdict(fam.name, fam.label, False, None, math.nan, math.nan, math.nan,
                             math.nan, math.nan, math.nan, (), None, (), modulation=modulation)
    ok_bands = _ok_bands(c, held)
    det_rows = fund[np.array([b in set(ok_bands) for b in c["band"][fund]], dtype=bool)]
    pick = det_rows if det_rows.size else fund
    i = int(pick[np.argmax(c["floor_ratio_db"][pick])])  # the first of equal maxima
    band, f1 = c["band"][i], float(c["frequency_hz"][i])
    agree = tuple(str(c["band"][j]) for j in det_rows
                  if abs(float(c["frequency_hz"][j]) - f1) <= _tolerance(f1, df_hz))
    first = {b: int(np.flatnonzero(c["band"] == b)[0]) for b in held}
    n_distinct = distinct_bands([(float(c["band_low_hz"][first[b]]),
                                  float(c["band_high_hz"][first[b]])) for b in agree])
    inb = c["band"] == band
    found = np.flatnonzero(inb & c["detected"])
    harmonics = tuple(int(k) for k in sorted(set(c["order"][found][c["sideband"][found] == 0])))
    sb = fam.sideband_name if (c["sideband"][found] != 0).any() else None
    lines = tuple((int(c["order"][j]), int(c["sideband"][j]), float(c["frequency_hz"][j]))
                  for j in found)
    v = FamilyVerdict(
        fam.name, fam.label, bool(ok_bands), str(band), float(c["band_low_hz"][i]),
        float(c["band_high_hz"][i]), f1, float(c["amplitude"][i]),
        float(c["floor_ratio_db"][i]), float(c["threshold_db"][i]), harmonics, sb,
        tuple(str(b) for b in ok_bands), bands_agreeing=agree if ok_bands else (),
        n_bands_held=len(held), n_orders=int(c["order"][inb & (c["sideband"] == 0)].max()),
        modulation=modulation, lines=lines, n_distinct=n_distinct if ok_bands else 0)
    return replace(v, level=evidence_level(v))


def _own_level(v: FamilyVerdict, shared: str) -> str | None:
    """The evidence level of ``v`` without its harmonic that falls on another family's line
    (``shared`` = ``"3 BPFO = 2 BPFI"``): the fundamental and another of its harmonics must be
    left (a harmonic series without the shared line; issue 24 second pass: 2 BPFI = 3 BPFO no
    longer removes a BPFI series whose fundamental and third harmonic stand on their own)."""
    k = int(shared.split()[0])
    rest = tuple(h for h in v.harmonics if h != k)
    if 1 not in rest or len(rest) < 2:
        return None
    return evidence_level(replace(v, harmonics=rest))


def _rivals(own: str | None, v: FamilyVerdict, primary: FamilyVerdict) -> bool:
    """A family sharing a harmonic with the diagnosis rivals it (cannot tell) when its own
    evidence (without the shared harmonic) is at the diagnosis's level, or, at any level, its
    fundamental stands within :data:`RIVAL_MARGIN_DB` of the diagnosis's margin (issue 24
    second pass: the former rule asked for ``medium`` own evidence as well; a one-band series
    as strong as the diagnosis's fundamental is a rival all the same)."""
    if own is None:
        return False
    if _RANK[own] >= _RANK[primary.level]:
        # no band tie-break here: v's agreeing bands were counted with the shared line
        return True
    return primary.margin_db - v.margin_db <= RIVAL_MARGIN_DB


#: Two families at the same evidence level conflict only when the stronger one is not found,
#: at one frequency, in more bands (evidence combined across demodulation bands: a family seen
#: in more bands is more credible; issue 24: all 4 bands 28/28 right, 1-2 bands 6/22). Not
#: applied to a family sharing a harmonic with the stronger one (its bands were counted with
#: the shared line).
BAND_TIE_BREAK = True


def _conflicts(v: FamilyVerdict, primary: FamilyVerdict) -> bool:
    """``v`` (weaker by :func:`_rank`) has evidence as strong as ``primary``'s: the same level
    (or higher) and, with :data:`BAND_TIE_BREAK`, as many agreeing bands."""
    if _RANK[v.level] < _RANK[primary.level]:
        return False
    return not (BAND_TIE_BREAK and _RANK[v.level] == _RANK[primary.level]
                and primary.n_bands > v.n_bands)


def _rank(v: FamilyVerdict) -> tuple:
    """Sort key, strongest first: a cage family below the others unless its evidence is high,
    then level, agreeing bands, margin."""
    cage_low = v.family == CAGE_FAMILY and v.level != "high"
    return (not cage_low, _RANK[v.level], v.n_bands, v.margin_db)


def _decide(out: Sequence[FamilyVerdict], by_fam: Mapping[str, FaultFamily], fr: float,
            df_hz: float) -> tuple[list[FamilyVerdict], str | None, tuple[str, ...]]:
    """Roles of the detected families (strongest first; explained ones set aside), the
    confidence and the candidates when the verdict cannot tell."""
    roles: dict[str, str] = {}
    why: dict[str, str] = {}
    accepted: list[tuple[FamilyVerdict, FaultFamily]] = []
    for v in sorted((v for v in out if v.detected), key=_rank, reverse=True):
        line, kind = _explanation(v, accepted, fr, df_hz)
        primary = accepted[0][0] if accepted else None
        if line:
            why[v.family] = line
            tie = kind == "shared" and _rivals(_own_level(v, line), v, primary)
            roles[v.family] = "candidate" if tie else "explained"
            continue
        strong = v.level in ("high", "medium") and v.family != CAGE_FAMILY
        if primary is None and v.family == CAGE_FAMILY:
            # cage-rate lines alone: a cage fault or the load-zone modulation of a rolling
            # element fault whose own lines are too weak; the envelope cannot tell them apart
            roles[v.family] = "candidate" if v.level in ("high", "medium") else "weak"
            continue
        if primary is None:
            roles[v.family] = "diagnosis"
        elif v.family != CAGE_FAMILY and _conflicts(v, primary):
            roles[v.family] = "candidate"  # evidence as strong as the diagnosis's: conflict
        elif strong:
            roles[v.family] = "second finding"
        else:
            roles[v.family] = "weak"
            continue
        accepted.append((v, by_fam[v.family]))
    candidates = tuple(f for f, r in roles.items() if r == "candidate")
    confidence = None
    if not accepted and candidates:  # cage-rate lines only
        candidates = candidates + tuple(f for f in ("bsf", "bsf2") if f in by_fam)
        confidence = CANNOT_TELL
    if accepted:
        confidence = accepted[0][0].level
        if candidates:
            candidates = (accepted[0][0].family,) + candidates
            roles[accepted[0][0].family] = "candidate"
            confidence = CANNOT_TELL
    new = [replace(v, role=roles.get(v.family), explained_by=why.get(v.family)) for v in out]
    return new, confidence, candidates


def fault_verdict(table, families: Sequence[FaultFamily], *, pfa: float, n_tests: int,
                  fr: float, df_hz: float = 0.0) -> Verdict:
    """Verdict per family from the envelope rows of an :func:`analyze_signal` table.

    Each family is judged over the bands that can hold it (width >= :data:`HOLD_ORDERS` x its
    fundamental) and gets an :func:`evidence_level`. The strongest family (level, agreeing
    bands, margin; a cage family only with ``high`` evidence) is the diagnosis; a weaker family
    whose lines a stronger one explains (:func:`_explanation`: its fundamental on ``k f +- m``
    spacings of that family or a shaft harmonic, the cage period of its train, or a harmonic
    shared with it, 3 BPFO = 2 BPFI on the 6205) is ``explained``; an unexplained one is a
    ``second finding`` only with ``medium`` evidence or better (``high`` for a cage), else
    ``weak``. Two families with evidence of the same level (or a shared harmonic with evidence
    as strong as the diagnosis's) give :data:`CANNOT_TELL`.

    Parameters
    ----------
    table : DataFrame
        ``analyze_signal``'s table (its ``detected`` column was computed at
        ``pfa / n_tests``).
    families : sequence of FaultFamily
    pfa : float
        Record-wise false-alarm probability.
    n_tests : int
        Number of family x band tests.
    fr : float
        Shaft rate (Hz), for the explanation of coincident lines.
    df_hz : float, default 0
        Bin spacing of the envelope spectra (Hz): two lines within ``max(2 df, 0.2 %)`` are
        one line.

    Returns
    -------
    Verdict
        One :class:`FamilyVerdict` per family, the confidence and the candidates; ``pfa_test``
        = ``pfa / n_tests``.
    """
    env = table[table["quantity"] == "envelope_spectrum"]
    out = [_family_verdict(fam, env[env["base"] == fam.name], float(df_hz)) for fam in families]
    out, confidence, candidates = _decide(out, {f.name: f for f in families}, float(fr),
                                          float(df_hz))
    return Verdict(tuple(out), float(pfa), int(n_tests), float(pfa) / max(int(n_tests), 1),
                   confidence, candidates)
