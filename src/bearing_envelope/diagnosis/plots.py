"""Figures of the envelope analysis: kurtogram map and envelope spectrum with markers.

Object-oriented matplotlib (:class:`matplotlib.figure.Figure`, Agg canvas), so nothing here
touches pyplot's global state or needs a display. Every function draws into ``ax`` when given
(and returns it), or creates a figure and returns its axes.
"""

from __future__ import annotations

import os
import textwrap

import numpy as np
from matplotlib.figure import Figure  # this module only draws: it is imported on demand
from matplotlib.patches import Rectangle

from .faults import display_name

__all__ = ["FAMILY_COLORS", "plot_envelope_spectrum", "plot_fault_lines", "plot_kurtogram",
           "save_analysis_figures"]


def _axes(ax, figsize):
    if ax is not None:
        return ax
    fig = Figure(figsize=figsize, layout="constrained")
    return fig.add_subplot()


def plot_kurtogram(kurtogram, ax=None, *, title: str | None = None, cmap: str = "viridis",
                   mark_best: bool = True, freq_unit: str = "kHz"):
    """Kurtogram map: frequency (x) against level (y, top = level 0), colour = kurtosis.

    Parameters
    ----------
    kurtogram : Kurtogram
        Result of :func:`bearing_envelope.signal.fast_kurtogram`.
    ax : matplotlib Axes, optional
        Where to draw; a new figure otherwise.
    title : str, optional
        Default: the best cell (level, centre, bandwidth, kurtosis).
    cmap : str
        Colour map.
    mark_best : bool
        Outline the best cell.
    freq_unit : {"kHz", "Hz"}
        Unit of the frequency axis.

    Returns
    -------
    matplotlib Axes
    """
    kg = kurtogram
    ax = _axes(ax, (7.0, 4.2))
    scale = 1e-3 if freq_unit == "kHz" else 1.0
    nrow = kg.matrix.shape[0]
    im = ax.imshow(kg.matrix, aspect="auto", origin="upper", cmap=cmap, interpolation="nearest",
                   extent=(0.0, kg.fs / 2 * scale, nrow - 0.5, -0.5))
    ax.set_yticks(np.arange(nrow))
    ax.set_yticklabels([f"{lev:.1f}" for lev in kg.levels])
    ax.set_xlabel(f"frequency ({freq_unit})")
    ax.set_ylabel("level")
    ax.figure.colorbar(im, ax=ax, label="kurtosis")
    if mark_best:
        lo, hi = kg.band
        ax.add_patch(Rectangle((lo * scale, kg.row - 0.5), (hi - lo) * scale, 1.0, fill=False,
                               edgecolor="red", linewidth=1.5))
    if title is None:
        title = (f"K_max = {kg.kurtosis:.2f} at level {kg.level:.2f}, "
                 f"fc = {kg.fc * scale:.3g} {freq_unit}, B = {kg.bandwidth * scale:.3g} "
                 f"{freq_unit}")
    ax.set_title(title, fontsize=9)
    return ax


def plot_envelope_spectrum(f, amplitude, *, base: float | None = None, fr: float | None = None,
                           n_harmonics: int = 5, n_sidebands: int = 1, fmax: float | None = None,
                           ax=None, title: str | None = None, base_label: str = "BPFI",
                           unit: str = "", color: str = "C0"):
    """Envelope spectrum with the harmonics ``k x base`` and sidebands ``k x base +- m x fr``.

    Parameters
    ----------
    f, amplitude : ndarray
        From :func:`bearing_envelope.signal.envelope_spectrum`.
    base : float, optional
        Fault frequency (Hz) whose harmonics are marked (dashed red lines).
    fr : float, optional
        Shaft rate (Hz): sidebands marked by dotted grey lines.
    n_harmonics, n_sidebands : int
        How many harmonics (k = 1..K) and sidebands per side (m = 1..M) to mark.
    fmax : float, optional
        Upper end of the frequency axis; default ``(n_harmonics + 0.5) * base`` or fs/2.
    ax, title
        As in :func:`plot_kurtogram`.
    base_label : str
        Legend label of the harmonics.
    unit : str
        Unit of the amplitude, for the axis label.
    color : str
        Line colour.

    Returns
    -------
    matplotlib Axes
    """
    ax = _axes(ax, (7.0, 3.6))
    f = np.asarray(f)
    amplitude = np.asarray(amplitude)
    if fmax is None:
        fmax = (n_harmonics + 0.5) * base if base else f[-1]
    sel = f <= fmax
    ax.plot(f[sel], amplitude[sel], color=color, linewidth=0.8)
    if base:
        for k in range(1, n_harmonics + 1):
            ax.axvline(k * base, color="red", linestyle="--", linewidth=0.8, alpha=0.8,
                       label=f"k x {base_label}" if k == 1 else None)
            if fr:
                for m in range(1, n_sidebands + 1):
                    for s in (-1, 1):
                        ax.axvline(k * base + s * m * fr, color="0.4", linestyle=":",
                                   linewidth=0.8,
                                   label="+- m x fr" if (k, m, s) == (1, 1, -1) else None)
        ax.legend(loc="upper right", fontsize=8)
    ax.set_xlim(0, fmax)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel(f"envelope amplitude{f' ({unit})' if unit else ''}")
    if title:
        ax.set_title(title, fontsize=9)
    return ax


#: Colours of the fault families on the plots (others cycle through the rest).
FAMILY_COLORS = {"bpfo": "tab:red", "bpfi": "tab:green", "bsf": "tab:purple",
                 "bsf2": "tab:brown", "ftf": "tab:orange"}


def plot_fault_lines(f, amplitude, lines: dict, *, fmax: float | None = None, ax=None,
                     title: str | None = None, unit: str = "", color: str = "C0"):
    """Envelope spectrum with every fault family's lines as found.

    Parameters
    ----------
    f, amplitude : ndarray
        The spectrum.
    lines : mapping
        ``family name -> records`` of :func:`bearing_envelope.diagnosis.faults.search_lines`
        (``analyze_signal(..., full_output=True)[1]["bands"][name]["lines"]``). Each harmonic
        is marked at the frequency found (dashed, one colour per family, a dot on the peak
        when detected), each sideband dotted in the same colour.
    fmax : float, optional
        Upper end of the axis; default 3.5 x the highest fundamental found.
    ax, title, unit, color
        As in :func:`plot_envelope_spectrum`.

    Returns
    -------
    matplotlib Axes
    """
    ax = _axes(ax, (8.0, 4.0))
    f = np.asarray(f)
    amplitude = np.asarray(amplitude)
    fund = [r["frequency_hz"] for recs in lines.values() for r in recs
            if r["order"] == 1 and r["sideband"] == 0]
    if fmax is None:
        fmax = 3.5 * max(fund) if fund else f[-1]
    sel = f <= fmax
    ax.plot(f[sel], amplitude[sel], color=color, linewidth=0.7)
    spare = iter(["tab:pink", "tab:olive", "tab:cyan", "tab:gray", "black"] * 10)
    for name, recs in lines.items():
        c = FAMILY_COLORS.get(name) or next(spare)
        first = True
        for r in recs:
            fk = r["frequency_hz"]
            if fk > fmax:
                continue
            det = bool(r.get("detected"))
            if r["sideband"] == 0:
                label = None
                if first:
                    q1 = next(q for q in recs if q["order"] == 1 and q["sideband"] == 0)
                    f1, d1 = q1["frequency_hz"], bool(q1.get("detected"))
                    label = (f"k x {display_name(name)} ({f1:.1f} Hz"
                             f"{', detected' if d1 else ''})")
                    first = False
                ax.axvline(fk, color=c, linestyle="--", linewidth=0.9, alpha=0.8, label=label)
            else:
                ax.axvline(fk, color=c, linestyle=":", linewidth=0.8, alpha=0.7)
            if det:
                ax.plot([fk], [r["amplitude"]], "o", color=c, markersize=3.5)
    if lines:
        ax.legend(loc="upper right", fontsize=7)
    ax.set_xlim(0, fmax)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel(f"envelope amplitude{f' ({unit})' if unit else ''}")
    if title:
        ax.set_title(title, fontsize=9)
    return ax


def save_analysis_figures(details: dict, outdir, *, prefix: str = "", base: str | None = None,
                          n_harmonics: int = 5, n_sidebands: int = 1, unit: str = "",
                          dpi: int = 120, fmt: str = "png") -> list[str]:
    """Write the kurtogram and one envelope spectrum per band from
    ``analyze_signal(..., full_output=True)[1]``; returns the paths written.

    Files: ``{prefix}kurtogram.{fmt}`` (if a kurtogram was computed) and
    ``{prefix}envelope_{band name}.{fmt}``. Every fault family's harmonics and sidebands are
    marked where they were found (:func:`plot_fault_lines`); with ``base`` (a family name) only
    that family's nominal ``k x base`` and ``+- m x fr`` (:func:`plot_envelope_spectrum`).
    """
    os.makedirs(outdir, exist_ok=True)
    paths = []
    kg = details.get("kurtogram")
    if kg is not None:
        fig = Figure(figsize=(7.0, 4.2), layout="constrained")
        plot_kurtogram(kg, fig.add_subplot())
        p = os.path.join(outdir, f"{prefix}kurtogram.{fmt}")
        fig.savefig(p, dpi=dpi)
        paths.append(p)
    freqs = details.get("frequencies", {})
    verdict = details.get("verdict")
    for name, b in details.get("bands", {}).items():
        lo, hi = b["band"]
        clamp = " (clamped)" if b["provenance"].get("clamped") else ""
        title = f"{name}: band {lo:.0f} - {hi:.0f} Hz{clamp}"
        if base is None and b.get("lines") is not None:
            fig = Figure(figsize=(8.0, 4.0), layout="constrained")
            if verdict is not None and name == getattr(verdict.diagnosis, "band", None):
                title += "\n" + textwrap.fill(f"verdict: {verdict.summary_lines()[0]}", 110)
            plot_fault_lines(b["f"], b["amplitude"], b["lines"], ax=fig.add_subplot(),
                             title=title, unit=unit)
        else:
            fig = Figure(figsize=(7.0, 3.6), layout="constrained")
            key = base or "bpfi"
            plot_envelope_spectrum(b["f"], b["amplitude"], base=freqs.get(key),
                                   fr=details.get("fr"), n_harmonics=n_harmonics,
                                   n_sidebands=n_sidebands, ax=fig.add_subplot(), title=title,
                                   base_label=key.upper(), unit=unit)
        p = os.path.join(outdir, f"{prefix}envelope_{name}.{fmt}")
        fig.savefig(p, dpi=dpi)
        paths.append(p)
    return paths
