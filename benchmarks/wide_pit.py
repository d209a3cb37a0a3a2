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

Run: ``python benchmarks/wide_pit.py`` (about 10 CPU s). Prints one row per diameter.
"""

from __future__ import annotations

import math
import time

import numpy as np

from bearing_envelope.contact import solve_contact
from bearing_envelope.physics.geometry import hertz_estimate
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene
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


if __name__ == "__main__":
    main()
