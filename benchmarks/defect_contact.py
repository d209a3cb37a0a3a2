"""The defect contact law of the dynamic model (issue 42 parts 1 and 3): the cost and measured
errors of the ``F(x, delta)`` table per fidelity for the CWRU 6205 outer-race pits, and the
defect's characteristic scales for the CWRU records' pits and the default sweep's scene.

``python -m benchmarks defect_contact [--fidelity draft standard] [--scales-only]`` prints the
markdown tables of ``docs/dynamics.md`` ("Defect contact law").
"""

from __future__ import annotations

import argparse
import copy
import time
from pathlib import Path

import yaml

from bearing_envelope.physics.defect_contact import build_defect_table, defect_scales
from bearing_envelope.physics.scene import Scene

ROOT = Path(__file__).resolve().parents[1]
#: CWRU pit diameters (in) and their EDM depth (um, 0.011 in).
CWRU_PITS_IN = (0.007, 0.014, 0.021)
CWRU_DEPTH_UM = 279.4
INCH_UM = 25400.0
#: CWRU drive-end nominal speeds (rpm) per motor load (hp): the records' index.
CWRU_RPM = {0: 1797.0, 1: 1772.0, 2: 1750.0, 3: 1730.0}
#: Where each CWRU pit meets its event: (label, location, position_deg).
CWRU_SITES = (("OR 6:00", "outer_race", 0.0), ("OR 3:00", "outer_race", 90.0),
              ("IR", "inner_race", 0.0), ("ball", "rolling_element", 0.0))


def rig_scene(diameter_in: float, location: str = "outer_race", position_deg: float = 0.0,
              rpm: float = 1797.0, shape: str | None = None, length_um: float | None = None,
              clearance_um: "float | None | str" = "rig"):
    """The virtual rig's scene (config_rig.yaml, its load) with one CWRU pit; ``clearance_um``
    None: the catalogue's clearance instead of the rig's identified preload."""
    cfg = yaml.safe_load((ROOT / "config_rig.yaml").read_text())
    m = copy.deepcopy(cfg["scene"])
    if clearance_um != "rig":
        m["bearing"].pop("radial_clearance_um", None)
        if clearance_um is not None:
            m["bearing"]["radial_clearance_um"] = clearance_um
    w = diameter_in * INCH_UM
    m["defect"].update(location=location, position_deg=position_deg, width_um=w,
                       length_um=w if length_um is None else length_um)
    if shape:
        m["defect"]["shape"] = shape
    m["operation"] = {**m.get("operation", {}), "shaft_rate_hz": rpm / 60.0}
    return Scene.from_mapping(m, load_kN=cfg["rig"]["load_kN"], depth_um=CWRU_DEPTH_UM)


def table_rows(fidelities, pits=CWRU_PITS_IN) -> list[str]:
    """One row per (fidelity, pit): cost and measured errors of the OR 6:00 table."""
    out = ["| fidelity | pit in | nodes x x delta | grid cells | dx, dy um | delta_max um | "
           "solves | iterations per solve | CPU s | healthy vs Hertz | interp. err (local / of max) | "
           "resume at x=0 um | rigid drop um |", "|" + "---|" * 13]
    for fid in fidelities:
        for d in pits:
            t = build_defect_table(rig_scene(d), fid)
            out.append(
                f"| {fid} | {d:.3f} | {t.x_m.size} x {t.delta_m.size} | "
                f"{t.info['grid_shape'][0]} x {t.info['grid_shape'][1]} | "
                f"{1e6 * t.grid_dx_m:.3g}, {1e6 * t.grid_dy_m:.3g} | {1e6 * t.delta_m[-1]:.2f} | "
                f"{t.n_solves} | {t.info['iterations'] / t.n_solves:.1f} | {t.cpu_s:.1f} | {t.discretisation_error:.1e} | "
                f"{100 * t.interpolation_error:.1f} % / "
                f"{100 * t.interpolation_error_of_max:.2f} % | "
                f"{1e6 * t.resume_approach(0.0):.3f} | {1e6 * t.rigid_drop_m:.3f} |")
    return out


def roller_rows(fidelity: str = "draft") -> list[str]:
    """The default sweep's roller (500 kN, 50 um pit): cost, and where its healthy contact
    leaves Hertz (the roller ends)."""
    t = build_defect_table(Scene.default(load_kN=500.0, depth_um=50.0), fidelity)
    mid = t.x_m.size // 2
    out = [f"Default scene (500 kN, h 50 um, inner race), {fidelity}: {t.x_m.size} x "
           f"{t.delta_m.size} nodes, {t.info['grid_shape'][0]} x {t.info['grid_shape'][1]} "
           f"cells of {1e6 * t.grid_dx_m:.3g} x {1e6 * t.grid_dy_m:.3g} um, {t.n_solves} solves, "
           f"{t.cpu_s:.1f} CPU s; interpolation error {100 * t.interpolation_error:.1f} % / "
           f"{100 * t.interpolation_error_of_max:.2f} % of max.", "",
           "| delta um | F healthy kN | K delta^1.5 kN | F(0, delta)/F healthy |",
           "|---|---|---|---|"]
    for j in range(1, t.delta_m.size):
        out.append(f"| {1e6 * t.delta_m[j]:.2f} | {1e-3 * t.healthy_force_n[j]:.2f} | "
                   f"{1e-3 * t.hertz_k * t.delta_m[j] ** 1.5:.2f} | "
                   f"{t.force_n[mid, j] / t.healthy_force_n[j]:.5f} |")
    return out


def static_rows(fidelity: str = "standard", pits=CWRU_PITS_IN) -> list[str]:
    """An element under its static 6:00 load centred over the pit: the force it keeps at the
    healthy approach and how far it moves in to carry its load, round pit against a long slot
    (3 mm axially) of the same width."""
    out = ["| pit in | shape | Q N | delta_H(Q) um | F(0, delta_H)/Q | delta(0, Q) um | "
           "moves in um | resumes at um |", "|" + "---|" * 8]
    for d in pits:
        for shape, length in (("cylinder", None), ("flat", 3000.0)):
            sc = rig_scene(d, shape=shape, length_um=length)
            t = build_defect_table(sc, fidelity, n_checks=0)
            q = defect_scales(sc).element_load_n
            dh, d0 = t.approach(1.0, q), t.approach(0.0, q)
            label = "round" if shape == "cylinder" else "slot 3 mm"
            out.append(f"| {d:.3f} | {label} | {q:.1f} | {1e6 * dh:.3f} | "
                       f"{float(t.force(0.0, dh)) / q:.2f} | {1e6 * d0:.3f} | "
                       f"{1e6 * (d0 - dh):.3f} | {1e6 * t.resume_approach(0.0):.3f} |")
    return out


def _scale_row(label: str, s) -> str:
    return (f"| {label} | {s.element_load_n:.3g} | {1e6 * s.contact_half_width_m:.0f} | "
            f"{1e6 * s.pit_length_m:.0f} | {s.pit_over_contact:.2f} | "
            f"{1e6 * s.rigid_drop_m:.3f} | {1e6 * s.static_approach_m:.3f} | "
            f"{s.drop_over_approach:.2f} | {s.surface_speed_m_s:.3f} | "
            f"{1e6 * s.event_duration_s:.0f} | {1e-3 * s.natural_frequency_hz:.1f} | "
            f"{1e6 * s.natural_period_s:.1f} | {s.event_over_period:.2f} | "
            f"{1e6 * s.fall_time_s:.0f} |")


SCALE_HEADER = ["| scene | Q N | a_x um | w_x um | w_x/2a_x | drop um | delta(Q) um | "
                "drop/delta | v m/s | w_x/v us | f_n kHz | T_n us | (w_x/v)/T_n | fall us |",
                "|" + "---|" * 14]


def scale_rows() -> list[str]:
    """The CWRU pits at every site (0 hp), the hp speeds, and the default sweep's scene."""
    out = ["CWRU 6205 (config_rig.yaml: its load, preload and centrifugal force), 1797 rpm (0 hp):",
           ""] + SCALE_HEADER
    for label, loc, pos in CWRU_SITES:
        for d in CWRU_PITS_IN:
            out.append(_scale_row(f"{label} {d:.3f} in", defect_scales(rig_scene(d, loc, pos))))
    out += ["", "Motor load (hp) changes the speed only (the rig's radial load is the same): "
            "OR 6:00 per hp:", ""] + SCALE_HEADER
    for hp, rpm in CWRU_RPM.items():
        for d in CWRU_PITS_IN:
            out.append(_scale_row(f"{hp} hp {d:.3f} in", defect_scales(rig_scene(d, rpm=rpm))))
    out += ["", "The catalogue's clearance instead of the rig's preload (centrifugal force on, the "
            "rig's load), 1797 rpm:", ""] + SCALE_HEADER
    for label, pos in (("OR 3:00", 90.0), ("OR 12:00", 180.0)):
        for d in CWRU_PITS_IN:
            s = defect_scales(rig_scene(d, "outer_race", pos, clearance_um=None))
            out.append(_scale_row(f"{label} {d:.3f} in", s))
    out += ["", "Default sweep (config.yaml: FAG 534176, inner race, w = 2 h, 15.8 Hz):", ""] \
        + SCALE_HEADER
    for load in (250.0, 500.0, 750.0):
        for depth in (15.0, 50.0, 100.0):
            s = defect_scales(Scene.default(load_kN=load, depth_um=depth))
            out.append(_scale_row(f"{load:.0f} kN, h {depth:.0f} um", s))
    return out


def main(argv: list[str]) -> int:
    """Print the tables (``--help``: the options)."""
    ap = argparse.ArgumentParser(prog="python -m benchmarks defect_contact")
    ap.add_argument("--fidelity", nargs="+", default=["draft", "standard"])
    ap.add_argument("--scales-only", action="store_true")
    a = ap.parse_args(argv)
    t0 = time.process_time()
    print("\n".join(scale_rows()))
    if not a.scales_only:
        print()
        print("\n".join(table_rows(a.fidelity)))
        print()
        print("\n".join(static_rows(a.fidelity[-1])))
        if "draft" in a.fidelity:
            print()
            print("\n".join(roller_rows("draft")))
    print(f"\n(total CPU {time.process_time() - t0:.1f} s)")
    return 0


def smoke() -> None:
    """The same code path on one draft table and the scales."""
    scale_rows()
    table_rows(["draft"], pits=(0.007,))
    static_rows("draft", pits=(0.007,))
