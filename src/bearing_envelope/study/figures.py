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
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from matplotlib.colors import to_rgb  # noqa: E402

from ..diagnosis.faults import display_name  # noqa: E402
from ..diagnosis.plots import FIGURE_DPI  # noqa: E402
from ..io import atomic_dir, read_case  # noqa: E402
from ..physics.locations import get_location  # noqa: E402
from ..signal import spectral_kurtosis  # noqa: E402
from .pipeline import case_fault_lines  # noqa: E402
from .tables import public_mode  # noqa: E402

#: What the peak-pressure figure's note says of the grid when the caller does not name it.
GRID_NOTE = "stored in each case file"
#: Harmonic orders of the amplitude-against-depth figure.
ORDERS_VS_DEPTH = (1, 2)
#: Fault periods shown by the time-history figure.
TIME_HISTORY_PERIODS = 6.0
#: The fault line a figure names when the caller does not (the inner race's, the study's).
LINE_NAME = "BPFI"

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
]


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


def fig_harmonics_vs_depth(tidy: pd.DataFrame, band: str, path, *, orders=ORDERS_VS_DEPTH) -> Path:
    """Figs 12-20: envelope harmonic amplitudes k x BPFI against depth, one line per load
    (k x each location's fault frequency, one line per location and load, in a location sweep).

    Parameters
    ----------
    tidy : pandas.DataFrame
        The sweep's tidy harmonic table; the rows of ``band`` whose ``quantity`` starts with
        ``envelope_`` and whose ``sideband`` is 0 are drawn (``amplitude`` in Pa, drawn in MPa).
    band : str
        Band name.
    path : str or os.PathLike
        The PNG file (:func:`save_figure`).
    orders : sequence of int, keyword-only, default (1, 2)
        Harmonic orders ``k``, one panel each.

    Returns
    -------
    pathlib.Path
        ``path``, the PNG written.
    """
    env = tidy["quantity"].astype(str).str.startswith("envelope_")
    sel = tidy[(tidy["band"] == band) & env & (tidy["sideband"] == 0)]
    family = _family_title(sel["quantity"].unique(), "envelope_")
    fig, axes = plt.subplots(1, len(orders), figsize=(5 * len(orders), 4), squeeze=False)
    for ax, k in zip(axes[0], orders):
        g = sel[sel["order"] == k]
        _per_load(ax, g, "amplitude", 1e-6)
        ax.set_ylabel("envelope amplitude (MPa)")
        ax.set_title(f"{k} x {family}" if "/" not in family
                     else f"{k} x each location's line ({family})")
    lo_hi = sel[["band_low_hz", "band_high_hz"]].drop_duplicates()
    span = (
        f"{lo_hi.iloc[0, 0]:.0f}-{lo_hi.iloc[0, 1]:.0f} Hz" if len(lo_hi) == 1 else "band per case"
    )
    fig.suptitle(f"Envelope harmonics, band '{band}' ({span})")
    return save_figure(fig, path)


def draw_band_limits(bands: pd.DataFrame, *, fs: float | None = None):
    """Fig. 10: demodulation bands of every case, as a load x depth grid.

    Bands whose limits are the same in every case (fixed, fraction, orders) are drawn once, as
    bars on a frequency axis; each band that varies per case (the kurtogram's) gets a
    load x depth grid coloured by its centre frequency and labelled with its limits (kHz;
    ``*`` = clamped below Nyquist). The figure's size depends on the number of loads and
    depths, not on the number of rows of ``bands``.

    Parameters
    ----------
    bands : DataFrame
        The sweep's band table (``case, load_kN, depth_um, band, strategy, low_hz, high_hz,
        clamped``).
    fs : float, optional
        Sampling rate (Hz): Nyquist is marked.

    Returns
    -------
    matplotlib.figure.Figure
    """
    names = list(dict.fromkeys(bands["band"]))
    varying = [n for n in names
               if bands.loc[bands["band"] == n, ["low_hz", "high_hz"]].drop_duplicates().shape[0] > 1]
    fixed = [n for n in names if n not in varying]
    loads = sorted(bands["load_kN"].unique())
    depths = sorted(bands["depth_um"].unique())
    w_grid = min(max(0.6 * len(depths) + 1.5, 4.5), 9.0)
    h = min(max(0.55 * len(loads) + 1.8, 3.2), 6.0)
    ncols = len(varying) + 1
    fig, axes = plt.subplots(1, ncols, figsize=(w_grid * len(varying) + 5.0, h), squeeze=False,
                             gridspec_kw={"width_ratios": [w_grid] * len(varying) + [5.0]})
    for ax, name in zip(axes[0], varying):
        g = bands[bands["band"] == name]
        centre = np.full((len(loads), len(depths)), np.nan)
        for r in g.itertuples():
            centre[loads.index(r.load_kN), depths.index(r.depth_um)] = 0.5 * (r.low_hz + r.high_hz) / 1e3
        im = ax.imshow(centre, origin="lower", aspect="auto", cmap="viridis")
        for r in g.itertuples():
            i, j = loads.index(r.load_kN), depths.index(r.depth_um)
            bright = im.norm(centre[i, j]) > 0.6  # dark text on the bright end of viridis
            ax.text(j, i, f"{r.low_hz / 1e3:.1f}-\n{r.high_hz / 1e3:.1f}" + ("*" if r.clamped else ""),
                    ha="center", va="center", fontsize=6.5, color="k" if bright else "w")
        fig.colorbar(im, ax=ax, label="band centre (kHz)")
        ax.set_xticks(range(len(depths)), [f"{d:g}" for d in depths])
        ax.set_yticks(range(len(loads)), [f"{v:g}" for v in loads])
        ax.set_xlabel(depth_label(bands))
        ax.set_ylabel("load (kN)")
        ax.set_title(f"band '{name}' per case: limits in kHz (* clamped below Nyquist)", fontsize=9)
    ax = axes[0, -1]
    for i, name in enumerate(fixed):
        r = bands[bands["band"] == name].iloc[0]
        ax.barh(i, (r.high_hz - r.low_hz) / 1e3, left=r.low_hz / 1e3, color=f"C{i % 10}")
        ax.text(r.high_hz / 1e3, i, f" {r.low_hz / 1e3:.2f}-{r.high_hz / 1e3:.2f}", va="center",
                fontsize=7)
    for name in varying:
        g = bands[bands["band"] == name]
        i = len(fixed) + varying.index(name)
        ax.barh(i, (g.high_hz.max() - g.low_hz.min()) / 1e3, left=g.low_hz.min() / 1e3,
                color="0.85", hatch="//", edgecolor="0.5")
        ax.text(g.high_hz.max() / 1e3, i, " range over cases", va="center", fontsize=7)
    ax.set_yticks(range(len(fixed) + len(varying)), fixed + varying, fontsize=8)
    if fs:
        ax.axvline(fs / 2e3, color="k", ls="--", lw=0.8)
        ax.text(fs / 2e3, -0.6, "Nyquist", ha="right", va="bottom", fontsize=7)
    ax.set_xlabel("frequency (kHz)")
    ax.invert_yaxis()
    ax.grid(True, axis="x", alpha=0.3)
    ax.set_title("bands equal in every case", fontsize=9)
    fig.suptitle("Demodulation bands (cf. study Fig. 10)")
    fig.tight_layout()
    return fig


def fig_band_limits(bands: pd.DataFrame, path, *, fs: float | None = None) -> Path:
    """Fig. 10 (:func:`draw_band_limits`) saved as PNG.

    Parameters
    ----------
    bands : pandas.DataFrame
        The sweep's band table, as in :func:`draw_band_limits`.
    path : str or os.PathLike
        The PNG file (:func:`save_figure`).
    fs : float, optional, keyword-only
        Sampling rate (Hz): Nyquist is marked.

    Returns
    -------
    pathlib.Path
        ``path``, the PNG written.
    """
    return save_figure(draw_band_limits(bands, fs=fs), path)


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


def _spectra(spectra_file):
    with np.load(spectra_file) as s:
        return {key: s[key] for key in s.files}


def fig_raw_spectrum(spectra_file, case: str, fr: float, bpfi: float, path, *, fmax=None,
                     line_name: str = LINE_NAME) -> Path:
    """Fig. 7: raw amplitude spectrum of one case with k x fr and k x BPFI marked (``bpfi``:
    the case's fault frequency, named ``line_name``: BPFO, 2xBSF for other locations).

    Parameters
    ----------
    spectra_file : str or os.PathLike
        The case's spectra file (``.npz`` with ``raw_f``, Hz, and ``raw_a``, Pa; drawn in MPa
        on a log axis, the 0 Hz term quoted in GPa in the title).
    case : str
        Case name (title).
    fr : float
        Shaft rate, Hz (1-3 x fr marked).
    bpfi : float
        The fault frequency, Hz (its multiples up to ``fmax`` marked).
    path : str or os.PathLike
        The PNG file (:func:`save_figure`).
    fmax : float, optional, keyword-only
        Highest frequency drawn, Hz; default ``6 * bpfi``.
    line_name : str, keyword-only, default "BPFI"
        The fault line's display name (legend).

    Returns
    -------
    pathlib.Path
        ``path``, the PNG written.
    """
    s = _spectra(spectra_file)
    f, a = s["raw_f"], s["raw_a"]
    fmax = fmax or 6 * bpfi
    keep = (f > 0) & (f <= fmax)
    fig, ax = plt.subplots(figsize=(10, 4))
    ax.semilogy(f[keep], a[keep] / 1e6, lw=0.7, color="k")
    for k in range(1, int(fmax / bpfi) + 1):
        ax.axvline(k * bpfi, color="C3", ls="--", lw=0.8,
                   label=f"k x {line_name}" if k == 1 else None)
    for k in range(1, 4):
        ax.axvline(k * fr, color="C0", ls=":", lw=0.8, label="k x fr" if k == 1 else None)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("amplitude (MPa)")
    ax.legend()
    ax.set_title(f"Raw spectrum of p_max, {case} (0 Hz term: {float(a[0]) / 1e9:.3f} GPa) (cf. Fig. 7)")
    return save_figure(fig, path)


def sk_window(level: float, min_points: int = SK_MIN_POINTS) -> int:
    """STFT window (samples) of the spectral-kurtosis panel for a kurtogram level.

    The study takes the window from the kurtogram: a level-``L`` band is ``fs 2^-(L+1)`` wide,
    and a window of ``2^(L+1)`` samples has that resolution. At the shallow levels the
    kurtogram often picks (L = 2-3) that is 8-16 samples, i.e. 5-9 frequency points over
    0 - fs/2, too coarse to see where the kurtosis lies. The window is therefore the larger of
    ``2^ceil(L+1)`` and ``2 (min_points - 1)`` (256 samples, 129 points, by default).

    Parameters
    ----------
    level : float
        The kurtogram level ``L`` (may be fractional: the 1/3-binary levels).
    min_points : int, default :data:`SK_MIN_POINTS`
        Fewest frequency points of the panel (0 - fs/2).

    Returns
    -------
    int
        The window, samples.
    """
    return int(max(2 ** int(np.ceil(float(level) + 1.0)), 2 * (int(min_points) - 1)))


def draw_kurtogram(kurtogram, case: str, *, signal=None, fs=None, nperseg=None):
    """Fig. 9: fast kurtogram of one case, and its STFT spectral kurtosis when ``signal`` is given.

    Parameters
    ----------
    kurtogram : mapping
        The arrays of the case's kurtogram file (``matrix``, ``levels``, ``freqs``, ``best``).
    case : str
        Case name (title).
    signal : array, optional
        The analysed signal (at ``fs``); draws the SK panel.
    fs : float
        Sampling rate (Hz), with ``signal``.
    nperseg : int, optional
        STFT window; default :func:`sk_window` of the best level. The title states the window
        actually used and its frequency resolution.

    Returns
    -------
    matplotlib.figure.Figure
    """
    k = kurtogram
    ncols = 2 if signal is not None else 1
    fig, axes = plt.subplots(1, ncols, figsize=(6 * ncols, 4), squeeze=False)
    ax = axes[0, 0]
    level = None
    if "matrix" in k:
        m, levels, freqs = k["matrix"], k["levels"], k["freqs"]
        im = ax.imshow(m, aspect="auto", origin="upper", cmap="jet",
                       extent=[freqs[0] / 1e3, freqs[-1] / 1e3, len(levels) - 0.5, -0.5])
        ax.set_yticks(range(len(levels)), [f"{lv:.1f}" for lv in levels])
        fig.colorbar(im, ax=ax, label="kurtosis")
        best = k["best"]
        level = float(best[0])
        ax.set_title(f"kurtogram: level {best[0]:.1f}, fc {best[1] / 1e3:.2f} kHz, "
                     f"Bw {best[2] / 1e3:.2f} kHz, K {best[3]:.1f}", fontsize=9)
        ax.set_xlabel("frequency (kHz)")
        ax.set_ylabel("level")
    if signal is not None:
        if nperseg is None:
            nperseg = sk_window(level if level is not None else 7.0)
        nperseg = int(nperseg)
        f, sk = spectral_kurtosis(signal - np.mean(signal), fs, nperseg)
        axes[0, 1].plot(np.asarray(f) / 1e3, sk, color="k", lw=0.8)
        axes[0, 1].set_xlabel("frequency (kHz)")
        axes[0, 1].set_ylabel("spectral kurtosis")
        axes[0, 1].set_title(f"STFT spectral kurtosis: window {nperseg} samples "
                             f"({fs / nperseg:.0f} Hz resolution), 80 % overlap", fontsize=9)
        axes[0, 1].grid(True, alpha=0.3)
    fig.suptitle(f"{case} (cf. study Fig. 9)")
    fig.tight_layout()
    return fig


def fig_kurtogram(kurtogram_file, case: str, path, *, signal=None, fs=None, nperseg=None) -> Path:
    """Fig. 9 (:func:`draw_kurtogram` of the kurtogram file ``kurtogram_file``) saved as PNG.

    Parameters
    ----------
    kurtogram_file : str or os.PathLike
        The case's kurtogram file (``.npz``; the arrays :func:`draw_kurtogram` reads).
    case : str
        Case name (title).
    path : str or os.PathLike
        The PNG file (:func:`save_figure`).
    signal : array_like, optional, keyword-only
        The analysed signal: draws the spectral-kurtosis panel.
    fs : float, optional, keyword-only
        Sampling rate (Hz), with ``signal``.
    nperseg : int, optional, keyword-only
        STFT window, samples; default :func:`sk_window` of the best level.

    Returns
    -------
    pathlib.Path
        ``path``, the PNG written.
    """
    with np.load(kurtogram_file) as k:
        arrays = {key: k[key] for key in k.files}
    return save_figure(draw_kurtogram(arrays, case, signal=signal, fs=fs, nperseg=nperseg), path)


def fig_envelope_spectrum(spectra_file, case: str, band: str, fr: float, bpfi: float, path, *,
                          n_harmonics: int, n_sidebands: int, line_name: str = LINE_NAME,
                          spacing_name: str = "fr") -> Path:
    """Fig. 11: envelope spectrum of one case and band, BPFI harmonics and fr sidebands marked
    (another location: its fault frequency ``bpfi`` named ``line_name`` and its sideband
    spacing ``fr`` named ``spacing_name``).

    Parameters
    ----------
    spectra_file : str or os.PathLike
        The case's spectra file (``.npz`` with ``env_{band}_f``, Hz, and ``env_{band}_a``, Pa;
        drawn in MPa).
    case : str
        Case name (title).
    band : str
        Band name.
    fr : float
        Sideband spacing, Hz (the shaft rate for the inner race).
    bpfi : float
        The fault frequency, Hz.
    path : str or os.PathLike
        The PNG file (:func:`save_figure`).
    n_harmonics : int, keyword-only, default 3
        Harmonics ``k x bpfi`` marked.
    n_sidebands : int, keyword-only, default 2
        Sidebands ``+- m x fr`` marked around each harmonic.
    line_name, spacing_name : str, keyword-only
        Display names of the fault line (default ``"BPFI"``) and of the spacing (``"fr"``).

    Returns
    -------
    pathlib.Path
        ``path``, the PNG written.
    """
    s = _spectra(spectra_file)
    f, a = s[f"env_{band}_f"], s[f"env_{band}_a"]
    fig, ax = plt.subplots(figsize=(10, 4))
    ax.plot(f, a / 1e6, lw=0.8, color="k")
    for k in range(1, n_harmonics + 1):
        ax.axvline(k * bpfi, color="C3", ls="--", lw=0.9,
                   label=f"k x {line_name}" if k == 1 else None)
        for m in range(1, n_sidebands + 1):
            for sgn in (-1, 1):
                ax.axvline(k * bpfi + sgn * m * fr, color="C0", ls=":", lw=0.8,
                           label=(f"k x {line_name} ± m x {spacing_name}"
                                  if (k, m, sgn) == (1, 1, -1) else None))
    ax.set_xlim(0, f[-1] if len(f) else 1)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("envelope amplitude (MPa)")
    ax.legend()
    ax.set_title(f"Envelope spectrum, {case}, band '{band}' (cf. study Fig. 11)")
    return save_figure(fig, path)


def make_figures(*, harmonics, cases, bands, case_files, kurtogram_files, spectra_files,
                 example, analysis, outdir) -> list[Path]:
    """Draw every figure of the sweep into ``outdir`` (written to a temporary folder, then renamed).

    Parameters
    ----------
    harmonics, cases, bands : path
        The aggregate tables (tidy harmonics, per-case summary, band limits).
    case_files, kurtogram_files, spectra_files : mapping
        Case name -> path of its case file (the analysed one), kurtogram file and spectra file.
    example : mapping
        ``{"defect": name, "healthy": name, "pairs": [{"load_kN", "healthy", "defect"}, ...]}``:
        the case drawn alone (Figs 7, 9, 11) and the pairs of Figs 4 and 5
        (:func:`example_pairs`).
    analysis : bearing_envelope.study.sections.AnalysisSettings
        The config's ``analysis`` section, typed.
    outdir : path
        Output folder (replaced whole, :func:`bearing_envelope.io.atomic_dir`).

    Returns
    -------
    list of pathlib.Path
        The PNGs written, under ``outdir``: Figs 4-7, 9 (only when the analysis uses the
        kurtogram), 10, one Fig. 11 and one of Figs 12- per band, then Fig. 8.
    """
    outdir = Path(outdir)
    with atomic_dir(outdir) as tmp:
        tidy = pd.read_csv(harmonics)
        summary = pd.read_csv(cases)
        band_table = pd.read_csv(bands)
        read = {}

        def case(name):
            if name not in read:
                read[name] = read_case(case_files[name])
            return read[name]

        pairs = [(case(p["healthy"]), case(p["defect"])) for p in
                 (example.get("pairs") or [{"healthy": example["healthy"], "defect": example["defect"]}])]
        cd = case(example["defect"])
        lines, spacing = case_fault_lines(cd)
        family, f_line = next(iter(lines.items()))
        sb_name, f_sb = (spacing or {}).get(family, ("fr", cd.fr))
        line = {"line_name": display_name(family)}
        written = [
            fig_pressure_maps(pairs, tmp / "fig04_pressure_maps.png"),
            fig_time_histories(pairs, tmp / "fig05_time_histories.png"),
            fig_peak_pressure(summary, tmp / "fig06_peak_pressure.png", grid=_grid_text(cd)),
            fig_raw_spectrum(spectra_files[example["defect"]], example["defect"], cd.fr, f_line,
                             tmp / "fig07_raw_spectrum.png", **line),
        ]
        if analysis.needs_kurtogram:
            x = np.asarray(cd.signals[analysis.signal], dtype=float)
            written.append(fig_kurtogram(kurtogram_files[example["defect"]], example["defect"],
                                         tmp / "fig09_kurtogram_sk.png", signal=x, fs=cd.fs))
        written.append(fig_band_limits(band_table, tmp / "fig10_band_limits.png", fs=cd.fs))
        for b in analysis.bands:
            written.append(fig_envelope_spectrum(
                spectra_files[example["defect"]], example["defect"], b.name, f_sb, f_line,
                tmp / f"fig11_envelope_spectrum_{b.name}.png",
                n_harmonics=analysis.options.n_harmonics,
                n_sidebands=analysis.options.n_sidebands,
                spacing_name=display_name(sb_name), **line))
        for i, b in enumerate(analysis.bands):
            written.append(fig_harmonics_vs_depth(tidy, b.name, tmp / f"fig{12 + i:02d}_harmonics_{b.name}.png"))
        raw = tidy[(tidy["band"] == "raw") & (tidy["order"] <= 1)]
        written.append(_fig_raw_terms(raw, tmp / "fig08_raw_terms.png"))
    return [outdir / p.name for p in written]


def _fig_raw_terms(raw: pd.DataFrame, path) -> Path:
    """Fig. 8: raw-spectrum 0 Hz, 1 x fr and 1 x BPFI amplitudes against depth per load."""
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    faults = sorted(set(raw["quantity"].astype(str)) - {"raw_dc", "raw_fr"}) or ["raw_bpfi"]
    for ax, (q, title) in zip(axes, [("raw_dc", "0 Hz (mean)"), ("raw_fr", "1 x fr"),
                                      (faults, f"1 x {_family_title(faults, 'raw_')}")]):
        g = raw[raw["quantity"].isin([q] if isinstance(q, str) else q) & (raw["sideband"] == 0)]
        _per_load(ax, g, "amplitude", 1e-6)
        ax.set_ylabel("amplitude (MPa)")
        ax.set_title(title)
    fig.suptitle("Raw-spectrum terms vs load and depth (cf. study Fig. 8)")
    return save_figure(fig, path)


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


