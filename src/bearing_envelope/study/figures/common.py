"""What the sweep's figures share: the study's example cases (:func:`example_pairs`), the notes
on the elastic model and the grid, the fault line named by default, the atomic PNG write
(:func:`save_figure`), axis labels and per-load lines."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...diagnosis.faults import display_name
from ...diagnosis.plots import FIGURE_DPI
from ...io import public_mode
from ...physics.locations import get_location

__all__ = ["STUDY_EXAMPLES", "ELASTIC_NOTE", "LINE_NAME", "example_pairs", "save_figure",
           "depth_label", "location_line"]


#: The fault line a figure names when the caller does not (the inner race's, the study's).
LINE_NAME = "BPFI"


#: The study's example cases (its Figs 4 and 5): (load kN, defect depth um), each drawn next to
#: the healthy race at the same load.
STUDY_EXAMPLES: tuple[tuple[float, float], ...] = ((250.0, 15.0), (500.0, 50.0), (750.0, 100.0))

#: What every pressure figure says about its values.
ELASTIC_NOTE = ("Linear-elastic, frictionless contact (no plasticity): peaks above ~4 GPa "
                "(ISO 76 static capacity) would yield real steel; peaks at the defect rim and "
                "roller ends depend on the grid ({grid}).")

#: Fewest frequency points of the spectral-kurtosis panel (Fig. 9): window >= 2 (n - 1) samples.
SK_MIN_POINTS = 129


def example_pairs(cases, study=STUDY_EXAMPLES) -> list[dict]:
    """The sweep's cases nearest the study's examples, each with the healthy race of its load.

    Parameters
    ----------
    cases : iterable
        The sweep's cases: objects with ``load_kN``, ``depth_um`` and ``name`` (e.g.
        :class:`bearing_envelope.study.case_id.CaseId`).
    study : sequence of (load_kN, depth_um)
        Target cases; default :data:`STUDY_EXAMPLES` (250 kN / 15 um, 500 kN / 50 um,
        750 kN / 100 um).

    Returns
    -------
    list of dict
        ``{"load_kN", "healthy", "defect"}`` (case names), one per distinct nearest case, in
        the order of ``study``: the load nearest the target load (ties: the higher), at that
        load the shallowest depth as the healthy reference (the healthy race when the sweep has
        depth 0) and, among the deeper ones, the depth nearest the target (ties: the deeper).

    Raises
    ------
    ValueError
        No cases given.
    """
    cases = list(cases)
    if not cases:
        raise ValueError("example_pairs: no cases")
    loads = sorted({float(c.load_kN) for c in cases})
    out, seen = [], set()
    for load_t, depth_t in study:
        load = min(loads, key=lambda v: (abs(v - load_t), -v))
        at = [c for c in cases if float(c.load_kN) == load]
        healthy = min(at, key=lambda c: float(c.depth_um))
        damaged = [c for c in at if float(c.depth_um) > float(healthy.depth_um)] or at
        defect = min(damaged, key=lambda c: (abs(float(c.depth_um) - depth_t), -float(c.depth_um)))
        if defect.name in seen:
            continue
        seen.add(defect.name)
        out.append({"load_kN": load, "healthy": healthy.name, "defect": defect.name})
    return out


def _grid_text(case) -> str:
    """Grid spacings of a case's pressure snapshots (global and defect window, um)."""
    snaps = getattr(case, "snapshots", None) or {}
    if not snaps:
        return "grid in the case file"
    s = snaps[_top_snapshot(snaps)]
    parts = []
    for key, what in (("global", "global"), ("window", "defect window")):
        x, y = s.get(f"{key}_x"), s.get(f"{key}_y")
        if x is not None and y is not None and np.size(x) > 1 and np.size(y) > 1:
            parts.append(f"{what} {np.median(np.diff(np.asarray(x))) * 1e6:.0f} x "
                         f"{np.median(np.diff(np.asarray(y))) * 1e6:.0f} µm")
    return ", ".join(parts) or "grid in the case file"


def _top_snapshot(snaps) -> str:
    """Key of the snapshot at the highest roller load."""
    return max(snaps, key=lambda k: float(np.asarray(snaps[k]["roller_load"])))


def _note(fig, case, y=-0.02):
    fig.text(0.5, y, ELASTIC_NOTE.format(grid=_grid_text(case)), ha="center", va="top",
             fontsize=8, wrap=True, style="italic")


def save_figure(fig, path: str | os.PathLike, dpi: int = FIGURE_DPI) -> Path:
    """Save ``fig`` as PNG through a temporary file and close it.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure; closed afterwards, also when saving fails.
    path : str or os.PathLike
        The PNG file; its folder is created if missing. Replaced atomically (a temporary file
        in the same folder, given the mode a plain ``open`` would, then renamed).
    dpi : int, default 120
        Resolution, dots per inch (``bbox_inches="tight"``).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".png", dir=path.parent)
    os.close(fd)
    try:
        fig.savefig(tmp, dpi=dpi, bbox_inches="tight")
        public_mode(tmp)
        os.replace(tmp, path)
    finally:
        plt.close(fig)
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path


def depth_label(df: pd.DataFrame) -> str:
    """The depth axis's label: at the study's w = 2 h the axis varies the width too.

    Depth alone matters only while the pit bottom carries load (below 1.7-2.5 um at
    w = 2 h: docs/benchmarks.md, "Depth below which the pit bottom carries load"), so over
    15-100 um a w = 2 h sweep is a sweep of the defect's width.

    Parameters
    ----------
    df : pandas.DataFrame
        The sweep table plotted; a ``width_um`` column means the width is set on its own.

    Returns
    -------
    str
        The axis label (depth in um), naming ``w = 2h`` when the table has no width column.
    """
    if "width_um" in df.columns:
        return "defect depth h (µm)"
    return "defect depth h (µm), width w = 2h"


def _per_load(ax, df: pd.DataFrame, y: str, scale: float = 1.0, marker: str = "o"):
    """One line per load (per location and load when the table has a ``location`` column)."""
    keys = ["location", "load_kN"] if "location" in df.columns else ["load_kN"]
    for key, g in df.groupby(keys, sort=True):
        g = g.sort_values("depth_um")
        label = f"{key[-1]:g} kN" + (f", {key[0]}" if len(keys) > 1 else "")
        ax.plot(g["depth_um"], g[y] * scale, marker=marker, label=label)
    ax.set_xlabel(depth_label(df))
    ax.grid(True, alpha=0.3)
    ax.legend(title="load" if len(keys) == 1 else "load, location")


def location_line(location: str) -> str:
    """The display name of the fault line the sweep tests for a defect location (its
    :attr:`~bearing_envelope.physics.locations.FaultLocation.family`).

    Parameters
    ----------
    location : str
        A registered ``defect.location``.

    Returns
    -------
    str
        E.g. ``BPFO``.
    """
    return display_name(get_location(location).family)

#: Display names of the sweep's fault-family quantities (each location searches its own).
FAMILY_TITLES = {"bpfi": "BPFI", "bpfo": "BPFO", "2bsf": "2xBSF"}


def _family_title(quantities, prefix: str) -> str:
    """``"BPFI"`` (or ``"BPFI / BPFO"``) for the ``{prefix}_<family>`` quantities present."""
    fams = sorted({q[len(prefix):] for q in quantities})
    return " / ".join(FAMILY_TITLES.get(f, f) for f in fams) or "BPFI"
