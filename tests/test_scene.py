import dataclasses
import math

import pytest

from bearing_envelope.physics.fidelity import PRESETS, Fidelity, fidelity_from
from bearing_envelope.physics.scene import DEFAULT_SCENE, Scene, default_scene_mapping


def test_default_scene_numbers():
    s = Scene.default(load_kN=500, depth_um=50)
    b = s.bearing
    assert b.pitch_diameter_mm == pytest.approx(145.0)  # (110 + 180)/2
    # design.md hand numbers: R_i ~ 64.0 mm, Rx ~ 7.68 mm, Ry ~ 4233 mm, E* = 115.4 GPa
    assert b.inner_race_radius_m == pytest.approx(64.0e-3, abs=0.05e-3)
    assert b.rx_m == pytest.approx(7.68e-3, abs=0.005e-3)
    assert b.ry_m == pytest.approx(1.0 / (1 / 81.5e-3 - 1 / 83.1e-3))
    assert s.material.e_star_pa == pytest.approx(115.4e9, rel=1e-3)
    assert s.defect.width_um == 100.0  # 2 x depth
    # BPFI: stated 231.9 Hz reproduced by the override, geometry gives 194.2 Hz
    assert s.bpfi_hz == 231.9
    assert s.frequencies().bpfi == pytest.approx(194.2, abs=0.05)
    # implied cage rate: Z (fr - fc) = BPFI
    assert 22 * (15.8 - s.cage_rate_hz) == pytest.approx(231.9)
    assert s.n_samples == round(100 / 15.8 * 65000)  # ~411,000


def test_no_override_uses_geometry():
    s = Scene.from_mapping({"operation": {"bpfi_override_hz": None}}, load_kN=250, depth_um=0)
    assert s.bpfi_hz == pytest.approx(s.frequencies().bpfi)
    assert s.cage_rate_hz == pytest.approx(s.frequencies().ftf)


def test_mapping_round_trip():
    s = Scene.default(load_kN=750, depth_um=20)
    m = s.to_mapping()
    load_kN = m["load"].pop("value_kN")
    depth = m["defect"].pop("depth_um")
    s2 = Scene.from_mapping(m, load_kN=load_kN, depth_um=depth)
    assert s2 == s


@pytest.mark.parametrize(
    "mapping, depth, field",
    [
        ({}, -5.0, "scene.defect.depth_um"),
        ({"defect": {"length_um": 40000.0}}, 50.0, "scene.defect.length_um"),
        ({"defect": {"orientation": "circumferential", "width_um": 40000.0}}, 50.0,
         "scene.defect.width_um"),
        ({"defect": {"axial_position_mm": 17.9}}, 50.0, "scene.defect.axial_position_mm"),
        ({"bearing": {"rollers_per_row": 0}}, 50.0, "scene.bearing.rollers_per_row"),
        ({"bearing": {"rollers_per_row": 2.5}}, 50.0, "scene.bearing.rollers_per_row"),
        ({"operation": {"fs_hz": 5000.0}}, 50.0, "scene.operation.fs_hz"),
        ({"bearing": {"colour": "red"}}, 50.0, "scene.bearing.colour"),
        ({"wheels": 3}, 50.0, "scene.wheels"),
        ({"bearing": {"end_relief": {"kind": "radius", "radius_mm": 1.0, "x": 1}}}, 50.0,
         "scene.bearing.end_relief.x"),
        ({"bearing": {"end_relief": {"kind": "cone"}}}, 50.0, "scene.bearing.end_relief.kind"),
        ({"bearing": {"raceway_profile_radius_mm": 80.0}}, 50.0,
         "scene.bearing.raceway_profile_radius_mm"),
        ({"bearing": {"profile_file": "/nonexistent/profile.csv"}}, 50.0, "scene.bearing.profile_file"),
        ({"material": {"race": {"nu": 0.7}}}, 50.0, "scene.material.race.nu"),
        ({"load": {"mode": "axial"}}, 50.0, "scene.load.mode"),
        ({"operation": {"cage_slip_percent": -1}}, 50.0, "scene.operation.cage_slip_percent"),
        ({"operation": {"revolutions": 0}}, 50.0, "scene.operation.revolutions"),
    ],
)
def test_bad_scenes_name_the_field(mapping, depth, field):
    with pytest.raises(ValueError) as ei:
        Scene.from_mapping(mapping, load_kN=500, depth_um=depth)
    msg = str(ei.value)
    assert field in msg
    assert "allowed" in msg


def test_bad_scene_fails_before_any_solve(monkeypatch, tmp_path):
    import bearing_envelope.contact as contact
    import bearing_envelope.physics.solves.stats as solves
    from bearing_envelope.cli import main

    def boom(*a, **k):  # pragma: no cover - must not be reached
        raise AssertionError("solver called")

    monkeypatch.setattr(contact, "solve_contact", boom)
    monkeypatch.setattr(solves, "solve_contact", boom)
    cfg = tmp_path / "c.yaml"
    cfg.write_text("fidelity: draft\nscene:\n  bearing: {rollers_per_row: 0}\n")
    rc = main(["simulate", "--config", str(cfg), "--load-kn", "500", "--depth-um", "50",
               "-o", str(tmp_path / "x.h5")])
    assert rc == 2
    assert not (tmp_path / "x.h5").exists()


def test_default_mapping_is_a_copy():
    m = default_scene_mapping()
    m["bearing"]["rows"] = 7
    assert DEFAULT_SCENE["bearing"]["rows"] == 2


def test_fidelity_presets():
    assert set(PRESETS) == {"draft", "fast", "standard", "accurate", "paper"}
    assert fidelity_from(None).name == "standard"
    # issue 25 part 6: standard (the converged default) = fast (the former default) + rim strips
    # + a 40 um axial global grid; 2026-11-27: accurate = standard with a 10 um axial window
    # spacing and 5 um end strips 80 um wide
    fast, std, acc = (fidelity_from(n) for n in ("fast", "standard", "accurate"))
    assert fast.rim_dx_um is None and fast.global_dy_um == 80.0
    assert std.rim_dx_um == acc.rim_dx_um == 0.5
    assert std.global_dy_um == acc.global_dy_um == 40.0
    assert (acc.local_dy_um, acc.end_dy_um, acc.end_strip_um) == (10.0, 5.0, 80.0)
    assert std.end_dy_um is None
    for f in dataclasses.fields(Fidelity):
        if f.name not in ("name", "rim_dx_um", "global_dy_um", "local_dy_um", "end_dy_um",
                          "end_strip_um"):
            assert getattr(fast, f.name) == getattr(std, f.name) == getattr(acc, f.name), f.name
    assert PRESETS["draft"].rim_dx_um is None and PRESETS["paper"].rim_dx_um is None
    d = fidelity_from("draft")
    assert d.local_dx_um > PRESETS["paper"].local_dx_um
    f = fidelity_from({"preset": "draft", "n_loads": 4})
    assert isinstance(f, Fidelity) and f.n_loads == 4 and f.local_dx_um == d.local_dx_um
    with pytest.raises(ValueError, match="fidelity.n_loads"):
        fidelity_from({"n_loads": 1})
    with pytest.raises(ValueError, match="unknown"):
        fidelity_from({"grid": 3})
    with pytest.raises(ValueError, match="unknown preset"):
        fidelity_from("ultra")
    assert math.isfinite(fidelity_from("paper").tol)


@pytest.mark.parametrize("bad", [0, -7.36, float("inf"), float("nan"), "hard", True])
def test_bad_hardness_names_the_field(bad):
    with pytest.raises(ValueError, match=r"scene\.material\.hardness_GPa.*allowed"):
        Scene.from_mapping({"material": {"hardness_GPa": bad}}, load_kN=500, depth_um=50)


def test_hardness_default_elastic_and_round_trip():
    from bearing_envelope.physics.scene import BEARING_STEEL_HARDNESS_GPA

    s = Scene.default()
    assert s.material.hardness_GPa is None and s.material.hardness_pa is None
    h = Scene.from_mapping({"material": {"hardness_GPa": BEARING_STEEL_HARDNESS_GPA}}, load_kN=500,
                           depth_um=50)
    assert h.material.hardness_pa == pytest.approx(7.36e9)
    again = Scene.from_mapping({k: v for k, v in h.to_mapping().items() if k in ("bearing", "material")},
                               load_kN=500, depth_um=50)
    assert again.material == h.material
