"""The virtual rig on record sets other than the converted CWRU files: a manifest of synthetic
records of another bearing (described by its geometry), and a folder of the CWRU data center's
``.mat`` files as downloaded (written here with ``scipy.io.savemat``). Each record is a train of
impulses at its fault's rate ringing a 3.3 kHz mode (written out analytically), so its verdict
and its line are known by construction; the rig runs end to end on both (draft fidelity, 1 s
records) and writes a simulated twin of every fault record."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest
from scipy import io as sio

from bearing_envelope.study import rig
from bearing_envelope.study.rig import cwru

FS = 12_000.0


def _ringing(rate_hz, n, *, fs=FS, f_n=3300.0, zeta=0.03, amp=5.0, noise=0.3, seed=0):
    """Impulses at ``rate_hz`` (from 10 ms on) each ringing a damped cosine, in white noise."""
    rng = np.random.default_rng(seed)
    pulses = np.zeros(n)
    pulses[np.round((np.arange(0.01, n / fs, 1 / rate_hz)) * fs).astype(int)] = 1.0
    t = np.arange(int(0.02 * fs)) / fs
    wn = 2 * math.pi * f_n
    h = amp * np.exp(-zeta * wn * t) * np.cos(wn * math.sqrt(1 - zeta ** 2) * t)
    return np.convolve(pulses, h)[:n] + noise * rng.standard_normal(n)


def _bpfo(fr, z, d, pitch):
    return z / 2 * fr * (1 - d / pitch)


def _bpfi(fr, z, d, pitch):
    return z / 2 * fr * (1 + d / pitch)


def _run(conds, settings, out):
    contact = rig.simulate_excitations(conds, settings, out / "contact", log=lambda s: None)
    return rig.run_scorecard(conds, contact, out, "ref", settings=settings, log=lambda s: None)


def _check_run(card, out, truth):
    """Every record scored on both sides; the measured verdicts and lines are the records'."""
    assert sorted(card.record) == sorted(truth)
    for name, (family, rate_orders) in truth.items():
        r = card[card.record == name].iloc[0]
        assert r.family == family and r.meas_diagnosis == family
        assert r.meas_line_orders == pytest.approx(rate_orders, rel=0.005)
        with np.load(out / "sim" / f"{name}_sim.npz") as z:
            x, meta = z["x"], json.loads(str(z["meta_json"]))
        assert np.all(np.isfinite(x)) and np.std(x) > 0 and meta["source_record"] == name
    for f in ("scorecard.csv", "scorecard.md", "paths.json", "summary.json", "event_shape.csv",
              "size.md"):
        assert (out / f).is_file()


def test_rig_runs_on_a_manifest_of_another_bearing(tmp_path):
    """A bearing of 8 balls of 6.75 mm on 28.55 mm (the catalogue's SKF 6203) given by its
    geometry; loads stated in N; two outer-race records at 0 deg (the gain's reference) and an
    inner-race one; a healthy record left out."""
    z, d, pitch, fr = 8, 6.75, 28.55, 25.0
    n = int(2 * FS)
    recs = {"ref_or_500N": ("outer_race", _bpfo(fr, z, d, pitch), 500),
            "ref_or_1000N": ("outer_race", _bpfo(fr, z, d, pitch), 1000),
            "ir_500N": ("inner_race", _bpfi(fr, z, d, pitch), 500)}
    lines = ["file,location,length_um,depth_um,position_deg,load,shaft_hz,n_rollers,"
             "roller_diameter_mm,pitch_diameter_mm"]
    for i, (name, (loc, rate, load)) in enumerate(recs.items()):
        np.savez(tmp_path / f"{name}.npz", x=_ringing(rate, n, seed=i), fs=np.float64(FS))
        pos = "0" if loc == "outer_race" else ""
        lines.append(f"{name}.npz,{loc},150,100,{pos},{load},{fr},{z},{d},{pitch}")
    np.savez(tmp_path / "healthy.npz", x=np.random.default_rng(9).standard_normal(n),
             fs=np.float64(FS))
    lines.append(f"healthy.npz,none,,,,500,{fr},{z},{d},{pitch}")
    (tmp_path / "records.csv").write_text("\n".join(lines) + "\n")
    conds = rig.record_conditions([str(tmp_path / "records.csv")])
    assert [c.name for c in conds] == ["ir_500N", "ref_or_1000N", "ref_or_500N"]
    settings = rig.RigSettings(scene={"bearing": {"designation": "SKF 6203"}}, load_kN=1.0,
                               fidelity="draft")
    card = _run(conds, settings, tmp_path / "run")
    fam = {"outer_race": "bpfo", "inner_race": "bpfi"}
    _check_run(card, tmp_path / "run", {k: (fam[v[0]], v[1] / fr) for k, v in recs.items()})
    trend = pd.read_csv(tmp_path / "run" / "outer_race_trend.csv")
    assert list(trend.n) == [2]  # the two loads of the outer race: one trend, per N


def _mat(path, number, x, rpm=None, extra=None):
    data = {f"X{number:03d}_DE_time": x.reshape(-1, 1), f"X{number:03d}_FE_time": 0.1 * x[:, None]}
    if rpm is not None:
        data[f"X{number:03d}RPM"] = np.array([[rpm]])
    data.update(extra or {})
    sio.savemat(path, data)
    return str(path)


def test_mat_files_are_read_through_the_catalogue(tmp_path):
    """Record numbers from the variables, the shaft rate from X###RPM (nominal without it), a
    file holding two records read as the one of its name, the normal record left out."""
    x = np.zeros(1200)
    _mat(tmp_path / "105.mat", 105, x, rpm=1796)
    _mat(tmp_path / "146.mat", 146, x)                         # no RPM: 2 hp, 1750 rpm nominal
    _mat(tmp_path / "99.mat", 99, x, rpm=1750, extra={"X098_DE_time": x[:, None]})
    _mat(tmp_path / "renamed.mat", 3001, x, rpm=1797)
    rows = rig.manifest_rows([str(tmp_path)], log=lambda s: None)
    by = {r["name"] or r["file"].split("/")[-1]: r for r in rows}
    assert sorted(by) == ["105.mat", "146.mat", "renamed.mat"]     # 99: normal, left out
    conds = {c.name: c for c in rig.record_conditions([str(tmp_path)], log=lambda s: None)}
    ir, or3, ir28 = conds["105"], conds["146"], conds["renamed"]
    assert ir.location == "inner_race" and ir.shaft_hz == pytest.approx(1796 / 60)
    assert ir.length_um == pytest.approx(0.007 * 25400) and ir.depth_um == pytest.approx(279.4)
    assert ir.fs_hz == 12000.0 and ir.load == 0.0 and ir.n_samples == 1200
    assert or3.position_deg == 90.0 and or3.load == 2.0 and or3.shaft_hz == pytest.approx(1750 / 60)
    assert ir28.length_um == pytest.approx(711.2) and ir28.depth_um == pytest.approx(1270.0)
    _mat(tmp_path / "two.mat", 130, x, extra={"X131_DE_time": x[:, None]})
    with pytest.raises(ValueError, match=r"two.mat: 2 drive-end variables X###_DE_time"):
        rig.record_conditions([str(tmp_path / "two.mat")])
    _mat(tmp_path / "5.mat", 5, x)
    with pytest.raises(ValueError, match=r"record 5 is not a drive-end record of the CWRU"):
        rig.record_conditions([str(tmp_path / "5.mat")])


def test_catalogue_agrees_with_the_development_manifest():
    """Every record number of the package's CWRU development manifest is the catalogue's row:
    location, size, position, load and fs (two tables written from different sources)."""
    rows, unknown = cwru.development_rows(["cwru_105_IR007_0hp_DE12.npz", "x.npz"])
    assert len(rows) == 1 and unknown == ["x.npz"]
    from importlib import resources

    text = resources.files("bearing_envelope").joinpath("data", cwru.DEVELOPMENT_MANIFEST)
    with text.open(encoding="utf-8") as fh:
        dev = pd.read_csv(fh)
    assert len(dev) == 39
    for _, r in dev[dev.record.notna()].iterrows():
        t = cwru.DRIVE_END[int(r.record)]
        assert (t["location"], t["fs_hz"], t["load"]) == (r.location, r.fs_hz, r.load)
        assert t["length_um"] == r.length_um and t["depth_um"] == r.depth_um
        assert (t["position_deg"] is None) == pd.isna(r.position_deg)
        assert t["position_deg"] is None or t["position_deg"] == r.position_deg
        assert r.shaft_hz == pytest.approx(t["rpm"] / 60, rel=1e-6)


def test_rig_runs_on_a_folder_of_data_center_mat_files(tmp_path):
    """105.mat (inner race, 0.007 in) and 130.mat (outer race at 6:00, the gain's reference by
    ``--gain-reference 130``) as downloaded, 2 s each, beside the normal 097.mat."""
    z, d, pitch = 9, 7.94, 39.04
    fr = 1797 / 60
    n = int(2 * FS)
    _mat(tmp_path / "105.mat", 105, _ringing(_bpfi(fr, z, d, pitch), n, seed=1), rpm=1797)
    _mat(tmp_path / "130.mat", 130, _ringing(_bpfo(fr, z, d, pitch), n, seed=2), rpm=1797)
    _mat(tmp_path / "097.mat", 97, np.random.default_rng(3).standard_normal(n), rpm=1797)
    conds = rig.record_conditions([str(tmp_path)], log=lambda s: None)
    assert [c.name for c in conds] == ["105", "130"]
    settings = rig.RigSettings(scene={"bearing": {"designation": "SKF 6205-2RS"}},
                               load_kN=1.0, fidelity="draft")
    out = tmp_path / "run"
    contact = rig.simulate_excitations(conds, settings, out / "contact", log=lambda s: None)
    card = rig.run_scorecard(conds, contact, out, "130", settings=settings, log=lambda s: None)
    _check_run(card, out, {"105": ("bpfi", _bpfi(1, z, d, pitch)),
                           "130": ("bpfo", _bpfo(1, z, d, pitch))})


def test_cli_simulates_a_folder_of_mat_files(tmp_path):
    """``bearing-envelope rig FOLDER --config C --simulate-only``: the command line of the rig,
    unchanged, on the data center's files; one contact history per fault record."""
    from bearing_envelope.cli import main

    data = tmp_path / "downloads"
    data.mkdir()
    _mat(data / "130.mat", 130, np.zeros(3000), rpm=1797)
    _mat(data / "097.mat", 97, np.zeros(3000), rpm=1797)
    cfg = tmp_path / "rig.yaml"
    cfg.write_text("rig: {load_kN: 1.0, fidelity: draft}\n"
                   "scene: {bearing: {designation: SKF 6205-2RS}}\n")
    out = tmp_path / "run"
    assert main(["rig", str(data), "--config", str(cfg), "-o", str(out), "--simulate-only"]) == 0
    assert sorted(p.name for p in (out / "contact").iterdir()) == ["130_contact.npz"]
    with np.load(out / "contact" / "130_contact.npz") as z:
        assert float(z["fs"]) == FS and z["removed_force"].size >= 3000
