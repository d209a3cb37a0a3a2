"""Config files merge one way everywhere (workflow, check-config): a designation is a complete
bearing, and a partial file is an overlay of config.yaml.

Independent truths: the CWRU drive-end bearing's published BPFI and BPFO multipliers (CWRU
Bearing Data Center: 5.4152 and 3.5848 x fr for the SKF 6205-2RS).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from bearing_envelope.cli import main
from bearing_envelope.physics.history import simulate
from bearing_envelope.study.case_id import CaseId
from bearing_envelope.study.config_read import merge_configs, read_configs
from bearing_envelope.study.settings import workflow_settings

ROOT = Path(__file__).resolve().parents[1]
CWRU_BPFI, CWRU_BPFO = 5.4152, 3.5848

#: The eight lines of issue 31: a user names their bearing and nothing else of it.
EIGHT_LINES = """\
sweep:
  loads_kN: [1, 2]
  depths_um: [0, 50]
scene:
  bearing: {designation: SKF 6205-2RS}
  defect: {location: outer_race}
"""


def test_merge_keeps_other_keys_and_replaces_lists():
    base = {"a": {"b": 1, "c": [1, 2]}, "d": 1}
    assert merge_configs(base, {"a": {"c": [3]}, "e": 2}) == {"a": {"b": 1, "c": [3]}, "d": 1,
                                                             "e": 2}
    assert base == {"a": {"b": 1, "c": [1, 2]}, "d": 1}   # not changed


def test_a_designation_replaces_the_base_bearing_and_its_override():
    base = {"scene": {"bearing": {"roller_diameter_mm": 17.45, "rows": 2},
                      "operation": {"bpfi_override_hz": 231.9, "fs_hz": 48000.0}}}
    out = merge_configs(base, {"scene": {"bearing": {"designation": "SKF 6205-2RS"}}})
    assert out["scene"] == {"bearing": {"designation": "SKF 6205-2RS"},
                            "operation": {"fs_hz": 48000.0}}


@pytest.mark.parametrize("run_dir", ["repo_root", "elsewhere"])
def test_designation_only_configfile_is_that_bearing_with_or_without_config_yaml(
        tmp_path, monkeypatch, run_dir):
    """Issue 34: ``--configfile`` giving only a designation, run from the repository root (over
    config.yaml) or in another directory, is the named bearing, not the study's keys under
    its label."""
    overlay = tmp_path / "designation.yaml"
    overlay.write_text("scene:\n  bearing:\n    designation: SKF 6205-2RS\n")
    wd = tmp_path / "run"
    wd.mkdir()
    if run_dir == "repo_root":
        shutil.copy(ROOT / "config.yaml", wd / "config.yaml")
    else:
        (wd / "other.yaml").write_text("sweep: {loads_kN: [250], depths_um: [0, 50]}\n")
    monkeypatch.chdir(wd)
    files = [overlay] if run_dir == "repo_root" else [wd / "other.yaml", overlay]
    st = workflow_settings(files)
    sc = st.scene(st.cases[-1])
    assert sc.bearing.designation == "SKF 6205-2RS" and sc.bearing.kind == "ball"
    assert sc.bearing.roller_diameter_mm == 7.94 and sc.bearing.rollers_per_row == 9
    ff = sc.frequencies()
    assert sc.bpfi_hz == pytest.approx(CWRU_BPFI * ff.fr, rel=2e-4)   # geometric: no override
    assert ff.bpfo == pytest.approx(CWRU_BPFO * ff.fr, rel=2e-4)


def test_the_eight_line_config_runs(tmp_path, monkeypatch, capsys):
    path = tmp_path / "mine.yaml"
    path.write_text(EIGHT_LINES)
    monkeypatch.chdir(tmp_path)
    assert main(["check-config", str(path)]) == 0
    assert "4 cases: F1kN_h0um_or, F1kN_h50um_or, F2kN_h0um_or, F2kN_h50um_or" in \
        capsys.readouterr().out
    st = workflow_settings([path])
    case = CaseId(1, 50, None, "outer_race")
    assert case in st.cases
    sc = st.scene(case)
    assert sc.bearing.designation == "SKF 6205-2RS" and sc.defect.location == "outer_race"
    # one case simulated (short record: the kinematics and the contact are the config's)
    short = case.scene({**st.scene_mapping, "operation": {"revolutions": 1.0}})
    hist = simulate(short, "draft")
    assert hist.signals["p_max"].size == short.n_samples
    assert float(hist.signals["p_max"].max()) > 0


def test_check_config_merges_a_partial_file_over_config_yaml(tmp_path, monkeypatch, capsys):
    """From the repository root a partial file is checked as the workflow runs it: over
    config.yaml (the CWRU overlay alone has no analysis: section, the merge has)."""
    monkeypatch.chdir(ROOT)
    assert main(["check-config", "config_cwru.yaml"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("config.yaml + config_cwru.yaml: valid") and "2 cases" in out
    merged = read_configs(["config.yaml", "config_cwru.yaml"])
    assert len(merged["analysis"]["bands"]) == 5 and merged["sweep"]["loads_kN"] == [1.0]
