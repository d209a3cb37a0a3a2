"""Every value checked before any job, in bounded time (issue 34).

Each hostile input of the issue is either refused before any job with one line naming the
field (or option, or file) or runs; a property test draws configs near the limits of every
field and asserts exactly that.
"""

from __future__ import annotations

import errno
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from hypothesis import HealthCheck, given, settings, strategies as st

from bearing_envelope.checks import check_input_file
from bearing_envelope.io import read_tidy, write_tidy
from bearing_envelope.io.artefacts import ArtefactFormatError
from bearing_envelope.io.vocabulary import TIDY_COLUMNS
from bearing_envelope.physics.geometry import read_profile
from bearing_envelope.study.limits import precheck
from bearing_envelope.study.provenance import log_to
from bearing_envelope.study.recovery import is_dry_run
from bearing_envelope.study.config_read import ConfigError, read_configs
from bearing_envelope.study.settings import load_settings

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


@pytest.fixture(scope="module")
def base():
    """The draft test config with the default sensor section (the hostile set's base)."""
    from benchmarks.hostile_configs import base_config

    return base_config()


def _write(tmp_path, cfg, name="c.yaml"):
    p = tmp_path / name
    p.write_text(yaml.safe_dump(cfg, sort_keys=False, width=10 ** 6))
    return p


def _refusal(path) -> str:
    with pytest.raises(ConfigError) as err:
        precheck(load_settings(path))
    msg = str(err.value)
    assert "\n" not in msg
    return msg


def _with(cfg, *kv):
    from benchmarks.hostile_configs import _multi

    return _multi(cfg, kv)


# ----------------------------------------------------------------------------- files
@pytest.mark.parametrize("path, says", [("/dev/zero", "system file"), ("/proc/self/status",
                                                                       "system file"),
                                        ("/", "is a directory"), ("/nonexistent", "cannot be read")])
def test_input_files_are_refused_before_reading(path, says):
    with pytest.raises(ValueError, match=says):
        check_input_file(path, "profile", max_bytes=1000)


def test_input_file_size_and_emptiness(tmp_path):
    empty, big, ok = tmp_path / "e.csv", tmp_path / "b.csv", tmp_path / "o.csv"
    empty.write_text("")
    big.write_bytes(b"1 2\n" * 1000)
    ok.write_text("1 2\n")
    with pytest.raises(ValueError, match="is empty"):
        check_input_file(empty, "f", max_bytes=100)
    with pytest.raises(ValueError, match="at most 100 bytes"):
        check_input_file(big, "f", max_bytes=100)
    assert check_input_file(ok, "f", max_bytes=100) == str(ok)
    with pytest.raises(ValueError, match="is a directory"):
        check_input_file(tmp_path, "f", max_bytes=100)


def test_profile_files_in_a_config_are_refused_in_one_line(tmp_path, base):
    empty = tmp_path / "empty.csv"
    empty.write_text("")
    huge = tmp_path / "huge.csv"
    huge.write_text("".join(f"{y},{1e300 if y == 0 else 0.0}\n" for y in range(-17, 18)))
    for value, says in (("/dev/zero", "system file"), (str(empty), "is empty"),
                        (str(huge), "smaller than the roller radius")):
        msg = _refusal(_write(tmp_path, _with(base, ("scene", "bearing", "profile_file"), value)))
        assert "scene.bearing.profile_file" in msg and says in msg, msg


# ----------------------------------------------------------------------------- YAML
@pytest.mark.parametrize("text, says", [
    ("sweep: " + "[" * 20000 + "]" * 20000 + "\n", "nested too deep"),
    ("a: " + "[" * 40 + "]" * 40 + "\n", "nested more than 32 deep"),
    ("a: 1:30\n", "base-60"),
    ("a: 0750\n", "octal"),
    ("a: 0x10\n", "hexadecimal"),
])
def test_yaml_oddities_are_one_line(tmp_path, text, says):
    p = tmp_path / "c.yaml"
    p.write_text(text)
    with pytest.raises(ConfigError, match=says) as err:
        load_settings(p)
    assert "\n" not in str(err.value)


def test_plain_numbers_still_read(tmp_path):
    from bearing_envelope.study.config_read import read_yaml

    p = tmp_path / "c.yaml"
    p.write_text("a: [90, 1.5, -2.0e-3, 1_000, 0, .5, +3]\n")
    assert read_yaml(p)["a"] == [90, 1.5, -2e-3, 1000, 0, 0.5, 3]


# ----------------------------------------------------------------------------- bounded time
def test_a_huge_sweep_is_refused_before_any_case_is_built(tmp_path, base):
    cfg = _with(base, ("sweep", "loads_kN"), list(range(1, 1001)),
                ("sweep", "depths_um"), [0] + [1 + 0.5 * i for i in range(999)])
    p = _write(tmp_path, cfg)
    t0 = time.process_time()
    msg = _refusal(p)
    # the count, not a measured time, is the test: 10^6 cases would take ~50 min to build
    assert "1,000,000 cases" in msg and "limits.max_cases" in msg
    assert time.process_time() - t0 < 60   # a generous guard against expanding the sweep


def test_max_cases_is_overridable(tmp_path, base):
    cfg = _with(base, ("sweep", "loads_kN"), [100, 200, 300], ("limits", "max_cases"), 5)
    assert "at most 5" in _refusal(_write(tmp_path, cfg))
    cfg = _with(cfg, ("limits", "max_cases"), 6)
    assert len(load_settings(_write(tmp_path, cfg)).cases) == 6


# ----------------------------------------------------------------------------- values
@pytest.mark.parametrize("kv, field", [
    ((("scene", "defect", "edge_radius_um"), 1e6), "scene.defect.edge_radius_um"),
    ((("scene", "defect", "position_deg"), 90), "defect.position_deg"),
    ((("scene", "operation", "noise_snr_db"), -1e300), "scene.operation.noise_snr_db"),
    ((("sensor", "excitation_scale"), 1e308), "sensor.excitation_scale"),
    ((("sensor", "tones"), [{"order": 1, "level_db": 1e300}]), "sensor.tones[0].level_db"),
    ((("scene", "operation", "noise_seed"), 10 ** 70), "scene.operation.noise_seed"),
    ((("sensor", "seed"), 2 ** 63), "sensor.seed"),
    ((("scene", "bearing", "radial_clearance_um"), 20000.0), "radial_clearance_um"),
    ((("analysis", "bands"), [{"name": "b" * 300, "strategy": "kurtogram"}]),
     "analysis.bands[0].name"),
    ((("analysis", "bands"), [{"name": "tiny", "strategy": "fixed", "low_hz": 0.007,
                               "high_hz": 0.014}]), "analysis.bands[tiny]"),
    ((("analysis", "nlevel"), 12, ("scene", "operation", "revolutions"), 1),
     "scene.operation.revolutions"),
])
def test_values_that_failed_inside_a_job_are_refused(tmp_path, base, kv, field):
    msg = _refusal(_write(tmp_path, _with(base, *kv)))
    assert field in msg, msg


def test_a_load_beyond_the_hardness_everywhere_is_refused(tmp_path, base):
    cfg = _with(base, ("scene", "bearing"), {"designation": "SKF 6205-2RS"},
                ("scene", "operation", "bpfi_override_hz"), None, ("sweep", "loads_kN"), [5000])
    msg = _refusal(_write(tmp_path, cfg))
    assert "sweep.loads_kN[0]" in msg and "hardness" in msg
    # the study's highest load on its own bearing passes (Hertz mean pressure ~2.7 GPa)
    assert load_settings(ROOT / "config.yaml").sweep.loads_kN[-1] == 750
    precheck(load_settings(ROOT / "config.yaml"))


def test_edge_radius_bound_matches_the_rim_geometry(tmp_path, base):
    """A 50 um deep, 100 um wide flat defect: the rim arc r - sqrt(r^2 - 50^2) (um) at the
    centre keeps 0.5 um (1 %) at r = (50^2 + 0.5^2) / 1 = 2500.25 um (independent algebra)."""
    ok = _with(base, ("scene", "defect", "edge_radius_um"), 2450.0)
    precheck(load_settings(_write(tmp_path, ok)))
    bad = _with(base, ("scene", "defect", "edge_radius_um"), 2550.0)
    assert "<= 2500 um" in _refusal(_write(tmp_path, bad))


def test_integral_floats_become_integers(tmp_path, base):
    st_ = load_settings(_write(tmp_path, _with(base, ("analysis", "harmonics"), 3.0)))
    assert type(st_.analysis.options.n_harmonics) is int and st_.analysis.options.n_harmonics == 3


# ----------------------------------------------------------------------------- dry runs
@pytest.mark.parametrize("argv", [["--dry-r"], ["--summ"], ["--list-conda-envs"], ["--dr"],
                                  ["-j1", "--detailed-summ"]])
def test_abbreviated_and_listing_options_are_dry_runs(argv):
    assert is_dry_run(["snakemake", *argv])


def test_a_profile_with_dry_run_is_a_dry_run(tmp_path):
    prof = tmp_path / "prof"
    prof.mkdir()
    (prof / "config.yaml").write_text("dry-run: true\n")
    assert is_dry_run(["snakemake", "--profile", str(prof)])
    assert not is_dry_run(["snakemake", "-j1"])


# ----------------------------------------------------------------------------- disk, tables
def test_a_full_disk_ends_a_job_in_one_line(tmp_path):
    log = tmp_path / "job.log"
    with pytest.raises(SystemExit) as err:
        with log_to(log):
            raise OSError(errno.ENOSPC, "No space left on device")
    assert "disk full" in str(err.value.code) and "\n" not in str(err.value.code)
    assert log.read_text().count("\n") == 1


def test_an_edited_per_case_table_is_refused(tmp_path):
    df = pd.DataFrame({c: [1.0, 2.0] for c in TIDY_COLUMNS})
    p = write_tidy(tmp_path / "F1kN_h0um.csv", df, sealed=True)
    pd.testing.assert_frame_equal(read_tidy(p, sealed=True), df)
    text = Path(p).read_text()
    Path(p).write_text(text.replace("2.0", "2.5"))
    with pytest.raises(ArtefactFormatError, match="edited after it was written"):
        read_tidy(p, sealed=True)
    write_tidy(p, df)   # unsealed (an older file, or written by hand)
    with pytest.raises(ArtefactFormatError, match="no '# content_sha256="):
        read_tidy(p, sealed=True)


# ----------------------------------------------------------------------------- analyze
def test_analyze_inputs_are_refused_in_one_line(tmp_path):
    from scipy.io import wavfile

    from bearing_envelope.io.records import read_record

    x = np.random.default_rng(0).standard_normal(12000)
    npy = tmp_path / "a.npy"
    np.save(npy, x)
    raw = bytearray(npy.read_bytes())
    short = tmp_path / "short.npy"
    short.write_bytes(bytes(raw).replace(b"(12000,)", b"(10000,)", 1))
    broken = tmp_path / "broken.npy"
    broken.write_bytes(bytes(raw).replace(b"(12000,)", b"(12000,'", 1))
    wav = tmp_path / "w.wav"
    wavfile.write(wav, 12000, (1000 * x).astype(np.int16))
    cut = tmp_path / "cut.wav"
    cut.write_bytes(wav.read_bytes()[: int(0.9 * wav.stat().st_size)])
    meta = tmp_path / "m.npz"
    np.savez(meta, x=x, fs=12000.0, meta_json=np.array('{"shaft_hz": 29.'))
    for path, says in ((short, "samples would be left out"), (broken, "no valid .npy header"),
                       (cut, "truncated WAV"), (meta, "'meta_json' is not valid JSON")):
        with pytest.raises(ValueError, match=says) as err:
            read_record(str(path))
        assert "\n" not in str(err.value)
    assert read_record(str(npy))["x"].size == 12000


@pytest.mark.parametrize("target", ["/dev/full", "/sys/x.csv"])
def test_analyze_table_on_a_system_path_is_refused_before_the_batch(target, capsys):
    from bearing_envelope.cli import main

    rc = main(["analyze", str(ROOT / "tests/data/real/cwru_105_IR007_0hp_DE12.npz"),
               "--table", target])
    err = capsys.readouterr().err
    assert rc != 0 and "--table" in err and "system path" in err and err.count("\n") == 1


# ----------------------------------------------------------------------------- property
#: Values near the limits of any field: zero, signs, the float range's ends, integral floats,
#: huge integers, wrong types.
NEAR_LIMITS = st.one_of(
    st.sampled_from([0, -1, 1, 0.5000001, 1e-300, 1e300, 2 ** 63, 10 ** 70, 3.0, 359.999,
                     "abc", True, None, [1, 2], {"a": 1}]),
    st.floats(allow_nan=False, allow_infinity=False, width=64),
    st.integers(min_value=-2 ** 70, max_value=2 ** 70),
)


def _leaf_paths():
    from benchmarks.hostile_configs import _leaves, base_config

    b = base_config()
    return [p for p in _leaves(b) if p and p[0] not in ("paper_run", "tradeoff")]


@settings(max_examples=int(os.environ.get("HARDENING_EXAMPLES", "6")), deadline=None,
          derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                   HealthCheck.too_slow])
@given(path=st.sampled_from(_leaf_paths()), value=NEAR_LIMITS)
def test_a_config_near_the_limits_is_refused_in_one_line_or_runs(tmp_path, base, path, value):
    """Refused before any job (one line naming a field), or its first case runs through the
    simulation, bands and envelope jobs at the config's (draft) fidelity."""
    from benchmarks.hostile_configs import _names_field, _set, run_jobs

    cfg = _set(base, path, value)
    cfg.pop("sensor", None) if path[0] != "sensor" else None   # keep the run short
    p = _write(tmp_path, cfg, f"h{abs(hash((path, repr(value)))) % 10 ** 8}.yaml")
    try:
        settings_ = load_settings(p)
        precheck(settings_)
    except ConfigError as exc:
        msg = str(exc)
        assert "\n" not in msg and _names_field(msg.replace(str(p), "FILE")), msg
        return
    one = settings_.cases[:1]
    object.__setattr__(settings_, "sweep", type(settings_.sweep)(
        (one[0].load_kN,), (one[0].depth_um,), None if one[0].width_um is None else
        (one[0].width_um,), None if one[0].location is None else (one[0].location,)))
    status, msg = run_jobs(settings_, tmp_path)
    assert status == "ran", msg


def test_hostile_benchmark_smoke():
    from benchmarks.hostile_configs import smoke

    smoke()
