"""The load zone's edge (issue 43): what is a load, what the pit meets, where a ball turns.

Independent answers: the zero-clearance zone ends at 90 deg exactly (Harris: ``cos psi_l =
P_d / (2 delta_r)``); the +10 um zone of the CWRU 6205 at 1 kN ends at 75.36 deg and the
config_rig scene loads a ball at 12:00 with Q_i = 7.0 N (the issue's independent numbers);
the rounding of ``delta_r cos(pi/2)`` is an epsilon of ``delta_r``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearing_envelope.physics import locations
from bearing_envelope.physics.exposure import exposure, exposure_line
from bearing_envelope.physics.history import check_resolved, simulate
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.locations import (ROLLING_ELEMENT, rolling_element_kinematics,
                                                spin_is_free)
from bearing_envelope.physics.scene import Scene


def cwru(position_deg, clearance_um, roller_load="smooth", location="outer_race", load_kN=1.0,
         centrifugal=False, **defect):
    m = {"bearing": {"designation": "SKF 6205-2RS", "radial_clearance_um": clearance_um},
         "operation": {"shaft_rate_hz": 29.95, "fs_hz": 48000.0, "revolutions": 1},
         "load": {"roller_load": roller_load, "centrifugal": centrifugal},
         "defect": {"shape": "cylinder", "width_um": 177.8, "location": location,
                    "position_deg": position_deg, **defect}}
    return Scene.from_mapping(m, load_kN=load_kN, depth_um=279.4)


def test_a_compression_within_rounding_is_not_a_load():
    ld = scene_load_distribution(cwru(90.0, 0.0))
    q90 = float(ld.load_at(math.pi / 2, "outer"))
    assert 0 < q90 < 1e-15                    # delta_r cos(pi/2) = 6e-17 delta_r: 2e-22 N
    assert not ld.loaded(q90)
    # the tolerance: the load of a compression of a few epsilons of delta_r
    d_eps = np.finfo(float).eps * ld.delta_r
    assert ld.stiffness * d_eps ** 1.5 < ld.rounding_load < ld.stiffness * (16 * d_eps) ** 1.5
    # a hundredth of a degree inside the zone is a load
    assert ld.loaded(ld.load_at(math.radians(89.99), "outer"))


def test_zero_clearance_at_3_00_is_never_loaded_and_solves_nothing(roller_load="smooth"):
    sc = cwru(90.0, 0.0, roller_load)
    exp = exposure(sc, scene_load_distribution(sc))
    assert not exp["loaded"]
    assert "outer_race at 90 deg: the defect never meets a loaded contact" in exposure_line(sc, exp)
    check_resolved(sc, "draft")                 # nothing to solve, nothing refused
    h = simulate(sc, "draft")
    assert h.stats["n_solves"] == 0
    assert not np.any(h.roller_load) and not np.any(h.signals["p_max"])
    assert not np.any(h.signals["contact_area"])
    # just inside the edge the pit is loaded
    inside = cwru(89.0, 0.0, roller_load)
    assert exposure(inside, scene_load_distribution(inside))["loaded"]


def test_zero_clearance_at_3_00_discrete_meets_only_the_element_over_the_pit():
    # the element whose contact holds the pit reaches 0.3 mm (a_H + w/2) before 3:00: it carries
    # the zone's last, tiny loads; elements further round are not over the pit
    sc = cwru(90.0, 0.0, "discrete")
    ld = scene_load_distribution(sc)
    exp = exposure(sc, ld)["races"]["outer"]
    reach = (1.376e-4 + 88.9e-6) / (0.5e-3 * (39.04 + 7.94))      # rad; a_H at 487 N by Hertz
    edge = float(ld.load_at(math.pi / 2 - reach, "outer"))
    assert exp["q_max_N"] == pytest.approx(edge, rel=0.05) and exp["q_max_N"] < 1.0
    assert exp["loaded_fraction"] == pytest.approx(0.5, abs=0.01)


def test_the_plus_10_um_zone_ends_at_75_36_deg():
    ld = scene_load_distribution(cwru(0.0, 10.0))
    assert math.degrees(ld.half_angle) == pytest.approx(75.36, abs=0.01)


@pytest.mark.parametrize("position_deg", [75.36, 75.3])
def test_a_contact_too_small_for_the_solver_is_refused_in_one_line(position_deg):
    sc = cwru(position_deg, 10.0)
    exp = exposure(sc, scene_load_distribution(sc))
    assert exp["loaded"] and exp["races"]["outer"]["q_max_N"] < 0.05
    with pytest.raises(ValueError) as pre:
        check_resolved(sc, "draft")             # the same refusal, before any solve
    with pytest.raises(ValueError) as e:
        simulate(sc, "draft")
    msg = str(e.value)
    assert str(pre.value) == msg
    assert "\n" not in msg and f"outer_race at {position_deg:g} deg" in msg
    assert "defect.position_deg" in msg and "radial_clearance_um 10" in msg
    assert "75.36 deg" in msg and "global_dx_um" in msg
    # the boundary: draft's finest grid (25 um / 2^3 = 3.125 um) resolves 2a >= 12.5 um, 0.046 N
    # by a_H ~ Q^(1/3) from 1.376e-4 m at 487 N; standard's (1.25 um) 5 um, 0.003 N
    two_a = 2 * 1.376e-4 * (exp["races"]["outer"]["q_max_N"] / 487.0) ** (1 / 3)
    assert two_a < 4 * 25e-6 / 8
    if two_a >= 4 * 10e-6 / 8:                  # 0.03 N at 75.3 deg: 10.8 um
        check_resolved(sc, "standard")          # solved on standard's grids halved twice
    else:                                       # 2.8e-4 N at 75.36 deg: 2.3 um
        with pytest.raises(ValueError, match="even refined to 1.25 um"):
            check_resolved(sc, "standard")


@pytest.mark.parametrize("position_deg", [75.36, 75.3])
def test_discrete_loads_at_the_edge_run_on_a_table_from_a_resolved_load(position_deg):
    # the element over the pit carries < 1 N: below the table's first node (scaled); the table
    # reaches the loads of the elements between passages (up to 20 deg nearer 0)
    sc = cwru(position_deg, 10.0, "discrete")
    ld = scene_load_distribution(sc)
    exp = exposure(sc, ld)
    assert exp["loaded"] and exp["races"]["outer"]["q_max_N"] < 1.0
    (q_max, q_min), = sc.defect.fault_location.table_loads(sc, ld, exp).values()
    assert q_min is None
    edge = float(ld.load_at(math.radians(position_deg - 20.0), "outer"))
    assert q_max == pytest.approx(edge, rel=1e-3)
    check_resolved(sc, "draft")                 # the table's loads are resolved: no refusal


def test_discrete_load_at_3_00_with_clearance_is_not_a_load_the_pit_meets():
    # 3:00 lies 14.6 deg outside the +10 um zone; the element over the pit (within a_H + w/2 =
    # 0.3 mm, 0.9 deg of arc) is unloaded; the neighbours at 70-75 deg are not over the pit
    sc = cwru(90.0, 10.0, "discrete")
    ld = scene_load_distribution(sc)
    angles = sc.defect.fault_location.passage_angles(sc, ld, 101)["outer"]
    r_o = 0.5e-3 * (39.04 + 7.94)
    assert np.ptp(angles) * r_o / 2 == pytest.approx(1.42e-4 + 88.9e-6, rel=0.05)
    exp = exposure(sc, ld)
    assert not exp["loaded"]
    h = simulate(sc, "draft")
    assert h.stats["n_solves"] == 0 and not np.any(h.signals["p_max"])


def _rig_scene(clearance_um):
    return cwru(0.0, clearance_um, location="rolling_element", load_kN=0.1, centrifugal=True,
                spin_axis="wandering", spin_seed=5)


def test_the_rig_scene_loads_every_ball_all_round_so_its_spin_axis_is_held():
    sc = _rig_scene(-3.94)
    ld = scene_load_distribution(sc)
    assert float(ld.load_at(math.pi, "inner")) == pytest.approx(7.0, rel=0.05)
    assert not spin_is_free(ld)
    theta = 2 * math.pi * np.arange(0, 10, 0.05)            # ten cage turns
    held = rolling_element_kinematics(sc, theta, redraw=False)["track_offset"]
    assert np.unique(held).size == 1
    # the history reads the held orientation: capture what the contacts are asked
    seen = []

    def capture(scene, race, q, track_offset):
        seen.append(np.asarray(track_offset))
        return np.zeros(np.shape(q), bool)

    class Zero:
        def evaluate(self, q, x):
            return np.zeros_like(q), np.zeros_like(q)

        def evaluate_integrals(self, q, x, use_numba=True):
            z = np.zeros_like(q)
            return {k: z for k in ("removed_force", "approach", "approach_change",
                                   "contact_area")}

    mp = pytest.MonkeyPatch()
    mp.setattr(locations.rolling_element, "on_track", capture)
    try:
        t = np.linspace(0.0, 10.0 / sc.cage_rate_hz, 400)
        ROLLING_ELEMENT.signals(sc, {"inner": Zero(), "outer": Zero()}, ld, t)
    finally:
        mp.undo()
    assert seen and all(np.unique(s).size == 1 for s in seen)


def test_with_clearance_the_ball_is_free_where_least_loaded_and_redrawn_each_turn():
    sc = _rig_scene(10.0)
    ld = scene_load_distribution(sc)
    assert float(ld.load_at(math.pi, "inner")) == 0.0 and spin_is_free(ld)
    theta = 2 * math.pi * np.arange(10) + 0.1                # one sample in each of ten turns
    free = rolling_element_kinematics(sc, theta)["track_offset"]
    assert np.unique(free).size == 10


def test_a_light_real_contact_is_solved_on_grids_refined_for_it():
    # CWRU 3:00 with +10 um and centrifugal force only: F_c = 0.224 N at 1797 rpm (m w_c^2 D/2,
    # docs/scene.md); a_H scales as Q^(1/3) from the 1.376e-4 m at 487 N: 2a = 21.2 um,
    # 0.85 draft cells (25 um): three halvings (3.125 um) give 6.8 cells, two only 3.4
    sc = cwru(90.0, 10.0, centrifugal=True)            # 29.95 Hz = 1797 rpm
    ld = scene_load_distribution(sc)
    (q_max, _), = sc.defect.fault_location.table_loads(sc, ld, exposure(sc, ld)).values()
    assert q_max == pytest.approx(0.224, rel=0.01)
    two_a = 2 * 1.376e-4 * (q_max / 487.0) ** (1 / 3)
    assert two_a == pytest.approx(21.2e-6, rel=0.01)
    check_resolved(sc, "draft")                 # no refusal
    from bearing_envelope.physics.history import MIN_CONTACT_CELLS, table_fidelity
    from bearing_envelope.physics.fidelity import PRESETS
    draft = PRESETS["draft"]
    fid = table_fidelity(sc.for_race("outer"), draft, q_max)
    assert fid.global_dx_um == draft.global_dx_um / 8 and fid.local_dx_um == draft.local_dx_um / 8
    assert two_a / (1e-6 * fid.global_dx_um) >= MIN_CONTACT_CELLS > two_a / (2e-6 * fid.global_dx_um)
    # a resolved table is solved on the fidelity itself (the default sweep is untouched)
    assert table_fidelity(sc.for_race("outer"), draft, 487.0) is draft
    h = simulate(sc, "draft")
    info = h.table.info
    assert info["grid_halvings"] == 3 and info["global_dx"] == pytest.approx(3.125e-6)
    assert h.signals["removed_force"].max() > 0.5 * q_max   # the pit sheds the light contact
