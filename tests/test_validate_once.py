"""Validated once, everywhere (issue 44 part 5, issue 43's stress test).

- A job (a cluster job parses the workflow again) takes the main process's settings
  (study.handoff): no loader, no pre-run check; a call counter on the loader in the job's
  process is the independent witness.
- A YTE-templated overlay: Snakemake evaluates it before any workflow code (its behaviour); the
  refusal says so in one line, and ``check-config`` refuses it without evaluating it.
- The pre-run cost estimate covers every expensive axis and names the field.
- ``paper_run`` that is not a finished run, and an empty config file: one answer everywhere.
- A per-case table edited in place (mtime kept) is found before the DAG and rebuilt.
"""

from __future__ import annotations

import os
import pickle
import re
import subprocess
import sys
from pathlib import Path

import pytest

from bearing_envelope.cli import main
from bearing_envelope.io.integrity import seal_text, sealed_text_problem
from bearing_envelope.study.handoff import ENV_VAR, HandOffError, hand_off, take_over
from bearing_envelope.study.limits import (DEFAULT_LIMITS, checked_settings, estimate_jobs,
                                           paper_run_tables)
from bearing_envelope.study.recovery import Artefact, recover_artefacts
from bearing_envelope.study.config_read import ConfigError, config_files
from bearing_envelope.study.settings import workflow_settings

ROOT = Path(__file__).resolve().parents[1]
DRAFT = ROOT / "tests" / "data" / "config_draft.yaml"
ONE_LOAD = "sweep: {loads_kN: [250], depths_um: [0, 50]}\n"

#: A call counter loaded at interpreter start (``sitecustomize``): each call of a counted
#: function appends "<pid> <name>" to $BE_COUNT_LOG. Written by the test, not the package.
COUNTER = '''
import importlib.abc, importlib.machinery, os, sys
LOG, TARGETS = os.environ["BE_COUNT_LOG"], {}
for item in os.environ["BE_COUNT_TARGETS"].split(","):
    mod, func = item.split(":")
    TARGETS.setdefault(mod, []).append(func)

class Finder(importlib.abc.MetaPathFinder):
    def find_spec(self, fullname, path, target=None):
        if fullname not in TARGETS:
            return None
        spec = importlib.machinery.PathFinder.find_spec(fullname, path)
        run = spec.loader.exec_module
        def exec_module(module):
            run(module)
            for name in TARGETS[fullname]:
                f = getattr(module, name)
                def counted(*a, _f=f, _n=name, **k):
                    with open(LOG, "a") as fh:
                        fh.write(f"{os.getpid()} {_n}\\n")
                    return _f(*a, **k)
                setattr(module, name, counted)
        spec.loader.exec_module = exec_module
        return spec

sys.meta_path.insert(0, Finder())
'''

LOADER = "bearing_envelope.study.settings:workflow_settings"
CHECK = "bearing_envelope.study.limits:precheck"
TAKE = "bearing_envelope.study.handoff:take_over"


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


def _counted_env(tmp_path) -> tuple[dict, Path]:
    site = tmp_path / "counter"
    site.mkdir(exist_ok=True)
    (site / "sitecustomize.py").write_text(COUNTER)
    log = tmp_path / "count.log"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(site), str(ROOT / "src")]),
               BE_COUNT_LOG=str(log), BE_COUNT_TARGETS=",".join([LOADER, CHECK, TAKE]))
    env.pop(ENV_VAR, None)
    return env, log


def _calls(log: Path) -> dict:
    out: dict = {}
    for line in log.read_text().splitlines() if log.exists() else []:
        out[line.split()[1]] = out.get(line.split()[1], 0) + 1
    return out


# ------------------------------------------------------------------------ hand-off to jobs


def test_a_job_takes_the_settings_its_main_process_checked(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    files = [DRAFT, _write(tmp_path, "one.yaml", ONE_LOAD)]
    st = workflow_settings(files)
    address = hand_off(st, tmp_path / "state", files)
    got = take_over(address, files)
    assert got.cases == st.cases and got.config == st.config
    assert all(got.scene(c) == st.scene(c) for c in st.cases)


def test_a_hand_off_is_refused_when_its_bytes_or_the_config_changed(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    one = _write(tmp_path, "one.yaml", ONE_LOAD)
    st = workflow_settings([DRAFT, one])
    address = hand_off(st, tmp_path / "state", [DRAFT, one])
    one.write_text(ONE_LOAD.replace("250", "251"))            # the job's config differs
    with pytest.raises(HandOffError, match="differ from the ones its main process validated"):
        take_over(address, [DRAFT, one])
    one.write_text(ONE_LOAD)
    pickled = next((tmp_path / "state").glob("settings-*.pickle"))
    pickled.write_bytes(pickle.dumps({"not": "the settings"}))   # replaced: never unpickled
    with pytest.raises(HandOffError, match="not the ones the main process wrote"):
        take_over(address, [DRAFT, one])
    with pytest.raises(HandOffError, match="not a settings hand-off"):
        take_over("results/whatever", [DRAFT, one])


def _job(tmp_path, env, *, dry=True) -> subprocess.CompletedProcess:
    """One job as a cluster executor starts it: a fresh Snakemake in remote mode."""
    cmd = [sys.executable, "-m", "snakemake", "--snakefile", str(ROOT / "Snakefile"),
           "--target-jobs", "simulate:case=F250kN_h0um", "--allowed-rules", "simulate",
           "--cores", "1", "--mode", "remote", "--force", *(["-n"] if dry else []),
           "--configfiles", str(DRAFT), str(tmp_path / "one.yaml")]
    return subprocess.run(cmd, env=env, capture_output=True, text=True, cwd=tmp_path)


def test_a_cluster_job_runs_neither_the_loader_nor_the_pre_run_check(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    files = [DRAFT, _write(tmp_path, "one.yaml", ONE_LOAD)]
    env, log = _counted_env(tmp_path)
    env[ENV_VAR] = hand_off(workflow_settings(files), tmp_path / ".snakemake" / "be",
                            config_files(files))
    out = _job(tmp_path, env)
    assert out.returncode == 0, out.stderr[-2000:]
    assert _calls(log) == {"take_over": 1}
    # without the hand-off (an executor that passes no environment) the job validates again
    log.unlink()
    del env[ENV_VAR]
    out = _job(tmp_path, env)
    assert out.returncode == 0, out.stderr[-2000:]
    assert _calls(log) == {"workflow_settings": 1}


def test_the_main_process_checks_once_and_hands_off(tmp_path):
    _write(tmp_path, "one.yaml", ONE_LOAD)
    env, log = _counted_env(tmp_path)
    cmd = [sys.executable, "-m", "snakemake", "--snakefile", str(ROOT / "Snakefile"),
           "--cores", "1", "--configfile", str(DRAFT), str(tmp_path / "one.yaml"),
           "--touch", "results/cases/F250kN_h0um.h5"]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, cwd=tmp_path)
    assert _calls(log) == {"workflow_settings": 1, "precheck": 1}, out.stderr[-2000:]


# ------------------------------------------------------------------------ YTE templates


def test_a_yte_overlay_is_refused_in_one_line_saying_snakemake_evaluated_it(tmp_path):
    witness = tmp_path / "witness"
    yte = _write(tmp_path, "yte.yaml", f"__use_yte__: true\nfidelity: ?open({str(witness)!r}, "
                                        f"'w').write('x') and 'draft'\n")
    env, log = _counted_env(tmp_path)
    cmd = [sys.executable, "-m", "snakemake", "--snakefile", str(ROOT / "Snakefile"), "-n",
           "--cores", "1", "--configfile", str(DRAFT), str(yte)]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode == 1 and not (tmp_path / "results").exists()
    line = [ln for ln in out.stderr.splitlines() if "invalid configuration" in ln]
    assert len(line) == 1 and "__use_yte__" in line[0]
    assert "Snakemake has already evaluated this file as a YTE template" in line[0]
    # Snakemake's behaviour, measured: its code ran before the workflow's first line
    assert witness.exists()
    assert _calls(log) == {"workflow_settings": 1}          # the loader ran once and refused


def test_check_config_refuses_a_yte_overlay_without_evaluating_it(tmp_path, monkeypatch, capsys):
    witness = tmp_path / "witness"
    yte = _write(tmp_path, "yte.yaml", f"__use_yte__: true\nfidelity: ?open({str(witness)!r}, "
                                        f"'w').write('x') and 'draft'\n")
    monkeypatch.chdir(ROOT)
    assert main(["check-config", str(yte)]) == 2
    assert "__use_yte__" in capsys.readouterr().err and not witness.exists()


# ------------------------------------------------------------------------ the cost estimate


@pytest.fixture(scope="module")
def base():
    """The default sweep (config.yaml: standard fidelity, 100 revolutions, the sensor)."""
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        return workflow_settings([])
    finally:
        os.chdir(cwd)


def _jobs(settings, **changes):
    case = settings.cases[0]          # F250kN_h0um: healthy, so it has a false_alarms job
    diag = settings.diagnosability
    diag = type(diag)(**{**diag.__dict__, **changes})
    return {j.rule: j for j in estimate_jobs(case.name, settings.scene(case), settings.analysis,
                                             settings.sensor, diag, healthy=True)}


def test_the_false_alarm_estimate_grows_with_trials_and_snr_levels(base):
    """Trials x SNR levels records: the cost beyond the job's start is proportional to both
    (checked on two values of each, not on the formula)."""
    t10, t20 = _jobs(base, false_alarm_trials=10), _jobs(base, false_alarm_trials=20)
    start = _jobs(base, false_alarm_trials=0)["false_alarms"].cpu_seconds
    assert t20["false_alarms"].cpu_seconds - start == pytest.approx(
        2 * (t10["false_alarms"].cpu_seconds - start))
    s5 = _jobs(base, snr_db=(0.0,) * 5)["diagnose"].cpu_seconds
    s10 = _jobs(base, snr_db=(0.0,) * 10)["diagnose"].cpu_seconds
    s0 = _jobs(base, snr_db=())["diagnose"].cpu_seconds
    assert s10 - s0 == pytest.approx(2 * (s5 - s0))


@pytest.mark.parametrize("overlay, field", [
    ("diagnosability: {false_alarm_trials: 1000000}\n", "diagnosability.false_alarm_trials"),
    ("diagnosability: {false_alarm_trials: 1000000000}\n", "diagnosability.false_alarm_trials"),
    ("fidelity: {preset: draft, global_dx_um: 1, global_dy_um: 16}\n", "fidelity.global_dx_um"),
    ("diagnosability: {snr_db: [%s]}\n" % ", ".join(["10"] * 10000), "diagnosability.snr_db"),
    ("analysis: {bands: [%s]}\n" % ", ".join(
        f"{{name: b{i}, strategy: fixed, low_hz: {1000 + i}, high_hz: {2000 + i}}}"
        for i in range(1000)), "analysis.bands"),
], ids=["trials-1e6", "trials-1e9", "global-dx-1-dy-16", "10000-snr-levels", "1000-bands"])
def test_a_resource_bomb_is_refused_in_one_line_naming_its_field(tmp_path, monkeypatch, overlay,
                                                                 field):
    monkeypatch.chdir(ROOT)
    with pytest.raises(ConfigError) as err:
        checked_settings([_write(tmp_path, "bomb.yaml", overlay)])
    msg = str(err.value)
    assert msg.startswith(field) and "\n" not in msg and "limits.max_case_cpu_s" in msg
    assert f"<= {DEFAULT_LIMITS['max_case_cpu_s']:g} CPU s" in msg


def test_a_raised_limit_accepts_what_the_default_refuses(tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    bomb = "diagnosability: {false_alarm_trials: 1000}\n"
    with pytest.raises(ConfigError, match="false_alarm_trials"):
        checked_settings([_write(tmp_path, "a.yaml", bomb)])
    checked_settings([_write(tmp_path, "b.yaml", bomb + "limits: {max_case_cpu_s: 1000000}\n")])


@pytest.mark.parametrize("name", ["config.yaml", "config_paper.yaml", "config_cwru.yaml",
                                  "config_cwru_or.yaml", "config_cwru_ball.yaml",
                                  "config_cwru_locations.yaml", "tests/data/config_draft.yaml"])
def test_the_repository_configs_fit_the_default_limits(monkeypatch, name):
    monkeypatch.chdir(ROOT)
    checked_settings([] if name == "config.yaml" else [name])


# ------------------------------------------------------------------------ paper_run, empty files


def test_paper_run_must_be_a_finished_run(tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    for run, says in (("/nonexistent/run", "is not a folder"),
                      (str(tmp_path), "has no " + str(tmp_path / "results" / "tables"))):
        with pytest.raises(ConfigError) as err:
            checked_settings([_write(tmp_path, "p.yaml", f"paper_run: {run}\n"
                                                          f"sweep: {{loads_kN: [250], depths_um: [0]}}\n")])
        assert str(err.value).startswith("paper_run: ") and says in str(err.value)
    tables = tmp_path / "results" / "tables"
    tables.mkdir(parents=True)
    for n in ("cases", "harmonics", "bands"):
        (tables / f"{n}.csv").write_text("x\n")
    assert paper_run_tables(str(tmp_path)) == {n: str(tables / f"{n}.csv")
                                               for n in ("cases", "harmonics", "bands")}
    assert paper_run_tables(None) == {}


@pytest.mark.parametrize("text", ["", "# only a comment\n\n", "---\n", "~\n"])
def test_an_empty_config_file_gets_one_answer(tmp_path, monkeypatch, capsys, text):
    """check-config, the benchmark (its check is check-config's) and Snakemake all refuse it."""
    from benchmarks.hostile_configs import check

    empty = _write(tmp_path, "empty.yaml", text)
    monkeypatch.chdir(ROOT)
    assert main(["check-config", str(empty)]) == 2
    err = capsys.readouterr().err
    assert "holds no settings" in err and len(err.strip().splitlines()) == 1
    assert check(str(empty))["status"] == "refused"
    out = subprocess.run([sys.executable, "-m", "snakemake", "--snakefile",
                          str(ROOT / "Snakefile"), "-n", "--cores", "1", "--configfile",
                          str(empty)], capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode != 0 and "Config file must be given as JSON or YAML" in out.stdout + out.stderr


def test_an_empty_mapping_is_a_valid_overlay(tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    st, _ = checked_settings([_write(tmp_path, "e.yaml", "{}\n")])
    assert len(st.cases) == 27


# ------------------------------------------------------------------------ sealed tables


def test_an_edit_that_keeps_the_mtime_is_found_and_rebuilt(tmp_path):
    table = tmp_path / "t.csv"
    table.write_text(seal_text("a,b\n1,2.5\n"))
    assert sealed_text_problem(table) is None
    st = table.stat()
    table.write_text(table.read_text().replace("2.5", "2.6"))
    os.utime(table, ns=(st.st_atime_ns, st.st_mtime_ns))
    assert "edited after it was written" in sealed_text_problem(table)
    marker, consumer = tmp_path / "m" / "t", tmp_path / "sum.csv"
    consumer.write_text("x")
    art = Artefact(str(table), str(marker), (str(consumer),), "sealed table")
    said = []
    dry = recover_artefacts([art], dry_run=True, warn=said.append)
    assert dry.set_aside == [str(table)] and table.exists() and not marker.exists()
    assert len(said) == 1 and "a real run moves it aside" in said[0]
    recover_artefacts([art], dry_run=False, warn=said.append)
    assert not table.exists() and marker.exists() and "moved aside" in said[-1]
    assert len(list(tmp_path.glob("t.csv.unreadable-*"))) == 1


def _smk(wd, *args):
    cmd = [sys.executable, "-m", "snakemake", "results/tables/harmonics.csv", "--snakefile",
           str(ROOT / "Snakefile"), "--directory", str(wd), "--cores", "2", *args,
           "--configfile", str(DRAFT), str(wd / "one.yaml")]
    return subprocess.run(cmd, capture_output=True, text=True, cwd=wd)


def test_an_edited_per_case_table_is_rebuilt_before_aggregate_reads_it(tmp_path):
    """Issue 43: the edit (mtime kept) was found only by aggregate, as a 12-line traceback,
    after which Snakemake deleted results/tables/harmonics.csv. Now: one line before any job,
    the table rebuilt (envelope) and aggregated again, its content the original's."""
    _write(tmp_path, "one.yaml", "sweep: {loads_kN: [250], depths_um: [50]}\n")
    first = _smk(tmp_path)
    assert first.returncode == 0, first.stderr[-3000:]
    table = tmp_path / "results" / "harmonics" / "F250kN_h50um.csv"
    original = table.read_text()
    st = table.stat()
    lines = original.split("\n")
    lines[2] = lines[2].replace(",0.0,", ",0.5,", 1)
    assert lines[2] != original.split("\n")[2]
    table.write_text("\n".join(lines))
    os.utime(table, ns=(st.st_atime_ns, st.st_mtime_ns))
    dry = _smk(tmp_path, "-n")
    said = [ln for ln in (dry.stdout + dry.stderr).splitlines() if ln.startswith("warning:")]
    assert len(said) == 1 and "edited after it was written" in said[0] and table.exists()
    run = _smk(tmp_path)
    log = run.stdout + run.stderr
    assert run.returncode == 0 and "Traceback" not in log, log[-3000:]
    assert re.search(r"^envelope\s+1$", log, re.M) and re.search(r"^aggregate\s+1$", log, re.M)
    assert table.read_text() == original
    assert (tmp_path / "results" / "tables" / "harmonics.csv").is_file()
    assert len(list(table.parent.glob("F250kN_h50um.csv.unreadable-*"))) == 1


def test_a_job_meeting_a_damaged_input_ends_in_one_line(tmp_path):
    from bearing_envelope.io import ArtefactFormatError
    from bearing_envelope.study.provenance import log_to

    with pytest.raises(SystemExit) as end:
        with log_to(tmp_path / "job.log"):
            raise ArtefactFormatError("results/harmonics/x.csv: edited after it was written")
    assert str(end.value) == ("bearing_envelope: damaged input: results/harmonics/x.csv: edited "
                              "after it was written")
    assert "Traceback" in (tmp_path / "job.log").read_text()    # the log keeps the whole story
