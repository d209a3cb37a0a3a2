"""The one vocabulary of the tidy tables: column names, band strategies, quantity names.

Used by :mod:`bearing_envelope.study.tables` (the sweep's tables and ``bearing-envelope analyze``
through :func:`bearing_envelope.study.tables.tidy_from_analysis`) and by :mod:`bearing_envelope.io`
(the readers check the columns). Documented once, in ``docs/file-format.md`` ("Tidy tables").
A leaf module: it imports nothing from the package.
"""

from __future__ import annotations

import math

__all__ = ["TIDY_COLUMNS", "TIDY_EXTRA_COLUMNS", "TIDY_SORT", "RAW_BAND", "BAND_STRATEGIES",
           "QUANTITIES", "quantity_name", "CASE_TABLE_COLUMNS", "BAND_TABLE_COLUMNS"]

#: Columns of every tidy table, in order (documented in docs/file-format.md, "Tidy tables"):
#: ``band`` is the band's name (``analysis.bands[].name``; ``raw`` for the raw spectrum),
#: ``band_strategy`` how it was chosen (one of :data:`BAND_STRATEGIES`).
TIDY_COLUMNS = [
    "case",
    "load_kN",
    "depth_um",
    "band",
    "band_strategy",
    "band_low_hz",
    "band_high_hz",
    "quantity",
    "order",
    "sideband",
    "frequency_hz",
    "amplitude",
]

#: Optional columns that follow :data:`TIDY_COLUMNS` when present, in this order (``floor``,
#: ``floor_ratio_db``, ``threshold_db``, ``detected``: the local spectral floor of a line and its
#: detection, :mod:`bearing_envelope.diagnosis.detection.faults`; ``rel_error_est``, ``error_est``,
#: ``error_basis``: the estimated discretisation error, :mod:`bearing_envelope.study.accuracy`).
TIDY_EXTRA_COLUMNS = ["base", "target_hz", "clamped", "scaling", "signal", "floor",
                      "floor_ratio_db", "threshold_db", "detected", "rel_error_est", "error_est",
                      "error_basis"]

#: Row order of an aggregated tidy table.
TIDY_SORT = ["load_kN", "depth_um", "band", "quantity", "order", "sideband"]

#: ``band`` and ``band_strategy`` of the raw-spectrum rows.
RAW_BAND = "raw"

#: Allowed values of ``band_strategy``.
BAND_STRATEGIES = ("raw", "kurtogram", "fraction", "orders", "fixed")

#: Quantity names of the tidy tables. ``<fault>`` stands for a fault frequency's name
#: (``bpfi``, ``bpfo``, ...): ``raw_bpfi``, ``envelope_bpfi``, ...
QUANTITIES = {
    "raw_dc": "mean of the signal (raw spectrum at 0 Hz); order 0",
    "raw_fr": "raw amplitude spectrum at k x fr (sinusoid amplitude, one-sided)",
    "raw_<fault>": "raw amplitude spectrum at k x the fault frequency",
    "envelope_<fault>": "envelope spectrum at k x the fault frequency found + m x the family's "
                        "sideband spacing (fr for bpfi, ftf for bsf/bsf2; sideband m)",
    "envelope_bpfi": "sweep, inner-race cases: k x BPFI, sidebands m x fr",
    "envelope_bpfo": "sweep, outer-race cases: k x BPFO, sidebands m x fr (a check: none "
                     "expected under a steady load)",
    "envelope_2bsf": "sweep, rolling-element cases: k x 2 BSF (family bsf2), sidebands m x FTF",
    "bandpass_peak": "max |band-passed signal|; order 0",
    "kurtogram_kurtosis": "kurtosis of the best kurtogram cell (dimensionless); "
                          "frequency_hz = its centre",
}

#: The measure names of :func:`bearing_envelope.diagnosis.analyze_signal` whose tidy quantity name
#: joins a prefix and the ``base`` (``raw_spectrum`` + ``bpfi`` -> ``raw_bpfi``).
_MEASURE_PREFIX = {"raw_spectrum": "raw", "envelope_spectrum": "envelope"}

#: Fault families whose tidy name is not the family's key: 2 x BSF (family ``bsf2``) reads
#: ``2bsf`` (``envelope_2bsf``, ``raw_2bsf``).
_BASE_TIDY_NAME = {"bsf2": "2bsf"}


def quantity_name(measure: str, base=None) -> str:
    """Tidy quantity name of an ``analyze_signal`` measure and base.

    ``("raw_spectrum", "dc") -> "raw_dc"``, ``("envelope_spectrum", "bpfi") -> "envelope_bpfi"``,
    ``("envelope_spectrum", "bsf2") -> "envelope_2bsf"``; other measures (``bandpass_peak``,
    ``kurtogram_kurtosis``) keep their name.

    Parameters
    ----------
    measure : str
        An ``analyze_signal`` measure (``raw_spectrum``, ``envelope_spectrum``, ...).
    base : str, optional
        The line's base (``dc``, ``fr``, ``bpfi``, ``bsf2``, ...); required for a spectrum.

    Returns
    -------
    str
        The tidy table's quantity name.

    Raises
    ------
    ValueError
        A spectrum measure without a base.
    """
    prefix = _MEASURE_PREFIX.get(measure)
    if prefix is None:
        return str(measure)
    if base is None or (isinstance(base, float) and math.isnan(base)) or str(base) == "<NA>":
        raise ValueError(f"quantity {measure!r} needs a base (dc, fr or a fault frequency name)")
    return f"{prefix}_{_BASE_TIDY_NAME.get(str(base), base)}"



#: Columns every per-case summary table (``cases.csv``) holds (more follow them).
CASE_TABLE_COLUMNS = ["case", "load_kN", "depth_um", "p_max_peak_Pa", "p_max_defect_peak_Pa",
                      "bpfi_used_hz", "fs_hz"]

#: Columns of the band table (``bands.csv``): one row per case and band; ``strategy`` is the
#: band's strategy (``band_strategy`` in the tidy tables).
BAND_TABLE_COLUMNS = ["case", "load_kN", "depth_um", "band", "strategy", "low_hz", "high_hz",
                      "clamped"]
