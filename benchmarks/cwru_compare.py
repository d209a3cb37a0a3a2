"""Simulated CWRU envelope spectra next to the shared CWRU development records (issue 23 part 6).

For each fault location of a CWRU location sweep (``config_cwru.yaml`` +
``config_cwru_locations.yaml``) the simulated p_max history of the 0.007 in pit and the CWRU
drive-end record of the same fault at 0 hp (1797 rpm) go through the same chain
(:func:`bearing_envelope.diagnosis.analyze_signal`: kurtogram band, envelope spectrum, the
location's family from the scene, +-1 % search): inner race 105 (IR007), outer race 130
(OR007 at 6:00), ball 118 (B007). The figure shows both envelope spectra on an order axis
(x shaft rate) with the fault lines and sideband spacings marked, each normalised to its own
largest line (the transfer path to the accelerometer is unknown: amplitudes are not compared).
The table lists the measured line frequencies in orders, both sides, and whether they agree.

Run: ``python benchmarks/cwru_compare.py --run /path/to/sweep --out docs/img/cwru_envelope_orders.png``
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from bearing_envelope.diagnosis import AnalysisOptions, analyze_signal  # noqa: E402
from bearing_envelope.diagnosis.faults import display_name  # noqa: E402
from bearing_envelope.io import read_case  # noqa: E402
from bearing_envelope.study.pipeline import case_fault_lines  # noqa: E402
from bearing_envelope.study.settings import CaseId  # noqa: E402

#: The shared development records (read only; no other CWRU data is used).
RECORDS = Path(__file__).resolve().parents[2] / "shared" / "data" / "real" / "cwru_de12"
#: Location -> CWRU record file of the same fault (0.007 in, 0 hp, 1797 rpm).
RECORD_OF = {"inner_race": "cwru_105_IR007_0hp_DE12.npz",
             "outer_race": "cwru_130_OR007at6_0hp_DE12.npz",
             "rolling_element": "cwru_118_B007_0hp_DE12.npz"}
#: The simulated case of each location: 1 kN (assumed), 0.011 in deep, 0.007 in pit.
CASE_OF = {loc: CaseId(1.0, 279.4, 177.8, loc).name for loc in RECORD_OF}
#: Envelope harmonics and sidebands read on both sides.
HARMONICS, SIDEBANDS = 3, 2
#: Kurtogram depth of the band choice (both sides).
NLEVEL = 6
#: Two measured lines agree when both are detected and their orders differ by less than this
#: fraction of the nominal order (the line search's own +-1 % window).
AGREE_FRACTION = 0.01


def analyse(x, fs, fr, lines, spacing):
    """analyze_signal with the kurtogram band and the location's family; (table, spectrum)."""
    options = AnalysisOptions(bands=[{"name": "kurtogram", "strategy": "kurtogram"}],
                              n_harmonics=HARMONICS, n_sidebands=SIDEBANDS, nlevel=NLEVEL,
                              sideband_spacing=spacing)
    table, det = analyze_signal(x, fs, fr=fr, fault_frequencies=lines, options=options,
                                full_output=True)
    b = det["bands"]["kurtogram"]
    env = table[(table["quantity"] == "envelope_spectrum")].copy()
    return env, (b["f"], b["amplitude"], b["band"])


def real_record(location):
    """(x, fs, fr) of the CWRU record of a location."""
    with np.load(RECORDS / RECORD_OF[location], allow_pickle=False) as z:
        meta = json.loads(str(z["meta_json"]))
        return np.asarray(z["x"], float), float(z["fs"]), float(meta["shaft_hz"])


def compare_location(run: Path, location: str):
    """Both analyses of one location: rows of the agreement table and the two spectra."""
    case = read_case(run / "results" / "cases" / f"{CASE_OF[location]}.h5")
    lines, spacing = case_fault_lines(case)
    fr_sim = float(case.fr)
    sim, spec_sim = analyse(np.asarray(case.signals["p_max"], float), float(case.fs), fr_sim,
                            lines, spacing)
    x, fs, fr_real = real_record(location)
    real, spec_real = analyse(x, fs, fr_real, lines, spacing)
    family = next(iter(lines))
    rows = []
    for (k, m), s in sim.groupby(["order", "sideband"]):
        r = real[(real["order"] == k) & (real["sideband"] == m)].iloc[0]
        s = s.iloc[0]
        o_sim, o_real = s["frequency_hz"] / fr_sim, r["frequency_hz"] / fr_real
        nominal = s["target_hz"] / fr_sim
        both = bool(s["detected"]) and bool(r["detected"])
        rows.append({"location": location, "line": f"{k} x {display_name(family)}"
                     + (f" {'+' if m > 0 else '-'} {abs(m)} x {display_name(spacing[family][0]) if spacing else 'fr'}"
                        if m else ""),
                     "nominal_order": nominal, "sim_order": o_sim, "sim_detected": bool(s["detected"]),
                     "real_order": o_real, "real_detected": bool(r["detected"]),
                     "agree": both and abs(o_sim - o_real) <= AGREE_FRACTION * nominal})
    return rows, (spec_sim, fr_sim), (spec_real, fr_real), lines, spacing


def draw(panels, path: Path) -> None:
    """One row per location: simulated (left) and CWRU (right) envelope spectra in orders."""
    fig, axes = plt.subplots(len(panels), 2, figsize=(12, 3.0 * len(panels)), squeeze=False)
    for row, (loc, sim, real, lines, spacing) in zip(axes, panels):
        family, f_line = next(iter(lines.items()))
        sb_name, f_sb = (spacing or {}).get(family, ("fr", sim[1]))
        for ax, ((f, a, band), fr), who in ((row[0], sim, "simulated p_max"),
                                              (row[1], real, f"CWRU {RECORD_OF[loc][5:8]}")):
            top = (HARMONICS + 0.7) * f_line / fr
            keep = (f > 0) & (f / fr <= top)
            ax.plot(f[keep] / fr, a[keep] / np.max(a[keep]), color="k", lw=0.7)
            for k in range(1, HARMONICS + 1):
                ax.axvline(k * f_line / fr, color="C3", ls="--", lw=0.8)
                for m in (-2, -1, 1, 2):
                    ax.axvline((k * f_line + m * f_sb) / fr, color="C0", ls=":", lw=0.7)
            ax.set_xlim(0, top)
            ax.set_title(f"{loc}: {who}, band {band[0] / 1e3:.1f}-{band[1] / 1e3:.1f} kHz",
                         fontsize=9)
            ax.set_ylabel("envelope / its max")
        row[0].text(0.99, 0.9, f"red: k x {display_name(family)}; blue: ± m x "
                    f"{display_name(sb_name)}", transform=row[0].transAxes, ha="right",
                    fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("order (x shaft rate)")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None) -> None:
    """Compare every location and write the figure and the table (Markdown to stdout)."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--run", type=Path, required=True, help="the CWRU location sweep's directory")
    p.add_argument("--out", type=Path, default=Path("docs/img/cwru_envelope_orders.png"))
    p.add_argument("--csv", type=Path, default=None, help="also write the table as CSV")
    args = p.parse_args(argv)
    rows, panels = [], []
    for loc in RECORD_OF:
        r, sim, real, lines, spacing = compare_location(args.run, loc)
        rows += r
        panels.append((loc, sim, real, lines, spacing))
    draw(panels, args.out)
    df = pd.DataFrame(rows)
    if args.csv:
        df.to_csv(args.csv, index=False)
    print(df.to_markdown(index=False, floatfmt=".4f"))


if __name__ == "__main__":
    main()
