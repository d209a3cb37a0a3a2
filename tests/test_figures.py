"""Figures: each test checks a defect a reader found in the drawn figure (issue 16).

The figures are drawn from small synthetic cases and tables (no sweep), so every test is fast;
the workflow test draws them from a real draft sweep.
"""

from __future__ import annotations

import re
from types import SimpleNamespace

import matplotlib
import numpy as np
import pandas as pd
import pytest

matplotlib.use("Agg")

from bearing_envelope.study import figures  # noqa: E402
from bearing_envelope.study.case_id import CaseId  # noqa: E402

FS, FR, BPFI = 65000.0, 15.8, 231.9


def fake_case(load, depth, *, revolutions=3.0, event_at=None):
    """A case-like object: p_max(t) = a load-zone hump per revolution plus, with a defect,
    one short dip-and-spike per BPFI period, the largest at ``event_at`` (s)."""
    t = np.arange(int(revolutions * FS / FR)) / FS
    p = 1e9 * (load / 250.0) * np.clip(np.cos(2 * np.pi * FR * t), 0, None)
    pd_ = np.zeros_like(t)
    if depth:
        k = np.arange(int(t[-1] * BPFI)) / BPFI
        for i, tk in enumerate(k):
            amp = 1e8 * (1 + depth / 50.0) * (2.0 if event_at is not None and abs(tk - event_at) < 0.5 / BPFI else 1.0)
            pd_ += amp * np.exp(-0.5 * ((t - tk) / 2e-5) ** 2)
        p = p + pd_
    snap = {"roller_load": 1e3 * load / 10, "global_x": np.linspace(-4e-4, 4e-4, 20),
            "global_y": np.linspace(-0.017, 0.017, 30), "global_pressure": np.ones((20, 30)) * 1e9,
            "window_x": np.linspace(-2e-4, 2e-4, 40), "window_y": np.linspace(-5e-4, 5e-4, 10),
            "window_pressure": np.ones((3, 40, 10)) * 2e9, "offsets": np.array([-1e-4, 0.0, 1e-4])}
    return SimpleNamespace(time=t, p_max=p, p_max_defect=pd_ if depth else np.zeros_like(t),
                           fr=FR, bpfi=BPFI, fs=FS, load_kN=float(load), depth_um=float(depth),
                           snapshots={"load_0": snap}, signals={"p_max": p})


def default_sweep_ids():
    return [CaseId(f, d) for f in (250, 500, 750) for d in (0, 15, 20, 30, 40, 50, 60, 80, 100)]


# --- Figs 4 and 5: the study's six panels -------------------------------------------------

def test_example_pairs_are_the_studys_cases_in_the_default_sweep():
    pairs = figures.example_pairs(default_sweep_ids())
    assert [(p["healthy"], p["defect"]) for p in pairs] == [
        ("F250kN_h0um", "F250kN_h15um"), ("F500kN_h0um", "F500kN_h50um"),
        ("F750kN_h0um", "F750kN_h100um")]


def test_example_pairs_take_the_nearest_cases_present():
    ids = [CaseId(f, d) for f in (250, 750) for d in (0, 50)]
    pairs = figures.example_pairs(ids)
    # 500 kN is equally far from 250 and 750 kN: the higher load; duplicates are dropped
    assert [(p["healthy"], p["defect"]) for p in pairs] == [
        ("F250kN_h0um", "F250kN_h50um"), ("F750kN_h0um", "F750kN_h50um")]


def test_fig4_draws_every_load_of_the_study_with_and_without_defect():
    pairs = [(fake_case(f, 0), fake_case(f, d)) for f, d in figures.STUDY_EXAMPLES]
    fig = figures.draw_pressure_maps(pairs)
    titles = [ax.get_title() for ax in fig.axes if ax.get_title()]
    for f, d in figures.STUDY_EXAMPLES:
        assert any(t.startswith(f"{f:g} kN, 0 µm") for t in titles), titles
        assert any(t.startswith(f"{f:g} kN, {d:g} µm") for t in titles), titles
    matplotlib.pyplot.close(fig)


def _texts(fig):
    return " ".join(t.get_text() for t in fig.texts)


@pytest.mark.parametrize("draw", ["pressure_maps", "time_histories", "peak_pressure"])
def test_pressure_figures_say_elastic_and_grid_dependent(draw):
    pairs = [(fake_case(250, 0), fake_case(250, 15))]
    if draw == "peak_pressure":
        cases = pd.DataFrame({"load_kN": [250, 250], "depth_um": [0, 15],
                              "p_max_peak_Pa": [2e9, 6e9], "p_max_defect_peak_Pa": [2e9, 9e9]})
        fig = figures.draw_peak_pressure(cases, grid="defect window 2 x 40 µm")
    else:
        fig = getattr(figures, f"draw_{draw}")(pairs)
    text = _texts(fig)
    assert "elastic" in text and "grid" in text and "µm" in text, text
    matplotlib.pyplot.close(fig)


def test_fig5_zoom_is_time_from_each_cases_own_largest_event():
    """Each defect case centred on its own largest event, on one relative time axis: the
    former figure plotted absolute times and spanned 0-4000 ms."""
    pairs = [(fake_case(250, 0), fake_case(250, 15, event_at=0.05)),
             (fake_case(750, 0), fake_case(750, 100, event_at=0.15))]
    fig = figures.draw_time_histories(pairs, periods=6.0)
    zoom = fig.axes[1]
    half_ms = 3.0 / BPFI * 1e3
    lo, hi = zoom.get_xlim()
    assert lo == pytest.approx(-half_ms) and hi == pytest.approx(half_ms)
    lines = zoom.get_lines()
    assert len(lines) == 4
    for line in lines:
        x = line.get_xdata()
        assert x.min() >= -half_ms - 1e-9 and x.max() <= half_ms + 1e-9
        assert x.max() - x.min() > 0.95 * 2 * half_ms
    for defect, healthy in zip(lines[0::2], lines[1::2]):  # the largest event sits at 0
        x, y = defect.get_xdata(), defect.get_ydata() - healthy.get_ydata()
        assert abs(x[np.argmax(y)]) < 0.5 / BPFI * 1e3
    matplotlib.pyplot.close(fig)


def test_fig5_healthy_trace_is_drawn_visibly_over_the_defect_trace():
    pairs = [(fake_case(250, 0), fake_case(250, 15))]
    fig = figures.draw_time_histories(pairs)
    for ax in fig.axes:
        defect, healthy = ax.get_lines()
        assert "0 µm" in healthy.get_label() and "15 µm" in defect.get_label()
        assert healthy.get_zorder() > defect.get_zorder()
        assert healthy.get_linestyle() != defect.get_linestyle()
        assert matplotlib.colors.to_hex(healthy.get_color()) != matplotlib.colors.to_hex(defect.get_color())
    matplotlib.pyplot.close(fig)


# --- Fig 9: the spectral-kurtosis window the title states is the one used ------------------

def test_fig9_title_states_the_window_used_and_sk_is_resolved():
    rng = np.random.default_rng(0)
    x = rng.standard_normal(65000)
    levels = np.array([0, 1, 1.6, 2, 2.6, 3])
    kg = {"matrix": rng.random((6, 48)), "levels": levels, "freqs": np.linspace(0, FS / 2, 48),
          "best": np.array([3.0, 28437.5, 4062.5, 5.0])}  # level 3: 2^(3+1) = 16 samples
    fig = figures.draw_kurtogram(kg, "F750kN_h100um", signal=x, fs=FS)
    ax = fig.axes[-1] if fig.axes[-1].get_lines() else fig.axes[1]
    ax = next(a for a in fig.axes if a.get_lines())
    m = re.search(r"window (\d+) samples \((\d+) Hz resolution\)", ax.get_title())
    assert m, ax.get_title()
    window = int(m.group(1))
    f = ax.get_lines()[0].get_xdata()
    assert len(f) == window // 2 + 1  # the STFT used that window
    assert np.diff(f)[0] * 1e3 == pytest.approx(FS / window)
    assert int(m.group(2)) == round(FS / window)
    assert len(f) >= 129  # enough frequency points to see where the kurtosis lies
    matplotlib.pyplot.close(fig)


def test_sk_window():
    assert figures.sk_window(3) == 256
    assert figures.sk_window(8) == 512
    assert figures.sk_window(2.585) == 256
    assert figures.sk_window(3, min_points=9) == 16


# --- Fig 10: bounded size whatever the number of cases ---------------------------------------

def band_table(loads, depths):
    rows = []
    for f in loads:
        for d in depths:
            name = CaseId(f, d).name
            lo = 16250.0 if d < 50 else 10833.0
            for band, strat, l, h in (("kurtogram", "kurtogram", lo, min(lo * 2, 31850.0)),
                                      ("fs4_3fs8", "fraction", 16250.0, 24375.0),
                                      ("bpfi_3_6", "orders", 695.7, 1391.4),
                                      ("bpfi_10_13", "orders", 2319.0, 3014.7),
                                      ("fixed", "fixed", 8125.0, 16250.0)):
                rows.append({"case": name, "load_kN": float(f), "depth_um": float(d), "band": band,
                             "strategy": strat, "low_hz": l, "high_hz": h, "clamped": h == 31850.0})
    return pd.DataFrame(rows)


@pytest.mark.parametrize("loads, depths", [((250, 500, 750), (0, 15, 20, 30, 40, 50, 60, 80, 100)),
                                           ((100, 250, 400, 500, 750), tuple(range(0, 120, 10)))])
def test_fig10_size_is_bounded(tmp_path, loads, depths):
    from PIL import Image

    bands = band_table(loads, depths)
    path = figures.fig_band_limits(bands, tmp_path / "fig10.png", fs=FS)
    with Image.open(path) as im:
        w, h = im.size
    assert w <= 2000 and h <= 1000, (w, h)  # the former strip was 1146 x 4605 px
    assert w / h < 4.0


def test_fig10_shows_every_kurtogram_band_and_the_fixed_bands_once():
    bands = band_table((250, 500, 750), (0, 15, 100))
    fig = figures.draw_band_limits(bands, fs=FS)
    grid = fig.axes[0]
    labels = [t.get_text() for t in grid.texts]
    assert len(labels) == 9  # one cell per case
    assert any(lbl.endswith("*") for lbl in labels)  # clamped bands are marked
    bars = next(ax for ax in fig.axes if ax.get_title().startswith("bands equal"))
    names = [t.get_text() for t in bars.get_yticklabels()]
    assert names == ["fs4_3fs8", "bpfi_3_6", "bpfi_10_13", "fixed", "kurtogram"]
    matplotlib.pyplot.close(fig)


# --- diagnosability maps: no label runs into the next panel ---------------------------------

def test_diagnosability_map_labels_do_not_overlap_panels():
    rows = [{"load_kN": f, "depth_um": d, "snr_db": s, "statistic_db": 5.0 + d / 10 + s / 5,
             "detected": d > 0 and s > 0}
            for f in (250, 500, 750) for d in (0, 15, 50, 100) for s in (-20, -10, 0, 10, 20)]
    fig = figures.draw_diagnosability_map(pd.DataFrame(rows), "fixed")
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    panels = [ax for ax in fig.axes if ax.get_title().endswith("kN")]
    assert len(panels) == 3
    for left, right in zip(panels, panels[1:]):
        a, b = left.get_tightbbox(r), right.get_tightbbox(r)
        assert a.x1 <= b.x0 + 1.0, (a, b)  # tight boxes (labels included) do not overlap
    assert sum(ax.get_ylabel() == "SNR (dB)" for ax in panels) == 1
    matplotlib.pyplot.close(fig)


def test_figure_folders_are_swapped_whole_and_writers_never_share_a_temp_folder(tmp_path):
    # issue 17 item 6: two runs (one started after --unlock beside another) shared
    # results/figures.tmp/ and both failed; figures and report tables use io.atomic_dir
    from bearing_envelope.io import atomic_dir

    out = tmp_path / "figures"
    with atomic_dir(out) as a, atomic_dir(out) as b:
        assert a != b and a.parent == b.parent == tmp_path
        (a / "x.png").write_text("a")
        (b / "x.png").write_text("b")
    assert (out / "x.png").read_text() == "a"          # the outer writer finished last
    with atomic_dir(out) as c:
        (c / "y.png").write_text("c")
    assert sorted(p.name for p in out.iterdir()) == ["y.png"]   # replaced whole
    with pytest.raises(RuntimeError):
        with atomic_dir(out) as d:
            (d / "z.png").write_text("half")
            raise RuntimeError("interrupted")
    assert sorted(p.name for p in out.iterdir()) == ["y.png"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["figures"]


@pytest.mark.parametrize("widths", [None, [60.0, 60.0]])
def test_depth_axis_says_the_width_follows_the_depth_unless_width_is_its_own_axis(widths):
    """At w = 2 h the 'depth' axis varies the width (the pit bottom is not touched above
    ~2 um), so the label says so; with ``sweep.widths_um`` the width is a column of its own."""
    cases = pd.DataFrame({"load_kN": [250, 250], "depth_um": [0, 15],
                          "p_max_peak_Pa": [2e9, 6e9], "p_max_defect_peak_Pa": [2e9, 9e9]})
    if widths is not None:
        cases["width_um"] = widths
    fig = figures.draw_peak_pressure(cases)
    labels = [ax.get_xlabel() for ax in fig.axes]
    matplotlib.pyplot.close(fig)
    assert all(("w = 2h" in lab) == (widths is None) for lab in labels), labels
    assert all(lab.startswith("defect depth h") for lab in labels), labels
