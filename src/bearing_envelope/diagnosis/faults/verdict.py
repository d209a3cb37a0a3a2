"""The per-record verdict (:class:`Verdict`, :func:`fault_verdict`): which family is explained by
a stronger one, the diagnosis, a second finding, or :data:`CANNOT_TELL`."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

from .evidence import (CAGE_FAMILY, CAGE_MAX_DIVISOR, CANNOT_TELL, EXPLAIN_MAX_ORDER,
                       EXPLAIN_MAX_SIDEBAND, FamilyVerdict, RIVAL_MARGIN_DB, _RANK, _family_verdict,
                       _ranges, _tolerance, evidence_level)
from .families import FaultFamily, display_name

__all__ = ["Verdict", "fault_verdict"]


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
        The families the table was searched for (:func:`fault_families` of the same
        frequencies), in its order.
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

    Examples
    --------
    An outer-race fault of a 6205 at 29.95 Hz: impacts at BPFO (107.36 Hz) ringing at 3 kHz
    in noise, searched for BPFO and BPFI over the default bands:

    >>> import numpy as np
    >>> from bearing_envelope.diagnosis import (AnalysisOptions, analyze_signal,
    ...                                         fault_families, fault_verdict)
    >>> fs, fr, freqs = 12000.0, 29.95, {"bpfo": 107.36, "bpfi": 162.19}
    >>> t = np.arange(2**15) / fs
    >>> tau = t % (1 / freqs["bpfo"])
    >>> rng = np.random.default_rng(1)
    >>> x = (np.exp(-tau / 2e-3) * np.sin(2 * np.pi * 3000 * tau)
    ...      + 0.2 * rng.standard_normal(t.size))
    >>> table = analyze_signal(x, fs, fr=fr, fault_frequencies=freqs)
    >>> families = fault_families(freqs, fr=fr)
    >>> bands = table[table.quantity == "envelope_spectrum"]["band"].nunique()
    >>> v = fault_verdict(table, families, pfa=AnalysisOptions().pfa,
    ...                   n_tests=len(families) * bands, fr=fr, df_hz=fs / x.size)
    >>> [(f.family, f.detected, f.role) for f in v.families]
    [('bpfo', True, 'diagnosis'), ('bpfi', False, None)]
    """
    env = table[table["quantity"] == "envelope_spectrum"]
    out = [_family_verdict(fam, env[env["base"] == fam.name], float(df_hz)) for fam in families]
    out, confidence, candidates = _decide(out, {f.name: f for f in families}, float(fr),
                                          float(df_hz))
    return Verdict(tuple(out), float(pfa), int(n_tests), float(pfa) / max(int(n_tests), 1),
                   confidence, candidates)
