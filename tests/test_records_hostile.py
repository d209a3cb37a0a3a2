"""Hostile `analyze` inputs that used to be refused late or for the wrong reason (issue 43):
finite samples at a scale whose squares overflow, a rate entry that is not one number, a
negative shaft rate in meta_json, a CSV time column rounded to its printed decimals."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from bearing_envelope.cli import main
from bearing_envelope.io.analysis import analyze_file, read_task
from bearing_envelope.io.records import read_record

FS = 12_000.0


def _signal(n=6000, seed=0):
    rng = np.random.default_rng(seed)
    return np.sin(2 * np.pi * 1000.0 * np.arange(n) / FS) + 0.1 * rng.standard_normal(n)


@pytest.mark.parametrize("scale", [1e305, 1e-310])
def test_finite_samples_at_a_hostile_scale_are_refused_before_any_work(tmp_path, scale, capsys):
    f = tmp_path / "scaled.npz"
    np.savez(f, x=_signal() * scale, fs=np.float64(FS))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning on the way to the refusal
        with pytest.raises(ValueError, match=r"samples peak at \|x\| = .*allowed: a peak "
                                             r"within 1e-50-1e\+50"):
            read_record(str(f))
        rc = main(["analyze", str(f), "--fr", "29.95", "--bpfi", "162"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "peak at" in err[0]


@pytest.mark.parametrize("scale", [1e40, 1e-40])
def test_a_scale_inside_the_range_is_read_as_written(tmp_path, scale):
    f = tmp_path / "scaled.npz"
    x = _signal() * scale
    np.savez(f, x=x, fs=np.float64(FS))
    assert np.array_equal(read_record(str(f))["x"], x)


def test_an_fs_entry_that_is_not_one_number_is_named(tmp_path):
    f = tmp_path / "fs2.npz"
    np.savez(f, x=_signal(), fs=np.array([FS, FS]))
    with pytest.raises(ValueError, match=r"'fs' holds float64 of shape \(2,\); allowed: one "
                                         r"real number"):
        read_record(str(f))


@pytest.mark.parametrize("fr, match", [(-29.95, r"fr = -29\.95; pass a shaft rate > 0"),
                                       ("fast", r"shaft_hz = 'fast'; allowed: a shaft rate > 0")])
def test_a_bad_shaft_rate_in_meta_json_is_named_with_its_value(tmp_path, fr, match):
    f = tmp_path / "neg.npz"
    np.savez(f, x=_signal(24000), fs=np.float64(FS), meta_json=json.dumps({"shaft_hz": fr}))
    with pytest.raises(ValueError, match=match):
        analyze_file(str(f), bpfi=162.0)


def _csv(path, t, x, decimals):
    with open(path, "w") as fh:
        fh.write("time,x\n")
        for a, b in zip(t, x):
            fh.write(f"{a:.{decimals}f},{b:.6f}\n")


def test_a_time_column_rounded_to_six_decimals_is_uniform(tmp_path):
    """12 kHz: an 83.333 us step written to 1 us; the rate read end to end is exact to 1e-6."""
    f = tmp_path / "t6.csv"
    x = _signal()
    _csv(f, np.arange(x.size) / FS, x, 6)
    assert read_record(str(f))["fs"] == pytest.approx(FS, rel=1e-6)


def test_fs_option_overrides_a_time_column_that_is_not_uniform(tmp_path):
    f = tmp_path / "jitter.csv"
    x = _signal()
    t = np.arange(x.size) / FS
    t[3000:] += 5e-6  # one step 6 % long, written to 1 ns
    _csv(f, t, x, 9)
    with pytest.raises(ValueError, match="not uniformly sampled.*give --fs"):
        read_record(str(f))
    assert read_record(str(f), fs=FS)["fs"] is None  # the caller's rate wins
    assert np.allclose(read_task(str(f), fs=FS)["x"], x, atol=1e-6)
    assert read_task({"file": str(f), "fs": FS})["fs"] is None


# ---------------------------------------------------------------------------------------
# benchmarks/hostile_records.py's findings (2026-12-06): each refused in one line naming the
# field, where it used to be analysed silently, crash or name something else.

def _refusal(argv, capsys) -> str:
    """``analyze ARGV``'s one-line refusal (exit code 2)."""
    rc = main(["analyze", *argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1, err
    return err[0]


@pytest.mark.parametrize("entries, named", [
    ({"fs": FS, "sampling_rate": 2 * FS, "fr": 29.95}, ("'fs' = 12000.0", "'sampling_rate'")),
    ({"fs": FS, "fr": 29.95, "rpm": 900.0}, ("'fr' = 29.95", "'rpm' = 900.0")),
    ({"fs": FS, "fr": 29.95, "shaft_hz": 15.0}, ("'fr'", "'shaft_hz' = 15.0")),
])
def test_two_entries_giving_one_rate_differently_are_refused(tmp_path, entries, named):
    """The file contradicts itself: neither entry is picked silently."""
    f = tmp_path / "two.npz"
    np.savez(f, x=_signal(), **{k: np.float64(v) for k, v in entries.items()})
    with pytest.raises(ValueError, match="contradict each other") as exc:
        read_record(str(f))
    assert all(n in str(exc.value) for n in named)


def test_entries_that_agree_are_read(tmp_path):
    """1797 rpm written to the unit is 29.95 Hz: they agree (within RATE_AGREEMENT)."""
    f = tmp_path / "agree.npz"
    np.savez(f, x=_signal(), fs=np.float64(FS), fr=np.float64(29.95), rpm=np.float64(1797.0),
             meta_json=json.dumps({"shaft_hz": 29.95}))
    assert read_record(str(f))["fr"] == 29.95


def test_meta_json_contradicting_the_shaft_rate_is_refused(tmp_path):
    f = tmp_path / "meta.npz"
    np.savez(f, x=_signal(), fs=np.float64(FS), fr=np.float64(29.95),
             meta_json=json.dumps({"shaft_hz": 15.0}))
    with pytest.raises(ValueError, match=r"meta_json shaft_hz' = 15\.0 contradict"):
        read_record(str(f))


def test_meta_json_nested_too_deeply_is_one_line(tmp_path, capsys):
    """Used to be a RecursionError traceback from json."""
    f = tmp_path / "deep.npz"
    np.savez(f, x=_signal(), fs=np.float64(FS), meta_json="[" * 100000 + "]" * 100000)
    msg = _refusal([str(f), "--fr", "29.95", "--bpfi", "162"], capsys)
    assert "'meta_json' is nested too deeply" in msg


@pytest.fixture()
def record(tmp_path):
    f = tmp_path / "rec.npz"
    np.savez(f, x=_signal(24000), fs=np.float64(FS), fr=np.float64(29.95))
    return str(f)


@pytest.mark.parametrize("name", ["6205\x01", "6205; rm -rf /", "6205\n6203", "6205 6203"])
def test_a_designation_is_not_guessed_from_part_of_it(record, name, capsys):
    """Each used to be read as the 6205 (its number found inside the text)."""
    msg = _refusal([record, "--bearing", name], capsys)
    assert msg.startswith("bearing-envelope analyze: error: --bearing: got ")


@pytest.mark.parametrize("z", ["1", "16", "100000"])
def test_rollers_that_do_not_fit_the_pitch_circle_are_refused(record, z, capsys):
    """7.94 mm balls on a 39.04 mm pitch circle: D sin(pi/Z) >= d holds for Z = 2 .. 15
    (sin(pi/15) = 0.2079 > 7.94/39.04 = 0.2034 > sin(pi/16) = 0.1951). Z = 1 used to be
    refused as '--sidebands', 100000 as a BPFO above Nyquist."""
    msg = _refusal([record, "--n-rollers", z, "--roller-diameter-mm", "7.94",
                    "--pitch-diameter-mm", "39.04"], capsys)
    assert f"--n-rollers: got {z}; allowed: 2 .. 15" in msg


def test_a_geometry_whose_lines_pass_nyquist_names_its_options(record, capsys):
    msg = _refusal([record, "--n-rollers", "9", "--roller-diameter-mm", "1e-300",
                    "--pitch-diameter-mm", "39.04"], capsys)
    assert ("bearing geometry (--n-rollers, --roller-diameter-mm/-in, "
            "--pitch-diameter-mm/-in) (bsf = ") in msg


@pytest.mark.parametrize("bands, named", [
    ("[]", "--bands: got an empty list; allowed: at least one band (or an empty list with "
           "--fixed-band)"),
    ('[{"name": "b", "strategy": "fixed", "low_hz": "low", "high_hz": 2000}]',
     "--bands: fixed band: band edges must be numbers"),
])
def test_bad_band_lists_name_bands(record, bands, named, capsys):
    """An empty list used to end in 'file: ...: detected' (a KeyError), a text edge in
    float()'s own message."""
    assert named in _refusal([record, "--bearing", "6205", "--bands", bands], capsys)


def test_bands_given_a_folder_names_bands(record, tmp_path, capsys):
    msg = _refusal([record, "--bearing", "6205", "--bands", str(tmp_path)], capsys)
    assert "--bands: " in msg and "is a directory" in msg


@pytest.mark.parametrize("window", ["nonsense", "", "kaiser", "boxcar;rm"])
def test_a_window_scipy_does_not_know_is_refused_as_the_option(record, window, capsys):
    """Used to pass the option check and fail deep in the chain with scipy's message."""
    msg = _refusal([record, "--bearing", "6205", "--window", window], capsys)
    assert msg.startswith("bearing-envelope analyze: error: --window: got ")


def test_a_minimum_bandwidth_above_nyquist_names_the_option(record, capsys):
    msg = _refusal([record, "--bearing", "6205", "--min-bandwidth", "1e9"], capsys)
    assert "--min-bandwidth: got 1e+09 Hz; allowed: at most fs/2 = 6000 Hz" in msg


def test_a_time_column_in_g_format_with_a_jump_is_not_uniform(tmp_path):
    """'%.9g' writes t = 0 as '0': its printed step (1 s) used to be taken as the column's
    precision, and a 6 % long step or a 1 s gap passed as uniform."""
    x = _signal()
    for shift in (5e-6, 1.0):
        t = np.arange(x.size) / FS
        t[x.size // 2:] += shift
        f = tmp_path / f"g{shift}.csv"
        f.write_text("time,x\n" + "".join(f"{a:.9g},{b:.9g}\n" for a, b in zip(t, x)))
        with pytest.raises(ValueError, match="not uniformly sampled"):
            read_record(str(f))
    f = tmp_path / "g.csv"   # the same format, uniform: read, fs exact to the printed digits
    f.write_text("time,x\n" + "".join(f"{a:.9g},{b:.9g}\n"
                                      for a, b in zip(np.arange(x.size) / FS, x)))
    assert read_record(str(f))["fs"] == pytest.approx(FS, rel=1e-6)


def test_an_npy_of_format_3_is_read(tmp_path):
    """Version 3.0 (a UTF-8 header) used to crash on a numpy without _read_array_header."""
    x = _signal()
    body = "{'descr': '<f8', 'fortran_order': False, 'shape': (%d,), }" % x.size
    head = len(body) + 1 + 12
    text = (body + " " * (-head % 64) + "\n").encode()
    f = tmp_path / "v3.npy"
    f.write_bytes(b"\x93NUMPY\x03\x00" + len(text).to_bytes(4, "little") + text + x.tobytes())
    assert np.array_equal(read_record(str(f))["x"], x)


def test_a_cwru_rpm_written_as_text_is_refused(tmp_path):
    from scipy.io import savemat

    f = tmp_path / "X105.mat"
    savemat(f, {"X105_DE_time": _signal()[:, None], "X105RPM": "1797"})
    with pytest.raises(ValueError, match=r"'X105RPM' holds <U4 data; allowed: one number"):
        read_record(str(f))


def test_fs_option_overrides_an_uneven_mat_time_vector(tmp_path):
    """--fs used to be ignored by the .mat reader: refused 'give --fs' with --fs given."""
    from scipy.io import savemat

    x = _signal()
    t = np.arange(x.size) / FS
    t[x.size // 2:] += 5e-6
    f = tmp_path / "t.mat"
    savemat(f, {"a": x, "time": t})
    with pytest.raises(ValueError, match="not uniformly sampled.*give --fs"):
        read_record(str(f))
    assert read_record(str(f), fs=FS)["fs"] is None


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_a_fifo_is_refused_not_read(tmp_path, suffix):
    """Opening a FIFO blocks until a writer comes: the command used to hang."""
    import os

    f = tmp_path / f"pipe{suffix}"
    os.mkfifo(f)
    with pytest.raises(ValueError, match=r"is a FIFO; allowed: a regular signal file"):
        read_record(str(f))


def test_a_binary_manifest_names_the_manifest(tmp_path, capsys):
    f = tmp_path / "m.csv"
    f.write_bytes(bytes(range(256)) * 16)
    msg = _refusal(["--manifest", str(f), "--fr", "29.95", "--bearing", "6205"], capsys)
    assert "error: --manifest: " in msg and "is not a UTF-8 text CSV" in msg


def test_the_windows_accepted_without_scipy_are_scipys():
    """The fast path's names (no scipy.signal import in a simulate job) are windows scipy makes."""
    from scipy.signal import get_window

    from bearing_envelope.diagnosis.options import PLAIN_WINDOWS, AnalysisOptions

    for name in sorted(PLAIN_WINDOWS):
        assert get_window(name, 16).shape == (16,)
        assert AnalysisOptions(window=name).window == name
