"""Fault diagnosis on top of :mod:`bearing_envelope.signal`: fault families and their line
search, the detection statistic and its false-alarm threshold, the whole analysis chain of one
signal, and its plots.

- :mod:`.faults`: fault families (BPFO, BPFI, BSF, 2 x BSF, FTF), line search, verdict;
- :mod:`.detection`: line-to-floor statistic, exact threshold, false-alarm rates;
- :mod:`.speed`: the shaft rate measured from the raw spectrum's shaft harmonics;
- :mod:`.lines`: raw-spectrum terms and harmonic/sideband amplitudes of a base line;
- :mod:`.analysis`: :func:`analyze_signal`, bands x envelope x lines in one call;
- :mod:`.records`: :func:`analyze_record`, one measured record (an array or a record already
  read) with every decision of ``bearing-envelope analyze``, a typed :class:`RecordAnalysis`;
- :mod:`.batch`: :func:`analyze_records`, many records in parallel, the verdict table;
- :mod:`.plots`: figures of an analysis (matplotlib, imported on demand).
"""

from .analysis import COLUMNS, analyze_signal, fault_frequency_map
from .options import KURTOGRAM_MIN_ORDERS, AnalysisOptions, options_with
from .faults import (CANNOT_TELL, CONFIDENCE_LEVELS, DEFAULT_SEARCH_PERCENT, FamilyVerdict,
                     FaultFamily, Verdict, evidence_level, fault_families, fault_verdict,
                     search_lines)
from .lines import harmonic_amplitudes, raw_terms
from .records import RECORD_OPTIONS, RecordAnalysis, RecordFailure, analyze_record
from .batch import analyze_records, verdict_table
from .speed import ShaftRate, estimate_shaft_rate

__all__ = ["COLUMNS", "KURTOGRAM_MIN_ORDERS", "AnalysisOptions", "analyze_signal", "options_with",
           "fault_frequency_map", "CANNOT_TELL", "CONFIDENCE_LEVELS", "DEFAULT_SEARCH_PERCENT",
           "FamilyVerdict", "FaultFamily", "Verdict", "evidence_level", "fault_families",
           "fault_verdict",
           "search_lines", "harmonic_amplitudes", "raw_terms", "ShaftRate",
           "estimate_shaft_rate", "RECORD_OPTIONS", "RecordAnalysis", "RecordFailure",
           "analyze_record", "analyze_records", "verdict_table"]
