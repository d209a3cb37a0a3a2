"""Figures of the sweep (matplotlib, Agg), numbered after the source study.

Each function draws one figure from tables or case files and saves a PNG atomically.
Fig. 4 pressure maps, 5 time histories, 6 peak pressure vs load and depth, 7 raw spectrum,
9 kurtogram and spectral kurtosis, 10 band limits per case, 11 envelope spectrum,
12-20 harmonic amplitude vs depth per load for each band.
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

from .tables import _public_mode  # noqa: E402

__all__ = [
    "save_figure",
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


def save_figure(fig, path: str | os.PathLike, dpi: int = 120) -> Path:
    """Save ``fig`` as PNG through a temporary file and close it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".png", dir=path.parent)
    os.close(fd)
    try:
        fig.savefig(tmp, dpi=dpi, bbox_inches="tight")
        _public_mode(tmp)
        os.replace(tmp, path)
    finally:
        plt.close(fig)
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path


def _per_load(ax, df: pd.DataFrame, y: str, scale: float = 1.0, marker: str = "o"):
    for load, g in df.groupby("load_kN", sort=True):
        g = g.sort_values("depth_um")
        ax.plot(g["depth_um"], g[y] * scale, marker=marker, label=f"{load:g} kN")
    ax.set_xlabel("defect depth (µm)")
    ax.grid(True, alpha=0.3)
    ax.legend(title="load")


def fig_peak_pressure(cases: pd.DataFrame, path) -> Path:
    """Fig. 6: peak contact pressure against depth, one line per load (whole contact and defect)."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    _per_load(axes[0], cases, "p_max_peak_Pa", 1e-9)
    axes[0].set_ylabel("peak pressure (GPa)")
    axes[0].set_title("max over the whole contact")
    _per_load(axes[1], cases, "p_max_defect_peak_Pa", 1e-9)
    axes[1].set_title("max near the defect")
    fig.suptitle("Peak contact pressure vs load and defect depth (cf. study Fig. 6)")
    return save_figure(fig, path)


def fig_harmonics_vs_depth(tidy: pd.DataFrame, band: str, path, *, orders=(1, 2)) -> Path:
    """Figs 12-20: envelope harmonic amplitudes k x BPFI against depth, one line per load."""
    sel = tidy[(tidy["band"] == band) & (tidy["quantity"] == "envelope_bpfi") & (tidy["sideband"] == 0)]
    fig, axes = plt.subplots(1, len(orders), figsize=(5 * len(orders), 4), squeeze=False)
    for ax, k in zip(axes[0], orders):
        g = sel[sel["order"] == k]
        _per_load(ax, g, "amplitude", 1e-6)
        ax.set_ylabel("envelope amplitude (MPa)")
        ax.set_title(f"{k} x BPFI")
    lo_hi = sel[["band_low_hz", "band_high_hz"]].drop_duplicates()
    span = (
        f"{lo_hi.iloc[0, 0]:.0f}-{lo_hi.iloc[0, 1]:.0f} Hz" if len(lo_hi) == 1 else "band per case"
    )
    fig.suptitle(f"Envelope harmonics, band '{band}' ({span})")
    return save_figure(fig, path)


def fig_band_limits(bands: pd.DataFrame, path) -> Path:
    """Fig. 10: demodulation band limits of every case and strategy."""
    strategies = list(dict.fromkeys(bands["band"]))
    fig, ax = plt.subplots(figsize=(10, 0.35 * len(bands) + 1.5))
    labels = []
    for i, row in enumerate(bands.sort_values(["band", "load_kN", "depth_um"]).itertuples()):
        c = f"C{strategies.index(row.band) % 10}"
        ax.plot([row.low_hz / 1e3, row.high_hz / 1e3], [i, i], color=c, lw=4)
        labels.append(f"{row.band}  {row.case}")
    ax.set_yticks(range(len(labels)), labels, fontsize=7)
    ax.set_xlabel("frequency (kHz)")
    ax.grid(True, axis="x", alpha=0.3)
    ax.set_title("Demodulation bands per case (cf. study Fig. 10)")
    return save_figure(fig, path)




def fig_pressure_maps(defect_case, healthy_case, path) -> Path:
    """Fig. 4: pressure fields of the most loaded roller, without and with the defect.

    Left: the whole-roller (global) solution of the healthy case; right: the local window
    with the defect at the offset nearest the contact centre.
    """
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    snaps_h = healthy_case.snapshots or defect_case.snapshots
    key = sorted(snaps_h)[-1]
    s = snaps_h[key]
    im = axes[0].pcolormesh(np.asarray(s["global_y"]) * 1e3, np.asarray(s["global_x"]) * 1e3,
                            np.asarray(s["global_pressure"]) / 1e9, shading="auto", cmap="viridis")
    axes[0].set_title(f"no defect, roller load {float(s['roller_load']) / 1e3:.1f} kN")
    axes[0].set_xlabel("axial y (mm)")
    axes[0].set_ylabel("rolling x (mm)")
    fig.colorbar(im, ax=axes[0], label="pressure (GPa)")
    sd = defect_case.snapshots[sorted(defect_case.snapshots)[-1]]
    wp = np.asarray(sd["window_pressure"])
    offs = np.asarray(sd["offsets"])
    j = int(np.argmin(np.abs(offs)))
    im = axes[1].pcolormesh(np.asarray(sd["window_y"]) * 1e3, np.asarray(sd["window_x"]) * 1e3,
                            wp[j] / 1e9, shading="auto", cmap="viridis")
    axes[1].set_title(
        f"defect {defect_case.depth_um:g} µm at offset {offs[j] * 1e6:.0f} µm (local window)")
    axes[1].set_xlabel("axial y (mm)")
    fig.colorbar(im, ax=axes[1], label="pressure (GPa)")
    fig.suptitle(f"Contact pressure, {defect_case.load_kN:g} kN (cf. study Fig. 4)")
    return save_figure(fig, path)


def fig_time_histories(cases, path, *, periods: float = 6.0) -> Path:
    """Fig. 5: p_max(t) of several cases: a full revolution and a zoom on a few BPFI periods."""
    fig, axes = plt.subplots(2, 1, figsize=(10, 6))
    for c in cases:
        t = np.asarray(c.time)
        label = f"{c.load_kN:g} kN, {c.depth_um:g} µm"
        rev = t <= 1.0 / c.fr
        axes[0].plot(t[rev] * 1e3, np.asarray(c.p_max)[rev] / 1e9, lw=0.8, label=label)
        k = np.argmax(np.asarray(c.p_max_defect))
        t0 = max(0.0, t[k] - 0.5 * periods / c.bpfi)
        z = (t >= t0) & (t <= t0 + periods / c.bpfi)
        axes[1].plot(t[z] * 1e3, np.asarray(c.p_max)[z] / 1e9, lw=0.8, label=label)
    axes[0].set_title("one shaft revolution")
    axes[1].set_title(f"{periods:g} BPFI periods around the largest defect event")
    for ax in axes:
        ax.set_xlabel("time (ms)")
        ax.set_ylabel("max contact pressure (GPa)")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("Maximum contact pressure time history (cf. study Fig. 5)")
    fig.tight_layout()
    return save_figure(fig, path)


def _spectra(results_dir, case):
    return np.load(Path(results_dir) / "spectra" / f"{case}.npz")


def fig_raw_spectrum(results_dir, case: str, fr: float, bpfi: float, path, *, fmax=None) -> Path:
    """Fig. 7: raw amplitude spectrum of one case with k x fr and k x BPFI marked."""
    s = _spectra(results_dir, case)
    f, a = s["raw_f"], s["raw_a"]
    fmax = fmax or 6 * bpfi
    keep = (f > 0) & (f <= fmax)
    fig, ax = plt.subplots(figsize=(10, 4))
    ax.semilogy(f[keep], a[keep] / 1e6, lw=0.7, color="k")
    for k in range(1, int(fmax / bpfi) + 1):
        ax.axvline(k * bpfi, color="C3", ls="--", lw=0.8, label="k x BPFI" if k == 1 else None)
    for k in range(1, 4):
        ax.axvline(k * fr, color="C0", ls=":", lw=0.8, label="k x fr" if k == 1 else None)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("amplitude (MPa)")
    ax.legend()
    ax.set_title(f"Raw spectrum of p_max, {case} (0 Hz term: {float(a[0]) / 1e9:.3f} GPa) (cf. Fig. 7)")
    return save_figure(fig, path)


def fig_kurtogram(results_dir, case: str, path, *, signal=None, fs=None, nperseg=None) -> Path:
    """Fig. 9: fast kurtogram of one case (and its STFT spectral kurtosis when the signal is given)."""
    k = np.load(Path(results_dir) / "bands" / f"{case}_kurtogram.npz")
    ncols = 2 if signal is not None else 1
    fig, axes = plt.subplots(1, ncols, figsize=(6 * ncols, 4), squeeze=False)
    ax = axes[0, 0]
    if "matrix" in k:
        m, levels, freqs = k["matrix"], k["levels"], k["freqs"]
        im = ax.imshow(m, aspect="auto", origin="upper", cmap="jet",
                       extent=[freqs[0] / 1e3, freqs[-1] / 1e3, len(levels) - 0.5, -0.5])
        ax.set_yticks(range(len(levels)), [f"{lv:.1f}" for lv in levels])
        fig.colorbar(im, ax=ax, label="kurtosis")
        best = k["best"]
        ax.set_title(f"kurtogram: level {best[0]:.1f}, fc {best[1] / 1e3:.2f} kHz, "
                     f"Bw {best[2] / 1e3:.2f} kHz, K {best[3]:.1f}", fontsize=9)
        ax.set_xlabel("frequency (kHz)")
        ax.set_ylabel("level")
        if nperseg is None:
            nperseg = int(round(2.0 ** (best[0] + 1)))
    if signal is not None:
        from .signal import spectral_kurtosis

        f, sk = spectral_kurtosis(signal - np.mean(signal), fs, max(int(nperseg or 256), 16))
        axes[0, 1].plot(np.asarray(f) / 1e3, sk, color="k", lw=0.8)
        axes[0, 1].set_xlabel("frequency (kHz)")
        axes[0, 1].set_ylabel("spectral kurtosis")
        axes[0, 1].set_title(f"STFT spectral kurtosis, window {nperseg}, 80 % overlap", fontsize=9)
        axes[0, 1].grid(True, alpha=0.3)
    fig.suptitle(f"{case} (cf. study Fig. 9)")
    fig.tight_layout()
    return save_figure(fig, path)


def fig_envelope_spectrum(results_dir, case: str, band: str, fr: float, bpfi: float, path, *,
                          n_harmonics: int = 3, n_sidebands: int = 2) -> Path:
    """Fig. 11: envelope spectrum of one case and band, BPFI harmonics and fr sidebands marked."""
    s = _spectra(results_dir, case)
    f, a = s[f"env_{band}_f"], s[f"env_{band}_a"]
    fig, ax = plt.subplots(figsize=(10, 4))
    ax.plot(f, a / 1e6, lw=0.8, color="k")
    for k in range(1, n_harmonics + 1):
        ax.axvline(k * bpfi, color="C3", ls="--", lw=0.9, label="k x BPFI" if k == 1 else None)
        for m in range(1, n_sidebands + 1):
            for sgn in (-1, 1):
                ax.axvline(k * bpfi + sgn * m * fr, color="C0", ls=":", lw=0.8,
                           label="k x BPFI ± m x fr" if (k, m, sgn) == (1, 1, -1) else None)
    ax.set_xlim(0, f[-1] if len(f) else 1)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("envelope amplitude (MPa)")
    ax.legend()
    ax.set_title(f"Envelope spectrum, {case}, band '{band}' (cf. study Fig. 11)")
    return save_figure(fig, path)


def make_figures(*, harmonics, cases, bands, results_dir, example, analysis, outdir) -> list[Path]:
    """Draw every figure of the sweep into ``outdir`` (written to a temporary folder, then renamed).

    Parameters
    ----------
    harmonics, cases, bands : path
        The aggregate tables (``results/tables/*.csv``).
    results_dir : path
        Where ``cases/``, ``bands/`` and ``spectra/`` live.
    example : mapping
        ``{"defect": case name, "healthy": case name}`` drawn alone (Figs 4, 5, 7, 9, 11).
    analysis : mapping
        The config's ``analysis`` section.
    outdir : path
        Output folder.
    """
    import shutil

    from .io import read_case

    outdir = Path(outdir)
    tmp = outdir.with_name(outdir.name + ".tmp")
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir(parents=True)
    tidy = pd.read_csv(harmonics)
    summary = pd.read_csv(cases)
    band_table = pd.read_csv(bands)
    rd = Path(results_dir)
    cd = read_case(rd / "cases" / f"{example['defect']}.h5")
    ch = read_case(rd / "cases" / f"{example['healthy']}.h5")
    written = [
        fig_pressure_maps(cd, ch, tmp / "fig04_pressure_maps.png"),
        fig_time_histories([ch, cd], tmp / "fig05_time_histories.png"),
        fig_peak_pressure(summary, tmp / "fig06_peak_pressure.png"),
        fig_raw_spectrum(rd, example["defect"], cd.fr, cd.bpfi, tmp / "fig07_raw_spectrum.png"),
    ]
    if any(b["strategy"] == "kurtogram" for b in analysis["bands"]):
        x = np.asarray(cd.signals[analysis.get("signal", "p_max")], dtype=float)
        written.append(fig_kurtogram(rd, example["defect"], tmp / "fig09_kurtogram_sk.png",
                                     signal=x, fs=cd.fs))
    written.append(fig_band_limits(band_table, tmp / "fig10_band_limits.png"))
    for b in analysis["bands"]:
        written.append(fig_envelope_spectrum(
            rd, example["defect"], b["name"], cd.fr, cd.bpfi,
            tmp / f"fig11_envelope_spectrum_{b['name']}.png",
            n_harmonics=int(analysis.get("harmonics", 3)),
            n_sidebands=int(analysis.get("sidebands", 2))))
    for i, b in enumerate(analysis["bands"]):
        written.append(fig_harmonics_vs_depth(tidy, b["name"], tmp / f"fig{12 + i:02d}_harmonics_{b['name']}.png"))
    raw = tidy[(tidy["band"] == "raw") & (tidy["order"] <= 1)]
    written.append(_fig_raw_terms(raw, tmp / "fig08_raw_terms.png"))
    shutil.rmtree(outdir, ignore_errors=True)
    tmp.rename(outdir)
    return [outdir / p.name for p in written]


def _fig_raw_terms(raw: pd.DataFrame, path) -> Path:
    """Fig. 8: raw-spectrum 0 Hz, 1 x fr and 1 x BPFI amplitudes against depth per load."""
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    for ax, (q, title) in zip(axes, [("raw_dc", "0 Hz (mean)"), ("raw_fr", "1 x fr"),
                                      ("raw_bpfi", "1 x BPFI")]):
        g = raw[(raw["quantity"] == q) & (raw["sideband"] == 0)]
        _per_load(ax, g, "amplitude", 1e-6)
        ax.set_ylabel("amplitude (MPa)")
        ax.set_title(title)
    fig.suptitle("Raw-spectrum terms vs load and depth (cf. study Fig. 8)")
    return save_figure(fig, path)


def fig_diagnosability_maps(df: pd.DataFrame, outdir) -> list[Path]:
    """Heat maps of the BPFI detection statistic: one figure per band, one panel per load,
    depth x SNR cells coloured by the statistic (dB) and marked where detected.

    Written to a temporary folder, then renamed to ``outdir``.
    """
    import shutil

    outdir = Path(outdir)
    tmp = outdir.with_name(outdir.name + ".tmp")
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir(parents=True)
    written = []
    vmax = float(np.nanmax(df["statistic_db"])) if len(df) else 1.0
    for band, g in df.groupby("band", sort=False):
        loads = sorted(g["load_kN"].unique())
        fig, axes = plt.subplots(1, len(loads), figsize=(4.2 * len(loads), 3.8), squeeze=False)
        for ax, load in zip(axes[0], loads):
            s = g[g["load_kN"] == load]
            stat = s.pivot_table(index="snr_db", columns="depth_um", values="statistic_db")
            det = s.pivot_table(index="snr_db", columns="depth_um", values="detected")
            im = ax.imshow(stat.to_numpy(), origin="lower", aspect="auto", cmap="magma",
                           vmin=0.0, vmax=vmax)
            ax.set_xticks(range(stat.shape[1]), [f"{d:g}" for d in stat.columns])
            ax.set_yticks(range(stat.shape[0]), [f"{v:g}" for v in stat.index])
            for i in range(stat.shape[0]):
                for j in range(stat.shape[1]):
                    if bool(det.to_numpy()[i, j]):
                        ax.text(j, i, "✓", ha="center", va="center", color="cyan", fontsize=11)
            ax.set_xlabel("defect depth (µm)")
            ax.set_ylabel("SNR (dB)")
            ax.set_title(f"{load:g} kN")
        fig.colorbar(im, ax=axes[0].tolist(), label="BPFI line / background (dB)")
        fig.suptitle(f"BPFI detection in the synthetic acceleration, band '{band}' (✓ = detected)")
        written.append(save_figure(fig, tmp / f"diagnosability_{band}.png"))
    shutil.rmtree(outdir, ignore_errors=True)
    tmp.rename(outdir)
    return [outdir / p.name for p in written]
