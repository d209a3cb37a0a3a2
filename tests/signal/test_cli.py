import numpy as np
import pandas as pd
import pytest
import scipy.io

from bearing_envelope.cli import main
from conftest import fault_signal

FS, FR, BPFI, FN = 20000.0, 15.8, 231.9, 6000.0


@pytest.fixture(scope="module")
def x():
    return fault_signal(fs=FS, n=2**15, fr=FR, bpfi=BPFI, fn=FN, seed=11)


def test_csv_with_time_column(tmp_path, x, capsys):
    path = tmp_path / "rec.csv"
    pd.DataFrame({"time": np.arange(x.size) / FS, "DE": x}).to_csv(path, index=False)
    out_csv = tmp_path / "out" / "table.csv"
    rc = main(["analyze", str(path), "--fr", str(FR), "--bpfi", str(BPFI), "--csv", str(out_csv),
               "--plot", str(tmp_path / "figs"), "--fixed-band", "5000", "7000"])
    assert rc == 0
    text = capsys.readouterr().out
    assert "fs = 20000 Hz" in text and "kurtogram: level" in text
    assert "envelope_bpfi" in text            # the sweep's tidy quantity names
    df = pd.read_csv(out_csv)
    assert {"raw_dc", "raw_fr", "raw_bpfi", "envelope_bpfi", "bandpass_peak"} <= set(df.quantity)
    assert set(df.band_strategy) <= {"raw", "kurtogram", "fraction", "orders", "fixed"}
    for c in ["band", "band_strategy", "band_low_hz", "band_high_hz", "quantity", "order", "sideband",
              "frequency_hz", "amplitude"]:
        assert c in df.columns
    assert set(df.band) == {"raw", "kurtogram", "fs4_3fs8", "bpfi_3_6", "bpfi_10_13",
                                     "fixed"}
    kg = df[df.quantity == "kurtogram_kurtosis"].iloc[0]
    assert kg.band_low_hz <= FN <= kg.band_high_hz
    figs = sorted(p.name for p in (tmp_path / "figs").iterdir())
    assert "rec_kurtogram.png" in figs and "rec_envelope_kurtogram.png" in figs
    assert len(figs) == 6


def test_headerless_csv_geometry_and_column_index(tmp_path, x, capsys):
    path = tmp_path / "raw.csv"
    np.savetxt(path, np.c_[np.zeros_like(x), x], delimiter=",")
    rc = main(["analyze", str(path), "--fs", str(FS), "--fr", str(FR), "--column", "1",
               "--n-rollers", "9", "--roller-diameter-mm", "7.94", "--pitch-diameter-mm",
               "39.04", "--bands", '[{"name": "f", "strategy": "fixed", "low_hz": 5000, '
               '"high_hz": 7000}]'])
    assert rc == 0
    text = capsys.readouterr().out
    assert "bpfi = 85.56" in text and "bpfo" in text  # 5.4152 x 15.8 Hz


def test_npz_mat_npy(tmp_path, x, capsys):
    np.savez(tmp_path / "a.npz", accel=x, fs=FS)
    scipy.io.savemat(tmp_path / "b.mat", {"X105_DE_time": x[:, None], "RPM": 948.0})
    np.save(tmp_path / "c.npy", x)
    args = ["--fr", str(FR), "--bpfi", str(BPFI), "--nlevel", "6"]
    assert main(["analyze", str(tmp_path / "a.npz"), *args]) == 0
    assert main(["analyze", str(tmp_path / "b.mat"), "--fs", str(FS), "--column",
                 "X105_DE_time", *args]) == 0
    assert main(["analyze", str(tmp_path / "c.npy"), "--fs", str(FS), *args]) == 0
    text = capsys.readouterr().out
    assert "npz:accel" in text and "mat:X105_DE_time" in text and "(npy)" in text


@pytest.mark.parametrize(
    "extra, match",
    [
        ([], "fs: the file does not give"),
        (["--fs", "20000"], "bpfi: pass --bpfi"),
        (["--fs", "20000", "--bpfi", "231.9", "--fixed-band", "5000", "12000"],
         "--fixed-band: HIGH_HZ 12000 is above the Nyquist frequency 10000 Hz"),
        (["--fs", "-1", "--bpfi", "231.9"], "fs must be"),
        (["--fs", "20000", "--n-rollers", "9"], "give --n-rollers, --roller-diameter-mm"),
    ],
)
def test_errors(tmp_path, x, capsys, extra, match):
    np.save(tmp_path / "c.npy", x)
    rc = main(["analyze", str(tmp_path / "c.npy"), "--fr", str(FR), *extra])
    assert rc == 2
    assert match in capsys.readouterr().err


def test_missing_file_and_bad_column(tmp_path, x, capsys):
    assert main(["analyze", str(tmp_path / "nope.csv"), "--fs", "1", "--fr", "1",
                 "--bpfi", "1"]) == 2
    assert "no such file" in capsys.readouterr().err
    np.savez(tmp_path / "a.npz", a=x, b=x)
    assert main(["analyze", str(tmp_path / "a.npz"), "--fs", str(FS), "--fr", str(FR),
                 "--bpfi", str(BPFI)]) == 2
    assert "several variables" in capsys.readouterr().err


def test_case_file_through_read_case(tmp_path, x, capsys, monkeypatch):
    import types

    import bearing_envelope.io as bio

    calls = []

    def fake_read_case(path):
        calls.append(path)
        return types.SimpleNamespace(fs=FS, fr=FR, bpfi=BPFI, signals={"p_max": x, "p_max_defect": -x})

    monkeypatch.setattr(bio, "read_case", fake_read_case)
    path = tmp_path / "F500kN_h50um.h5"
    path.write_bytes(b"")
    assert main(["analyze", str(path), "--signal", "p_max_defect", "--nlevel", "6"]) == 0
    text = capsys.readouterr().out
    assert calls == [str(path)]
    assert "case:p_max_defect" in text and "bpfi = 231.9 Hz" in text and "fr = 15.8 Hz" in text
    # a --fault adds a family; the case's BPFI stays
    assert main(["analyze", str(path), "--nlevel", "6", "--fault", "bpfo=150"]) == 0
    text = capsys.readouterr().out
    assert "bpfo = 150 Hz, bpfi = 231.9 Hz" in text
    assert main(["analyze", str(path), "--signal", "nope"]) == 2
    assert "no signal 'nope'" in capsys.readouterr().err


def test_help_is_plain_text(capsys):
    """The help shows no reStructuredText markup (roles, double back-quotes)."""
    with pytest.raises(SystemExit):
        main(["analyze", "--help"])
    text = capsys.readouterr().out
    assert "--search-percent" in text and "--fault NAME=HZ" in text and "--json" in text
    for markup in (":func:", ":mod:", "``", "::"):
        assert markup not in text


def test_full_band_and_clamp(tmp_path, x, capsys):
    """--fixed-band 0 fs/2 is the full band (clamped to 0.98 fs/2); above Nyquist it needs
    --clamp."""
    np.save(tmp_path / "c.npy", x)
    base = ["analyze", str(tmp_path / "c.npy"), "--fs", str(FS), "--fr", str(FR), "--bpfi",
            str(BPFI), "--bands", "[]", "--csv", str(tmp_path / "t.csv")]
    assert main([*base, "--fixed-band", "0", str(FS / 2)]) == 0
    assert "# band fixed: 0 - 9800 Hz (fixed, clamped)" in capsys.readouterr().out
    t = pd.read_csv(tmp_path / "t.csv")
    assert set(t[t.band == "fixed"].band_high_hz) == {0.98 * FS / 2}
    assert main([*base, "--fixed-band", "0", "12000"]) == 2
    assert "add --clamp" in capsys.readouterr().err
    assert main([*base, "--fixed-band", "0", "12000", "--clamp"]) == 0


def test_routes_option(tmp_path, x, capsys):
    # the routes join the verdict by default (their lines in the summary); --routes envelope
    # leaves the envelope bands alone; a route that does not exist is refused before any work
    np.save(tmp_path / "c.npy", x)
    base = ["analyze", str(tmp_path / "c.npy"), "--fs", str(FS), "--fr", str(FR),
            "--bpfi", str(BPFI)]
    assert main(base) == 0
    out = capsys.readouterr().out
    assert "decided by:" in out and "route pre-whitened SES" in out
    assert main([*base, "--routes", "envelope"]) == 0
    assert "decided by:" not in capsys.readouterr().out
    assert main([*base, "--routes", "cpw,nope"]) == 2
    assert "--routes" in capsys.readouterr().err
