"""The pre-run check at the load zone's edge and on refined grids (issue 43 leftovers).

Independent answers: the zero-clearance zone ends at 90 deg exactly (Harris: ``cos psi_l =
P_d / (2 delta_r)``), so a pit at 3:00 never meets a loaded contact; the +10 um zone of the
CWRU 6205 at 1 kN ends at 75.36 deg, where the element load (2.8e-4 N) is a contact narrower
than draft's finest grid; the measured CPU time of a refined case bounds its estimate from
below; the solver's iteration counts on long global cells (docs/validation.md).
"""

from __future__ import annotations

import time

import pytest

from bearing_envelope.cli import main
from bearing_envelope.physics.history import check_resolved, simulate
from bearing_envelope.physics.scene import Scene
from bearing_envelope.study.config_read import ConfigError
from bearing_envelope.study.limits import (MAX_GLOBAL_CELL_ASPECT, checked_settings,
                                           estimate_case)

from test_validate_once import ROOT, _write

CASE = "F1kN_h279.4um_or"


def _overlay(position_deg, clearance_um, fidelity="draft", centrifugal=False, detection_map=True):
    return (f"fidelity: {fidelity}\n"
            f"diagnosability: {{enabled: {str(detection_map).lower()}}}\n"
            f"scene:\n"
            f"  bearing: {{designation: SKF 6205-2RS, radial_clearance_um: {clearance_um}}}\n"
            f"  operation: {{shaft_rate_hz: 29.95, fs_hz: 48000.0, revolutions: 10, "
            f"bpfi_override_hz: null}}\n"
            f"  load: {{centrifugal: {str(centrifugal).lower()}}}\n"
            f"  defect: {{location: outer_race, position_deg: {position_deg}, width_um: 177.8, "
            f"shape: cylinder}}\n"
            f"sweep: {{loads_kN: [1], depths_um: [279.4]}}\n")


def _scene(position_deg, clearance_um, centrifugal=False, revolutions=10):
    m = {"bearing": {"designation": "SKF 6205-2RS", "radial_clearance_um": clearance_um},
         "operation": {"shaft_rate_hz": 29.95, "fs_hz": 48000.0, "revolutions": revolutions,
                       "bpfi_override_hz": None},
         "load": {"centrifugal": centrifugal},
         "defect": {"shape": "cylinder", "width_um": 177.8, "location": "outer_race",
                    "position_deg": position_deg}}
    return Scene.from_mapping(m, load_kN=1.0, depth_um=279.4)


def test_check_config_reports_a_never_loaded_case_as_simulate_does(tmp_path, monkeypatch,
                                                                  capsys):
    monkeypatch.chdir(ROOT)
    path = _write(tmp_path, "p.yaml", _overlay(90, 0.0, detection_map=False))
    assert main(["check-config", str(path)]) == 0          # reported, not refused: as simulate
    err = capsys.readouterr().err.strip().splitlines()
    h = simulate(_scene(90, 0.0), "draft")
    assert h.stats["n_solves"] == 0                        # the zone ends at 90 deg exactly
    note = h.stats["exposure_note"]
    assert "never meets a loaded contact" in note
    assert err == [f"check-config: warning: case {CASE}: {note}"]
    _st, (est,) = checked_settings([path])
    assert est.note == note and est.n_solves == 0          # nothing solved, nothing estimated


def test_a_never_loaded_case_is_refused_when_the_run_builds_the_detection_map(tmp_path,
                                                                            monkeypatch):
    """The map's SNR is that of the defect's part of the record: none (its diagnose job met a
    constant record: "x is constant: its kurtogram is undefined")."""
    monkeypatch.chdir(ROOT)
    with pytest.raises(ConfigError) as err:
        checked_settings([_write(tmp_path, "p.yaml", _overlay(90, 0.0))])
    msg = str(err.value)
    assert msg.startswith(f"scene.defect.position_deg: case {CASE}: outer_race at 90 deg: the "
                          f"defect never meets a loaded contact")
    assert "diagnosability.enabled: false" in msg and "\n" not in msg
    checked_settings([_write(tmp_path, "q.yaml", _overlay(89, 0.0))])   # inside the zone


def test_an_unresolvable_contact_is_refused_before_any_job_with_simulates_line(tmp_path,
                                                                              monkeypatch):
    monkeypatch.chdir(ROOT)
    with pytest.raises(ValueError) as sim:
        check_resolved(_scene(75.36, 10.0), "draft")       # simulate's refusal (2.8e-4 N)
    with pytest.raises(ConfigError) as err:
        checked_settings([_write(tmp_path, "p.yaml", _overlay(75.36, 10.0))])
    msg = str(err.value)
    assert msg == f"scene.defect.position_deg: case {CASE}: {sim.value}"
    assert "\n" not in msg and "0.000276 N" in msg


def test_a_global_grid_the_solver_cannot_converge_on_is_refused(tmp_path, monkeypatch):
    """``global_dx_um: 0.1`` on draft's 400 um axial cells (4000:1) failed inside its job at
    max_iter; 1.5625 (256:1) ran (measured; docs/validation.md)."""
    monkeypatch.chdir(ROOT)
    draft = ROOT / "tests" / "data" / "config_draft.yaml"
    with pytest.raises(ConfigError) as err:
        checked_settings([draft, _write(tmp_path, "g.yaml",
                                        "fidelity: {preset: draft, global_dx_um: 0.1}\n")])
    msg = str(err.value)
    assert msg.startswith("fidelity.global_dx_um: got 0.1 um") and "\n" not in msg
    assert ">= 1.562 um" in msg and "4000:1" in msg
    assert MAX_GLOBAL_CELL_ASPECT == 400 / 1.5625
    checked_settings([draft, _write(tmp_path, "ok.yaml",
                                    "fidelity: {preset: draft, global_dx_um: 1.5625}\n")])
    with pytest.raises(ConfigError, match=r"^fidelity.global_dy_um: got 0.05 um"):
        checked_settings([draft, _write(tmp_path, "dy.yaml",
                                        "fidelity: {preset: draft, global_dy_um: 0.05}\n")])


def test_the_estimate_covers_a_light_contacts_refined_table():
    """The CWRU outer-race pit at 3:00 with the centrifugal force alone: a 0.224 N contact,
    solved on standard's grids halved once; its measured CPU time (11.9 s, 2026-12-05) was
    above the estimate that ignored the refinement (7.8 s)."""
    sc = _scene(90, 10.0, centrifugal=True, revolutions=1)
    est = estimate_case(CASE, sc, _standard())
    t0 = time.process_time()
    h = simulate(sc, "standard")
    cpu = time.process_time() - t0
    assert h.table.info["grid_halvings"] == 1
    assert cpu <= est.cpu_seconds <= 20 * cpu + 10
    assert h.stats["n_solves"] / 2 <= est.n_solves <= 2 * h.stats["n_solves"]


def _standard():
    from bearing_envelope.physics.fidelity import fidelity_from

    return fidelity_from("standard")
