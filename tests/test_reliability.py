"""Issue 22: nothing lost, nothing silently wrong.

Faults are made by the tests themselves (a bit flipped at a known byte, a file cut, a file
deleted, a run killed with SIGKILL, a second run started beside the first, a full file
system) and each run's final outputs are compared with those of an uninterrupted run of the
same tiny sweep (1 load x 2 depths, 1 revolution, draft fidelity, tables only).
"""

from __future__ import annotations

import errno
import os
import shutil
import signal
import struct
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest
import yaml

from bearing_envelope.io import (DiskFullError, case_file_problem, read_case, verify_file,
                                 write_sensor_case)
from bearing_envelope.study.recovery import is_dry_run
from bearing_envelope.study.tables import concat_tidy, pivot_tables

sys.path.insert(0, str(Path(__file__).parent))
from test_workflow import DRAFT, ROOT, job_counts  # noqa: E402

TARGET = "results/tables/harmonics.csv"
CASE_A = "results/cases/F500kN_h50um.h5"
CASE_B = "results/cases/F500kN_h0um.h5"


def run(wd: Path, cfg: Path, *args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Snakemake on the tiny sweep's tables (targets before --configfile)."""
    cmd = [sys.executable, "-m", "snakemake", TARGET, *args, "--snakefile", str(ROOT / "Snakefile"),
           "--directory", str(wd), "--cores", "2", "--configfile", str(cfg)]
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=wd)
    if check and proc.returncode != 0:
        raise AssertionError(f"snakemake failed ({proc.returncode}):\n{proc.stderr[-4000:]}")
    return proc


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """An uninterrupted run of the tiny sweep: (workdir, config)."""
    cfg = yaml.safe_load(DRAFT.read_text())
    cfg["sweep"] = {"loads_kN": [500], "depths_um": [0, 50]}
    cfg["scene"]["operation"]["revolutions"] = 1
    cfg["diagnosability"]["enabled"] = False
    root = tmp_path_factory.mktemp("tiny")
    path = root / "tiny.yaml"
    path.write_text(yaml.safe_dump(cfg))
    wd = root / "base"
    wd.mkdir()
    run(wd, path)
    return wd, path


def clone(base: Path, dst: Path) -> Path:
    shutil.copytree(base, dst, symlinks=True)
    shutil.rmtree(dst / ".snakemake" / "locks", ignore_errors=True)
    return dst


def same_outputs(wd: Path, base: Path) -> None:
    """Final outputs equal the uninterrupted run's (tables byte for byte, signals exactly)."""
    assert (wd / TARGET).read_bytes() == (base / TARGET).read_bytes()
    for case in (CASE_A, CASE_B):
        np.testing.assert_array_equal(read_case(wd / case).p_max, read_case(base / case).p_max)
        assert case_file_problem(wd / case) is None


def flip_bit(path: Path, offset: int, bit: int = 0) -> None:
    data = bytearray(path.read_bytes())
    data[offset] ^= 1 << bit
    path.write_bytes(bytes(data))


def chunk_offset(path: Path, dataset: str) -> int:
    """Byte offset of the middle of the first chunk of ``dataset``."""
    with h5py.File(path, "r") as f:
        info = f[dataset].id.get_chunk_info(0)
    return info.byte_offset + info.size // 2


def test_bit_flips_in_data_and_attribute_are_caught_and_rebuilt(tiny, tmp_path):
    base, cfg = tiny
    wd = clone(base, tmp_path / "wd")
    a, b = wd / CASE_A, wd / CASE_B
    flip_bit(a, chunk_offset(a, "signals/p_max"))
    # the bpfi attribute's float64 (231.9 Hz) is stored once in binary; flip a mantissa bit
    raw = b.read_bytes()
    at = raw.find(struct.pack("<d", 231.9))
    assert at > 0 and raw.count(struct.pack("<d", 231.9)) == 1
    flip_bit(b, at + 5, 3)
    with h5py.File(b, "r") as f:
        assert f.attrs["bpfi"] != 231.9  # the flip is real (and silent to HDF5)
    assert "checksum" in verify_file(a) and "digest mismatch" in verify_file(b)
    # a dry run reports and changes nothing, in its short and its long spelling (both at once:
    # a dry run takes no lock)
    flags = ("-n", "--dry-run")
    with ThreadPoolExecutor(2) as pool:
        drys = list(pool.map(lambda flag: run(wd, cfg, flag), flags))
    for flag, dry in zip(flags, drys):
        assert dry.stderr.count("a real run moves it aside") == 2, flag
    assert a.exists() and b.exists() and not list(a.parent.glob("*.unreadable-*"))
    out = run(wd, cfg)
    log = out.stderr + out.stdout
    assert job_counts(log) == {"simulate": 2, "bands": 2, "envelope": 2, "aggregate": 1}
    assert len(list(a.parent.glob("*.unreadable-*"))) == 2
    same_outputs(wd, base)


def test_deleted_and_truncated_case_files_are_rebuilt_with_their_downstream(tiny, tmp_path):
    base, cfg = tiny
    wd = clone(base, tmp_path / "wd")
    (wd / CASE_A).unlink()
    data = (wd / CASE_B).read_bytes()
    (wd / CASE_B).write_bytes(data[: len(data) // 3])
    out = run(wd, cfg)
    log = out.stderr + out.stdout
    assert job_counts(log) == {"simulate": 2, "bands": 2, "envelope": 2, "aggregate": 1}, log[-2000:]
    assert "unreadable HDF5" in log
    same_outputs(wd, base)


def test_killed_run_resumes_and_a_concurrent_run_is_refused(tiny, tmp_path):
    base, cfg = tiny
    wd = clone(base, tmp_path / "wd")
    (wd / CASE_A).unlink()
    cmd = [sys.executable, "-m", "snakemake", TARGET, "--snakefile", str(ROOT / "Snakefile"),
           "--directory", str(wd), "--cores", "1", "--configfile", str(cfg)]
    first = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=wd,
                             start_new_session=True)
    deadline = time.monotonic() + 300
    lock = wd / ".snakemake" / "locks"
    while time.monotonic() < deadline and not (lock.exists() and any(lock.iterdir())):
        time.sleep(0.2)
    assert first.poll() is None, "the first run ended before its lock was seen"
    os.killpg(first.pid, signal.SIGSTOP)  # frozen while it holds the lock: no race with its end
    try:
        second = run(wd, cfg, check=False)  # same folder, while the first holds the lock
    finally:
        os.killpg(first.pid, signal.SIGKILL)  # mid-run (its simulation or a later job)
    assert second.returncode != 0 and "Directory cannot be locked" in second.stderr
    first.wait()
    run(wd, cfg, "--unlock")
    run(wd, cfg)
    assert not list((wd / "results" / "cases").glob(".tmp-*"))
    same_outputs(wd, base)


def test_dry_run_detection_from_the_command_line():
    for argv in (["snakemake", "-n"], ["snakemake", "--dry-run"], ["snakemake", "--dryrun"],
                 ["snakemake", "-np", "-j2"], ["snakemake", "-pn"], ["x", "--touch"],
                 ["x", "--report", "r.html"], ["x", "--unlock"], ["x", "--summary"]):
        assert is_dry_run(argv), argv
    for argv in (["snakemake", "-j2"], ["snakemake", "--cores", "2", "-p"],
                 ["snakemake", "-c1", "--configfile", "n.yaml"], ["snakemake", "-sSnakefile"]):
        assert not is_dry_run(argv), argv


@pytest.fixture
def small_fs(tmp_path):
    """A 512 KiB file system (tmpfs, needs root), or skip with the reason."""
    mnt = tmp_path / "small"
    mnt.mkdir()
    proc = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=512k", "tmpfs", str(mnt)],
                          capture_output=True, text=True)
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs: {proc.stderr.strip() or proc.returncode}")
    yield mnt
    subprocess.run(["umount", str(mnt)], check=False)


def test_full_disk_gives_one_line_and_leaves_nothing(tiny, small_fs, monkeypatch):
    base, _ = tiny
    source = base / CASE_A
    case = read_case(source)
    acc = np.random.default_rng(0).standard_normal(200_000)  # 1.6 MB, incompressible
    target = small_fs / "sensor" / "F500kN_h50um.h5"
    with pytest.raises(DiskFullError) as err:
        write_sensor_case(target, acc, case=case, source=source)
    msg = str(err.value)
    assert "\n" not in msg and str(target) in msg and "MiB free" in msg and "needs about" in msg
    # the estimate passes (check bypassed): ENOSPC while writing gives the same one line
    monkeypatch.setattr("bearing_envelope.io.artefacts.require_free_space", lambda p, n: None)
    with pytest.raises(DiskFullError) as err:
        write_sensor_case(target, acc, case=case, source=source)
    assert err.value.errno == errno.ENOSPC and "\n" not in str(err.value)
    left = [p for p in small_fs.rglob("*") if p.is_file()]
    assert left == [], left


def test_tables_keep_every_width():
    """Two widths of one depth: both amplitudes reach the tidy table and the pivots."""
    rows = []
    for case, width, amp in (("F500kN_h50um_w100um", 100.0, 1.0), ("F500kN_h50um_w300um", 300.0, 3.0),
                             ("F500kN_h0um", None, 0.5)):
        rows.append({"case": case, "load_kN": 500.0, "depth_um": 0.0 if width is None else 50.0,
                     "band": "fixed", "band_strategy": "fixed", "band_low_hz": 1.0,
                     "band_high_hz": 2.0, "quantity": "envelope_bpfi", "order": 1.0,
                     "sideband": 0.0, "frequency_hz": 231.9, "amplitude": amp})
    from bearing_envelope.study.sections import SweepSettings

    cases = SweepSettings((500.0,), (0.0, 50.0), (100.0, 300.0)).cases()
    tidy = concat_tidy([pd.DataFrame([r]) for r in rows], cases)
    assert sorted(tidy["amplitude"]) == [0.5, 1.0, 3.0]
    assert tidy.set_index("case")["width_um"].to_dict() == pytest.approx(
        {"F500kN_h50um_w100um": 100.0, "F500kN_h50um_w300um": 300.0, "F500kN_h0um": np.nan},
        nan_ok=True)
    piv = pivot_tables(tidy)
    assert set(piv) == {"fixed__envelope_bpfi__1__w100", "fixed__envelope_bpfi__1__w300"}
    assert piv["fixed__envelope_bpfi__1__w100"].loc[500.0, 50.0] == 1.0
    assert piv["fixed__envelope_bpfi__1__w300"].loc[500.0, 50.0] == 3.0
    assert piv["fixed__envelope_bpfi__1__w300"].loc[500.0, 0.0] == 0.5
    # a duplicated cell (a sweep axis the table does not carry) is refused, not dropped
    dup = tidy.drop(columns="width_um").assign(case="F500kN_h50um")
    with pytest.raises(ValueError, match="share case"):
        concat_tidy([dup])


def _mutated(path: str, value):
    cfg = yaml.safe_load(DRAFT.read_text())
    node = cfg
    keys = path.split(".")
    for k in keys[:-1]:
        node = node.setdefault(k, {})
    node[keys[-1]] = value
    return cfg


#: Issue 22's valid-looking configs that used to pass the check and fail (or allocate GBs) in a
#: job: (name, config, text the one-line refusal must contain).
ISSUE22_CONFIGS = [
    ("revolutions 1e5", _mutated("scene.operation.revolutions", 1e5), "scene.operation.revolutions"),
    ("fs 1e12", _mutated("scene.operation.fs_hz", 1e12), "fs_hz"),
    ("oversample 1e7", _mutated("scene.operation.acquisition",
                                {"mode": "antialiased", "oversample": 10_000_000}),
     "scene.operation.acquisition.oversample"),
    ("local_dx 0.001 um", _mutated("fidelity", {"preset": "draft", "local_dx_um": 0.001}),
     "fidelity.local_dx_um"),
    ("n_loads 100000", _mutated("fidelity", {"preset": "draft", "n_loads": 100_000}),
     "fidelity.n_loads"),
    ("depth 1e-300", _mutated("sweep.depths_um", [0, 1e-300]), "sweep.depths_um[1]"),
    ("hardness 1e-9 GPa", _mutated("scene.material.hardness_GPa", 1e-9),
     "scene.material.hardness_GPa"),
    ("revolutions 0.01", _mutated("scene.operation.revolutions", 0.01),
     "scene.operation.revolutions"),
    ("unknown tradeoff knob", _mutated("tradeoff", {"knobs": {"warp_factor": [1, 2]}}),
     "tradeoff.knobs"),
    ("cpu limit", _mutated("limits", {"max_case_cpu_s": 0.01}), "limits.max_case_cpu_s"),
    ("memory limit", _mutated("limits", {"max_case_memory_GB": 0.01}),
     "limits.max_case_memory_GB"),
    ("missing profile", _mutated("scene.bearing.profile_file", "no/such/profile.csv"),
     "scene.bearing.profile_file"),
    ("__use_yte__", dict(yaml.safe_load(DRAFT.read_text()), __use_yte__=True), "__use_yte__"),
]


@pytest.mark.parametrize("name,cfg,field", ISSUE22_CONFIGS, ids=[c[0] for c in ISSUE22_CONFIGS])
def test_issue22_configs_are_refused_before_any_job(tmp_path, monkeypatch, name, cfg, field):
    """What common.smk runs (workflow_settings, then limits.precheck) refuses each config with
    one line naming the field, in well under a second, allocating nothing large."""
    from bearing_envelope.study.limits import precheck
    from bearing_envelope.study.config_read import ConfigError
    from bearing_envelope.study.settings import workflow_settings

    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    monkeypatch.chdir(tmp_path)   # the run directory: its config.yaml is read by the loader
    t0 = time.process_time()
    with pytest.raises(ConfigError) as err:
        precheck(workflow_settings())
    assert time.process_time() - t0 < 2.0
    msg = str(err.value)
    assert "\n" not in msg and field in msg, msg


@pytest.mark.parametrize("enabled", [True, False])
def test_map_background_is_checked_only_when_the_map_is_built(tmp_path, enabled):
    """One revolution leaves the fault line no background bins: refused (naming the field) when
    the run builds the detection map (sensor + diagnosability.enabled), accepted when it does
    not (the tiny sweep above). One revolution resolves bins of exactly fr: every bin is a shaft
    harmonic, which the map's background excludes."""
    from bearing_envelope.study.limits import precheck
    from bearing_envelope.study.config_read import ConfigError
    from bearing_envelope.study.settings import load_settings

    cfg = _mutated("scene.operation.revolutions", 1)
    cfg["diagnosability"]["enabled"] = enabled
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(cfg))
    if enabled:
        with pytest.raises(ConfigError, match=r"scene\.operation\.revolutions: got 1;"):
            precheck(load_settings(path))
    else:
        assert precheck(load_settings(path))


def test_alias_bomb_is_refused_fast(tmp_path):
    from bearing_envelope.study.config_read import ConfigError, read_yaml

    lines = ["a0: &a0 [" + ", ".join(["lol"] * 10) + "]"]
    lines += [f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]" for i in range(1, 9)]
    path = tmp_path / "bomb.yaml"
    path.write_text("\n".join(lines) + "\nsweep: *a8\n")
    t0 = time.process_time()
    with pytest.raises(ConfigError, match="expands to more than"):
        read_yaml(path)
    assert time.process_time() - t0 < 0.5


def test_default_configs_pass_the_limits():
    from bearing_envelope.study.limits import precheck
    from bearing_envelope.study.settings import load_settings

    for name in ("config.yaml", "tests/data/config_draft.yaml"):
        est = precheck(load_settings(ROOT / name))
        assert est and max(e.cpu_seconds for e in est) < 60 and max(e.memory_bytes for e in est) < 2e9


def test_full_disk_while_writing_a_case_file(small_fs, monkeypatch):
    """write_case on a nearly full file system: refused before writing with one line; with the
    check bypassed, ENOSPC while writing gives the same line and no crash (HDF5 builds the file
    in memory), and nothing is left behind."""
    from bearing_envelope.io import write_case
    from bearing_envelope.physics.history import simulate
    from bearing_envelope.physics.scene import Scene

    scene = Scene.from_mapping({"operation": {"revolutions": 0.2, "acquisition": {"mode": "point"}}},
                               load_kN=500, depth_um=50)
    hist = simulate(scene, "draft")
    (small_fs / "filler").write_bytes(b"\0" * (480 * 1024))  # leaves about 32 KiB
    target = small_fs / "cases" / "F500kN_h50um.h5"
    with pytest.raises(DiskFullError) as err:
        write_case(target, hist)
    assert "\n" not in str(err.value) and str(target) in str(err.value)
    monkeypatch.setattr("bearing_envelope.io.integrity.require_free_space", lambda p, n: None)
    with pytest.raises(DiskFullError) as err:
        write_case(target, hist)
    assert err.value.errno == errno.ENOSPC and "\n" not in str(err.value)
    assert sorted(p.name for p in small_fs.rglob("*") if p.is_file()) == ["filler"]


def test_sensor_case_is_checksummed_and_sealed(tiny, tmp_path):
    """The sensor case (a copy of the case plus /signals/acceleration) verifies; a bit flipped
    in the acceleration's first chunk is caught."""
    base, _ = tiny
    source = base / CASE_A
    out = tmp_path / "sensor" / "F500kN_h50um.h5"
    acc = np.random.default_rng(1).standard_normal(read_case(source).p_max.size)
    write_sensor_case(out, acc, case=read_case(source), source=source)
    assert verify_file(out) is None
    np.testing.assert_array_equal(read_case(out).signals["acceleration"], acc)
    flip_bit(out, chunk_offset(out, "signals/acceleration"))
    assert "checksum" in verify_file(out)


def test_profile_file_hash_is_stored_in_the_case(tmp_path):
    """A case made with a measured profile stores the SHA-256 of the file's bytes (computed
    here with hashlib, independently)."""
    import hashlib

    from bearing_envelope.io import write_case
    from bearing_envelope.physics.history import simulate
    from bearing_envelope.physics.scene import Scene

    prof = tmp_path / "profile.csv"
    prof.write_text("-17,10\n-8,2\n0,0\n8,2\n17,10\n")
    scene = Scene.from_mapping({"bearing": {"profile_file": str(prof)},
                                "operation": {"revolutions": 0.2, "acquisition": {"mode": "point"}}},
                               load_kN=500, depth_um=50)
    path = write_case(tmp_path / "F500kN_h50um.h5", simulate(scene, "draft"))
    assert read_case(path).attrs["profile_file_sha256"] == hashlib.sha256(prof.read_bytes()).hexdigest()


def test_cli_simulate_refuses_what_does_not_fit(tmp_path, capsys):
    from bearing_envelope.cli import main

    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(_mutated("scene.operation.revolutions", 1e5)))
    out = tmp_path / "case.h5"
    t0 = time.process_time()
    assert main(["simulate", "--config", str(path), "--load-kn", "250", "--depth-um", "50", "-q",
                 "-o", str(out)]) == 2
    assert time.process_time() - t0 < 5.0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "scene.operation.revolutions" in err and "GB" in err
    assert not out.exists()
