import os
from pathlib import Path

import h5py
import numpy as np
import pytest

from bearing_envelope.physics.history import simulate
from bearing_envelope.io import FORMAT_VERSION, Case, CaseFormatError, git_commit, read_case, write_case
from bearing_envelope.physics.scene import Scene


@pytest.fixture(scope="module")
def hist():
    s = Scene.from_mapping({"operation": {"revolutions": 1.0, "noise_snr_db": 20.0}},
                           load_kN=500, depth_um=30)
    return simulate(s, "draft")


def test_round_trip(tmp_path, hist):
    path = write_case(tmp_path / "cases" / "F500kN_h30um.h5", hist)
    assert os.listdir(tmp_path / "cases") == ["F500kN_h30um.h5"]  # no temp file left
    c = read_case(path)
    assert isinstance(c, Case)
    assert c.fs == 65000.0 and c.fr == 15.8 and c.bpfi == 231.9
    assert c.bpfi_geometry == pytest.approx(194.2, abs=0.05)
    # Z fr = BPFO + BPFI, for the geometric rates and for the rates the events run at (the
    # study's BPFI override acts through the cage rate: bpfo is the event rate)
    assert c.attrs["bpfo_geometry"] + c.bpfi_geometry == pytest.approx(22 * 15.8)
    assert c.bpfo + c.bpfi == pytest.approx(22 * 15.8)
    assert c.load_kN == 500 and c.depth_um == 30
    np.testing.assert_array_equal(c.time, hist.time)
    np.testing.assert_array_equal(c.p_max, hist.p_max)
    np.testing.assert_array_equal(c.p_max_defect, hist.p_max_defect)
    np.testing.assert_array_equal(c.roller_load, hist.roller_load)
    np.testing.assert_array_equal(c.defect_offset, hist.defect_offset)
    assert {"p_max", "p_max_defect", "p_max_clean", "p_max_defect_clean"} <= set(c.signals)
    assert c.scene["bearing"]["rollers_per_row"] == 22
    assert c.attrs["fidelity"]["name"] == "draft"
    assert c.attrs["format_version"] == FORMAT_VERSION
    assert "git_commit" in c.attrs and "package_version" in c.attrs
    assert c.table["p_max"].shape == (len(hist.table.q_nodes), len(hist.table.xi_nodes))
    assert "interp_max_rel_error_p_max" in c.table
    assert "load_0" in c.snapshots and c.snapshots["load_0"]["window_pressure"].ndim == 3
    with h5py.File(path) as f:
        assert f["signals/p_max"].attrs["units"] == "Pa"
        assert f["signals/roller_load"].attrs["units"] == "N"
        assert f["time"].attrs["units"] == "s"
        assert f["signals/p_max"].compression == "gzip" and f["signals/p_max"].chunks


def test_format_errors(tmp_path, hist):
    path = str(write_case(tmp_path / "a.h5", hist))
    with h5py.File(path, "a") as f:
        f.attrs["format_version"] = FORMAT_VERSION + 1
    with pytest.raises(CaseFormatError, match="format_version"):
        read_case(path)
    path = str(write_case(tmp_path / "b.h5", hist))
    with h5py.File(path, "a") as f:
        del f["signals/roller_load"]
    with pytest.raises(CaseFormatError, match="signals/roller_load"):
        read_case(path)
    (tmp_path / "c.h5").write_text("not hdf5")
    with pytest.raises(CaseFormatError):
        read_case(tmp_path / "c.h5")
    with pytest.raises(FileNotFoundError):
        read_case(tmp_path / "missing.h5")


def test_git_commit_without_git(tmp_path):
    assert git_commit(str(tmp_path)) == "unknown"


def test_cli_simulate(tmp_path):
    from bearing_envelope.cli import main

    cfg = tmp_path / "config.yaml"
    cfg.write_text("fidelity: draft\nscene:\n  operation: {revolutions: 0.5}\n")
    out = tmp_path / "F250kN_h0um.h5"
    rc = main(["simulate", "--config", str(cfg), "--load-kn", "250", "--depth-um", "0", "-q",
               "-o", str(out)])
    assert rc == 0
    c = read_case(out)
    assert c.depth_um == 0 and c.p_max.size == round(0.5 / 15.8 * 65000)


# ------------------------------------------------------------------ sweep artefacts (h15)
# Round trips of every artefact the workflow writes besides the case file: what is read back
# equals what was written, no temporary file is left, and another format version is refused.
import json  # noqa: E402

import pandas as pd  # noqa: E402

from bearing_envelope import io as beio  # noqa: E402


def _no_temp(directory):
    return not [p for p in os.listdir(directory) if p.startswith(".tmp-")]


def _bands():
    return beio.CaseBands(
        case="F500kN_h30um", load_kN=500.0, depth_um=30.0, fs=65000.0, signal="p_max",
        bands=(beio.BandLimits("kurtogram", "kurtogram", 16250.0, 24375.0, False,
                               {"level": 2.0, "fc": 20312.5}),
               beio.BandLimits("bpfi_10_13", "orders", 2319.0, 3014.7, False, {"low": 10}),
               beio.BandLimits("high", "fixed", 30000.0, 31850.0, True, {"clamped": True})),
        kurtogram={"level": 2.0, "fc": 20312.5, "bandwidth": 8125.0, "kurtosis": 7.25})


def test_bands_round_trip(tmp_path):
    doc = _bands()
    path = beio.write_bands(tmp_path / "bands" / "F500kN_h30um.json", doc)
    assert beio.read_bands(path) == doc and _no_temp(tmp_path / "bands")
    assert beio.read_bands(path).band("high").clamped is True
    with pytest.raises(KeyError, match="bands:"):
        doc.band("nope")
    raw = json.loads(open(path).read())
    assert raw["format"] == "bearing_envelope.bands" and raw["format_version"] == 1
    raw["format_version"] = 2
    (tmp_path / "v2.json").write_text(json.dumps(raw))
    with pytest.raises(beio.ArtefactFormatError, match="format_version 2"):
        beio.read_bands(tmp_path / "v2.json")
    del raw["format"]
    (tmp_path / "nofmt.json").write_text(json.dumps(raw))
    with pytest.raises(beio.ArtefactFormatError, match="not a bands file"):
        beio.read_bands(tmp_path / "nofmt.json")
    with pytest.raises(FileNotFoundError):
        beio.read_bands(tmp_path / "missing.json")


def test_kurtogram_round_trip(tmp_path):
    from bearing_envelope.signal import fast_kurtogram

    rng = np.random.default_rng(0)
    x = rng.standard_normal(4096)
    x[::512] += 20.0  # impulses: a kurtogram with a clear best cell
    kg = fast_kurtogram(x, 10000.0, 4)
    path = beio.write_kurtogram(tmp_path / "k.npz", kg)
    back = beio.read_kurtogram(path)
    np.testing.assert_array_equal(back.matrix, kg.matrix)
    np.testing.assert_array_equal(back.levels, kg.levels)
    np.testing.assert_array_equal(back.freqs, kg.freqs)
    assert (back.level, back.fc, back.bandwidth, back.kurtosis) == (
        kg.level, kg.fc, kg.bandwidth, kg.kurtosis)
    # the stored layout the figures read: matrix, levels, freqs, best
    with np.load(path) as z:
        assert {"matrix", "levels", "freqs", "best"} <= set(z.files)
    assert beio.read_kurtogram(beio.write_kurtogram(tmp_path / "none.npz", None)) is None
    assert _no_temp(tmp_path)
    with pytest.raises(beio.ArtefactFormatError, match="not a kurtogram file"):
        beio.read_kurtogram(beio.write_spectra(tmp_path / "s.npz", beio.CaseSpectra(
            np.zeros(2, np.float32), np.zeros(2, np.float32))))


def test_spectra_round_trip(tmp_path):
    f = np.linspace(0, 1000, 11)
    sp = beio.CaseSpectra(raw_f=np.arange(5, dtype=np.float32), raw_a=np.ones(5, np.float32),
                          envelope={"bpfi_10_13": (f, f ** 2), "fs4_3fs8": (f[:3], -f[:3])})
    back = beio.read_spectra(beio.write_spectra(tmp_path / "sp.npz", sp))
    assert back.raw_a.dtype == np.float32 and list(back.envelope) == ["bpfi_10_13", "fs4_3fs8"]
    np.testing.assert_array_equal(back.raw_f, sp.raw_f)
    for name, (ff, aa) in sp.envelope.items():
        np.testing.assert_array_equal(back.envelope[name][0], ff)
        np.testing.assert_array_equal(back.envelope[name][1], aa)
    with np.load(tmp_path / "sp.npz") as z:  # the keys the figures read
        assert {"raw_f", "raw_a", "env_bpfi_10_13_f", "env_bpfi_10_13_a"} <= set(z.files)


@pytest.mark.parametrize("suffix", [".h5", ".npz"])
def test_sensor_case_round_trip(tmp_path, hist, suffix):
    src = write_case(tmp_path / "F500kN_h30um.h5", hist)
    case = read_case(src)
    acc = np.sin(np.arange(case.p_max.size) * 0.1)
    out = beio.write_sensor_case(tmp_path / "sensor" / f"F500kN_h30um{suffix}", acc, case=case,
                                 source=src, provenance={"snr_db_achieved": 10.0, "seed": 3})
    s = beio.read_sensor(out)
    np.testing.assert_array_equal(s.acceleration, acc)
    assert s.fs == 65000.0 and s.time[1] == pytest.approx(1 / 65000.0)
    assert s.provenance["seed"] == 3 and s.provenance["sensor_format_version"] == 1
    assert "git_commit" in s.provenance and "package_version" in s.provenance
    assert s.frequencies["bpfi"] == 231.9 and s.frequencies["load_kN"] == 500.0
    assert _no_temp(tmp_path / "sensor")
    if suffix == ".h5":  # still a case file: the analysis reads it like any case
        c = read_case(out)
        np.testing.assert_array_equal(c.signals["acceleration"], acc)
        np.testing.assert_array_equal(c.p_max, case.p_max)
        with pytest.raises(beio.ArtefactFormatError, match="not a sensor file"):
            beio.read_sensor(src)  # a plain case has no acceleration
    with pytest.raises(ValueError, match=r"\.npz or \.h5.*out\.txt"):
        beio.write_sensor_case(tmp_path / "out.txt", acc, case=case, source=src)


def _tidy():
    rows = []
    for load in (250.0, 750.0):
        for depth in (0.0, 50.0):
            for k in (1, 2):
                rows.append({"case": f"F{load:g}kN_h{depth:g}um", "load_kN": load,
                             "depth_um": depth, "band": "fixed", "band_strategy": "fixed",
                             "band_low_hz": 8125.0, "band_high_hz": 16250.0,
                             "quantity": "envelope_bpfi", "order": k, "sideband": 0,
                             "frequency_hz": k * 231.9, "amplitude": load * depth / k + 0.1,
                             "signal": "p_max"})
    return pd.DataFrame(rows)


def test_tables_round_trip(tmp_path):
    from bearing_envelope.study.tables import band_table, pivot_tables

    tidy = _tidy()
    p = beio.write_tidy(tmp_path / "t" / "harmonics.csv", tidy)
    pd.testing.assert_frame_equal(beio.read_tidy(p), tidy)
    with pytest.raises(ValueError, match="amplitude"):
        beio.write_tidy(tmp_path / "bad.csv", tidy.drop(columns="amplitude"))
    tidy.drop(columns="band_strategy").to_csv(tmp_path / "old.csv", index=False)
    with pytest.raises(beio.ArtefactFormatError, match="band_strategy"):
        beio.read_tidy(tmp_path / "old.csv")
    bt = band_table([_bands()])
    pd.testing.assert_frame_equal(beio.read_band_table(beio.write_band_table(tmp_path / "b.csv", bt)), bt)
    cases = pd.DataFrame([{"case": "F250kN_h0um", "load_kN": 250.0, "depth_um": 0.0,
                           "p_max_peak_Pa": 2.4e9, "p_max_defect_peak_Pa": 2.4e9,
                           "bpfi_used_hz": 231.9, "fs_hz": 65000.0, "git_commit": "abc"}])
    pd.testing.assert_frame_equal(beio.read_case_table(beio.write_case_table(tmp_path / "c.csv", cases)),
                                  cases)
    piv = pivot_tables(tidy)
    d = beio.write_pivots(tmp_path / "t" / "pivots", piv)
    beio.write_pivots(d, piv)  # overwriting an existing folder works
    back = beio.read_pivots(d)
    assert sorted(back) == sorted(piv)
    for key, table in piv.items():
        pd.testing.assert_frame_equal(back[key], table, check_names=False, check_column_type=False)
        assert list(back[key].columns) == list(table.columns)
    assert _no_temp(tmp_path / "t") and _no_temp(tmp_path)


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    target = tmp_path / "x.csv"
    target.write_text("old\n")
    with pytest.raises(RuntimeError):
        with beio.atomic_path(target, ".csv") as tmp:
            open(tmp, "w").write("half")
            raise RuntimeError("interrupted")
    assert target.read_text() == "old\n" and _no_temp(tmp_path)


# ------------------------------------------------------------------ faults (issue 17 item 6)


def _dead_pid() -> int:
    import subprocess
    import sys

    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def test_stale_temporary_files_of_dead_writers_are_removed_at_the_next_write(tmp_path, hist):
    import subprocess
    import sys

    from bearing_envelope.io import clean_stale_temps, temp_path_for

    d = tmp_path / "cases"
    d.mkdir()
    own = Path(temp_path_for(d / "probe.h5"))       # .tmp-{host}~{pid}~{target}~{random}.h5
    host = own.name[len(".tmp-"):].split("~")[0]
    own.unlink()
    dead = d / f".tmp-{host}~{_dead_pid()}~F250kN_h0um.h5~abc.h5"        # SIGKILLed writer
    same_target = d / f".tmp-otherhost~1~F500kN_h30um.h5~def.h5"      # earlier try, same file
    live = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        alive = d / f".tmp-{host}~{live.pid}~F750kN_h0um.h5~ghi.h5"   # a job writing right now
        remote = d / ".tmp-otherhost~12345~F750kN_h50um.h5~jkl.h5"     # another node's writer
        for p in (dead, same_target, alive, remote):
            p.write_bytes(b"x" * 1000)
        write_case(d / "F500kN_h30um.h5", hist)
        left = sorted(p.name for p in d.iterdir())
        assert left == sorted(["F500kN_h30um.h5", alive.name, remote.name])
        assert clean_stale_temps(d) == []       # nothing more is stale while the writer lives
    finally:
        live.kill()
        live.wait()
    assert clean_stale_temps(d) == [str(alive)]


def test_unreadable_case_file_is_moved_aside_with_a_warning(tmp_path, hist):
    from bearing_envelope.io import case_file_problem, set_aside_unreadable

    good = write_case(tmp_path / "F500kN_h30um.h5", hist)
    assert case_file_problem(good) is None and set_aside_unreadable(good) is None
    assert set_aside_unreadable(tmp_path / "missing.h5") is None
    # truncated copy (a killed copy or a full disk)
    data = open(good, "rb").read()
    bad = tmp_path / "F250kN_h0um.h5"
    bad.write_bytes(data[: len(data) // 2])
    assert "unreadable HDF5" in case_file_problem(bad)
    with pytest.raises(CaseFormatError, match=r"rebuild it with `snakemake -j1 -f .*F250kN_h0um\.h5`"):
        read_case(bad)
    said = []
    aside = set_aside_unreadable(bad, warn=said.append)
    assert not bad.exists() and os.path.exists(aside) and ".unreadable-" in aside
    assert len(said) == 1 and "\n" not in said[0]
    assert str(bad) in said[0] and aside in said[0] and "rebuilt" in said[0]
    # another format version is not readable either
    with h5py.File(good, "a") as f:
        f.attrs["format_version"] = FORMAT_VERSION + 1
    assert "format_version" in case_file_problem(good)


def test_case_records_the_hardness(tmp_path):
    s = Scene.from_mapping({"operation": {"revolutions": 0.2, "acquisition": {"mode": "point"}},
                            "material": {"hardness_GPa": 7.36}}, load_kN=750, depth_um=50)
    h = simulate(s, "draft")
    c = read_case(write_case(tmp_path / "F750kN_h50um.h5", h))
    assert c.scene["material"]["hardness_GPa"] == 7.36
    assert c.attrs["solver"]["hardness_Pa"] == pytest.approx(7.36e9)
    # the bound holds in the history (point samples: no anti-alias filter ringing), and is reached
    assert c.p_max.max() == pytest.approx(7.36e9, rel=1e-12)
    assert c.p_max_defect.max() <= 7.36e9
    again = Scene.from_mapping({k: c.scene[k] for k in ("bearing", "material")},
                               load_kN=750, depth_um=50)
    assert again.material.hardness_pa == pytest.approx(7.36e9)
