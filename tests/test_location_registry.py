"""A fault location is one object registered in one table (issue 44 part 1).

The toy location below is defined here and registered at runtime: nothing else in the package
changes, yet the scene builds it, the history simulates it and the sweep's analysis searches its
family. That is the measure "files touched to add a location": its class and registration (one
module of ``physics/locations/`` and its import line) and its tests. The ast count at the end is
the other measure: no module outside the table switches on a location's name.
"""

from __future__ import annotations

import ast
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from bearing_envelope.physics.exposure import exposure, exposure_line
from bearing_envelope.physics.history import simulate
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.locations import (LOCATIONS, FaultLocation, cage_angle,
                                                contact_signals, get_location,
                                                outer_race_kinematics, register_location)
from bearing_envelope.physics.scene import Scene
from bearing_envelope.study.figures import location_line
from bearing_envelope.study.pipeline import case_fault_lines

SRC = Path(__file__).resolve().parents[1] / "src" / "bearing_envelope"
CWRU = {"bearing": {"designation": "SKF 6205-2RS", "radial_clearance_um": 10.0},
        "operation": {"shaft_rate_hz": 29.95, "fs_hz": 48000.0, "revolutions": 2},
        "defect": {"shape": "cylinder", "width_um": 177.8}}


def cwru(location, **defect):
    m = {k: dict(v) for k, v in CWRU.items()}
    m["defect"].update(location=location, **defect)
    return Scene.from_mapping(m, load_kN=1.0, depth_um=279.4)


class LoadPoint(FaultLocation):
    """Toy: a pit on the outer ring at the load direction, its sidebands searched at the cage
    rate. Every method written here from the geometry (no switch elsewhere learns of it)."""

    name, code, body = "toy_load_point", "tp", "outer ring"
    races, contact_race, family, sideband = ("outer",), "outer", "bpfo", "ftf"

    def thickness_m(self, bearing):
        return 1e-3 * 0.5 * (bearing.outside_diameter_mm - bearing.pitch_diameter_mm
                             - bearing.roller_diameter_mm)

    def room_m(self, bearing):
        return math.pi * bearing.race_radius_m("outer") / bearing.rollers_per_row, "half a pitch"

    def speed_m_s(self, scene):
        return 2 * math.pi * scene.cage_rate_hz * scene.bearing.outer_race_radius_m

    def angle(self, scene, t, *, t_end=None):
        return np.zeros(np.shape(t))

    def passage_angles(self, scene, ld, n):
        return {"outer": np.zeros(1)}

    def signals(self, scene, tables, ld, t, *, t_end=None, use_numba=True):
        kin = outer_race_kinematics(scene, cage_angle(scene, t, t_end=t_end))  # position 0
        q = ld.load_at(np.zeros(np.shape(t)), "outer")
        out = contact_signals(tables["outer"], q, kin["offset"], use_numba)
        out.update(roller_load=q, defect_offset=kin["offset"])
        return out


@pytest.fixture
def toy():
    loc = register_location(LoadPoint())
    yield loc
    del LOCATIONS[loc.name]


def test_get_location_names_the_value_and_the_allowed_ones():
    assert get_location("outer_race") is LOCATIONS["outer_race"]
    with pytest.raises(ValueError) as e:
        get_location("cage")
    msg = str(e.value)
    assert "\n" not in msg and "'cage'" in msg
    assert "inner_race | outer_race | rolling_element" in msg
    with pytest.raises(ValueError, match=r"scene.defect.location: got 'cage'; allowed: "
                                         r"inner_race \| outer_race \| rolling_element"):
        cwru("cage")


def test_a_name_or_code_is_registered_once(toy):
    class Again(LoadPoint):
        code = "zz"
    with pytest.raises(ValueError, match="already registered"):
        register_location(Again())
    with pytest.raises(ValueError, match="already registered"):
        register_location(type("Code", (LoadPoint,), {"name": "other"})())


def test_the_inner_race_is_a_location_like_the_others():
    names = [loc.name for loc in LOCATIONS.values()]
    assert names[:3] == ["inner_race", "outer_race", "rolling_element"]
    ir = LOCATIONS["inner_race"]
    assert (ir.code, ir.family, ir.sideband, ir.races) == ("ir", "bpfi", "fr", ("inner",))
    # the speed of the default scene's defect through its contact: 4.24 m/s (history docstring)
    assert cwru("inner_race").defect.fault_location is ir
    assert Scene.default().defect_speed_m_s == pytest.approx(4.24, abs=0.01)


def test_a_toy_location_registered_at_runtime_runs_end_to_end(toy):
    sc = cwru("toy_load_point")
    assert sc.defect.fault_location is toy and sc.bearing.contact_race == "outer"
    # the scene's rules come from the object: no angle, no wandering spin
    with pytest.raises(ValueError, match="position_deg: got 90.*'outer_race'"):
        cwru("toy_load_point", position_deg=90.0)
    with pytest.raises(ValueError, match="spin_axis: got 'wandering'.*'rolling_element'"):
        cwru("toy_load_point", spin_axis="wandering")
    ld = scene_load_distribution(sc)
    exp = exposure(sc, ld)
    assert exp["loaded"] and exp["races"]["outer"]["loaded_fraction"] == 1.0
    assert exp["races"]["outer"]["q_max_N"] == pytest.approx(ld.q_max_outer, rel=1e-12)
    # the same physics as the built-in outer race at 6:00: the same history, bit for bit
    toy_hist = simulate(sc, "draft")
    ref = simulate(cwru("outer_race", position_deg=0.0), "draft")
    for k in ("p_max", "p_max_defect", "removed_force", "contact_area"):
        np.testing.assert_array_equal(toy_hist.signals[k], ref.signals[k])
    assert set(toy_hist.tables) == {"outer"} and "n_rows_fallback" in toy_hist.stats
    # the analysis searches its family with its own sideband spacing
    rates = {"fr": 29.95, "bpfi": 162.2, "bpfo": 107.4, "ftf": 11.9, "bsf": 70.6}
    case = SimpleNamespace(scene={"defect": {"location": "toy_load_point"}}, **rates)
    assert case_fault_lines(case) == ({"bpfo": 107.4}, {"bpfo": ("ftf", 11.9)})
    assert location_line("toy_load_point") == "BPFO"
    assert exposure_line(sc, exp) is None


# --- the measure: sites that switch on a location string outside the table ------------------

#: The virtual rig's files still switching on location names (issue 44 part 6 moves them into a
#: rig subpackage; converted once it has merged); every other module must show none.
PENDING = ("study/rig",)


def location_switch_sites(root: Path = SRC) -> dict[str, list[int]]:
    """``file -> lines`` where a location name (a string constant) is compared, used as a
    dict key, a subscript, a member of a tuple/list/set tested with ``in``, or where a
    location list is indexed (``DEFECT_LOCATIONS[0]``), outside ``physics/locations/``."""
    names = set(LOCATIONS)
    out: dict[str, list[int]] = {}
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root).as_posix()
        if rel.startswith("physics/locations/"):
            continue
        lines = sorted(_sites(ast.parse(path.read_text()), names))
        if lines:
            out[rel] = lines
    return out


def _is_name(node, names) -> bool:
    if isinstance(node, ast.Constant) and node.value in names:
        return True
    return isinstance(node, (ast.Tuple, ast.List, ast.Set)) and any(
        isinstance(e, ast.Constant) and e.value in names for e in node.elts)


def _sites(tree, names):
    for node in ast.walk(tree):
        if isinstance(node, ast.Compare) and any(_is_name(n, names)
                                                 for n in [node.left, *node.comparators]):
            yield node.lineno
        elif isinstance(node, ast.Dict) and any(_is_name(k, names) for k in node.keys if k):
            yield node.lineno
        elif isinstance(node, ast.Subscript) and (
                _is_name(node.slice, names)
                or getattr(node.value, "id", getattr(node.value, "attr", "")) in (
                    "DEFECT_LOCATIONS", "LOCATION_FAMILIES", "LOCATION_CODES")):
            yield node.lineno
        elif isinstance(node, ast.match_case) and _is_name(getattr(node.pattern, "value", None),
                                                           names):
            yield node.lineno


def test_no_module_outside_the_table_switches_on_a_location_name():
    sites = location_switch_sites()
    outside = {f: v for f, v in sites.items() if not f.startswith(PENDING)}
    assert outside == {}, outside


def test_the_counter_finds_each_kind_of_switch(tmp_path):
    (tmp_path / "m.py").write_text(
        "if loc == 'inner_race':\n    pass\n"
        "x = {'outer_race': 1}\n"
        "y = loc in ('rolling_element', 'x')\n"
        "z = DEFECT_LOCATIONS[0]\n"
        "w = table['inner_race']\n"
        "DEFAULT = {'location': 'inner_race'}\n")   # a value, not a switch
    assert location_switch_sites(tmp_path) == {"m.py": [1, 3, 4, 5, 6]}


def test_the_schema_lists_no_location():
    # the config schema leaves the names to the registry: a new location needs no schema edit
    text = (SRC / "data" / "config.schema.yaml").read_text()
    assert "enum: [inner_race" not in text
