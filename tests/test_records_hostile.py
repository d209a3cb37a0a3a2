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
