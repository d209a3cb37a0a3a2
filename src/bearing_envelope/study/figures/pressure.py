"""Figures of the contact: pressure maps (Fig. 4), time histories (Fig. 5) and the peak pressure
against load and depth (Fig. 6)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.colors import to_rgb

from .common import ELASTIC_NOTE, _note, _per_load, _top_snapshot, save_figure

__all__ = ["GRID_NOTE", "TIME_HISTORY_PERIODS", "draw_pressure_maps", "draw_time_histories",
           "draw_peak_pressure", "fig_pressure_maps", "fig_time_histories", "fig_peak_pressure"]


#: What the peak-pressure figure's note says of the grid when the caller does not name it.
GRID_NOTE = "stored in each case file"


#: Fault periods shown by the time-history figure.
TIME_HISTORY_PERIODS = 6.0


def draw_peak_pressure(cases: pd.DataFrame, *, grid: str = GRID_NOTE):
    """Fig. 6: peak contact pressure against depth, one line per load (whole contact and defect).

    ``grid`` is printed in the elastic/grid-dependence note under the panels.

    Parameters
    ----------
    cases : pandas.DataFrame
        The per-case summary table: ``load_kN``, ``depth_um``, ``p_max_peak_Pa`` and
        ``p_max_defect_peak_Pa`` (Pa; drawn in GPa), and ``location`` (one line per location
        and load) or ``width_um`` (axis label) where the sweep has them.
    grid : str, keyword-only
        The grid spacings, as text, for :data:`ELASTIC_NOTE`.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels (whole contact, defect neighbourhood), a dotted line at 4 GPa; not saved.
    """
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2), sharey=True)
    _per_load(axes[0], cases, "p_max_peak_Pa", 1e-9)
    axes[0].set_ylabel("peak pressure (GPa)")
    axes[0].set_title("max over the whole contact")
    _per_load(axes[1], cases, "p_max_defect_peak_Pa", 1e-9)
    axes[1].set_title("max near the defect")
    for ax in axes:
        ax.axhline(4.0, color="0.4", lw=0.8, ls=":")
    axes[0].text(0.01, 4.0, " 4 GPa (ISO 76)", va="bottom", fontsize=7, color="0.3",
                 transform=axes[0].get_yaxis_transform())
    fig.suptitle("Peak contact pressure vs load and defect depth (cf. study Fig. 6)")
    fig.tight_layout()
    fig.text(0.5, -0.02, ELASTIC_NOTE.format(grid=grid), ha="center", va="top", fontsize=8,
             wrap=True, style="italic")
    return fig


def fig_peak_pressure(cases: pd.DataFrame, path, *, grid: str = GRID_NOTE) -> Path:
    """Fig. 6 (:func:`draw_peak_pressure`) saved as PNG.

    Parameters
    ----------
    cases : pandas.DataFrame
        As in :func:`draw_peak_pressure`.
    path : str or os.PathLike
        The PNG file (:func:`save_figure`).
    grid : str, keyword-only
        As in :func:`draw_peak_pressure`.

    Returns
    -------
    pathlib.Path
        ``path``, the PNG written.
    """
    return save_figure(draw_peak_pressure(cases, grid=grid), path)


def draw_pressure_maps(pairs):
    """Fig. 4: pressure fields of the most loaded roller, healthy and with the defect, per load.

    Parameters
    ----------
    pairs : sequence of (healthy Case, defect Case)
        One row of panels each (see :func:`example_pairs`): left the whole-roller (global)
        solution of the healthy case at its highest tabulated roller load, right the defect
        window of the defect case at the same load with the defect at the offset nearest the
        contact centre.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, not saved (:func:`save_figure` writes it).
    """
    pairs = list(pairs)
    fig, axes = plt.subplots(len(pairs), 2, figsize=(11, 3.3 * len(pairs)), squeeze=False)
    for row, (healthy, defect) in zip(axes, pairs):
        snaps_h = healthy.snapshots or defect.snapshots
        s = snaps_h[_top_snapshot(snaps_h)]
        p = np.asarray(s["global_pressure"]) / 1e9
        im = row[0].pcolormesh(np.asarray(s["global_y"]) * 1e3, np.asarray(s["global_x"]) * 1e3,
                               p, shading="auto", cmap="viridis")
        row[0].set_title(f"{healthy.load_kN:g} kN, {healthy.depth_um:g} µm: roller load "
                         f"{float(s['roller_load']) / 1e3:.1f} kN, peak {p.max():.2f} GPa",
                         fontsize=9)
        row[0].set_ylabel("rolling x (mm)")
        fig.colorbar(im, ax=row[0], label="pressure (GPa)")
        sd = defect.snapshots[_top_snapshot(defect.snapshots)]
        wp = np.asarray(sd["window_pressure"])
        offs = np.asarray(sd["offsets"])
        j = int(np.argmin(np.abs(offs)))
        im = row[1].pcolormesh(np.asarray(sd["window_y"]) * 1e3, np.asarray(sd["window_x"]) * 1e3,
                               wp[j] / 1e9, shading="auto", cmap="viridis")
        row[1].set_title(f"{defect.load_kN:g} kN, {defect.depth_um:g} µm at offset "
                         f"{offs[j] * 1e6:.0f} µm (defect window): peak {wp[j].max() / 1e9:.2f} GPa",
                         fontsize=9)
        fig.colorbar(im, ax=row[1], label="pressure (GPa)")
    for ax in axes[-1]:
        ax.set_xlabel("axial y (mm)")
    fig.suptitle("Contact pressure without and with the defect (cf. study Fig. 4)")
    fig.tight_layout()
    _note(fig, pairs[-1][1])
    return fig


def fig_pressure_maps(pairs, path) -> Path:
    """Fig. 4 (:func:`draw_pressure_maps`) saved as PNG.

    Parameters
    ----------
    pairs : sequence of (healthy Case, defect Case)
        As in :func:`draw_pressure_maps`.
    path : str or os.PathLike
        The PNG file (:func:`save_figure`).

    Returns
    -------
    pathlib.Path
        ``path``, the PNG written.
    """
    return save_figure(draw_pressure_maps(pairs), path)


def draw_time_histories(pairs, *, periods: float = TIME_HISTORY_PERIODS):
    """Fig. 5: p_max(t), one shaft revolution and a zoom on the largest defect event.

    Parameters
    ----------
    pairs : sequence of (healthy Case, defect Case)
        One colour per pair (load). The healthy trace is drawn dashed, on top of the defect
        trace, so both stay visible where they coincide.
    periods : float
        Width of the zoom in BPFI periods, centred on the largest event of each defect case
        (``argmax p_max_defect``); time in the zoom is relative to that event (the healthy
        trace of the same load is shown over the same times).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, not saved (:func:`save_figure` writes it).
    """
    fig, axes = plt.subplots(2, 1, figsize=(10, 7))
    for i, (healthy, defect) in enumerate(pairs):
        colour = f"C{i % 10}"
        t = np.asarray(defect.time)
        k = int(np.argmax(np.asarray(defect.p_max_defect)))
        half = 0.5 * periods / defect.bpfi
        for case, kw in ((defect, dict(ls="-", lw=1.1, zorder=2, alpha=0.9, color=colour)),
                         (healthy, dict(ls="--", lw=0.9, zorder=3, color=_darker(colour)))):
            tc = np.asarray(case.time)
            p = np.asarray(case.p_max) / 1e9
            label = f"{case.load_kN:g} kN, {case.depth_um:g} µm"
            rev = tc <= 1.0 / case.fr
            axes[0].plot(tc[rev] * 1e3, p[rev], label=label, **kw)
            z = np.abs(tc - t[k]) <= half
            axes[1].plot((tc[z] - t[k]) * 1e3, p[z], label=label, **kw)
        axes[1].set_xlim(-half * 1e3, half * 1e3)
    axes[0].set_title("one shaft revolution (healthy race dashed)", fontsize=10)
    axes[0].set_xlabel("time (ms)")
    axes[1].set_title(f"{periods:g} BPFI periods around each defect case's largest event",
                      fontsize=10)
    axes[1].set_xlabel("time from the largest defect event (ms)")
    for ax in axes:
        ax.set_ylabel("max contact pressure (GPa)")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=7, ncol=3)
    fig.suptitle("Maximum contact pressure time history (cf. study Fig. 5)")
    fig.tight_layout()
    if pairs:
        _note(fig, pairs[-1][1])
    return fig


def _darker(colour: str) -> tuple:
    return tuple(0.55 * c for c in to_rgb(colour))


def fig_time_histories(pairs, path, *, periods: float = TIME_HISTORY_PERIODS) -> Path:
    """Fig. 5 (:func:`draw_time_histories`) saved as PNG.

    Parameters
    ----------
    pairs : sequence of (healthy Case, defect Case)
        As in :func:`draw_time_histories`.
    path : str or os.PathLike
        The PNG file (:func:`save_figure`).
    periods : float, keyword-only, default 6.0
        Width of the zoom in BPFI periods.

    Returns
    -------
    pathlib.Path
        ``path``, the PNG written.
    """
    return save_figure(draw_time_histories(pairs, periods=periods), path)
