"""A family's evidence in one record: its lines over the bands (:class:`FamilyVerdict`), which
bands are distinct (:func:`distinct_bands`) and the confidence level (:func:`evidence_level`)
with its thresholds."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from .families import FaultFamily, SIDEBAND_SPACING, display_name

__all__ = ["CANNOT_TELL", "CONFIDENCE_LEVELS", "FamilyVerdict", "distinct_bands",
           "evidence_level"]


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


def _tolerance(f0: float, df_hz: float) -> float:
    """Half-width (Hz) within which two found lines are the same line: ``max(2 df,
    AGREE_PERCENT % of f0)``."""
    return max(2.0 * df_hz, AGREE_PERCENT / 100.0 * abs(f0))


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
