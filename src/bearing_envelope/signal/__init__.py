"""Envelope analysis of bearing signals: spectra, fast kurtogram, spectral kurtosis, bands,
Hilbert envelope, harmonic and sideband amplitudes, and the whole chain in one call.

Usable on the simulated pressure histories and on measured vibration recordings alike.
Plot helpers live in :mod:`bearing_envelope.signal.plots` (imported on demand: matplotlib).
"""

from .analysis import COLUMNS, analyze_signal, fault_frequency_map
from .faults import (DEFAULT_SEARCH_PERCENT, FaultFamily, FamilyVerdict, Verdict,
                     fault_families, fault_verdict, search_lines)
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
from .envelope import (bandpass, envelope, envelope_spectrum, harmonic_amplitudes, peak_value,
                       settling_samples)
from .kurtogram import Kurtogram, fast_kurtogram, kurtogram_levels, max_kurtogram_level
from .sk import spectral_kurtosis
from .spectrum import amplitude_at, amplitude_spectrum, raw_terms

__all__ = [
    "COLUMNS",
    "DEFAULT_BANDS",
    "DEFAULT_SEARCH_PERCENT",
    "FamilyVerdict",
    "FaultFamily",
    "NYQUIST_MARGIN",
    "Kurtogram",
    "Verdict",
    "amplitude_at",
    "amplitude_spectrum",
    "analyze_signal",
    "band_fixed",
    "band_fraction",
    "band_from_kurtogram",
    "band_orders",
    "bandpass",
    "clamp_band",
    "envelope",
    "envelope_spectrum",
    "fast_kurtogram",
    "fault_families",
    "fault_frequency_map",
    "fault_verdict",
    "harmonic_amplitudes",
    "kurtogram_levels",
    "max_kurtogram_level",
    "peak_value",
    "raw_terms",
    "resolve_band",
    "settling_samples",
    "search_lines",
    "spectral_kurtosis",
]
