"""Signal processing for bearing diagnostics, free of bearing words: spectra, fast kurtogram,
spectral kurtosis, bands, band-pass and Hilbert envelope.

Usable on the simulated pressure histories and on measured vibration recordings alike. What
knows about fault families (line search, verdicts, the whole analysis chain in
:func:`~bearing_envelope.diagnosis.analysis.analyze_signal`) lives one layer up, in
:mod:`bearing_envelope.diagnosis`; its public names are still reachable from here
(``from bearing_envelope.signal import analyze_signal``) for code written before the split.
"""

import importlib

from .bands import (
    DEFAULT_BANDS,
    NYQUIST_MARGIN,
    band_fixed,
    band_fraction,
    band_from_kurtogram,
    band_orders,
    clamp_band,
    resolve_band,
)
from .envelope import bandpass, envelope, envelope_spectrum, peak_value, settling_samples
from .kurtogram import Kurtogram, fast_kurtogram, kurtogram_levels, max_kurtogram_level
from .sk import spectral_kurtosis
from .infogram import Infogram, infogram
from .bandselect import infogram_band, protrugram_band
from .spectrum import amplitude_at, amplitude_spectrum, prewhiten

#: Names that moved to :mod:`bearing_envelope.diagnosis` (module of each), still importable
#: from here. Resolved on first use (PEP 562), so importing ``signal`` never imports the layer
#: above it.
MOVED_TO_DIAGNOSIS = {
    "COLUMNS": "analysis",
    "analyze_signal": "analysis",
    "fault_frequency_map": "analysis",
    "DEFAULT_SEARCH_PERCENT": "faults",
    "FaultFamily": "faults",
    "FamilyVerdict": "faults",
    "Verdict": "faults",
    "fault_families": "faults",
    "fault_verdict": "faults",
    "search_lines": "faults",
    "harmonic_amplitudes": "lines",
    "raw_terms": "lines",
}

__all__ = [
    "DEFAULT_BANDS",
    "NYQUIST_MARGIN",
    "Infogram",
    "Kurtogram",
    "amplitude_at",
    "amplitude_spectrum",
    "band_fixed",
    "band_fraction",
    "band_from_kurtogram",
    "band_orders",
    "bandpass",
    "clamp_band",
    "envelope",
    "envelope_spectrum",
    "fast_kurtogram",
    "infogram",
    "infogram_band",
    "kurtogram_levels",
    "max_kurtogram_level",
    "peak_value",
    "prewhiten",
    "protrugram_band",
    "resolve_band",
    "settling_samples",
    "spectral_kurtosis",
]


def __getattr__(name):
    """The names of :data:`MOVED_TO_DIAGNOSIS`, from their new module."""
    if name in MOVED_TO_DIAGNOSIS:
        module = importlib.import_module(f"bearing_envelope.diagnosis.{MOVED_TO_DIAGNOSIS[name]}")
        return getattr(module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
