import numpy as np
from matplotlib.figure import Figure

from bearing_envelope.diagnosis import AnalysisOptions, analyze_signal
from bearing_envelope.signal import envelope_spectrum, fast_kurtogram
from bearing_envelope.diagnosis.plots import (
    plot_envelope_spectrum,
    plot_kurtogram,
    save_analysis_figures,
)


def test_plot_functions(fault, tmp_path):
    x, fs = fault["x"][: 2**15], fault["fs"]
    kg = fast_kurtogram(x, fs, 6)
    ax = plot_kurtogram(kg)
    assert ax.get_ylabel() == "level" and len(ax.patches) == 1
    fig = Figure()
    ax2 = fig.add_subplot()
    assert plot_kurtogram(kg, ax2, mark_best=False) is ax2
    f, a = envelope_spectrum(x, fs, kg.band if kg.band[1] < fs / 2 else (kg.band[0], 9000))
    ax3 = plot_envelope_spectrum(f, a, base=fault["bpfi"], fr=fault["fr"], n_harmonics=3,
                                 n_sidebands=2)
    # 3 harmonics + 3 * 2 * 2 sidebands
    assert len(ax3.lines) == 1 + 3 + 12
    assert ax3.get_xlim()[1] == 3.5 * fault["bpfi"]


def test_save_analysis_figures(fault, tmp_path):
    df, det = analyze_signal(
        fault["x"][: 2**15],
        fault["fs"],
        fr=fault["fr"],
        bpfi=fault["bpfi"],
        full_output=True,
        options=AnalysisOptions(nlevel=6),
    )
    paths = save_analysis_figures(det, tmp_path, prefix="case_")
    names = sorted(p.split("/")[-1] for p in paths)
    assert names == sorted(["case_kurtogram.png", "case_envelope_kurtogram.png",
                            "case_envelope_fs4_3fs8.png", "case_envelope_bpfi_3_6.png",
                            "case_envelope_bpfi_10_13.png"])
    assert all((tmp_path / n).stat().st_size > 1000 for n in names)


def test_every_family_marked(fault, tmp_path):
    """plot_fault_lines draws one dashed line per harmonic and one dotted per sideband of every
    family (at the frequencies found), and one dot per detected line."""
    from bearing_envelope.physics.kinematics import fault_frequencies
    from bearing_envelope.diagnosis.plots import plot_fault_lines

    ff = fault_frequencies(fault["fr"], 9, 7.94, 39.04)
    faults = {"bpfo": ff.bpfo, "bpfi": fault["bpfi"], "bsf": ff.bsf, "ftf": ff.ftf}
    _, det = analyze_signal(
        fault["x"][: 2**15],
        fault["fs"],
        fr=fault["fr"],
        fault_frequencies=faults,
        full_output=True,
        options=AnalysisOptions(
            n_harmonics=3,
            bands=[{"name": "b", "strategy": "fixed", "low_hz": 5000.0, "high_hz": 7000.0}],
        ),
    )
    lines = det["bands"]["b"]["lines"]
    assert set(lines) == {"bpfo", "bpfi", "bsf", "bsf2", "ftf"}
    fmax = 3000.0
    ax = plot_fault_lines(det["bands"]["b"]["f"], det["bands"]["b"]["amplitude"], lines,
                          fmax=fmax)
    recs = [r for v in lines.values() for r in v if r["frequency_hz"] <= fmax]
    vlines = [ln for ln in ax.lines if ln.get_linestyle() in ("--", ":")]
    dots = [ln for ln in ax.lines if ln.get_marker() == "o"]
    assert len(vlines) == len(recs)
    assert sum(ln.get_linestyle() == ":" for ln in vlines) == sum(r["sideband"] != 0 for r in recs)
    assert len(dots) == sum(bool(r["detected"]) for r in recs) > 0
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert len(labels) == 5 and any(t.startswith("k x BPFI (") and "detected" in t
                                    for t in labels)
