"""Recorded contact signals stay within their physical range: a pressure in ``[0, H]``.

The anti-alias filter (linear, with negative taps) rings on a peak the contact solver flattens
at the hardness ``H`` and on a load that falls to 0; the acquisition clips its output back into
the signal's physical range and records how many samples it clipped (issue 43).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from bearing_envelope.physics.acquisition import (acquire, antialias_undershoot, clip_to_bounds,
                                                  signal_bounds)
from bearing_envelope.physics.history import simulate
from bearing_envelope.physics.scene import Scene

ROOT = Path(__file__).resolve().parents[1]

H = 7.36e9          # the bound of the pressure, Pa
FS = 10_000.0


def _capped_pulses(t):
    """A train of pressure pulses flattened at ``H`` (a narrow Gaussian of peak 1.5 H, clipped
    at H) that fall to exactly 0 between pulses: the shape of a pit's rim peak under the cap."""
    phase = (t * 50.0) % 1.0 - 0.5                       # 50 pulses per second
    p = np.minimum(1.5 * H * np.exp(-(phase / 0.004) ** 2), H)
    p[np.abs(phase) > 0.02] = 0.0
    return {"p_max": p, "approach": p * 1e-15 - 1e-6}


def _acq(**kw):
    return acquire(_capped_pulses, 4000, FS, mode="antialiased", oversample=8, **kw)


def test_unclipped_filter_rings_past_the_cap_and_below_zero():
    """The reproduction: without bounds the filtered pressure leaves [0, H] (the finding)."""
    p = _acq()["p_max"]
    u = antialias_undershoot(8)
    assert p.max() > H * (1 + 1e-4) and p.min() < -1e-4 * H
    assert p.max() <= H * (1 + u) * (1 + 1e-9) and p.min() >= -u * H * (1 + 1e-9)


def test_recorded_pressure_within_zero_and_the_cap_with_the_count_reported():
    clipped = {}
    free = _acq()
    out = _acq(bounds={"p_max": (0.0, H)}, clipped=clipped)
    p = out["p_max"]
    assert p.min() == 0.0 and p.max() == H                 # reaches the bounds, never past
    above, below = free["p_max"] > H, free["p_max"] < 0.0
    assert clipped["p_max"]["samples"] == int(above.sum() + below.sum()) > 0
    assert clipped["p_max"]["max_excess"] == pytest.approx(
        max(free["p_max"].max() - H, -free["p_max"].min()), rel=1e-12)
    # every sample inside the range is the filter's output, bit for bit
    inside = ~(above | below)
    assert np.array_equal(p[inside], free["p_max"][inside])
    # an unbounded signal is not touched and not counted
    assert np.array_equal(out["approach"], free["approach"]) and "approach" not in clipped


def test_clip_at_the_boundary():
    """A sample exactly at a bound is in range (not counted); one ulp past it is clipped."""
    y = np.array([0.0, H, np.nextafter(H, np.inf), -5e-324, 1.0])
    rec = {}
    out = clip_to_bounds(y, (0.0, H), rec, "p")
    assert list(out) == [0.0, H, H, 0.0, 1.0]
    assert rec["p"]["samples"] == 2
    same = clip_to_bounds(out, (0.0, H), rec, "p")
    assert same is out and rec["p"]["samples"] == 2        # nothing more to clip: counted once


def test_signal_bounds_follow_the_hardness():
    elastic = Scene.default()
    assert signal_bounds(elastic)["p_max"] == (0.0, math.inf)
    hard = Scene.from_mapping({"material": {"hardness_GPa": 7.36}}, load_kN=500, depth_um=50)
    assert signal_bounds(hard)["p_max"] == signal_bounds(hard)["p_max_defect"] == (0.0, H)


def test_the_reproduction_records_no_pressure_past_the_cap():
    """Issue 43's case: the CWRU inner-race pit of config_cwru.yaml (SKF 6205-2RS, 1 kN, 0.011 in
    deep, 0.007 in wide, H = 7.36 GPa) at ``standard``: the table is capped at H and the filter
    rang to 7.44 GPa and -0.13 GPa; now p_max and p_max_defect lie in [0, H], reach H, and the
    clipped samples are counted in the case's acquisition record (2 revolutions, 14 CPU s)."""
    import yaml

    scene = yaml.safe_load((ROOT / "config_cwru.yaml").read_text())["scene"]
    scene["operation"]["revolutions"] = 2
    sc = Scene.from_mapping(scene, load_kN=1.0, depth_um=279.4)
    assert sc.material.hardness_pa == H
    h = simulate(sc, "standard")
    assert h.acquisition["internal_range"]["p_max"][1] == H      # the table is capped at H
    for name in ("p_max", "p_max_defect"):
        x = h.signals[name]
        assert x.min() == 0.0 and x.max() == H, name           # at the bounds, never past
    clipped = h.acquisition["clipped"]
    u = antialias_undershoot(h.acquisition["oversample"])
    for name in ("p_max", "p_max_defect"):
        assert clipped[name]["samples"] > 0
        assert 0 < clipped[name]["max_excess"] <= u * H * (1 + 1e-9)
