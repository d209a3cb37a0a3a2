"""Figures of the sweep (matplotlib, Agg), numbered after the source study.

Each ``fig_*`` function draws one figure from tables or case objects and saves a PNG atomically;
the ``draw_*`` functions behind the figures whose layout has been wrong before return the
:class:`matplotlib.figure.Figure` unsaved, so tests can check what is drawn. No function knows
where the workflow keeps its results: every input is a path or an object passed in.

Fig. 4 pressure maps, 5 time histories, 6 peak pressure vs load and depth, 7 raw spectrum,
8 raw terms, 9 kurtogram and spectral kurtosis, 10 demodulation bands per case,
11 envelope spectrum, 12-20 harmonic amplitude vs depth per load for each band.

Contact pressures are those of a linear-elastic, frictionless half-space: no plasticity, so peaks
far above the ~4 GPa of ISO 76's static capacity are shown as computed, and peaks at the defect
rim and the roller ends depend on the grid (:data:`ELASTIC_NOTE` is printed on Figs 4-6).

One concern per module: :mod:`.common` (example cases, notes, :func:`save_figure`, labels),
:mod:`.pressure` (Figs 4-6), :mod:`.spectra` (Figs 7, 9-20), :mod:`.diagnosability` (the
diagnosability maps), :mod:`.sweep` (:func:`make_figures`); this module selects the Agg backend
before any of them imports pyplot, and re-exports.
"""
import matplotlib

matplotlib.use("Agg")  # before any module of the package imports pyplot

# the modules import pyplot: after the backend is chosen
from .common import (ELASTIC_NOTE, LINE_NAME, STUDY_EXAMPLES, depth_label,  # noqa: E402
                     example_pairs, location_line, save_figure)
from .diagnosability import draw_diagnosability_map, fig_diagnosability_maps  # noqa: E402
from .pressure import (GRID_NOTE, TIME_HISTORY_PERIODS, draw_peak_pressure,  # noqa: E402
                       draw_pressure_maps, draw_time_histories, fig_peak_pressure,
                       fig_pressure_maps, fig_time_histories)
from .spectra import (ORDERS_VS_DEPTH, draw_band_limits, draw_kurtogram,  # noqa: E402
                      fig_band_limits, fig_envelope_spectrum, fig_harmonics_vs_depth,
                      fig_kurtogram, fig_raw_spectrum, sk_window)
from .sweep import make_figures  # noqa: E402

__all__ = [
    "STUDY_EXAMPLES",
    "ELASTIC_NOTE",
    "example_pairs",
    "sk_window",
    "save_figure",
    "draw_pressure_maps",
    "draw_time_histories",
    "draw_peak_pressure",
    "draw_kurtogram",
    "draw_band_limits",
    "draw_diagnosability_map",
    "fig_pressure_maps",
    "fig_time_histories",
    "fig_peak_pressure",
    "fig_raw_spectrum",
    "fig_kurtogram",
    "fig_band_limits",
    "fig_envelope_spectrum",
    "fig_harmonics_vs_depth",
    "make_figures",
    "fig_diagnosability_maps",
    "GRID_NOTE",
    "ORDERS_VS_DEPTH",
    "TIME_HISTORY_PERIODS",
    "LINE_NAME",
    "depth_label",
    "location_line",
]
