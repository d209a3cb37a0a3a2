import os

import h5py
import numpy as np
import pytest

from bearing_envelope.history import simulate
from bearing_envelope.io import FORMAT_VERSION, Case, CaseFormatError, git_commit, read_case, write_case
from bearing_envelope.scene import Scene


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
    assert c.bpfo + c.bpfi_geometry == pytest.approx(22 * 15.8)
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
