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

from ..signal.envelope import DEFAULT_FILTER_ORDER, bandpass, envelope
from .options import AnalysisOptions
from .faults import display_name

#: Resolution of a written figure (dots per inch); the one-page record figure an analyst reads:
#: :data:`RECORD_FIGURE_DPI`.
FIGURE_DPI = 120
RECORD_FIGURE_DPI = 90
#: Colour of a plotted spectrum.
LINE_COLOR = "C0"
#: Nominal lines marked on an envelope spectrum drawn for a family (``k x base``, k = 1..5, and
#: ``+- m fr``, m = 1): more than the analysis searches, to show where the next ones would lie.
NOMINAL_HARMONICS_SHOWN = 5
NOMINAL_SIDEBANDS_SHOWN = 1
#: Fault periods of band-passed signal shown under an envelope waveform.
WAVEFORM_PERIODS_SHOWN = 8.0

__all__ = ["FAMILY_COLORS", "plot_envelope_spectrum", "plot_envelope_waveform",
           "plot_fault_lines", "plot_kurtogram", "plot_raw_spectrum", "plot_record_lines",
           "save_analysis_figures", "save_record_figure", "shown_family"]


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
                           n_harmonics: int = NOMINAL_HARMONICS_SHOWN,
                           n_sidebands: int = NOMINAL_SIDEBANDS_SHOWN, fmax: float | None = None,
                           ax=None, title: str | None = None, base_label: str = "BPFI",
                           unit: str = "", color: str = LINE_COLOR):
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
                     title: str | None = None, unit: str = "", color: str = LINE_COLOR):
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
                          n_harmonics: int = NOMINAL_HARMONICS_SHOWN,
                          n_sidebands: int = NOMINAL_SIDEBANDS_SHOWN, unit: str = "",
                          dpi: int = FIGURE_DPI, fmt: str = "png") -> list[str]:
    """Write the kurtogram and one envelope spectrum per band from
    ``analyze_signal(..., full_output=True)[1]``; returns the paths written.

    Files: ``{prefix}kurtogram.{fmt}`` (if a kurtogram was computed) and
    ``{prefix}envelope_{band name}.{fmt}``. Every fault family's harmonics and sidebands are
    marked where they were found (:func:`plot_fault_lines`); with ``base`` (a family name) only
    that family's nominal ``k x base`` and ``+- m x fr`` (:func:`plot_envelope_spectrum`).

    Parameters
    ----------
    details : dict
        The details mapping (``kurtogram``, ``frequencies``, ``fr``, ``bands``, ``verdict``).
    outdir : str or path-like
        Output folder, created if missing.
    prefix : str, default ""
        Prefix of every file name.
    base : str, optional
        A family name (a key of ``details["frequencies"]``): plot only its nominal lines.
    n_harmonics, n_sidebands : int, default 5, 1
        Harmonics and shaft-rate sidebands marked when ``base`` is used (or a band has no
        ``lines``).
    unit : str, default ""
        Unit of the amplitude axis.
    dpi : int, default 120
        Resolution of the figures.
    fmt : str, default "png"
        File format (extension).

    Returns
    -------
    list of str
        The paths written, the kurtogram first.
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


# --------------------------------------------------------------- one record, for an analyst
def shown_family(details: dict) -> tuple[str | None, str | None]:
    """``(band, family)`` a record's figure shows: the diagnosis, else the first candidate of a
    "cannot tell", else the family closest to its threshold, else the first band and no
    family.

    Parameters
    ----------
    details : dict
        The details mapping of a record (``verdict``, ``bands``).

    Returns
    -------
    tuple of (str or None, str or None)
        Band name and family name; ``(None, None)`` without verdict or bands.
    """
    verdict = details.get("verdict")
    if verdict is not None:
        diag = verdict.diagnosis
        if diag is not None:
            return diag.band, diag.family
        by_name = {v.family: v for v in verdict.families}
        for name in getattr(verdict, "candidates", ()):  # "cannot tell": the first candidate
            v = by_name.get(name)
            if v is not None and v.band is not None:
                return v.band, v.family
        searched = [v for v in verdict.families if v.band is not None]
        if searched:
            best = max(searched, key=lambda v: v.margin_db
                       if np.isfinite(v.margin_db) else -np.inf)
            return best.band, best.family
    bands = list(details.get("bands", {}))
    return (bands[0] if bands else None), None


def _peak_hold(x, y, columns: int = 3000):
    """At most ``2 columns`` points of a long curve for display: per column its minimum and
    maximum (every peak stays visible; the data are not changed)."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.size <= 2 * columns:
        return x, y
    step = x.size // columns
    m = step * columns
    yy = y[:m].reshape(columns, step)
    xx = x[:m].reshape(columns, step)
    lo, hi = yy.argmin(axis=1), yy.argmax(axis=1)
    rows = np.arange(columns)
    first = np.minimum(lo, hi)
    second = np.maximum(lo, hi)
    xs = np.column_stack([xx[rows, first], xx[rows, second]]).ravel()
    ys = np.column_stack([yy[rows, first], yy[rows, second]]).ravel()
    return np.r_[xs, x[m:]], np.r_[ys, y[m:]]


def _db(a, ref):
    """``20 log10(a / ref)``, floored at -120 dB."""
    a = np.asarray(a, dtype=float)
    return 20.0 * np.log10(np.maximum(a, ref * 1e-6) / ref)


def _xscale(orders: bool, fr: float | None) -> tuple[float, str]:
    if orders and fr:
        return 1.0 / fr, f"order (x shaft rate fr = {fr:.4g} Hz)"
    return 1.0, "frequency (Hz)"


def plot_raw_spectrum(details: dict, ax=None, *, db: bool = False, orders: bool = False,
                      band: str | None = None, unit: str = ""):
    """Raw amplitude spectrum of a record, the band of the envelope shaded.

    Parameters
    ----------
    details : dict
        ``analyze_signal(..., full_output=True)[1]``.
    ax : matplotlib Axes, optional
    db : bool
        Amplitude in dB re the largest bin.
    orders : bool
        Frequency axis in orders of the shaft rate.
    band : str, optional
        Name of the band to shade.
    unit : str
        Unit of the amplitude.

    Returns
    -------
    matplotlib Axes
    """
    ax = _axes(ax, (8.0, 3.0))
    f, a = details["raw"]
    scale, xlabel = _xscale(orders, details.get("fr"))
    y = _db(a, np.max(a) or 1.0) if db else a
    ax.plot(*_peak_hold(np.asarray(f) * scale, y), color="0.25", linewidth=0.5)
    if band is not None and band in details.get("bands", {}):
        lo, hi = details["bands"][band]["band"]
        ax.axvspan(lo * scale, hi * scale, color="tab:blue", alpha=0.12,
                   label=f"band {band}")
        ax.legend(loc="upper right", fontsize=7)
    ax.set_xlim(0, f[-1] * scale)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("dB re max" if db else f"amplitude{f' ({unit})' if unit else ''}")
    ax.set_title("raw spectrum", fontsize=9)
    return ax


def plot_envelope_waveform(x, details: dict, band: str, ax=None, *,
                           periods: float = WAVEFORM_PERIODS_SHOWN,
                           family: str | None = None,
                           order: int = DEFAULT_FILTER_ORDER):
    """A stretch of the band-passed signal (grey) and its envelope, with the fault period.

    Parameters
    ----------
    x : array_like
        The record.
    details : dict
        ``analyze_signal(..., full_output=True)[1]``.
    band : str
        The band (a key of ``details["bands"]``).
    ax : matplotlib Axes, optional
    periods : float
        Length shown, in periods of ``family``'s frequency found (else 0.1 s).
    family : str, optional
        The family whose period is marked.
    order : int
        Butterworth order of the band-pass (as in the analysis).

    Returns
    -------
    matplotlib Axes
    """

    ax = _axes(ax, (8.0, 2.6))
    fs = float(details["fs"])
    lo, hi = details["bands"][band]["band"]
    f1 = _found(details, band, family)
    length = periods / f1 if f1 else 0.1
    n_show = max(16, min(int(length * fs), np.size(x)))
    n_seg = min(np.size(x), max(4 * n_show, 8192))
    start = (np.size(x) - n_seg) // 2
    seg = np.asarray(x[start:start + n_seg], dtype=float)
    seg = seg - seg.mean()
    y = bandpass(seg, fs, (lo, hi), order=order)
    env = envelope(y)
    i0 = (n_seg - n_show) // 2
    t = np.arange(n_show) / fs * 1e3
    ax.plot(t, y[i0:i0 + n_show], color="0.7", linewidth=0.5, label="band-passed")
    ax.plot(t, env[i0:i0 + n_show], color="tab:blue", linewidth=0.9, label="envelope")
    if f1:
        ax.vlines(np.arange(int(periods) + 1) * 1e3 / f1, 0, 1, transform=ax.get_xaxis_transform(),
                  color=FAMILY_COLORS.get(family, "tab:red"), linestyle=":", linewidth=0.6)
    ax.set_xlim(0, t[-1])
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("amplitude")
    title = f"envelope waveform, band {band} ({lo:.0f}-{hi:.0f} Hz)"
    if f1:
        title += f"; dotted: period of {display_name(family)} ({1e3 / f1:.2f} ms)"
    ax.set_title(title, fontsize=9)
    ax.legend(loc="upper right", fontsize=7)
    return ax


def _found(details, band, family):
    if family is None:
        return None
    recs = details["bands"][band].get("lines", {}).get(family) or []
    r1 = next((r for r in recs if r["order"] == 1 and r["sideband"] == 0), None)
    return None if r1 is None else float(r1["frequency_hz"])


def plot_record_lines(details: dict, band: str, family: str | None = None, ax=None, *,
                      n_harmonics: int = AnalysisOptions.n_harmonics, db: bool = False,
                      fmax: float | None = None,
                      orders: bool = False, unit: str = ""):
    """Envelope spectrum of one band: the lines of ``family`` labelled (k x name at each
    harmonic found, sidebands dotted, a dot where detected), every other family's searched
    lines in grey, unlabelled.

    Parameters
    ----------
    details : dict
        ``analyze_signal(..., full_output=True)[1]``.
    band : str
        The band shown.
    family : str, optional
        The family labelled (the diagnosis, or the closest); None: all in grey.
    ax : matplotlib Axes, optional
    n_harmonics : int
        Harmonics the default ``fmax`` covers.
    db : bool
        Amplitude in dB re the largest line shown.
    fmax : float, optional
        Upper frequency (Hz); default ``(n_harmonics + 0.5)`` x the family's fundamental found.
    orders : bool
        Frequency axis in orders of the shaft rate.
    unit : str
        Unit of the amplitude.

    Returns
    -------
    matplotlib Axes
    """
    ax = _axes(ax, (8.0, 3.6))
    b = details["bands"][band]
    f, a = np.asarray(b["f"]), np.asarray(b["amplitude"])
    lines = b.get("lines") or {}
    f1 = _found(details, band, family)
    if fmax is None:
        fund = [r["frequency_hz"] for recs in lines.values() for r in recs
                if r["order"] == 1 and r["sideband"] == 0]
        fmax = (n_harmonics + 0.5) * f1 if f1 else (3.5 * max(fund) if fund else f[-1])
    fmax = min(fmax, f[-1])
    sel = (f <= fmax) & (f > 0)
    scale, xlabel = _xscale(orders, details.get("fr"))
    ref = float(np.max(a[sel])) if sel.any() and np.max(a[sel]) > 0 else 1.0
    y = _db(a, ref) if db else a
    ax.plot(*_peak_hold(f[sel] * scale, y[sel]), color="C0", linewidth=0.7)
    xaxis = ax.get_xaxis_transform()
    grey = [r["frequency_hz"] * scale for name, recs in lines.items() if name != family
            for r in recs if r["sideband"] == 0 and r["frequency_hz"] <= fmax]
    if grey:
        ax.vlines(grey, 0, 1, transform=xaxis, color="0.65", linestyle="--", linewidth=0.6,
                  label="other families searched")
    recs = [r for r in (lines.get(family) or []) if r["frequency_hz"] <= fmax]
    if family is not None and recs:
        c = FAMILY_COLORS.get(family, "tab:red")
        harm = [r for r in recs if r["sideband"] == 0]
        ax.vlines([r["frequency_hz"] * scale for r in harm], 0, 1, transform=xaxis, color=c,
                  linestyle="--", linewidth=0.9)
        ax.vlines([r["frequency_hz"] * scale for r in recs if r["sideband"] != 0], 0, 1,
                  transform=xaxis, color=c, linestyle=":", linewidth=0.7)
        for r in harm:
            ax.annotate(f"{r['order']}x{display_name(family)}", (r["frequency_hz"] * scale, 0.97),
                        xycoords=xaxis, xytext=(2, -8), textcoords="offset points", fontsize=7,
                        color=c)
        det = [r for r in recs if r.get("detected")]
        ax.plot([r["frequency_hz"] * scale for r in det],
                [_db(r["amplitude"], ref) if db else r["amplitude"] for r in det], "o", color=c,
                markersize=3.5)
    ax.set_xlim(0, fmax * scale)
    if not db:
        ax.set_ylim(bottom=0)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("dB re max" if db else f"envelope amplitude{f' ({unit})' if unit else ''}")
    lo, hi = b["band"]
    what = (f"{display_name(family)} ({f1:.2f} Hz) marked; dots: detected" if f1
            else "no family found")
    ax.set_title(f"envelope spectrum, band {band} ({lo:.0f}-{hi:.0f} Hz): {what}", fontsize=9)
    if grey:
        ax.legend(loc="center right", fontsize=7, framealpha=0.8)  # the top holds the labels
    return ax


def save_record_figure(x, details: dict, path, *, n_harmonics: int = AnalysisOptions.n_harmonics,
                       db: bool = False, fmax: float | None = None, orders: bool = False,
                       title: str | None = None, dpi: int = RECORD_FIGURE_DPI) -> str:
    """One figure an analyst reads: raw spectrum, envelope waveform and envelope spectrum of
    the band of the verdict (:func:`shown_family`), the verdict as its title.

    Parameters
    ----------
    x : array_like
        The record.
    details : dict
        ``analyze_signal(..., full_output=True)[1]``.
    path : str
        The PNG to write (its folder is created).
    n_harmonics, db, fmax, orders
        See :func:`plot_record_lines` (``db`` and ``orders`` also for the raw spectrum).
    title : str, optional
        First title line (e.g. the file).
    dpi : int
        Resolution.

    Returns
    -------
    str
        ``path``.
    """
    band, family = shown_family(details)
    fig = Figure(figsize=(9.0, 8.5))  # fixed margins: constrained layout doubles the cost
    ax_raw, ax_wave, ax_env = fig.subplots(3, 1, height_ratios=[1.0, 0.9, 1.4])
    fig.subplots_adjust(left=0.1, right=0.98, bottom=0.06, top=0.88, hspace=0.45)
    plot_raw_spectrum(details, ax_raw, db=db, orders=orders, band=band)
    if band is not None:
        plot_envelope_waveform(x, details, band, ax_wave, family=family)
        plot_record_lines(details, band, family, ax_env, n_harmonics=n_harmonics, db=db,
                          fmax=fmax, orders=orders)
    verdict = details.get("verdict")
    head = [] if title is None else [str(title)]
    if verdict is not None:
        head.append(textwrap.fill(f"verdict: {verdict.summary_lines()[0]}", 120))
    if head:
        fig.suptitle("\n".join(head), fontsize=9)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=dpi)
    return str(path)
