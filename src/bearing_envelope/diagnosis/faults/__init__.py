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

One concern per module: :mod:`.families` (the families and their display names),
:mod:`.search` (the line search), :mod:`.evidence` (a family's evidence and confidence),
:mod:`.verdict` (the per-record verdict); this module only re-exports.
"""

from .evidence import CANNOT_TELL, CONFIDENCE_LEVELS, FamilyVerdict, distinct_bands, evidence_level
from .families import (DEFAULT_SEARCH_PERCENT, FAMILY_LABELS, SIDEBAND_SPACING, FaultFamily,
                       display_name, fault_families)
from .search import search_lines
from .verdict import Verdict, fault_verdict

__all__ = [
    "CANNOT_TELL",
    "CONFIDENCE_LEVELS",
    "DEFAULT_SEARCH_PERCENT",
    "FAMILY_LABELS",
    "SIDEBAND_SPACING",
    "FaultFamily",
    "FamilyVerdict",
    "Verdict",
    "display_name",
    "distinct_bands",
    "evidence_level",
    "fault_families",
    "fault_verdict",
    "search_lines",
]
