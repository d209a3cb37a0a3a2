"""Fault diagnosis on top of :mod:`bearing_envelope.signal`: fault families and their line
search, the detection statistic and its false-alarm threshold, the whole analysis chain of one
signal, and its plots.

- :mod:`.faults`: fault families (BPFO, BPFI, BSF, 2 x BSF, FTF), line search, verdict;
- :mod:`.detection`: line-to-floor statistic, exact threshold, false-alarm rates;
- :mod:`.lines`: raw-spectrum terms and harmonic/sideband amplitudes of a base line;
- :mod:`.analysis`: :func:`analyze_signal`, bands x envelope x lines in one call;
- :mod:`.plots`: figures of an analysis (matplotlib, imported on demand).
"""

from .analysis import (COLUMNS, KURTOGRAM_MIN_ORDERS, AnalysisOptions, analyze_signal,
                       fault_frequency_map)
from .faults import (CANNOT_TELL, CONFIDENCE_LEVELS, DEFAULT_SEARCH_PERCENT, FamilyVerdict,
                     FaultFamily, Verdict, evidence_level, fault_families, fault_verdict,
                     search_lines)
from .lines import harmonic_amplitudes, raw_terms

__all__ = ["COLUMNS", "KURTOGRAM_MIN_ORDERS", "AnalysisOptions", "analyze_signal",
           "fault_frequency_map", "CANNOT_TELL", "CONFIDENCE_LEVELS", "DEFAULT_SEARCH_PERCENT",
           "FamilyVerdict", "FaultFamily", "Verdict", "evidence_level", "fault_families",
           "fault_verdict",
           "search_lines", "harmonic_amplitudes", "raw_terms"]
