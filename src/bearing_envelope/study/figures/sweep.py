"""Every figure of the sweep from its tables and files (:func:`make_figures`), the raw terms
(Fig. 8) among them."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...diagnosis.faults import display_name
from ...io import atomic_dir, read_case
from ..pipeline import case_fault_lines
from .common import _family_title, _grid_text, _per_load, save_figure
from .pressure import fig_peak_pressure, fig_pressure_maps, fig_time_histories
from .spectra import (fig_band_limits, fig_envelope_spectrum, fig_harmonics_vs_depth,
                      fig_kurtogram, fig_raw_spectrum)

__all__ = ["make_figures"]


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
