"""Roller-end pressure peak of the no-defect contact and its grid convergence (issue 12 part 6).

    nice -n 5 python benchmarks/roller_end.py

Global no-defect solve over the whole roller (the route of the history table,
``history.global_solve``) at the most loaded roller's Q_max of each bearing load, with the
``standard`` global grid (10 um across rolling x 80 um axial) and the axial spacing halved down
to 10 um (and 5 um across rolling at 20 um axial). Prints a markdown table: loaded half-length,
pressure at the centre, maximum and where, end / centre; then the change of the end peak per
halving of the axial spacing, its observed order and Richardson value.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.geometry import hertz_estimate
from bearing_envelope.physics.solves import SolveStats, global_solve
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene

LOADS = (250.0, 500.0, 750.0)
GRIDS = ((10.0, 160.0), (10.0, 80.0), (10.0, 40.0), (10.0, 20.0), (10.0, 10.0), (5.0, 20.0))


def solve(load, dx, dy):
    sc = Scene.from_mapping(None, load_kN=load, depth_um=0.0)
    q = scene_load_distribution(sc).q_max
    fid = fidelity_from({"preset": "standard", "global_dx_um": dx, "global_dy_um": dy})
    a = hertz_estimate(sc, q).a
    c0 = time.process_time()
    grid, sol = global_solve(sc, fid, q, fid.global_extent * a, SolveStats())
    p = sol.pressure
    loaded_y = grid.y[np.any(p > 0, axis=0)]
    i, j = np.unravel_index(int(np.argmax(p)), p.shape)
    jc = int(np.argmin(np.abs(grid.y)))
    return {"load": load, "q_kN": 1e-3 * q, "dx": dx, "dy": dy,
            "half_length_mm": 1e3 * (np.max(np.abs(loaded_y)) + 0.5 * grid.dy),
            "p_centre": 1e-9 * float(p[:, jc].max()), "p_max": 1e-9 * float(p.max()),
            "y_max_mm": 1e3 * abs(float(grid.y[j])), "cpu_s": time.process_time() - c0}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.parse_args(argv)
    rows = [solve(load, dx, dy) for load in LOADS for dx, dy in GRIDS]
    print("| F (kN) | Q_max (kN) | global grid (um) | loaded half-length (mm) | p at the centre "
          "(GPa) | maximum (GPa), where | end / centre | CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['load']:g} | {r['q_kN']:.2f} | {r['dx']:g} x {r['dy']:g} | "
              f"{r['half_length_mm']:.2f} | {r['p_centre']:.2f} | {r['p_max']:.2f}, |y| = "
              f"{r['y_max_mm']:.2f} mm | {r['p_max'] / r['p_centre']:.2f} | {r['cpu_s']:.1f} |")
    print()
    print("| F (kN) | end peak at dy = 80 / 40 / 20 / 10 um (GPa) | order p (40, 20, 10) | "
          "Richardson (GPa) | error of 80 um |")
    print("|---|---|---|---|---|")
    for load in LOADS:
        v = {r["dy"]: r["p_max"] for r in rows if r["load"] == load and r["dx"] == 10.0}
        f40, f20, f10 = v[40.0], v[20.0], v[10.0]
        d1, d2 = f10 - f20, f20 - f40
        if d1 and d2 and d1 * d2 > 0:
            p = math.log(abs(d2 / d1), 2)
            fx = f10 + d1 / (2 ** p - 1) if p > 0 else float("nan")
        else:
            p, fx = float("nan"), float("nan")
        err = abs(v[80.0] - fx) / fx if math.isfinite(fx) else float("nan")
        print(f"| {load:g} | {v[80.0]:.2f} / {f40:.2f} / {f20:.2f} / {f10:.2f} | {p:.2f} | "
              f"{fx:.2f} | {100 * err:.0f} % |")


if __name__ == "__main__":
    main()
