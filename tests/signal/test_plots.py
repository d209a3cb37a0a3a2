import numpy as np
from matplotlib.figure import Figure

from bearing_envelope.signal import analyze_signal, envelope_spectrum, fast_kurtogram
from bearing_envelope.signal.plots import (
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
    df, det = analyze_signal(fault["x"][: 2**15], fault["fs"], fr=fault["fr"],
                             bpfi=fault["bpfi"], nlevel=6, full_output=True)
    paths = save_analysis_figures(det, tmp_path, prefix="case_")
    names = sorted(p.split("/")[-1] for p in paths)
    assert names == sorted(["case_kurtogram.png", "case_envelope_kurtogram.png",
                            "case_envelope_fs4_3fs8.png", "case_envelope_bpfi_3_6.png",
                            "case_envelope_bpfi_10_13.png"])
    assert all((tmp_path / n).stat().st_size > 1000 for n in names)
