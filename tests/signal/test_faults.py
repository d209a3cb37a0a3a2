"""Fault families, the speed-error-proof line search and the verdict, on signals whose answer
is known by construction."""

import json

import numpy as np
import pytest

from bearing_envelope.diagnosis import AnalysisOptions, analyze_signal
from bearing_envelope.signal import envelope_spectrum
from bearing_envelope.diagnosis.faults import (FaultFamily, fault_families, search_lines)

FS, N, FC = 12000.0, 2**17, 3500.0
FR_NOM = 30.0  # nominal shaft rate; the actual one is 0.5 % lower
SPEED = 0.995


def _am(lines, *, noise=0.02, seed=0):
    """Carrier at FC whose envelope is 1 + sum(m cos 2 pi f t) for (f, m) in ``lines``, plus
    white noise (answer: the envelope spectrum reads m at f)."""
    t = np.arange(N) / FS
    env = 1.0 + sum(m * np.cos(2 * np.pi * f * t) for f, m in lines)
    rng = np.random.default_rng(seed)
    return env * np.cos(2 * np.pi * FC * t) + noise * rng.standard_normal(N)


def test_families_and_sideband_spacing():
    fams = {f.name: f for f in fault_families(
        {"bpfo": 107.0, "bpfi": 162.0, "bsf": 70.0, "ftf": 12.0, "gear": 87.0}, fr=30.0)}
    assert list(fams) == ["bpfo", "bpfi", "bsf", "bsf2", "ftf", "gear"]
    assert fams["bsf2"].frequency_hz == 140.0
    assert (fams["bpfi"].sideband_name, fams["bpfi"].sideband_hz) == ("fr", 30.0)
    assert (fams["bsf"].sideband_name, fams["bsf"].sideband_hz) == ("ftf", 12.0)
    assert fams["bsf2"].sideband_hz == 12.0
    assert fams["bpfo"].sideband_name is None and fams["ftf"].sideband_name is None
    assert fams["gear"].sideband_name is None and fams["gear"].label == "gear line"
    # BSF without FTF: no spacing known, no sidebands; an override gives one
    assert fault_families({"bsf": 70.0}, fr=30.0)[0].sideband_name is None
    assert fault_families({"gear": 87.0}, fr=30.0, sidebands={"gear": "fr"})[0].sideband_hz == 30.0


def test_search_follows_the_actual_speed():
    """BPFI and its fr sidebands all sit 0.5 % low (the shaft turns slower than nominal): the
    +-1 % search finds the fundamental, harmonic 2 at 2 f_found, and the sidebands at
    f_found +- 0.995 fr; the former +-0.2 % search reads noise."""
    bpfi_nom = 162.0
    bpfi, fr = SPEED * bpfi_nom, SPEED * FR_NOM
    x = _am([(bpfi, 0.3), (2 * bpfi, 0.15), (bpfi - fr, 0.08), (bpfi + fr, 0.06),
             (2 * bpfi - fr, 0.05)])
    f, a = envelope_spectrum(x, FS, (2000.0, 5000.0))
    df = f[1] - f[0]
    fam = fault_families({"bpfi": bpfi_nom}, fr=FR_NOM)[0]
    recs = {(r["order"], r["sideband"]): r for r in
            search_lines(f, a, fam, fr=FR_NOM, n_harmonics=2, n_sidebands=1)}
    for (k, m), (true_hz, amp) in {(1, 0): (bpfi, 0.3), (2, 0): (2 * bpfi, 0.15),
                                   (1, -1): (bpfi - fr, 0.08), (1, 1): (bpfi + fr, 0.06),
                                   (2, -1): (2 * bpfi - fr, 0.05)}.items():
        r = recs[(k, m)]
        assert abs(r["frequency_hz"] - true_hz) <= df, (k, m)
        assert r["amplitude"] == pytest.approx(amp, rel=0.16), (k, m)  # <= 1.4 dB scalloping
        assert r["detected"] and r["floor_ratio_db"] > 30.0
    assert recs[(1, 0)]["target_hz"] == bpfi_nom
    assert not recs[(2, 1)]["detected"]  # no line there
    narrow = search_lines(f, a, fam, fr=FR_NOM, n_harmonics=1, n_sidebands=0,
                          tolerance_hz=0.002 * bpfi_nom)[0]
    assert narrow["amplitude"] < 0.01 and not narrow["detected"]


def test_verdict_inner_race_and_json(tmp_path, capsys):
    """An inner-race signature (BPFI, 3 harmonics, fr sidebands, 0.5 % slow) -> the diagnosis
    is an inner race fault, and nothing else is detected; the CLI's --json carries it."""
    from bearing_envelope.cli import main

    bpfi_nom, bpfo_nom = 5.4152 * FR_NOM, 3.5848 * FR_NOM
    bpfi, fr = SPEED * bpfi_nom, SPEED * FR_NOM
    lines = [(k * bpfi, 0.3 / k) for k in (1, 2, 3)]
    lines += [(k * bpfi + s * fr, 0.06 / k) for k in (1, 2, 3) for s in (-1, 1)]
    x = _am(lines)
    faults = {"bpfo": bpfo_nom, "bpfi": bpfi_nom, "bsf": 2.357 * FR_NOM, "ftf": 0.3983 * FR_NOM}
    bands = [{"name": "fixed", "strategy": "fixed", "low_hz": 2000.0, "high_hz": 5000.0}]
    _, det = analyze_signal(
        x,
        FS,
        fr=FR_NOM,
        fault_frequencies=faults,
        full_output=True,
        options=AnalysisOptions(bands=bands, n_harmonics=3),
    )
    v = det["verdict"]
    assert v.diagnosis.family == "bpfi" and [d.family for d in v.detected] == ["bpfi"]
    assert v.diagnosis.harmonics == (1, 2, 3) and v.diagnosis.sideband_name == "fr"
    assert v.n_tests == 5 and v.pfa_test == pytest.approx(0.002)
    assert abs(v.diagnosis.frequency_hz - bpfi) <= FS / N
    assert v.summary_lines()[0].startswith(
        f"inner race fault: BPFI {v.diagnosis.frequency_hz:.1f} Hz, harmonics 1-3, fr sidebands, ")
    assert "in band fixed (2000-5000 Hz) [confidence low: " in v.summary_lines()[0]
    assert v.confidence == "low"  # one band can hold it: never more than low

    np.save(tmp_path / "ir.npy", x)
    args = ["analyze", str(tmp_path / "ir.npy"), "--fs", str(FS), "--fr", str(FR_NOM),
            "--bands", json.dumps(bands), *sum((["--fault", f"{k}={v}"] for k, v in
                                                 faults.items()), [])]
    assert main([*args, "--json"]) == 0
    captured = capsys.readouterr()
    doc = json.loads(captured.out)
    assert doc["verdict"]["diagnosis"] == "bpfi"
    assert doc["verdict"]["diagnosis_label"] == "inner race fault"
    assert doc["verdict"]["confidence"] == "low" and doc["verdict"]["evidence"] == v.evidence
    # the command runs every route (RECORD_OPTIONS): the library's lines, then the routes'
    n = len(v.summary_lines())
    assert doc["verdict"]["summary"][:n] == v.summary_lines()
    assert doc["verdict"]["summary"][n] == "decided by: envelope"
    assert {f["name"] for f in doc["families"]} == {"bpfo", "bpfi", "bsf", "bsf2", "ftf"}
    fund = [r for r in doc["lines"] if r["base"] == "bpfi" and r["order"] == 1
            and r["sideband"] == 0 and r["quantity"] == "envelope_bpfi"][0]
    assert fund["detected"] is True and abs(fund["frequency_hz"] - bpfi) < 0.1
    assert "verdict: inner race fault" in captured.err  # the human summary goes to stderr
    assert main([*args, "--json", str(tmp_path / "r.json")]) == 0
    assert "verdict: inner race fault" in capsys.readouterr().out
    assert json.loads((tmp_path / "r.json").read_text())["verdict"]["diagnosis"] == "bpfi"


def test_verdict_false_alarm_design():
    """On band-passed Gaussian noise no family may be detected more often than the record-wise
    pfa: 40 records at pfa = 0.25 (five families, two bands: each line at 0.025) give at most
    18 records with a detection (the 99.9 % quantile of Binomial(40, 0.25)); the per-line
    rate at the per-test pfa is checked against its design in tests/test_diagnosis.py."""
    faults = {"bpfo": 107.4, "bpfi": 162.2, "bsf": 70.6, "ftf": 11.9}
    bands = [{"name": "a", "strategy": "fixed", "low_hz": 1000.0, "high_hz": 2000.0},
             {"name": "b", "strategy": "fixed", "low_hz": 3000.0, "high_hz": 4500.0}]
    rng = np.random.default_rng(7)
    hits, lines, line_hits = 0, 0, 0
    for _ in range(40):
        x = rng.standard_normal(2**15)
        table, det = analyze_signal(
            x,
            FS,
            fr=FR_NOM,
            fault_frequencies=faults,
            full_output=True,
            options=AnalysisOptions(bands=bands, n_harmonics=2, n_sidebands=0, pfa=0.25),
        )
        hits += bool(det["verdict"].detected)
        fund = table[(table.quantity == "envelope_spectrum") & (table.order == 1)]
        lines += len(fund)
        line_hits += int(fund.detected.sum())
    assert hits <= 18
    # each fundamental is tested at 0.25 / 10: 400 tests, expected <= 10 detections
    assert line_hits <= 22, line_hits
    assert lines == 40 * 10


def test_custom_family_and_user_spacing():
    """A user line ("gear", 87 Hz) gets no sidebands by default, fr sidebands on request."""
    x = _am([(87.0, 0.2), (87.0 - 31.0, 0.05), (87.0 + 31.0, 0.05), (174.0, 0.1)])
    bands = [{"name": "b", "strategy": "fixed", "low_hz": 2000.0, "high_hz": 5000.0}]
    t0 = analyze_signal(
        x, FS, fr=31.0, fault_frequencies={"gear": 87.0}, options=AnalysisOptions(bands=bands)
    )
    env0 = t0[t0.quantity == "envelope_spectrum"]
    assert set(env0.sideband) == {0}
    t1, det = analyze_signal(
        x,
        FS,
        fr=31.0,
        fault_frequencies={"gear": 87.0},
        full_output=True,
        options=AnalysisOptions(bands=bands, sideband_spacing={"gear": "fr"}, n_sidebands=1),
    )
    env1 = t1[(t1.quantity == "envelope_spectrum") & (t1.order == 1)]
    assert set(env1.sideband) == {-1, 0, 1} and env1.detected.all()
    assert det["verdict"].diagnosis.summary().startswith("gear line: gear 87.0 Hz, harmonics")


def test_library_rejects_frequencies_above_nyquist():
    x = np.random.default_rng(0).standard_normal(4096)
    with pytest.raises(ValueError, match="'bsf' = 600 Hz is at or above the Nyquist"):
        analyze_signal(x, 1000.0, fr=10.0, fault_frequencies={"bsf": 600.0})
    # below the resolution the library still reads the bins (the CLI refuses, naming the
    # option): no floor can be measured around 0.5 Hz with 0.24 Hz bins
    t = analyze_signal(
        x,
        1000.0,
        fr=10.0,
        fault_frequencies={"ftf": 0.5},
        options=AnalysisOptions(
            bands=[{"name": "b", "strategy": "fixed", "low_hz": 100.0, "high_hz": 400.0}]
        ),
    )
    low = t[(t.base == "ftf") & (t.quantity == "envelope_spectrum")]
    assert low.floor.isna().all() and low.detected.isna().all()


def test_family_dataclass_is_frozen():
    fam = FaultFamily("bpfi", 162.0, "fr", 30.0, "inner race fault")
    with pytest.raises(AttributeError):
        fam.frequency_hz = 1.0


def test_verdict_explains_coincident_lines():
    """A user family at 72 Hz = BPFI - 3 fr (with its 2nd harmonic present) is detected but
    explained by the stronger BPFI family; one at 90 Hz = 3 fr by the shaft."""
    fr, bpfi = 30.0, 162.0
    x = _am([(bpfi, 0.3), (2 * bpfi, 0.15), (bpfi - fr, 0.08), (bpfi + fr, 0.08),
             (bpfi - 3 * fr, 0.05), (2 * (bpfi - 3 * fr), 0.03), (90.0, 0.04), (180.0, 0.03)])
    bands = [{"name": "b", "strategy": "fixed", "low_hz": 2000.0, "high_hz": 5000.0}]
    _, det = analyze_signal(
        x,
        FS,
        fr=fr,
        fault_frequencies={"bpfi": bpfi, "g72": 72.0, "s90": 90.0},
        full_output=True,
        options=AnalysisOptions(bands=bands, n_sidebands=3),
    )
    v = {f.family: f for f in det["verdict"].families}
    assert all(v[k].detected for k in ("bpfi", "g72", "s90"))
    assert v["bpfi"].explained_by is None
    assert v["g72"].explained_by == "BPFI - 3 fr" and v["s90"].explained_by == "3 fr"
    assert [d.family for d in det["verdict"].detected] == ["bpfi"]
    assert det["verdict"].summary_lines()[1].startswith("explained: g72 line: g72 72.0 Hz")
