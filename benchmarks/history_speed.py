"""Speed and accuracy of the time history (run by hand; results in docs/benchmarks.md).

1. Per case at a fidelity (default ``standard``): wall time, contact solves, solver share, table
   errors, for a few load x depth cases of the default scene (100 revolutions, 411,392 samples).
2. Brute force against the table route: a direct (zoom) contact solve at every sample over a
   stretch of BPFI periods centred on the load-zone centre, compared with the synthesised samples:
   speed-up per case and max |dp|/p.
3. Per-sample synthesis over the whole case: numba kernel against numpy, side by side.
4. Grid convergence of the defect peak (draft / standard / paper) at one (Q, x).

Usage::

    python benchmarks/history_speed.py [--fidelity standard] [--periods 1] [--out results.json]

The machine is shared: the ratios are measured side by side in the same process.
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import time

import numpy as np

from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.history import kinematics, simulate, synthesize, synthesize_numpy
from bearing_envelope.physics.solves import SolveStats
from bearing_envelope.physics.table import direct_pressure
from bearing_envelope.physics.scene import Scene


def per_case(fid, cases):
    rows = []
    for load, depth in cases:
        s = Scene.default(load_kN=load, depth_um=depth)
        h = simulate(s, fid)
        st, info = h.stats, h.table.info
        rows.append({
            "load_kN": load, "depth_um": depth, "wall_s": st["wall_seconds"],
            "n_solves": st["n_solves"], "solver_share": st["solver_seconds"] / st["wall_seconds"],
            "table_nodes": list(h.table.ratio.shape),
            "interp_max": info.get("interp_max_rel_error_p_max", 0.0),
            "interp_rms": info.get("interp_rms_rel_error_p_max", 0.0),
            "any_offset_max": info.get("any_offset_max_rel_error_p_max", 0.0),
            "zoom_consistency": info["zoom_consistency_max"],
            "force_change": info["approach_force_change_max"],
            "p_max_GPa": float(h.p_max.max() / 1e9),
        })
        print(json.dumps(rows[-1]), flush=True)
    return rows


def brute_force(fid, load, depth, periods):
    s = Scene.default(load_kN=load, depth_um=depth)
    t0 = time.perf_counter()
    h = simulate(s, fid)
    t_case = time.perf_counter() - t0
    fs, bpfi = s.operation.fs_hz, s.bpfi_hz
    # samples of `periods` BPFI periods centred on an event near the load-zone centre (t = 0 is
    # such an event; take the one a whole revolution later so no edge effects)
    k0 = round(bpfi / s.operation.shaft_rate_hz)
    c = int(round(k0 * fs / bpfi))
    half = int(round(0.5 * periods * fs / bpfi))
    idx = np.arange(c - half, c + half)
    kin = kinematics(s, h.time[idx])
    q = h.load_distribution.load_at(kin["theta_shaft"])
    stats = SolveStats()
    t1 = time.perf_counter()
    direct = np.array([direct_pressure(s, fid, float(qq), float(xx), kappa=h.table.kappa,
                                       stats=stats) for qq, xx in zip(q, kin["offset"])])
    t_brute = time.perf_counter() - t1
    per_sample = t_brute / idx.size
    err = np.abs(h.p_max[idx] - direct[:, 0]) / direct[:, 0]
    errd = np.abs(h.p_max_defect[idx] - direct[:, 1]) / np.max(direct[:, 0])
    # the same comparison with the offsets snapped to the window grid (no sub-cell jitter)
    dx = h.table.info["window_dx"]
    xs = np.round(kin["offset"] / dx) * dx
    near = np.abs(kin["offset"]) < h.table.scale(q)      # only where the defect matters
    sel = np.flatnonzero(near)
    snapped = np.array([direct_pressure(s, fid, float(q[i]), float(xs[i]), kappa=h.table.kappa)
                        for i in sel])
    tab = h.table.evaluate(q[sel], xs[sel])[0]
    err_snap = np.abs(tab - snapped[:, 0]) / snapped[:, 0] if sel.size else np.zeros(1)
    out = {
        "load_kN": load, "depth_um": depth, "samples": int(idx.size),
        "samples_with_defect_in_contact": int(sel.size),
        "case_wall_s": t_case, "brute_per_sample_s": per_sample,
        "brute_solves": stats.n_solves,
        "brute_case_estimate_s": per_sample * h.time.size,
        "speedup_per_case": per_sample * h.time.size / t_case,
        "speedup_same_samples": t_brute / t_case,
        "max_rel_err_p_max": float(err.max()), "rms_rel_err_p_max": float(np.sqrt(np.mean(err ** 2))),
        "max_err_p_max_defect_over_pmax": float(errd.max()),
        "max_rel_err_p_max_on_grid_offsets": float(err_snap.max()),
    }
    print(json.dumps(out), flush=True)
    return out


def synthesis(fid, load=500, depth=50, repeat=5):
    s = Scene.default(load_kN=load, depth_um=depth)
    h = simulate(s, "draft")
    t = h.time
    synthesize(s, h.table, h.load_distribution, t[:100])  # JIT warm-up
    tn, tp = [], []
    for _ in range(repeat):
        a = time.perf_counter()
        synthesize(s, h.table, h.load_distribution, t)
        b = time.perf_counter()
        synthesize_numpy(s, h.table, h.load_distribution, t)
        c = time.perf_counter()
        tn.append(b - a)
        tp.append(c - b)
    out = {"samples": int(t.size), "numba_s": min(tn), "numpy_s": min(tp),
           "numpy_over_numba": min(tp) / min(tn)}
    print(json.dumps(out), flush=True)
    return out


def convergence(load=500, depth=50, xs=(0.0, 0.1e-3)):
    s = Scene.default(load_kN=load, depth_um=depth)
    from bearing_envelope.physics.loads import scene_load_distribution

    q = scene_load_distribution(s).q_max
    rows = []
    for name in ("draft", "standard", "paper"):
        fid = fidelity_from(name)
        for x in xs:
            t0 = time.perf_counter()
            P, Pd = direct_pressure(s, fid, q, x)
            rows.append({"fidelity": name, "local_dx_um": fid.local_dx_um, "x_um": x * 1e6,
                         "P_GPa": P / 1e9, "seconds": time.perf_counter() - t0})
            print(json.dumps(rows[-1]), flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fidelity", default="standard")
    ap.add_argument("--periods", type=float, default=1.0, help="BPFI periods of brute force")
    ap.add_argument("--skip", nargs="*", default=[], choices=["cases", "brute", "synth", "conv"])
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    fid = fidelity_from(args.fidelity)
    res = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
           "machine": subprocess.run("lscpu | head -15", shell=True, capture_output=True,
                                     text=True).stdout, "python": platform.python_version(),
           "fidelity": fid.to_dict()}
    if "synth" not in args.skip:
        res["synthesis"] = synthesis(fid)
    if "cases" not in args.skip:
        res["cases"] = per_case(fid, [(250, 15), (500, 50), (750, 100), (750, 15), (500, 0)])
    if "brute" not in args.skip:
        res["brute"] = brute_force(fid, 500, 50, args.periods)
    if "conv" not in args.skip:
        res["convergence"] = convergence()
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(res, fh, indent=1)


if __name__ == "__main__":
    main()
