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
only the fundamental when a single harmonic is asked for) are detected there. Testing F
families in B bands makes ``F x B`` tests; each line is tested at ``pfa / (F x B)``
(Bonferroni), so that on a record without any fault line the probability of any false
"detected" in the verdict is at most ``pfa`` (default 1 %), whatever the dependence between
the bands. Real envelope spectra are crowded (shaft harmonics, the fault's own sidebands, and
kinematic coincidences: BPFO = n FTF, BPFI = n (fr - FTF)), so the families detected are
ranked by their margin above the threshold; a weaker family whose fundamental falls on a line
of a stronger detected family (``k f``, k <= 5, or ``k f +- m`` times that family's own
sideband spacing, |m| <= 3) or on a shaft harmonic is marked as explained by it. The
**diagnosis** is the strongest family; other unexplained families are listed as "also above
threshold".
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from ..signal.spectrum import amplitude_at, default_tolerance

__all__ = [
    "DEFAULT_SEARCH_PERCENT",
    "FAMILY_LABELS",
    "SIDEBAND_SPACING",
    "FaultFamily",
    "FamilyVerdict",
    "Verdict",
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
                items.append(("bsf2", 2.0 * v))
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
    from .detection import detection_statistic

    # only [0.5, 1.5] x line (+ the search window and the local-maximum check's neighbours)
    # enters the statistic: pass that slice, not the whole spectrum
    df = f[1] - f[0]
    i0 = max(0, int(math.floor((0.5 * line_hz - half) / df)) - 2)
    i1 = min(f.size, int(math.ceil((1.5 * line_hz + half) / df)) + 3)
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
    n_harmonics: int = 2,
    n_sidebands: int = 1,
    search_percent: float = DEFAULT_SEARCH_PERCENT,
    tolerance_hz: float | None = None,
    pfa: float = 0.01,
    interpolate: bool = False,
    window="hann",
    n: int | None = None,
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
    n_harmonics : int, default 2
        Harmonics k = 1..K.
    n_sidebands : int, default 1
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
        jmax = int(math.ceil(1.5 * (n_harmonics + 1))) + 1
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

    half1 = float(tolerance_hz) if tolerance_hz is not None else p / 100.0 * F
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


@dataclass(frozen=True)
class FamilyVerdict:
    """The decision on one fault family over all bands of a record.

    Attributes
    ----------
    family, label : str
        Family name and what a detection means.
    detected : bool
        Fundamental and second harmonic detected in at least one band.
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
        For a detected family whose fundamental falls on a line of a stronger detected family
        or on a shaft harmonic: that line (``"BPFI - 5 fr"``, ``"3 fr"``).
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

    @property
    def margin_db(self) -> float:
        """``floor_ratio_db - threshold_db``."""
        return self.floor_ratio_db - self.threshold_db

    def summary(self) -> str:
        """One line, e.g. ``inner race fault: BPFI 161.7 Hz, harmonics 1-3, fr sidebands,
        37.1 dB above floor (threshold 12.0 dB), in band kurtogram (0-5880 Hz)``."""
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


@dataclass(frozen=True)
class Verdict:
    """Per-record verdict of :func:`fault_verdict`.

    Attributes
    ----------
    families : tuple of FamilyVerdict
        One per fault family, in the order of the table.
    pfa : float
        Record-wise false-alarm probability (any family in any band).
    n_tests : int
        Family x band tests; each line is tested at ``pfa_test = pfa / n_tests``.
    pfa_test : float
        The per-test false-alarm probability behind every ``threshold_db``.
    statistic : str
        Statement of the statistic, the threshold and the decision rule.
    """

    families: tuple[FamilyVerdict, ...]
    pfa: float
    n_tests: int
    pfa_test: float
    statistic: str = field(default=(
        "S = 20 log10(peak / floor), floor = median amplitude over [0.5, 1.5] x line without "
        "the family's lines and the shaft harmonics; a line is detected if S > "
        "threshold_db(pfa / n_tests, bins searched) (diagnosis.threshold_db, Rayleigh noise) "
        "and it is a local maximum; a family is detected in a band if its fundamental and "
        "its second harmonic are"))

    @property
    def detected(self) -> tuple[FamilyVerdict, ...]:
        """The families detected and not explained by a stronger one, strongest first."""
        return tuple(sorted((v for v in self.families if v.detected and not v.explained_by),
                            key=lambda v: -v.margin_db))

    @property
    def diagnosis(self) -> FamilyVerdict | None:
        """The strongest detected family, or None."""
        d = self.detected
        return d[0] if d else None

    def summary_lines(self) -> list[str]:
        """The diagnosis line, then ``also above threshold`` and ``explained`` lines; or one
        ``no bearing fault line detected`` line."""
        d = self.detected
        if not d:
            best = max((v for v in self.families if v.band is not None),
                       key=lambda v: v.margin_db, default=None)
            tail = "" if best is None else (
                f" (closest: {display_name(best.family)} {best.floor_ratio_db:.1f} dB against "
                f"{best.threshold_db:.1f} dB in band {best.band}, harmonics detected "
                f"{_ranges(best.harmonics) if best.harmonics else 'none'})")
            return [f"no bearing fault detected at a record-wise false-alarm probability of "
                    f"{self.pfa:g}{tail}"]
        lines = [d[0].summary()]
        lines += [f"also above threshold: {v.summary()}" for v in d[1:]]
        lines += [f"explained: {v.summary()}" for v in self.families
                  if v.detected and v.explained_by]
        return lines

    def to_dict(self) -> dict:
        """Plain JSON-able form."""
        fams = []
        for v in self.families:
            d = {k: getattr(v, k) for k in v.__dataclass_fields__}
            d["harmonics"] = list(v.harmonics)
            d["bands_detected"] = list(v.bands_detected)
            for k, x in d.items():
                if isinstance(x, float) and not math.isfinite(x):
                    d[k] = None
            fams.append(d)
        diag = self.diagnosis
        return {"diagnosis": None if diag is None else diag.family,
                "diagnosis_label": "no fault" if diag is None else diag.label,
                "pfa": self.pfa, "n_tests": self.n_tests, "pfa_test": self.pfa_test,
                "statistic": self.statistic, "summary": self.summary_lines(), "families": fams}


def _explanation(v: FamilyVerdict, stronger: Sequence[tuple[FamilyVerdict, FaultFamily]],
                 fam: FaultFamily, fr: float, half: float) -> str | None:
    """The line of a stronger family (``k f``, k <= 5, or ``k f +- m`` times its own sideband
    spacing, |m| <= 3, scaled by its speed ratio) or the shaft harmonic on which ``v``'s
    fundamental falls (within ``half``), or None."""
    f0 = v.frequency_hz
    for sv, sfam in stronger:
        s = sv.frequency_hz / sfam.frequency_hz
        sp = s * sfam.sideband_hz if sfam.sideband_hz else 0.0
        for k in range(1, 6):
            for m in (range(-3, 4) if sp else (0,)):
                c = k * sv.frequency_hz + m * sp
                if abs(f0 - c) <= half:
                    head = display_name(sv.family) if k == 1 else f"{k} {display_name(sv.family)}"
                    if m == 0:
                        return head
                    return (f"{head} {'+' if m > 0 else '-'} {abs(m)} "
                            f"{display_name(sfam.sideband_name)}")
    k = round(f0 / fr)
    if k >= 1 and abs(f0 - k * fr) <= half:
        return f"{k} fr"
    return None


def fault_verdict(table, families: Sequence[FaultFamily], *, pfa: float, n_tests: int,
                  fr: float, search_percent: float = DEFAULT_SEARCH_PERCENT) -> Verdict:
    """Verdict per family from the envelope rows of an :func:`analyze_signal` table.

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
    search_percent : float
        The fundamental's search half-width (percent), the tolerance of a coincidence.
    """
    env = table[table["quantity"] == "envelope_spectrum"]
    out = []
    for fam in families:
        rows = env[env["base"] == fam.name]
        fund = rows[(rows["order"] == 1) & (rows["sideband"] == 0)]
        fund = fund[np.isfinite(fund["floor_ratio_db"].to_numpy(dtype=float))]
        if fund.empty:
            out.append(FamilyVerdict(fam.name, fam.label, False, None, math.nan, math.nan,
                                     math.nan, math.nan, math.nan, math.nan, (), None, ()))
            continue
        ok_bands = []
        for band, g in rows.groupby("band", sort=False):
            det = g["detected"].fillna(False).astype(bool)
            h = g["sideband"] == 0
            k1 = det[h & (g["order"] == 1)].any()
            has2 = (h & (g["order"] == 2)).any()
            k2 = det[h & (g["order"] == 2)].any()
            if k1 and (k2 or not has2):
                ok_bands.append(band)
        det_rows = fund[fund["band"].isin(ok_bands)]
        pick = det_rows if not det_rows.empty else fund
        best = pick.loc[pick["floor_ratio_db"].astype(float).idxmax()]
        band = best["band"]
        inb = rows[rows["band"] == band]
        found = inb[inb["detected"].fillna(False).astype(bool)]
        harmonics = tuple(int(k) for k in sorted(set(found.loc[found["sideband"] == 0, "order"])))
        sb = fam.sideband_name if (found["sideband"] != 0).any() else None
        out.append(FamilyVerdict(
            fam.name, fam.label, bool(ok_bands), str(band), float(best["band_low_hz"]),
            float(best["band_high_hz"]), float(best["frequency_hz"]), float(best["amplitude"]),
            float(best["floor_ratio_db"]), float(best["threshold_db"]), harmonics, sb,
            tuple(str(b) for b in ok_bands)))
    # coincidences: strongest first; a weaker family on a stronger one's line is explained
    by_fam = {fam.name: fam for fam in families}
    order = sorted((v for v in out if v.detected), key=lambda v: -v.margin_db)
    accepted: list[tuple[FamilyVerdict, FaultFamily]] = []
    explained: dict[str, str] = {}
    for v in order:
        fam = by_fam[v.family]
        why = _explanation(v, accepted, fam, fr, search_percent / 100.0 * fam.frequency_hz)
        if why:
            explained[v.family] = why
        else:
            accepted.append((v, fam))
    out = [replace(v, explained_by=explained.get(v.family)) for v in out]
    return Verdict(tuple(out), float(pfa), int(n_tests), float(pfa) / max(int(n_tests), 1))
