"""Diagnosability maps: the detection probability over load and depth, one map per band."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...io import atomic_dir
from .common import LINE_NAME, depth_label, location_line, save_figure

__all__ = ["draw_diagnosability_map", "fig_diagnosability_maps"]


def draw_diagnosability_map(g: pd.DataFrame, band: str, *, vmax: float | None = None,
                            line_name: str = LINE_NAME):
    """Heat map of the BPFI detection statistic of one band: one panel per load, depth x SNR
    cells coloured by the statistic (dB) and marked where detected. Panels share the SNR axis,
    labelled once, so no label runs into the next panel. ``line_name``: the fault line tested
    (a location sweep: the location's, e.g. ``"BPFO (outer_race)"``).

    Parameters
    ----------
    g : pandas.DataFrame
        The diagnosability rows of one band (and location): ``load_kN``, ``depth_um``,
        ``snr_db``, ``statistic_db`` and ``detected``; one row per cell.
    band : str
        Band name (title).
    vmax : float, optional, keyword-only
        Top of the colour scale, dB (bottom 0 dB); default the largest statistic of ``g``.
    line_name : str, keyword-only, default "BPFI"
        The fault line tested (title, colour-bar label).

    Returns
    -------
    matplotlib.figure.Figure
        One panel per load; not saved.
    """
    loads = sorted(g["load_kN"].unique())
    if vmax is None:
        vmax = float(np.nanmax(g["statistic_db"])) if len(g) else 1.0
    fig, axes = plt.subplots(1, len(loads), figsize=(3.6 * len(loads) + 1.2, 3.8), squeeze=False,
                             sharey=True, layout="constrained")
    im = None
    for ax, load in zip(axes[0], loads):
        s = g[g["load_kN"] == load]
        stat = s.pivot_table(index="snr_db", columns="depth_um", values="statistic_db")
        det = s.pivot_table(index="snr_db", columns="depth_um", values="detected")
        im = ax.imshow(stat.to_numpy(), origin="lower", aspect="auto", cmap="magma",
                       vmin=0.0, vmax=vmax)
        ax.set_xticks(range(stat.shape[1]), [f"{d:g}" for d in stat.columns], fontsize=7)
        ax.set_yticks(range(stat.shape[0]), [f"{v:g}" for v in stat.index])
        for i in range(stat.shape[0]):
            for j in range(stat.shape[1]):
                if bool(det.to_numpy()[i, j]):
                    ax.text(j, i, "✓", ha="center", va="center", color="cyan", fontsize=11)
        ax.set_xlabel(depth_label(g))
        ax.set_title(f"{load:g} kN")
    axes[0, 0].set_ylabel("SNR (dB)")
    fig.colorbar(im, ax=axes[0].tolist(), label=f"{line_name.split()[0]} line / background (dB)")
    fig.suptitle(f"{line_name} detection in the synthetic acceleration, band '{band}' "
                 f"(✓ = detected)")
    return fig


def fig_diagnosability_maps(df: pd.DataFrame, outdir) -> list[Path]:
    """Heat maps of the BPFI detection statistic (:func:`draw_diagnosability_map`), one PNG per
    band, written to a temporary folder, then renamed to ``outdir``.

    Parameters
    ----------
    df : pandas.DataFrame
        The sweep's diagnosability table (columns as in :func:`draw_diagnosability_map`, plus
        ``band`` and, in a location sweep, ``location``: then one map per band and location).
        All maps share one colour scale, 0 dB to the largest statistic.
    outdir : str or os.PathLike
        Output folder (replaced whole, :func:`bearing_envelope.io.atomic_dir`).

    Returns
    -------
    list of pathlib.Path
        ``outdir/diagnosability_{band}.png`` (``_{band}_{location}.png``) per map.
    """
    outdir = Path(outdir)
    with atomic_dir(outdir) as tmp:
        written = []
        vmax = float(np.nanmax(df["statistic_db"])) if len(df) else 1.0
        if "location" not in df.columns:
            for band, g in df.groupby("band", sort=False):
                written.append(save_figure(draw_diagnosability_map(g, band, vmax=vmax),
                                           tmp / f"diagnosability_{band}.png"))
        else:  # a location sweep: one map per band and location (its own fault line)
            for (band, loc), g in df.groupby(["band", "location"], sort=False):
                name = f"{location_line(loc)} ({loc})"
                written.append(save_figure(
                    draw_diagnosability_map(g, band, vmax=vmax, line_name=name),
                    tmp / f"diagnosability_{band}_{loc}.png"))
    return [outdir / p.name for p in written]
