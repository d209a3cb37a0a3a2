"""Rim and roller-end peaks with and without a hardness bound, at two grid spacings (issue 13).

    nice -n 5 python benchmarks/plasticity.py > results/plasticity.jsonl

For each load (bearing mode, the most loaded roller Q_max), defect depth, hardness (None =
elastic, and ``BEARING_STEEL_HARDNESS_GPA``) and spacing, one zoom solve as the history does it
(``solve_load`` + ``defect_solve``, ``standard`` otherwise):

- rim peak: the maximum in the defect neighbourhood ``Pd`` over the defect offsets ``--offsets``
  (um), at window spacing ``local_dx_um`` = 2 (``standard``) and 1 um (``paper``);
- roller-end peak: the no-defect maximum outside the defect's read strip (the global grid) at
  global axial spacing ``global_dy_um`` = 80 (``standard``) and 40 um.

Prints one JSON line per solve (CPU seconds by ``time.process_time``) and a markdown table.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np

from bearing_envelope.physics import solves as hi
from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.geometry import gap_field
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import BEARING_STEEL_HARDNESS_GPA, Scene


def _scene(load_kN, depth_um, hardness_GPa):
    return Scene.from_mapping({"material": {"hardness_GPa": hardness_GPa},
                               "operation": {"revolutions": 1.0}}, load_kN=load_kN, depth_um=depth_um)


def rim(load_kN, depth_um, hardness_GPa, dx_um, offsets_um):
    s = _scene(load_kN, depth_um, hardness_GPa)
    q = scene_load_distribution(s).q_max
    fid = fidelity_from({"preset": "standard", "local_dx_um": dx_um})
    st = hi.SolveStats()
    t0 = time.process_time()
    node = hi.solve_load(s, fid, q, 1.0, st)
    out = []
    for xo in offsets_um:
        x = round(1e-6 * xo / node.window.dx) * node.window.dx
        ds = hi.defect_solve(s, fid, node, x, st)
        win = node.window
        plastic = ds.pressure >= s.material.hardness_pa if hardness_GPa else np.zeros(win.shape, bool)
        h = (gap_field(s, win, x) + node.u_ext + node.halfspace.displacement(ds.pressure)
             - node.approach)
        depth = float(np.max(-h[plastic])) if plastic.any() else 0.0
        out.append(dict(x_um=1e6 * x, Pd_GPa=ds.Pd / 1e9, P_GPa=ds.P / 1e9,
                        removed_force_N=ds.removed_force,
                        plastic_cells=int(plastic.sum()),
                        plastic_area_um2=1e12 * float(plastic.sum()) * win.dx * win.dy,
                        plastic_depth_um=1e6 * depth))
    return dict(kind="rim", load_kN=load_kN, depth_um=depth_um, hardness_GPa=hardness_GPa,
                dx_um=dx_um, q_max_N=q, window_dx_um=1e6 * node.window.dx,
                p0_window_GPa=node.w0 / 1e9, outside_max_GPa=node.outside_max / 1e9,
                Pd_max_GPa=max(o["Pd_GPa"] for o in out), offsets=out,
                cpu_s=time.process_time() - t0)


def roller_end(load_kN, hardness_GPa, dy_um):
    s = _scene(load_kN, 50.0, hardness_GPa)
    q = scene_load_distribution(s).q_max
    fid = fidelity_from({"preset": "standard", "global_dy_um": dy_um})
    st = hi.SolveStats()
    t0 = time.process_time()
    p_end = hi.outside_max(s, fid, q, 1.0, st)
    return dict(kind="roller_end", load_kN=load_kN, hardness_GPa=hardness_GPa, dy_um=dy_um,
                q_max_N=q, end_peak_GPa=p_end / 1e9, cpu_s=time.process_time() - t0)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=float, nargs="+", default=[500.0, 750.0])
    ap.add_argument("--depth", type=float, default=50.0)
    ap.add_argument("--dx", type=float, nargs="+", default=[2.0, 1.0])
    ap.add_argument("--dy", type=float, nargs="+", default=[80.0, 40.0])
    ap.add_argument("--offsets", type=float, nargs="+", default=[0.0, 40.0, 44.0, 48.0])
    ap.add_argument("--hardness", type=float, default=BEARING_STEEL_HARDNESS_GPA)
    ap.add_argument("--sweep", action="store_true",
                    help="instead: elastic rim peak at Q_max, x = 0, standard, for every case of "
                         "config.yaml's sweep, against the hardness")
    a = ap.parse_args(argv)
    if a.sweep:
        for load in (250.0, 500.0, 750.0):
            for depth in (15, 20, 30, 40, 50, 60, 80, 100):
                r = rim(load, float(depth), None, 2.0, [0.0])
                r["exceeds_hardness"] = r["Pd_max_GPa"] > a.hardness
                print(json.dumps(r), flush=True)
        return
    rows = []
    for load in a.loads:
        for H in (None, a.hardness):
            for dy in a.dy:
                r = roller_end(load, H, dy)
                rows.append(r)
                print(json.dumps(r), flush=True)
            for dx in a.dx:
                r = rim(load, a.depth, H, dx, a.offsets)
                rows.append(r)
                print(json.dumps(r), flush=True)
    print(f"\n| load (kN) | H (GPa) | rim peak, dx = {' / '.join(f'{v:g}' for v in a.dx)} um (GPa) | "
          f"roller-end peak, dy = {' / '.join(f'{v:g}' for v in a.dy)} um (GPa) |", file=sys.stderr)
    print("|---|---|---|---|", file=sys.stderr)
    for load in a.loads:
        for H in (None, a.hardness):
            rp = [r["Pd_max_GPa"] for r in rows if r["kind"] == "rim" and r["load_kN"] == load
                  and r["hardness_GPa"] == H]
            ep = [r["end_peak_GPa"] for r in rows if r["kind"] == "roller_end" and r["load_kN"] == load
                  and r["hardness_GPa"] == H]
            print(f"| {load:g} | {H or 'elastic'} | {' / '.join(f'{v:.2f}' for v in rp)} | "
                  f"{' / '.join(f'{v:.2f}' for v in ep)} |", file=sys.stderr)


if __name__ == "__main__":
    main()
