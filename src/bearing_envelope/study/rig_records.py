"""What the virtual rig reads from a CWRU record: its samples and meta, and the bearing's event
rates at its shaft rate (shared by :mod:`.rig` and :mod:`.rig_events`)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..physics.catalogue import bearing_geometry
from ..physics.kinematics import bearing_rates

__all__ = ["read_record", "rig_rates", "record_pairs", "pair_figure", "save_figure", "RIG_BEARING"]

#: The drive-end bearing of the CWRU rig (SKF 6205-2RS JEM, as in every record's meta
#: ``geometry``): its catalogue geometry (``data/bearings.yaml``; ``n_rollers``, diameters in
#: mm, contact angle in degrees).
RIG_BEARING = bearing_geometry("6205")


def read_record(path: str) -> tuple[np.ndarray, dict]:
    """A record's samples and meta (``x`` and ``meta_json`` of its ``.npz``; never unpickled).

    Parameters
    ----------
    path : str
        The ``.npz`` record.

    Returns
    -------
    (numpy.ndarray, dict)
        The samples (float) and the parsed meta.
    """
    with np.load(path, allow_pickle=False) as z:
        return np.asarray(z["x"], dtype=float), json.loads(str(z["meta_json"]))


def rig_rates(fr: float) -> dict:
    """The rig bearing's event rates at a shaft rate.

    Parameters
    ----------
    fr : float
        Shaft rate, Hz.

    Returns
    -------
    dict
        ``bpfo``, ``bpfi``, ``bsf``, ``bsf2`` (2 x BSF), Hz.
    """
    b = RIG_BEARING
    r = bearing_rates(fr, b["n_rollers"], b["roller_diameter_mm"], b["pitch_diameter_mm"],
                      b["contact_angle_deg"])
    return {k: r[k] for k in ("bpfo", "bpfi", "bsf", "bsf2")}


def record_pairs(conditions, sim_dir):
    """Each record and its simulated twin, in the order of a two-column figure.

    Parameters
    ----------
    conditions : sequence of RigCondition
        The records.
    sim_dir : path
        The simulated records (``<name>_sim.npz``).

    Yields
    ------
    (int, int, RigCondition, str, str)
        Row (the condition's index), column (0 measured, 1 simulated), the condition, side
        (``"meas"`` | ``"sim"``) and the record's path.
    """
    for i, c in enumerate(conditions):
        for j, (side, path) in enumerate((("meas", c.path),
                                          ("sim", Path(sim_dir) / f"{c.name}_sim.npz"))):
            yield i, j, c, side, str(path)


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


def save_figure(fig, axes, out_png, xlabel: str) -> str:
    """Label the bottom row, lay the figure out, write it and close it.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
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
