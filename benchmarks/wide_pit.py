"""A ball over an EDM pit wider than its contact: does it bridge the pit, and what does the
window solve's fixed approach miss? (issue 23 part 6, the 0.014 / 0.021 in CWRU pits).

Whole-ellipse solves (no window, no far field) of the CWRU drive-end ball's inner contact at the
most loaded ball's load (1 kN bearing load, ``config_cwru.yaml``), a round pit of diameter D and
depth 279.4 um (0.011 in) centred in the contact:

- ``A``: no pit, force control at Q: approach delta_0, peak p_0;
- ``B``: pit, **displacement control at delta_0** (what the sweep's window solve does: the
  defect is solved at the no-defect approach): force carried, peak, area;
- ``C``: pit, **force control at Q** (the ball sinks until the rest of the ellipse carries Q):
  extra approach, peak, area.

Then the sweep's own route against an independent answer, the scene's pit (cylinder, 20 um rim
radius): the window solve at the no-defect window approach (``physics.solves.defect_solve``,
``standard`` fidelity) and a whole-ellipse solve of the same gap field at the whole-ellipse
no-defect approach (no window, no frozen far field): removed force and peak pressure.

Run: ``python benchmarks/wide_pit.py`` (about a minute of CPU). Prints two tables.
"""

from __future__ import annotations

import math
import time

import numpy as np

from bearing_envelope.contact import solve_contact
from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.geometry import gap_field, hertz_estimate, make_grid
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene
from bearing_envelope.physics.solves import SolveStats, defect_solve, solve_load
from bearing_envelope.study.settings import read_yaml

#: CWRU pit diameters (um): 0.007, 0.014, 0.021 in.
PIT_DIAMETERS_UM = (177.8, 355.6, 533.4)
#: EDM pit depth (um): 0.011 in.
PIT_DEPTH_UM = 279.4
#: Grid spacing across rolling x axial (um) and half-extents (um).
DX_UM, DY_UM = 4.0, 20.0
HALF_X_UM, HALF_Y_UM = 420.0, 1400.0
#: Solver tolerance and iteration budget.
TOL, MAX_ITER = 1e-8, 5000
#: Assumed CWRU bearing load (kN), as in config_cwru.yaml.
LOAD_KN = 1.0
#: Whole-ellipse grid of the window comparison: spacing (um) across rolling x axial.
WHOLE_DX_UM, WHOLE_DY_UM = 2.0, 20.0
#: Fidelity preset of the window solves (the sweep's default).
FIDELITY = "standard"


def window_vs_whole(diameter_um: float) -> dict:
    """Removed force (N) and peak (Pa) of the window solve and of a whole-ellipse solve, both at
    their no-defect approach, for the scene's cylindrical pit of ``diameter_um`` at x_d = 0."""
    m = read_yaml("config_cwru.yaml")["scene"]
    m["defect"]["width_um"] = diameter_um
    sc = Scene.from_mapping(m, load_kN=LOAD_KN, depth_um=PIT_DEPTH_UM)
    q = scene_load_distribution(sc).q_max
    fid, stats = fidelity_from(FIDELITY), SolveStats()
    node = solve_load(sc, fid, q, 1.0, stats)
    ds = defect_solve(sc, fid, node, 0.0, stats)
    grid = make_grid(-HALF_X_UM * 1e-6, HALF_X_UM * 1e-6, -HALF_Y_UM * 1e-6, HALF_Y_UM * 1e-6,
                     WHOLE_DX_UM * 1e-6, WHOLE_DY_UM * 1e-6)
    kw = dict(tol=TOL, max_iter=MAX_ITER)
    e = sc.material.e_star_pa
    s0 = solve_contact(gap_field(sc, grid, None), grid.dx, grid.dy, q, e, **kw)
    s1 = solve_contact(gap_field(sc, grid, 0.0), grid.dx, grid.dy, None, e,
                       approach=s0.approach, **kw)
    removed = q - float(s1.pressure.sum()) * grid.dx * grid.dy
    return {"q": q, "window_removed": ds.removed_force, "whole_removed": removed,
            "window_peak": ds.P, "whole_peak": float(s1.pressure.max())}


def scene_and_load():
    """The CWRU inner contact's scene and the most loaded ball's load (N)."""
    m = read_yaml("config_cwru.yaml")["scene"]
    sc = Scene.from_mapping(m, load_kN=LOAD_KN, depth_um=0.0)
    return sc, scene_load_distribution(sc).q_max


def gap(sc, diameter_um: float | None):
    """Gap (m) of the ellipse with a centred round pit of ``diameter_um`` (flat bottom)."""
    x = np.arange(-HALF_X_UM, HALF_X_UM + 1e-9, DX_UM) * 1e-6
    y = np.arange(-HALF_Y_UM, HALF_Y_UM + 1e-9, DY_UM) * 1e-6
    X, Y = np.meshgrid(x, y, indexing="ij")
    g = X ** 2 / (2 * sc.bearing.rx_m) + Y ** 2 / (2 * sc.bearing.ry_m)
    if diameter_um is not None:
        g = g + np.where(X ** 2 + Y ** 2 <= (0.5e-6 * diameter_um) ** 2, PIT_DEPTH_UM * 1e-6, 0.0)
    return g


def solve(sc, g, force=None, approach=None):
    """One solve on the benchmark grid."""
    return solve_contact(g, DX_UM * 1e-6, DY_UM * 1e-6, force, sc.material.e_star_pa, tol=TOL,
                         max_iter=MAX_ITER, approach=approach)


def main() -> None:
    """Print the three solves per pit diameter."""
    sc, q = scene_and_load()
    h = hertz_estimate(sc, q)
    t0 = time.process_time()
    a = solve(sc, gap(sc, None), force=q)
    print(f"Q = {q:.1f} N, Hertz 2a = {2e6 * h.a:.1f} um, 2b = {2e6 * h.b:.1f} um, "
          f"p0 = {h.p0 / 1e9:.3f} GPa; solved: approach {a.approach * 1e6:.3f} um, "
          f"peak {a.pressure.max() / 1e9:.3f} GPa")
    print("| D (um) | D / 2a | D / 2b | B: force at delta_0 / Q | B: peak (GPa) | "
          "C: extra approach (um) | C: peak (GPa) | C: area / no-pit area | pit bottom loaded |")
    print("|---|---|---|---|---|---|---|---|---|")
    area0 = a.contact_area
    for d in PIT_DIAMETERS_UM:
        g = gap(sc, d)
        b = solve(sc, g, approach=a.approach)
        c = solve(sc, g, force=q)
        fb = float(b.pressure.sum()) * DX_UM * DY_UM * 1e-12
        inside = g > PIT_DEPTH_UM * 1e-6 * 0.5
        bottom = bool(np.any(c.pressure[inside] > 0))
        print(f"| {d:g} | {d / (2e6 * h.a):.2f} | {d / (2e6 * h.b):.2f} | {fb / q:.3f} | "
              f"{b.pressure.max() / 1e9:.3f} | {(c.approach - a.approach) * 1e6:.3f} | "
              f"{c.pressure.max() / 1e9:.3f} | {c.contact_area / area0:.3f} | {bottom} |")
    print(f"CPU {time.process_time() - t0:.1f} s; grid {DX_UM:g} x {DY_UM:g} um")
    assert math.isfinite(a.approach)
    print("\n| D (um) | removed force / Q: window | whole ellipse | peak (GPa): window | "
          "whole ellipse |")
    print("|---|---|---|---|---|")
    t0 = time.process_time()
    for d in PIT_DIAMETERS_UM:
        r = window_vs_whole(d)
        print(f"| {d:g} | {r['window_removed'] / r['q']:.4f} | {r['whole_removed'] / r['q']:.4f} "
              f"| {r['window_peak'] / 1e9:.3f} | {r['whole_peak'] / 1e9:.3f} |")
    print(f"CPU {time.process_time() - t0:.1f} s; window {FIDELITY}, whole ellipse "
          f"{WHOLE_DX_UM:g} x {WHOLE_DY_UM:g} um")


if __name__ == "__main__":
    main()
