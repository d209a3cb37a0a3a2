"""The fused RK4 loop (``kernels.rk4_loop``, ``simulate_dynamics(kernel="fast")``) against the
step-by-step reference (``kernels.rk4_run``, ``kernel="reference"``): the same arithmetic in the
same order, so every recorded signal and the end state equal to the bit, on short runs of the
6205 with a slot on the outer race, on the inner race and on a ball (each run checked to meet
its pit); and the loop's Python body (what runs without numba) against its compiled self."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from bearing_envelope.physics.dynamics import params_from_scene, simulate_dynamics, slot_law
from bearing_envelope.physics.dynamics.kernels import rk4_loop
from bearing_envelope.physics.dynamics.model import arrays, initial_state, record_names
from bearing_envelope.physics.dynamics.params import step_size
from test_dynamics_element_pit import slot_params
from test_dynamics_oracles import cwru_scene

#: The 0.007 in slot (m), its depth (m).
WIDTH, DEPTH = 177.8e-6, 279.4e-6


def race_params(race: str):
    """The 6205 (1 kN, 10 um clearance, 1797 rpm) with the slot on ``race``: on the outer race
    2 deg from the load (element 0 crosses it within 2 ms), on the inner race at 0."""
    p = params_from_scene(cwru_scene())
    k = p.k_outer if race == "outer" else p.k_inner
    law = slot_law(p.element_radius_m, WIDTH, DEPTH, k, 1.5, 30e-6)
    return p.with_(defect=law, defect_race=race, defect_angle_rad=math.radians(2.0))


SCENES = {"outer race": lambda: race_params("outer"), "inner race": lambda: race_params("inner"),
          "ball": slot_params}


@pytest.mark.parametrize("name", list(SCENES))
def test_fast_kernel_equals_the_reference_to_the_bit(name):
    p = SCENES[name]()
    got = {k: simulate_dynamics(p, 0.02, 12000.0, settle_s=1e-3, kernel=k)
           for k in ("fast", "reference")}
    fast, ref = got["fast"], got["reference"]
    assert ref.defect_force_peak_n > 1.0          # the run meets its pit
    assert fast.steps == ref.steps > 0
    for f in dataclasses.fields(fast):
        a, b = getattr(fast, f.name), getattr(ref, f.name)
        if isinstance(a, np.ndarray):
            assert a.shape == b.shape and np.array_equal(a, b), f.name
    assert fast.defect_force_peak_n == ref.defect_force_peak_n
    assert fast.t_end_s == ref.t_end_s


def test_fast_kernel_in_python_equals_its_compiled_self():
    # the loop's Python body is what runs when numba is missing (kernels.py: _jit is identity)
    p = race_params("outer")
    a = arrays(p, -1e-3, 1e-3)
    dt = step_size(p)
    rows = [np.empty((3, len(record_names(p.z)))) for _ in range(2)]
    ys = [initial_state(p, 0.0) for _ in range(2)]
    run = getattr(rk4_loop, "py_func", rk4_loop)
    t1 = run(ys[0], 0.0, dt, 3, 4, *a.kernel_args(), rows[0])
    t2 = rk4_loop(ys[1], 0.0, dt, 3, 4, *a.kernel_args(), rows[1])
    assert t1 == t2 == 12 * dt
    assert np.array_equal(ys[0], ys[1]) and np.array_equal(rows[0], rows[1])
    assert not np.array_equal(ys[0], initial_state(p, 0.0))


def test_unknown_kernel_is_refused_naming_the_choices():
    with pytest.raises(ValueError, match="kernel got 'rk5'; allowed: fast | reference"):
        simulate_dynamics(race_params("outer"), 0.01, 12000.0, kernel="rk5")
