"""The analysis of recordings as a library call (docs/analysis.md): ``analyze_record`` on an
array, a record read and a path; ``analyze_records`` in parallel; the command line as a thin
layer over it; one default of the analysis options; the documentation's example runs
(``analyze_record``'s docstring example runs in tests/test_doctests.py).

Truths: synthetic records with a known fault (impacts at the 6205's BPFI from the data
center's published factor 5.4152 x fr, or noise), the data center's label of a real record.
"""

import doctest
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from bearing_envelope.cli import main
from bearing_envelope.diagnosis import (RECORD_OPTIONS, AnalysisOptions, RecordAnalysis,
                                        RecordFailure, analyze_record,
                                        verdict_table)
from bearing_envelope.io import analysis as io_analysis
from conftest import fault_signal

ROOT = Path(__file__).resolve().parents[2]
REAL = ROOT / "tests" / "data" / "real" / "cwru_105_IR007_0hp_DE12.npz"
FS, FR = 20000.0, 15.8
BPFI_6205 = 5.4152 * FR  # CWRU data center's published inner-race factor of the 6205
OPTS = replace(RECORD_OPTIONS, nlevel=5)


@pytest.fixture(scope="module")
def fault():
    return fault_signal(fs=FS, n=2**15, fr=FR, bpfi=BPFI_6205, fn=6000.0, seed=3)


@pytest.fixture(scope="module")
def noise(fault):
    return np.random.default_rng(1).standard_normal(fault.size)


@pytest.fixture(scope="module")
def analysed(fault):
    return analyze_record(fault, FS, shaft_hz=FR, bearing="6205", options=OPTS)


def test_a_known_inner_race_fault_is_found(analysed):
    res = analysed
    assert isinstance(res, RecordAnalysis) and res.ok
    assert res.verdict.diagnosis.family == "bpfi"
    assert res.bearing == "SKF 6205-2RS" and res.source == "array" and res.fs == FS
    table = res.to_frame().set_index("family")
    assert set(table.index) == {"bpfo", "bpfi", "bsf", "bsf2", "ftf"}
    assert bool(table.loc["bpfi", "diagnosis"]) and bool(table.loc["bpfi", "detected"])
    assert abs(table.loc["bpfi", "h1_hz"] - BPFI_6205) < 0.005 * BPFI_6205
    lines = res.lines
    env = lines[(lines.quantity == "envelope_spectrum") & (lines.base == "bpfi")]
    assert set(env.order) == {1, 2, 3} and set(env.sideband) == {-2, -1, 0, 1, 2}


def test_noise_gets_no_diagnosis(noise):
    res = analyze_record(noise, FS, shaft_hz=FR, bearing="6205", options=OPTS)
    assert res.verdict.diagnosis is None
    assert not res.to_frame().diagnosis.any()


def test_array_record_and_path_give_the_same_result(fault, analysed, tmp_path):
    np.savez(tmp_path / "r.npz", x=fault, fs=FS)
    from_path = io_analysis.analyze_file(tmp_path / "r.npz", shaft_hz=FR, bearing="6205",
                                           options=OPTS)
    read = io_analysis.read_task(str(tmp_path / "r.npz"))
    from_read = analyze_record(read, shaft_hz=FR, bearing="6205", options=OPTS)
    for res in (from_path, from_read):
        pd.testing.assert_frame_equal(res.lines, analysed.lines)
        assert res.verdict.to_dict() == analysed.verdict.to_dict()
    assert from_path.source == "npz:x" and from_path.file == str(tmp_path / "r.npz")


def test_messages_name_the_parameters_or_the_callers_names(fault):
    with pytest.raises(ValueError, match=r"^n_harmonics: got 200; allowed: 1 \.\. 115 "):
        analyze_record(fault, FS, shaft_hz=FR, bearing="6205",
                       options=AnalysisOptions(n_harmonics=200))
    with pytest.raises(ValueError, match=r"^--harmonics: got 200"):
        analyze_record(fault, FS, shaft_hz=FR, bearing="6205",
                       options=AnalysisOptions(n_harmonics=200),
                       names={"n_harmonics": "--harmonics"})
    with pytest.raises(ValueError, match=r"^faults \(bsf = 12000 Hz\): .* Nyquist"):
        analyze_record(fault, FS, shaft_hz=FR, faults={"bsf": 12000.0})
    with pytest.raises(ValueError, match=r"^fs: the signal does not give the sampling"):
        analyze_record(fault, shaft_hz=FR, bpfi=BPFI_6205)
    with pytest.raises(ValueError, match=r"^bearing: got '6299'; allowed: "):
        analyze_record(fault, FS, shaft_hz=FR, bearing="6299")
    with pytest.raises(ValueError, match=r"^signal holds a constant signal"):
        analyze_record(np.ones(4096), FS, shaft_hz=FR, bpfi=BPFI_6205)


def test_a_default_depth_follows_the_record_a_requested_one_is_refused(fault):
    short = fault[:20000]  # 20000 samples: 7 levels at most
    res = analyze_record(short, FS, shaft_hz=FR, bpfi=BPFI_6205)
    assert res.nlevel == 7 and RECORD_OPTIONS.nlevel == 8
    with pytest.raises(ValueError, match=r"^nlevel: got 9; allowed: 1 \.\. 7"):
        analyze_record(short, FS, shaft_hz=FR, bpfi=BPFI_6205,
                       options=AnalysisOptions(nlevel=9))


def test_batch_in_parallel_equals_serial_and_a_bad_record_is_a_row(fault, noise, tmp_path):
    np.savez(tmp_path / "a.npz", x=fault, fs=FS)
    np.savez(tmp_path / "b.npz", x=noise, fs=FS)
    (tmp_path / "c.npy").write_bytes(b"not an npy file")
    items = [tmp_path / "a.npz", tmp_path / "b.npz", tmp_path / "c.npy", fault]
    runs = [io_analysis.analyze_files(items, FS, shaft_hz=FR, bearing="6205", options=OPTS,
                                        jobs=jobs) for jobs in (1, 2)]
    for results in runs:
        assert [r.ok for r in results] == [True, True, False, True]
        assert isinstance(results[2], RecordFailure)
        assert "no valid .npy header" in results[2].error
        assert results[0].signal is None  # compact: no samples, no spectra kept
    t1, t2 = (verdict_table(r) for r in runs)
    pd.testing.assert_frame_equal(t1, t2)
    assert len(t1) == 3 * 5 + 1 and list(t1[t1.status == "error"].record) == ["c"]
    assert set(t1[t1.diagnosis.fillna(False).astype(bool)].record) == {"a", "record_3"}


def test_the_command_line_prints_the_library_result(fault, tmp_path):
    """``bearing-envelope analyze --table`` writes the library's verdict table, no more."""
    np.savez(tmp_path / "a.npz", x=fault, fs=FS)
    assert main(["analyze", str(tmp_path / "a.npz"), "--fr", str(FR), "--bearing", "6205",
                 "--nlevel", "5", "--table", str(tmp_path / "t.csv")]) == 0
    cli = pd.read_csv(tmp_path / "t.csv")
    lib = io_analysis.analyze_file(str(tmp_path / "a.npz"), shaft_hz=FR, bearing="6205",
                                     options=OPTS).to_frame()
    lib.to_csv(tmp_path / "lib.csv", index=False)
    pd.testing.assert_frame_equal(cli, pd.read_csv(tmp_path / "lib.csv"))


def test_one_default_of_the_analysis_options():
    """The command line and the trade-off study hold no analysis default of their own: they
    read AnalysisOptions' (the sweep's; the schema's agreement is tests/test_defaults.py's)."""
    from bearing_envelope.cli import build_parser
    from bearing_envelope.study.tradeoff import analysis_used

    d = AnalysisOptions()
    assert (d.n_harmonics, d.n_sidebands, d.n_raw_harmonics) == (3, 2, 3)
    used = analysis_used(None)
    assert (used["harmonics"], used["sidebands"], used["raw_orders_fr"]) == (3, 2, 3)
    args = build_parser().parse_args(["analyze", "x.npy"])
    for opt in ("harmonics", "sidebands", "raw_harmonics", "nlevel", "search_percent", "pfa",
                "filter_order", "window", "level0", "speed"):
        assert getattr(args, opt) is None, opt  # the library's default
    assert RECORD_OPTIONS.measure_speed and not AnalysisOptions().measure_speed
    # a recording's options differ from the sweep's only in measuring the speed and running
    # every route of the verdict
    assert RECORD_OPTIONS.routes and not d.routes
    assert replace(RECORD_OPTIONS, measure_speed=False, routes=d.routes) == d


@pytest.mark.skipif(not REAL.exists(), reason="tests/data/real not present")
def test_docs_example_runs(monkeypatch):
    """docs/analysis.md, "Analyse a recording from Python", on the real record 105 (inner race
    fault, 0.007 in, data center label)."""
    monkeypatch.chdir(ROOT)
    result = doctest.testfile(str(ROOT / "docs" / "analysis.md"), module_relative=False,
                              optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted >= 5 and result.failed == 0
