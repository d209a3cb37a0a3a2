"""Rim strips at 0.5 um inside the 2 um window against a uniform 0.5 um window (issue 13.2).

    nice -n 5 python benchmarks/rim_refinement.py [--loads 500] [--depth 50] [--hardness GPa]

One case (bearing mode, the most loaded roller Q_max, default scene): at each defect offset,
the peak (maximum in the read strip P and in the defect neighbourhood P_d) and the removed force
from (a) the ``standard`` window (2 um), (b) the same plus rim strips at ``--rim-dx`` um
(``fidelity.rim_dx_um``), (c) a uniform window at ``--rim-dx`` (``local_dx_um``), with CPU
seconds (``time.process_time``) of the window-level solves (the no-defect global and window
solves are excluded: they are the same for (a) and (b)). Prints JSON lines.
"""

from __future__ import annotations

import argparse
import json
import time

from bearing_envelope.physics import solves as hi
from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=float, nargs="+", default=[500.0])
    ap.add_argument("--depth", type=float, default=50.0)
    ap.add_argument("--hardness", type=float, default=None)
    ap.add_argument("--rim-dx", type=float, default=0.5)
    ap.add_argument("--offsets", type=float, nargs="+", default=[0.0, 40.0, 44.0, 150.0])
    a = ap.parse_args(argv)
    for load in a.loads:
        s = Scene.from_mapping({"material": {"hardness_GPa": a.hardness},
                                "operation": {"revolutions": 1.0}}, load_kN=load, depth_um=a.depth)
        q = scene_load_distribution(s).q_max
        variants = {
            "window 2 um": {"preset": "standard"},
            f"window 2 um + rim strips {a.rim_dx:g} um": {"preset": "standard", "rim_dx_um": a.rim_dx},
            f"uniform window {a.rim_dx:g} um": {"preset": "standard", "local_dx_um": a.rim_dx},
        }
        for name, spec in variants.items():
            fid = fidelity_from(spec)
            st = hi.SolveStats()
            node = hi.solve_load(s, fid, q, 1.0, st)
            for xo in a.offsets:
                x = round(1e-6 * xo / node.window.dx) * node.window.dx
                t0 = time.process_time()
                ds = hi.defect_solve(s, fid, node, x, st)
                cpu = time.process_time() - t0
                print(json.dumps({"load_kN": load, "depth_um": a.depth, "hardness_GPa": a.hardness,
                                  "variant": name, "x_um": 1e6 * x, "P_GPa": ds.P / 1e9,
                                  "Pd_GPa": ds.Pd / 1e9, "removed_force_N": ds.removed_force,
                                  "area_change_um2": 1e12 * ds.area_change, "cpu_s": cpu}),
                      flush=True)


if __name__ == "__main__":
    main()
