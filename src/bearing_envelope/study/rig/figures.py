"""The rig's figures: records beside their simulated twins, two columns (measured left,
simulated right), one row per record; matplotlib imported on first use."""

from __future__ import annotations

import numpy as np

from ...signal.cycles import FLOOR_PERCENTILE, element_windows, synchronous_average
from .events import ELEMENT_BINS, record_pairs, squared_envelope
from .records import read_samples

__all__ = ["pair_figure", "finish_figure", "plot_side_by_side", "plot_element_folds"]


def pair_figure(n_rows: int, row_height_in: float):
    """A figure of ``n_rows`` x 2 axes (measured left, simulated right), matplotlib imported on
    first use (~1.5 s, only to draw).

    Parameters
    ----------
    n_rows : int
        Rows (records).
    row_height_in : float
        Height of a row, inch.

    Returns
    -------
    (matplotlib.figure.Figure, numpy.ndarray)
        The figure and its axes, shape ``(n_rows, 2)``, sharing x.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt.subplots(n_rows, 2, figsize=(11, row_height_in * n_rows + 0.6), squeeze=False,
                        sharex=True)


def finish_figure(fig, axes, out_png, xlabel: str) -> str:
    """Label the bottom row, lay the figure out, write it and close it.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (:func:`pair_figure`).
    axes : numpy.ndarray
        Its axes (:func:`pair_figure`).
    out_png : path
        The file written.
    xlabel : str
        Label of the bottom row's x axes.

    Returns
    -------
    str
        ``out_png``.
    """
    import matplotlib.pyplot as plt

    for ax in axes[-1]:
        ax.set_xlabel(xlabel, fontsize=7)
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    plt.close(fig)
    return str(out_png)


def plot_side_by_side(card, conditions, sim_dir, out_png, *, max_order: float = 12.0) -> str:
    """Envelope spectra (orders of fr) of measured and simulated records, side by side: one
    row per record, each in its own best band of its truth family (``card``'s bands).

    Parameters
    ----------
    card : pandas.DataFrame
        :func:`scorecard`'s result.
    conditions : sequence of RigCondition
        The records to draw (one row each).
    sim_dir : path
        Folder of the simulated records (``<name>_sim.npz``).
    out_png : path
        The PNG written.
    max_order : float
        Highest order of the shaft rate on the frequency axis.

    Returns
    -------
    str
        The figure's path.
    """
    from ...signal.envelope import envelope_spectrum

    fig, axes = pair_figure(len(conditions), 1.7)
    for i, j, c, side, path in record_pairs(conditions, sim_dir):
        row = card[card.record == c.name].iloc[0]
        x = read_samples(path)
        lo, hi, fr = row[f"{side}_band_low_hz"], row[f"{side}_band_high_hz"], row.meas_fr_hz
        ax = axes[i, j]
        if lo is None or not np.isfinite(lo):
            ax.text(0.5, 0.5, "no band", transform=ax.transAxes, ha="center")
            continue
        f, a = envelope_spectrum(x - x.mean(), c.fs_hz, (lo, hi), clamp=True,
                                 fmax_hz=max_order * fr)[:2]
        ax.plot(f / fr, a, lw=0.6, color="k" if side == "meas" else "C1")
        ax.set_xlim(0, max_order)
        ax.set_title(f"{c.name} {'measured' if side == 'meas' else 'simulated'}: "
                     f"{row[side + '_diagnosis'] or 'nothing'} "
                     f"({row[side + '_confidence'] if row[side + '_diagnosis'] else '-'}), "
                     f"band {lo:.0f}-{hi:.0f} Hz", fontsize=7)
        ax.tick_params(labelsize=6)
    return finish_figure(fig, axes, out_png, "envelope frequency / fr (orders)")


def plot_element_folds(conditions, sim_dir, out_png) -> str:
    """Squared-envelope averages at the cage's rate (one turn: each rolling element's event) of
    outer-race records, measured beside simulated, in fs/4-3fs/8: one row per record.

    Parameters
    ----------
    conditions : sequence of RigCondition
        Outer-race records (one row each).
    sim_dir : path
        The simulated records (``<name>_sim.npz``).
    out_png : path
        The figure.

    Returns
    -------
    str
        The figure's path.
    """
    fig, axes = pair_figure(len(conditions), 1.6)
    for i, j, c, side, path in record_pairs(conditions, sim_dir):
        x = read_samples(path)
        e, rate = squared_envelope(x, c.fs_hz, c.rates["bpfo"])
        z = c.bearing.n_rollers
        avg = synchronous_average(e, c.fs_hz, rate / z, bins=ELEMENT_BINS * z)
        floor = np.percentile(avg, FLOOR_PERCENTILE)
        avg = 1.0 + np.concatenate(element_windows(avg, z)) / floor
        ax = axes[i, j]
        ax.plot(np.arange(avg.size) / ELEMENT_BINS, avg, lw=0.7,
                color="k" if side == "meas" else "C1")
        for k in range(1, z):
            ax.axvline(k, color="0.8", lw=0.4)
        ax.set_title(f"{c.name} {'measured' if side == 'meas' else 'simulated'}", fontsize=7)
        ax.tick_params(labelsize=6)
    for ax in axes[:, 0]:
        ax.set_ylabel("over floor", fontsize=7)
    return finish_figure(fig, axes, out_png,
                         "cage turn, in rolling-element spacings (each element's event)")
