"""Width and depth as separate axes (issue 12 part 4): when does the depth change the history?

A pit whose bottom the deformed roller never reaches changes the contact only through its width
and rims, so two depths above the threshold give the same history and a depth below it does
not. The threshold is measured by :func:`bearing_envelope.physics.pit.depth_threshold` (direct window
solves at the most loaded roller) and checked against an independent answer: the roller sinks
into a traction-free slot of half-width c by ``2 p0 c / E*`` (face displacement of a Griffith
crack in plane strain; the rounded rims make the free slot a little narrower, so the measured
threshold lies a little below it).
"""

from __future__ import annotations

import numpy as np
import pytest

from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.history import simulate
from bearing_envelope.physics.pit import depth_threshold, pit_scene, slot_estimate

FID = fidelity_from({"preset": "draft", "n_checks": 0, "n_snapshot_offsets": 0})
LOAD = 500.0
WIDTH = 200.0   # um: 20 cells of the draft window across the pit


@pytest.fixture(scope="module")
def threshold():
    h, log = depth_threshold(LOAD, WIDTH, FID, h_lo=0.1, h_hi=100.0)
    return h, log


def test_threshold_matches_the_slot_estimate(threshold):
    h, log = threshold
    e_star = pit_scene(None, LOAD, 10.0, WIDTH).material.e_star_pa
    # by hand: p = 3.10 GPa at the centre of the 500 kN contact (draft), E* = 115.4 GPa:
    # 2 p c / E* = 2 x 3.10 x 100 / 115.4 = 5.4 um
    estimate = 2.0 * log[0].p_centre * 100.0 / e_star
    assert estimate == pytest.approx(slot_estimate(log[0].p_centre, e_star, WIDTH))
    assert 0.7 * estimate < h < 1.05 * estimate, (h, estimate)
    # the bisection bracket: loaded just below, free just above
    below = [r.depth_um for r in log if r.loaded]
    above = [r.depth_um for r in log if not r.loaded]
    assert max(below) < h <= min(above) < 1.02 * max(below)


def test_depth_changes_the_history_only_below_the_threshold(threshold):
    h, _ = threshold
    hist = {}
    for k in (0.5, 1.5, 3.0):
        sc = pit_scene({"operation": {"revolutions": 0.1}}, LOAD, k * h, WIDTH)
        hist[k] = simulate(sc, FID).signals

    def change(a, b, name):
        x, y = np.asarray(a[name]), np.asarray(b[name])
        return float(np.max(np.abs(x - y)) / np.max(np.abs(y)))

    for name in ("p_max", "removed_force", "approach_change", "contact_area"):
        same = change(hist[1.5], hist[3.0], name)     # bottom free at both depths
        other = change(hist[0.5], hist[3.0], name)    # bottom loaded at 0.5 h*
        assert same < 1e-3, (name, same)              # solver tolerance only
        # measured at draft: 1e-5..1e-4 against 2e-3 (area) .. 0.1-0.3 (p_max, forces)
        assert other > 1e-3 and other > 20 * same, (name, same, other)


def test_default_width_rule_never_loads_the_bottom_of_a_sweep_pit():
    """w = 2 h: the roller reaches the deepest line of the (round, r = 20 um) trough only for h of
    a few um, where the trough r - sqrt(r^2 - h^2) is as deep as the roller sinks into a slot of
    half-width h (2 p h / E*); the sweep's pits (>= 15 um) are far deeper, so their "depth" axis
    varies the width alone."""
    h, log = depth_threshold(LOAD, None, FID, h_lo=0.5, h_hi=100.0)
    e_star = pit_scene(None, LOAD, 10.0, None).material.e_star_pa
    # by hand: s = 2 x 3.10 / 115.4 = 0.0537, h* = 2 x 20 x s / (1 + s^2) = 2.14 um
    estimate = slot_estimate(log[0].p_centre, e_star, None)
    assert 2.0 < estimate < 2.3
    assert h == pytest.approx(estimate, rel=0.1)
    assert h < 15.0 / 3
