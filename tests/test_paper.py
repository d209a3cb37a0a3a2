"""bearing_envelope.study.paper: verdicts on tables built to reproduce (or contradict) each finding."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from bearing_envelope.study import paper

LOADS = (250.0, 500.0, 750.0)
DEPTHS = (0.0, 15.0, 20.0, 30.0, 40.0, 50.0, 60.0, 80.0, 100.0)


#: Depth jitter without a trend (Spearman with depth -0.21).
NO_TREND = dict(zip((15.0, 20.0, 30.0, 40.0, 50.0, 60.0, 80.0, 100.0), (3, -1, -4, 2, 4, -3, 1, -2)))


def study_like():
    """Tables in which every finding of the study holds by construction."""
    cases, rows, bands = [], [], []
    for f in LOADS:
        for d in DEPTHS:
            name = f"F{f:g}kN_h{d:g}um"
            cases.append({"case": name, "load_kN": f, "depth_um": d,
                          "p_max_peak_Pa": 2e9 + 1e7 * d ** 1.5, "p_max_defect_peak_Pa": (1 + f / 250) * 1e9 * (1 + (d / 30) ** 4),
                          "snapshot_roller_load_N": f * 100, "p_centre_Pa": 2e9,
                          "p_end_Pa": 1.5e9 if f <= 250 else 2.5e9,
                          "edge_ratio": 0.75 if f <= 250 else 1.25})

            def add(band, quantity, order, amp):
                rows.append({"case": name, "load_kN": f, "depth_um": d, "band": band,
                             "band_strategy": band, "band_low_hz": 1.0, "band_high_hz": 2.0,
                             "quantity": quantity, "order": order, "sideband": 0,
                             "frequency_hz": 0.0, "amplitude": amp})
            add("raw", "raw_dc", 0, 1e9 + 2e6 * f + 1e5 * d + 3e3 * f * d)  # exactly bilinear
            add("raw", "raw_fr", 1, 1e6 * f)                                 # load only
            add("raw", "raw_bpfi", 1, 1e2 * f * (1 + d))                     # load and depth, < 1 %
            dip = 0.5 if d == 60 else 1.0
            add("fixed", "envelope_bpfi", 1, f * d * dip + 1)                 # dip at 60 um
            add("bpfi_3_6", "envelope_bpfi", 1, 10 * f + NO_TREND.get(d, 0))  # linear, no depth trend
            add("bpfi_3_6", "envelope_bpfi", 2, f ** 2.5)                    # nonlinear in load
            add("bpfi_10_13", "envelope_bpfi", 1, f * (1 + d))
            add("bpfi_10_13", "envelope_bpfi", 2, 2 * f * (1 + d))            # correlated, higher
            add("kurtogram", "envelope_bpfi", 1, 1.0 + (d * 7919 % 13))       # no trend
            clamped = d >= 100 or (d == 80 and f == 750)
            lo = 1000.0 * (1 + (d * 31 + f) % 7)
            bands.append({"case": name, "load_kN": f, "depth_um": d, "band": "kurtogram",
                          "strategy": "kurtogram", "low_hz": lo, "high_hz": 31850.0 if clamped else lo * 2,
                          "clamped": clamped})
    return paper.Tables(pd.DataFrame(cases), pd.DataFrame(rows), pd.DataFrame(bands))


def verdicts(t):
    return {f.key: f.verdict for f in paper.findings(t)}


def test_every_finding_reproduced_on_tables_built_to_reproduce_it():
    v = verdicts(study_like())
    assert set(v) == {"pattern", "peak", "raw_small", "dc", "kurtogram_nyquist",
                      "kurtogram_misleading", "raw_fr", "raw_bpfi", "fixed", "bpfi_3_6", "bpfi_10_13"}
    assert all(x == paper.REPRODUCED for x in v.values()), v


def test_contradicted_findings_are_not_reproduced():
    t = study_like()
    h = t.harmonics.copy()
    fixed = h["band"] == "fixed"
    h.loc[fixed, "amplitude"] = h.loc[fixed, "load_kN"] * (1 + h.loc[fixed, "depth_um"])  # no dip
    ratio = (h["band"] == "bpfi_10_13") & (h["order"] == 2)
    h.loc[ratio, "amplitude"] *= 0.1                                                          # 2 x lower
    dc = h["quantity"] == "raw_dc"
    h.loc[dc, "amplitude"] = 1e9 * np.exp(h.loc[dc, "depth_um"] / 20)                      # not bilinear
    c = t.cases.copy()
    c["edge_ratio"] = 0.8                                                                    # Hertzian everywhere
    b = t.bands.copy()
    b["clamped"] = b["depth_um"] > 0                                                         # every case clamped
    v = verdicts(paper.Tables(c, h, b))
    assert v["fixed"] != paper.REPRODUCED
    assert v["bpfi_10_13"] != paper.REPRODUCED
    assert v["dc"] == paper.NOT
    assert v["pattern"] == paper.PARTLY  # 250 kN still right
    assert v["kurtogram_nyquist"] == paper.PARTLY


def test_flat_band_is_the_common_part_of_the_kurtogram_bands():
    b = pd.DataFrame({"band": "kurtogram", "depth_um": [0, 15, 30, 50, 80],
                      "low_hz": [0, 8000, 9000, 8500, 20000], "high_hz": [1, 17000, 16000, 18000, 30000]})
    assert paper.flat_band(b) == (9000.0, 16000.0)
    disjoint = pd.DataFrame({"band": "kurtogram", "depth_um": [15, 20, 30],
                             "low_hz": [1000, 8000, 8000], "high_hz": [2000, 16000, 16000]})
    assert paper.flat_band(disjoint) == (8000.0, 16000.0)  # the most frequent band


def test_page_renders_every_finding_and_is_atomic(tmp_path):
    rows = [(f, None) for f in paper.findings(study_like())]
    text = paper.render_markdown(rows, flat=(16250.0, 31850.0))
    assert text.count("**reproduced**") == len(rows)
    html = paper.render_html(text)
    assert html.count("<tr>") == len(rows) + 1
    path = paper.write_page(text, tmp_path / "sub" / "paper.md")
    assert path.read_text() == text and not list(path.parent.glob(".*"))


@pytest.mark.parametrize("with_paper", [False, True])
def test_compare_reads_tables_and_pairs_the_paper_run(tmp_path, with_paper):
    t = study_like()
    for name, df in (("cases", t.cases), ("harmonics", t.harmonics), ("bands", t.bands)):
        df.to_csv(tmp_path / f"{name}.csv", index=False)
    files = {n: tmp_path / f"{n}.csv" for n in ("cases", "harmonics", "bands")}
    rows = paper.compare(files["cases"], files["harmonics"], files["bands"],
                         paper=files if with_paper else None)
    assert len(rows) == 11
    assert all((p is not None) == with_paper for _, p in rows)
    if with_paper:
        assert "paper conventions" in paper.render_markdown(rows)
