"""Figures of the signal chain: raw spectrum (Fig. 7), kurtogram and spectral kurtosis (Fig. 9),
demodulation bands per case (Fig. 10), envelope spectrum (Fig. 11) and harmonic amplitude
against depth per load (Figs 12-20)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...signal import spectral_kurtosis
from .common import LINE_NAME, SK_MIN_POINTS, _family_title, _per_load, depth_label, save_figure

__all__ = ["ORDERS_VS_DEPTH", "sk_window", "draw_kurtogram", "draw_band_limits",
           "fig_raw_spectrum", "fig_kurtogram", "fig_band_limits", "fig_envelope_spectrum",
           "fig_harmonics_vs_depth"]


#: Harmonic orders of the amplitude-against-depth figure.
ORDERS_VS_DEPTH = (1, 2)


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
        The figure, not saved (:func:`save_figure` writes it).
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
        The figure, not saved (:func:`save_figure` writes it).
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
