"""Table-driven bad-input suite (issue 17): every rejected input goes through both entry points.

Each config in :data:`BAD_CONFIGS` is written to a file and run through

* the workflow's pre-run check: :func:`bearing_envelope.study.settings.workflow_settings`, the function
  ``workflow/rules/common.smk`` calls, given the config as Snakemake parses it (``yaml.safe_load``,
  which keeps the last of two equal keys) and the file (``tests/test_workflow.py`` runs a few of
  them through a real ``snakemake -n``);
* the command line: ``bearing-envelope simulate --config FILE`` (with the contact solver replaced
  by a function that fails the test if reached) and ``bearing-envelope check-config FILE``.

Each must fail with exit code 2 (CLI) or :class:`ConfigError` (workflow), with ONE line that names
the field, before any contact solve. The analyze command has its own table.
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml

from bearing_envelope.study.config_read import ConfigError
from bearing_envelope.study.settings import workflow_settings

ROOT = Path(__file__).resolve().parents[1]
DRAFT = yaml.safe_load((ROOT / "tests" / "data" / "config_draft.yaml").read_text())
NAN = float("nan")


def _set(path: str, value):
    """A mutation setting the dotted ``path`` (list indices as numbers) to ``value``."""
    def mutate(cfg):
        keys = [int(k) if k.isdigit() else k for k in path.split(".")]
        node = cfg
        for k in keys[:-1]:
            node = node[k]
        node[keys[-1]] = value
    return mutate


def _pop(path: str):
    def mutate(cfg):
        keys = path.split(".")
        node = cfg
        for k in keys[:-1]:
            node = node[k]
        node.pop(keys[-1])
    return mutate


def _all(*mutations):
    def mutate(cfg):
        for m in mutations:
            m(cfg)
    return mutate


def _band(**band):
    return lambda cfg: cfg["analysis"]["bands"].append(band)


# id -> (mutation of the draft config, or raw YAML text; regex the one-line message must match)
BAD_CONFIGS = {
    # issue 17 item 1: sweep values that would collapse into one case
    "depths-duplicate-float": (_set("sweep.depths_um", [0, 50, 50.0]), r"sweep\.depths_um"),
    "loads-duplicate": (_set("sweep.loads_kN", [250, 250]), r"sweep\.loads_kN"),
    "widths-duplicate": (_set("sweep.widths_um", [60, 60.0]), r"sweep\.widths_um"),
    # item 2: checked only inside jobs before; NaN through JSON Schema bounds
    "sensor-mode-at-nyquist": (_set("sensor.modes.0.f_n_hz", 32500.0), r"sensor\.modes\[0\]\.f_n_hz"),
    "sensor-mode-above-nyquist": (_set("sensor.modes.1.f_n_hz", 40000.0), r"sensor\.modes\[1\]\.f_n_hz"),
    "tone-above-nyquist": (_set("sensor.tones", [{"frequency_hz": 33000.0, "level_db": 0.0}]),
                           r"sensor\.tones\[0\]\.frequency_hz"),
    "tone-order-above-nyquist": (_set("sensor.tones", [{"order": 3000.0, "level_db": 0.0}]),
                                 r"sensor\.tones\[0\]\.order"),
    "zeta-nan": (_set("sensor.modes.0.zeta", NAN), r"sensor\.modes\[0\]\.zeta"),
    "sensor-snr-nan": (_set("sensor.snr_db", NAN), r"sensor\.snr_db"),
    "min-bandwidth-nan": (_set("analysis.min_bandwidth_hz", NAN), r"analysis\.min_bandwidth_hz"),
    "diagnosability-snr-nan": (_set("diagnosability.snr_db", [20, NAN]), r"diagnosability\.snr_db\[1\]"),
    "load-nan": (_set("sweep.loads_kN", [250, NAN]), r"sweep\.loads_kN\[1\]"),
    "fs-inf": (_set("scene.operation.fs_hz", float("inf")), r"scene\.operation\.fs_hz"),
    "max-level-above-nlevel": (_set("analysis.max_level", 9), r"analysis\.max_level"),
    "acceleration-without-snr": (_set("analysis.signal", "acceleration"), r"sensor\.snr_db"),
    "acceleration-without-sensor": (_all(_set("analysis.signal", "acceleration"), _pop("sensor")),
                                    r"analysis\.signal"),
    # item 3: what simulate --config used to skip
    "fidelity-misspelt": ("fidelty: draft\n", r"fidelty.*did you mean 'fidelity'"),
    "unknown-top-level": (_set("extra_section", {"a": 1}), r"extra_section: unknown key"),
    "unknown-scene-key": (_set("scene.defect.depthx", 1), r"scene\.defect\.depthx"),
    "fidelity-unknown-preset": (_set("fidelity", "ultra"), r"fidelity"),
    "fidelity-unknown-field": (_set("fidelity", {"preset": "draft", "grid": 3}), r"fidelity.*grid"),
    # item 4 and 7: YAML errors with line numbers, duplicate keys
    "yaml-syntax-error": ("scene:\n  operation: {fs_hz: 65000\n  load: {mode: bearing}\n",
                          r"line \d+, column \d+: YAML syntax error"),
    "yaml-duplicate-key": ("fidelity: draft\nscene:\n  defect: {edge_radius_um: 20.0}\n"
                           "  defect: {edge_radius_um: 5.0}\n", r"line 4: duplicate key 'defect'"),
    "yaml-tab-indent": ("scene:\n\toperation: {}\n", r"line 2, column 1: YAML syntax error"),
    "yaml-not-a-mapping": ("- 1\n- 2\n", r"must be a mapping"),
    # schema and cross-field checks (must stay one line, never the schema)
    "negative-depth": (_set("sweep.depths_um", [0, -5]), r"sweep\.depths_um\[1\]"),
    "load-as-string": (_set("sweep.loads_kN", ["250"]), r"sweep\.loads_kN\[0\]"),
    "band-above-nyquist": (_band(name="too_high", strategy="fixed", low_hz=30000.0, high_hz=40000.0),
                           r"analysis\.bands\[too_high\].*Nyquist"),
    "band-names-repeat": (_band(name="fixed", strategy="fixed", low_hz=100.0, high_hz=200.0),
                          r"analysis\.bands\[\d\]\.name"),
    "band-bad-name": (_band(name="a b", strategy="kurtogram"), r"analysis\.bands\[\d\]\.name"),
    "harmonics-too-many": (_set("analysis.harmonics", 200), r"analysis\.harmonics"),
    "zero-rollers": (_set("scene.bearing.rollers_per_row", 0), r"scene\.bearing\.rollers_per_row"),
    "cage-slip-too-large": (_set("scene.operation.cage_slip_percent", 60),
                            r"scene\.operation\.cage_slip_percent"),
    "fs-below-band": (_set("scene.operation.fs_hz", 5000.0), r"scene\.operation\.fs_hz"),
    "defect-too-long": (_set("scene.defect.length_um", 40000.0), r"scene\.defect\.length_um"),
    # issue 12 part 4: widths
    "width-zero": (_set("sweep.widths_um", [0]), r"sweep\.widths_um\[0\]"),
    "width-negative": (_set("sweep.widths_um", [60, -1]), r"sweep\.widths_um\[1\]"),
    "width-wider-than-contact": (_set("sweep.widths_um", [60, 1500]), r"sweep\.widths_um\[1\].*contact"),
    "width-twice": (_all(_set("sweep.widths_um", [60]), _set("scene.defect.width_um", 60)),
                    r"sweep\.widths_um"),
    "scene-width-zero": (_set("scene.defect.width_um", 0), r"scene\.defect\.width_um"),
    "scene-width-negative": (_set("scene.defect.width_um", -30), r"scene\.defect\.width_um"),
    "scene-width-wider-than-contact": (_set("scene.defect.width_um", 1500),
                                       r"scene\.defect\.width_um.*contact"),
    # issue 12 parts 1 and 2: acquisition and signal names
    "oversample-zero": (_set("scene.operation.acquisition", {"oversample": 0}),
                        r"scene\.operation\.acquisition\.oversample"),
    "oversample-negative": (_set("scene.operation.acquisition", {"mode": "antialiased",
                                                                 "oversample": -4}),
                            r"scene\.operation\.acquisition\.oversample"),
    "oversample-non-integer": (_set("scene.operation.acquisition", {"oversample": 2.5}),
                               r"scene\.operation\.acquisition\.oversample"),
    "oversample-unknown-word": (_set("scene.operation.acquisition", {"oversample": "fast"}),
                                r"scene\.operation\.acquisition\.oversample"),
    "acquisition-unknown-mode": (_set("scene.operation.acquisition", {"mode": "sinc"}),
                                 r"scene\.operation\.acquisition\.mode"),
    "signal-unknown": (_set("analysis.signal", "pmax"), r"analysis\.signal"),
    "signal-not-a-string": (_set("analysis.signal", 3), r"analysis\.signal"),
}


def _write(tmp_path: Path, spec) -> Path:
    p = tmp_path / "bad.yaml"
    if isinstance(spec, str):
        p.write_text(spec)
    else:
        cfg = copy.deepcopy(DRAFT)
        spec(cfg)
        p.write_text(yaml.safe_dump(cfg, sort_keys=False))
    return p


def _one_line(msg: str, pattern: str) -> None:
    import re

    lines = [ln for ln in msg.strip().splitlines() if ln.strip()]
    assert len(lines) == 1, msg
    # short, not a schema dump; the file names it starts with depend on where the test runs
    assert len(re.sub(r"\S*/\S*", "", lines[0])) < 500, msg
    assert re.search(pattern, lines[0]), msg
    assert "$schema" not in msg and "additionalProperties" not in msg, msg


@pytest.fixture
def no_solver(monkeypatch):
    """Make any contact solve fail the test: rejection must come before expensive work."""
    import bearing_envelope.contact as contact
    import bearing_envelope.physics.history as history
    import bearing_envelope.physics.solves.stats as solves

    def boom(*a, **k):  # pragma: no cover - reached only by a bug
        raise AssertionError("a contact solve ran for a config that should have been rejected")

    monkeypatch.setattr(contact, "solve_contact", boom)
    monkeypatch.setattr(solves, "solve_contact", boom)
    monkeypatch.setattr(history, "simulate", boom)


@pytest.mark.parametrize("key", sorted(BAD_CONFIGS))
def test_workflow_precheck_rejects(tmp_path, monkeypatch, key):
    spec, pattern = BAD_CONFIGS[key]
    path = _write(tmp_path, spec)
    monkeypatch.chdir(tmp_path)   # a run directory without a config.yaml under the file
    with pytest.raises(ConfigError) as info:
        workflow_settings([path])   # what common.smk calls with the --configfile files
    _one_line(str(info.value), pattern)
    assert str(path) in str(info.value)


@pytest.mark.parametrize("key", sorted(BAD_CONFIGS))
def test_cli_rejects_before_any_solve(tmp_path, capsys, no_solver, key):
    from bearing_envelope.cli import main

    spec, pattern = BAD_CONFIGS[key]
    path = _write(tmp_path, spec)
    out = tmp_path / "case.h5"
    for argv in (["simulate", "--config", str(path), "--load-kn", "250", "--depth-um", "50", "-q",
                  "-o", str(out)],
                 ["check-config", str(path)]):
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        _one_line(err, pattern)
        assert err.startswith(f"bearing-envelope {argv[0]}: error:")
    assert not out.exists()


def test_valid_draft_config_passes_both_entry_points(tmp_path, monkeypatch, capsys):
    from bearing_envelope.cli import main

    path = _write(tmp_path, lambda c: None)
    monkeypatch.chdir(tmp_path)
    st = workflow_settings([path])
    assert [c.name for c in st.cases] == ["F250kN_h0um", "F250kN_h50um", "F750kN_h0um", "F750kN_h50um"]
    assert main(["check-config", str(path)]) == 0
    assert "4 cases" in capsys.readouterr().out


# ------------------------------------------------------------------------------ simulate CLI
SIM_ARGS = {
    "output-is-directory": (["-o", "{tmp}"], r"-o/--output: .* is a directory"),
    "config-is-directory": (["--config", "{tmp}", "-o", "{tmp}/x.h5"], r"is a directory"),
    "config-missing": (["--config", "{tmp}/none.yaml", "-o", "{tmp}/x.h5"], r"config file not found"),
    "negative-depth": (["--depth-um", "-3", "-o", "{tmp}/x.h5"], r"depth_um"),
    "nan-load": (["--load-kn", "nan", "-o", "{tmp}/x.h5"], r"load_kN"),
    "zero-width": (["--width-um", "0", "-o", "{tmp}/x.h5"], r"width_um"),
    "unknown-fidelity": (["--fidelity", "ultra", "-o", "{tmp}/x.h5"], r"fidelity"),
}


@pytest.mark.parametrize("key", sorted(SIM_ARGS))
def test_simulate_arguments(tmp_path, capsys, no_solver, monkeypatch, key):
    from bearing_envelope.cli import main

    monkeypatch.chdir(tmp_path)  # no ./config.yaml here
    extra, pattern = SIM_ARGS[key]
    extra = [a.replace("{tmp}", str(tmp_path)) for a in extra]
    base = {"--load-kn": "250", "--depth-um": "50"}
    for k in ("--load-kn", "--depth-um"):
        if k in extra:
            base.pop(k)
    argv = ["simulate", "-q", *[x for kv in base.items() for x in kv], *extra]
    assert main(argv) == 2
    _one_line(capsys.readouterr().err, pattern)


def test_simulate_reads_config_yaml_of_the_working_directory(tmp_path, capsys, monkeypatch):
    """Without --config, ./config.yaml is read (and validated), and simulate says so."""
    from bearing_envelope.cli import main

    monkeypatch.chdir(tmp_path)
    (tmp_path / "config.yaml").write_text("fidelty: draft\n")
    assert main(["simulate", "--load-kn", "250", "--depth-um", "0", "-o", "x.h5"]) == 2
    assert "config.yaml: fidelty: unknown key" in capsys.readouterr().err
    (tmp_path / "config.yaml").write_text("fidelity: draft\nscene:\n  operation: {revolutions: 0.2}\n")
    assert main(["simulate", "--load-kn", "250", "--depth-um", "0", "-o", "x.h5"]) == 0
    err = capsys.readouterr().err
    assert "simulate: config config.yaml" in err
    from bearing_envelope.io import read_case

    c = read_case(tmp_path / "x.h5")
    assert c.attrs["fidelity"]["name"] == "draft" and c.attrs["case"] == "F250kN_h0um"


# ------------------------------------------------------------------------------- analyze CLI
ANALYZE_ARGS = {
    "3-d-array": ("x3.npy", [], r"file: .*3-D array"),
    "column-on-1-d": ("x1.npy", ["--column", "1"], r"--column: .*1-D array"),
    "column-out-of-range-npy": ("x2.npy", ["--column", "5"], r"--column: index 5 is out of range"),
    "column-out-of-range-csv": ("x.csv", ["--column", "3"], r"--column: index 3 is out of range"),
    "column-unknown-csv": ("x.csv", ["--column", "nope"], r"no column 'nope'"),
    "nlevel-0": ("x1.npy", ["--nlevel", "0"], r"--nlevel: got 0"),
    "nlevel-30": ("x1.npy", ["--nlevel", "30"], r"--nlevel: got 30; allowed: 1 \.\. 7"),
    "max-level-above-nlevel": ("x1.npy", ["--nlevel", "4", "--max-level", "5"], r"--max-level"),
    "csv-is-directory": ("x1.npy", ["--csv", "{tmp}"], r"--csv: .* is a directory"),
    "plot-is-file": ("x1.npy", ["--plot", "{tmp}/x1.npy"], r"--plot: .* is a file"),
    # a folder is a batch of records (issue 24 part 5); an empty one is refused
    "file-is-empty-directory": ("{tmp}/emptydir", [], r"file: .* is an empty directory"),
    "file-missing": ("none.npy", [], r"no such file"),
    "fs-nan": ("x1.npy", ["--fs", "nan"], r"--fs"),
    "fs-negative": ("x1.npy", ["--fs", "-1"], r"--fs"),
    "harmonics-0": ("x1.npy", ["--harmonics", "0"], r"--harmonics"),
    "npz-2-d-variable": ("x.npz", [], r"shape \(2, 20000\)"),
    # issue 14: records no spectrum can be read from, frequencies no spectrum can hold
    "empty-record": ("empty.npy", [], r"^bearing-envelope analyze: error: file: .* empty signal"),
    "constant-record": ("const.npy", [], r"file: .* constant signal"),
    "nan-record": ("nan.npy", [], r"file: .* 1 non-finite value"),
    "2-d-without-column": ("x2.npy", [], r"--column: .* 2-D array of shape \(20000, 2\)"),
    "fs-zero": ("x1.npy", ["--fs", "0"], r"--fs: fs must be a finite number > 0"),
    "fs-zero-in-file": ("fs0.npz", ["--fs", None], r"--fs: the file gives fs = 0"),
    "bpfi-above-nyquist": ("x1.npy", ["--bpfi", "700"],
                           r"--bpfi: 700 Hz is at or above the Nyquist"),
    "fault-above-nyquist": ("x1.npy", ["--fault", "bsf=600"],
                            r"--fault \(bsf = 600 Hz\): .* at or above the Nyquist "
                            r"frequency 500 Hz"),
    "geometry-above-nyquist": ("x1.npy", ["--fr", "200", "--n-rollers", "9",
                                          "--roller-diameter-in", "0.3126",
                                          "--pitch-diameter-in", "1.537"],
                               r"bearing geometry \(--n-rollers, --roller-diameter-mm/-in, "
                               r"--pitch-diameter-mm/-in\) \(bpfo = 716\.9.* at or above "
                               r"the Nyquist"),
    "fault-below-resolution": ("x1.npy", ["--fault", "ftf=0.2"],
                               r"--fault \(ftf = 0.2 Hz\): .* below the resolution .* 0\.05 Hz"),
    "fr-above-nyquist": ("x1.npy", ["--fr", "600"], r"--fr: 600 Hz is at or above the Nyquist"),
    "fault-syntax": ("x1.npy", ["--fault", "bpfo"], r"--fault: expected NAME=HZ"),
    "fault-negative": ("x1.npy", ["--fault", "bpfo=-3"], r"--fault bpfo: got -3"),
    "search-percent-0": ("x1.npy", ["--search-percent", "0"], r"--search-percent: got 0"),
    "pfa-1": ("x1.npy", ["--pfa", "1"], r"--pfa: got 1"),
    "mm-and-inch": ("x1.npy", ["--roller-diameter-mm", "7.94", "--roller-diameter-in", "0.31"],
                    r"--roller-diameter-in: give the roller diameter once"),
    "geometry-incomplete-inch": ("x1.npy", ["--n-rollers", "9", "--roller-diameter-in", "0.3"],
                                 r"bearing geometry: give --n-rollers"),
    "fixed-band-above-nyquist": ("x1.npy", ["--fixed-band", "100", "600"],
                                 r"--fixed-band: HIGH_HZ 600 is above .* add --clamp"),
}


@pytest.fixture
def signals(tmp_path):
    import pandas as pd

    x = np.random.default_rng(0).standard_normal(20000)
    np.save(tmp_path / "x1.npy", x)
    np.save(tmp_path / "x2.npy", np.c_[x, x])
    np.save(tmp_path / "x3.npy", x.reshape(10, 20, 100))
    np.savez(tmp_path / "x.npz", accel=np.vstack([x, x]))
    pd.DataFrame({"a": x[:4000], "b": x[:4000]}).to_csv(tmp_path / "x.csv", index=False)
    np.save(tmp_path / "empty.npy", np.zeros(0))
    np.save(tmp_path / "const.npy", np.full(20000, 0.25))
    xn = x.copy()
    xn[1234] = np.nan
    np.save(tmp_path / "nan.npy", xn)
    np.savez(tmp_path / "fs0.npz", accel=x, fs=0.0)
    (tmp_path / "emptydir").mkdir()
    return tmp_path


@pytest.mark.parametrize("key", sorted(ANALYZE_ARGS))
def test_analyze_arguments(signals, capsys, monkeypatch, key):
    from bearing_envelope.cli import main

    monkeypatch.chdir(signals)
    f, extra, pattern = ANALYZE_ARGS[key]
    tmp = str(signals)
    extra = [a.replace("{tmp}", tmp) if a is not None else a for a in extra]
    fs_args = [] if "--fs" in extra else ["--fs", "1000"]
    if "--fs" in extra and extra[extra.index("--fs") + 1] is None:  # fs only from the file
        i = extra.index("--fs")
        extra = extra[:i] + extra[i + 2:]
    argv = ["analyze", f.replace("{tmp}", tmp), "--fr", "10", "--bpfi", "55", *fs_args, *extra]
    assert main(argv) == 2
    _one_line(capsys.readouterr().err, pattern)


def test_analyze_default_nlevel_follows_a_short_signal(signals, capsys, monkeypatch):
    """Without --nlevel a short signal is analysed at the deepest level it allows (not an error)."""
    from bearing_envelope.cli import main

    monkeypatch.chdir(signals)
    assert main(["analyze", "x1.npy", "--fs", "1000", "--fr", "10", "--bpfi", "55",
                 "--bands", '[{"name": "kurtogram", "strategy": "kurtogram"}]']) == 0
    assert "kurtogram: level" in capsys.readouterr().out


@pytest.mark.parametrize("field,option", [("n_harmonics", "--harmonics"),
                                          ("n_sidebands", "--sidebands"),
                                          ("n_raw_harmonics", "--raw-harmonics"),
                                          ("nlevel", "--nlevel"),
                                          ("filter_order", "--filter-order")])
def test_analyze_option_ranges_are_analysis_options_own(signals, capsys, monkeypatch, field,
                                                        option):
    """The command holds no range of an analysis option: one past AnalysisOptions' bound is
    refused in one line naming the option and the library's range, before any file is read;
    the library names its own field."""
    from bearing_envelope.cli import main
    from bearing_envelope.diagnosis import AnalysisOptions
    from bearing_envelope.diagnosis.options import OPTION_SPECS

    lo, hi = OPTION_SPECS[field].low, OPTION_SPECS[field].high
    monkeypatch.chdir(signals)
    for bad in (lo - 1, hi + 1):
        assert main(["analyze", "none.npy", "--fs", "1000", "--fr", "10", "--bpfi", "55",
                     option, str(bad)]) == 2
        _one_line(capsys.readouterr().err,
                  rf"{option}: got {bad}; allowed: an integer {lo} \.\. {hi}( or None)?$")
        with pytest.raises(ValueError, match=rf"^AnalysisOptions\.{field} = {bad}: allowed "):
            AnalysisOptions(**{field: bad})
