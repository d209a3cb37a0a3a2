"""The contact angle's range is the radial bearing's, refused in one line naming the field.

The load distribution balances a radial load alone: its ring displacement grows as
``cos(alpha)^(-(n+1)/n)`` and has no solution as ``alpha`` nears 90 deg (89.999 deg was refused
as "load distribution: no equilibrium found", issue 43). Allowed: [0, 45] deg
(``MAX_CONTACT_ANGLE_DEG``; ISO 76/281: above 45 deg a thrust bearing).
"""

from __future__ import annotations

import math

import pytest

from bearing_envelope.physics.loads import scene_load_distribution, solve_row
from bearing_envelope.physics.scene import MAX_CONTACT_ANGLE_DEG, Scene
from bearing_envelope.study.settings import ConfigError, settings_from_mapping

BALL = "SKF 6205-2RS"


def _scene(alpha):
    return Scene.from_mapping({"bearing": {"designation": BALL, "contact_angle_deg": alpha}},
                              load_kN=1.0, depth_um=0.0)


@pytest.mark.parametrize("alpha", [89.999, 45.000001, 90.0, -1e-9, math.nan])
def test_outside_the_range_names_field_value_and_range(alpha):
    with pytest.raises(ValueError) as err:
        _scene(alpha)
    msg = str(err.value)
    assert msg.startswith(f"scene.bearing.contact_angle_deg: got {alpha!r}; allowed:"), msg
    assert "[0, 45] deg" in msg and "\n" not in msg


@pytest.mark.parametrize("alpha", [0.0, MAX_CONTACT_ANGLE_DEG])
def test_the_range_ends_solve(alpha):
    """At both ends the equilibrium is found, and it carries the load: sum Q cos(psi) cos(alpha)
    = the row's share (independent of the solver's own residual)."""
    ld = scene_load_distribution(_scene(alpha))
    carried = (ld.q * [math.cos(p) for p in ld.psi]).sum() * math.cos(ld.contact_angle_rad)
    assert carried == pytest.approx(ld.force_row, rel=1e-9)


def test_displacement_at_45_deg_within_its_closed_form_bound():
    """Zero clearance: Q ~ (delta_r cos(psi) cos(alpha))^n and sum Q cos(psi) cos(alpha) = F give
    delta_r proportional to cos(alpha)^(-(n+1)/n): 2^((n+1)/(2n)) = 2^(5/6) at 45 deg (balls)."""
    d0 = solve_row(1e3, 9, 0.0, exponent=1.5).delta_r
    d45 = solve_row(1e3, 9, 45.0, exponent=1.5).delta_r
    assert d45 / d0 == pytest.approx(2 ** (5 / 6), rel=1e-9)


def test_config_refuses_it_before_any_job():
    with pytest.raises(ConfigError, match=r"scene\.bearing\.contact_angle_deg"):
        settings_from_mapping({"sweep": {"loads_kN": [1.0], "depths_um": [0]},
                               "scene": {"bearing": {"designation": BALL,
                                                     "contact_angle_deg": 89.999}}})


def test_solver_failure_names_the_angle():
    """The library function (no scene check in front) still says which input it could not meet."""
    with pytest.raises(ValueError, match=r"contact_angle_deg 89\.999.*<= 45 deg"):
        solve_row(1e3, 9, 89.999, stiffness=1e10, exponent=1.5)
