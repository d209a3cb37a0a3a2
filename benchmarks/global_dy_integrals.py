"""The global axial grid and the integral signals (issue 25, fourth session), by hand.

    python benchmarks/global_dy_integrals.py probe --load 500 --depth 50 \\
        --gdy 80 40 20 10 --ldy 40 --out results_bench/gdy/probe_ldy40.csv
    python benchmarks/global_dy_integrals.py probe --load 500 --depth 50 \\
        --gdy 80 40 30 25 20 15 10 --ldy 5 --out results_bench/gdy/probe_ldy5.csv
    python benchmarks/global_dy_integrals.py probe --gdy 40 --ldy 40 20 10 5 2.5 \\
        --out results_bench/gdy/ladder_ldy.csv
    python benchmarks/global_dy_integrals.py tables --cases '[[500, 50], [750, 20]]' \\
        --gdy 80 40 20 10 --out results_bench/gdy/tables.csv
    python benchmarks/global_dy_integrals.py report results_bench/gdy/tables.csv

One load node (the table's highest roller load ``q_max`` of the scene, ``kappa`` 1) per global
axial spacing ``global_dy_um``; per node the window's axial layout (``j_lo``, ``j_hi``, ``m``,
its axial spacing and extent), the global force over the window's columns, the window's and the
global no-defect approach, the far field's response (:class:`FarResponse` members); per offset
(``--xi``: multiples of the Hertz half-width) the removed force's parts: the window's force
change at fixed approach (``dF_window``), the far field's uptake and ``removed_force``
(``dF_window - uptake``), and the defect's effective axial length as the window samples it
(the defect's depth summed over the window's columns at its centre row, over the full depth).
Fidelity: ``--preset`` (default ``standard``) with ``global_dy_um`` and ``local_dy_um`` set;
``--rim`` keeps the preset's rim strips (off by default: they move the removed force by
< 0.03 %); ``--sy`` raises the gap's least number of axial sub-points per cell (diagnosis).
The "old" runs of ``docs/benchmarks.md`` ("Global axial grid and the integral signals") ran this
script against the tree before the fix (``git archive f676a93 src | tar -x -C /tmp/old``,
``PYTHONPATH=/tmp/old/src``). CPU seconds (``time.process_time``) per node and per defect solve are recorded.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics import geometry
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene
from bearing_envelope.physics.solves import (SolveStats, _far_uptake, defect_solve, solve_load,
                                             window_spec)


def scene(load, depth, y_d_mm=0.0):
    return Scene.from_mapping({"operation": {"revolutions": 1.0},
                               "defect": {"axial_position_mm": y_d_mm}},
                              load_kN=load, depth_um=depth)


def node_row(sc, fid, nd, cpu) -> dict:
    win, grid = nd.window, nd.grid
    cell = win.dx * win.dy
    cols = (grid.y >= win.y[0] - 1e-12) & (grid.y <= win.y[-1] + 1e-12)
    f_glob = float(nd.pressure[:, cols].astype(float).sum()) * grid.dx * grid.dy
    far = nd.far
    return {"gdy_um": 1e6 * grid.dy, "win_dy_um": 1e6 * win.dy,
            "m": int(round(grid.dy / win.dy)), "n_cols_global": int(cols.sum()),
            "win_y0_um": 1e6 * (win.y[0] - 0.5 * win.dy),
            "win_y1_um": 1e6 * (win.y[-1] + 0.5 * win.dy),
            "f_global_window_cols_n": f_glob,
            "f_window0_n": float(nd.p_window0.sum()) * cell,
            "approach_window_um": 1e6 * nd.approach, "approach_global_um": 1e6 * nd.approach_global,
            "u_ext_centre_um": 1e6 * float(nd.u_ext[win.shape[0] // 2, win.shape[1] // 2]),
            "far_stiffness_n": far.stiffness if far else np.nan,
            "far_window_z_n": far.window_z if far else np.nan,
            "far_window_force_n": far.window_force if far else np.nan,
            "far_z_centre": float(far.z[win.shape[0] // 2, win.shape[1] // 2]) if far else np.nan,
            "p0_pa": nd.p0, "w0_pa": nd.w0, "node_cpu_s": cpu}


def defect_row(sc, fid, nd, x_d, stats) -> dict:
    win = nd.window
    cell = win.dx * win.dy
    c0 = time.process_time()
    ds = defect_solve(sc, fid, nd, x_d, stats)
    cpu = time.process_time() - c0
    up = _far_uptake(nd, ds.pressure)
    # the defect's axial length as the window's gap holds it: its depth summed along the row at
    # the defect's centre, over the full depth
    i = int(np.argmin(np.abs(win.x - x_d)))
    dg = geometry.gap_field(sc, win, x_d)[i] - geometry.gap_field(sc, win, None)[i]
    L_eff = float(np.sum(dg[np.isfinite(dg)])) * win.dy / (1e-6 * sc.defect.depth_um)
    return {"x_d_um": 1e6 * x_d, "removed_force_n": ds.removed_force,
            "dF_window_n": ds.removed_force + up, "uptake_n": up,
            "L_eff_um": 1e6 * L_eff,
            "p_max_pa": ds.P, "W_pa": ds.W, "defect_cpu_s": cpu}


def probe(load, depth, gdys, ldy, xis, preset, rim, sy=None, y_ds=(0.0,),
          end_dy=None) -> pd.DataFrame:
    if sy:  # diagnosis: the gap's axial sub-points per cell (gap_field's default is 2)
        geometry.gap_field.__kwdefaults__["supersample"] = (4, sy)
    q = scene_load_distribution(scene(load, depth)).q_max
    rows = []
    for gdy, ldy1, y_d in [(g, l, y) for g in gdys for l in ldy for y in y_ds]:
        sc = scene(load, depth, y_d)
        spec = {"preset": preset, "global_dy_um": gdy, "local_dy_um": ldy1}
        if not rim:
            spec["rim_dx_um"] = None
        if end_dy:
            spec["end_dy_um"] = end_dy
        fid = fidelity_from(spec)
        stats = SolveStats()
        c0 = time.process_time()
        nd = solve_load(sc, fid, q, 1.0, stats)
        nrow = node_row(sc, fid, nd, time.process_time() - c0)
        a = window_spec(sc, fid, q, 1.0)[0]
        for xi in xis:
            x_d = round(xi * a / nd.window.dx) * nd.window.dx
            r = {"load_kn": load, "depth_um": depth, "q_n": q, "ldy_um": ldy1, "end_dy_um": end_dy, "sy": sy or 2, "y_d_um": 1e3 * y_d, "xi": xi,
                 **nrow, **defect_row(sc, fid, nd, x_d, stats)}
            rows.append(r)
            print({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()},
                  flush=True)
    return pd.DataFrame(rows)


def tables(cases, gdys, ldy, preset) -> pd.DataFrame:
    """The table per case and global axial spacing: per load node its removed force over ``Q``
    at every offset (``rf``), its no-defect window maximum ``w0`` and the largest pressure ratio,
    and the table's CPU seconds."""
    from bearing_envelope.contact import halfspace as _hs
    from bearing_envelope.physics.table import build_table

    rows = []
    for load, depth in cases:
        sc = scene(load, depth)
        q_max = scene_load_distribution(sc).q_max
        for gdy in gdys:
            fid = fidelity_from({"preset": preset, "global_dy_um": gdy, "local_dy_um": ldy})
            with _hs._CACHE_LOCK:
                _hs._CACHE.clear()
            stats = SolveStats()
            c0 = time.process_time()
            table, nodes, _ = build_table(sc, fid, q_max=q_max, stats=stats, progress=None)
            cpu = time.process_time() - c0
            for i, nd in enumerate(nodes):
                for j, xi in enumerate(table.xi_nodes):
                    rows.append({"load_kn": load, "depth_um": depth, "gdy_um": gdy,
                                 "ldy_um": ldy, "node": i, "q_n": nd.q, "j": j, "xi": xi,
                                 "rf": table.ratio_force[i, j], "ratio": table.ratio[i, j],
                                 "w0_pa": nd.w0, "p0_pa": nd.p0,
                                 "win_dy_um": 1e6 * nd.window.dy, "table_cpu_s": cpu,
                                 "n_solves": stats.n_solves})
            print(f"{load:g} kN / {depth:g} um, gdy {gdy:g}: {cpu:.1f} CPU s, "
                  f"max rf {np.abs(table.ratio_force).max():.6g}", flush=True)
    return pd.DataFrame(rows)


def ladder(df: pd.DataFrame, value: str, floor: float = 0.05) -> pd.DataFrame:
    """Per case and global axial step (coarse -> fine), the relative change of ``value`` at each
    (load node, offset) where it is at least ``floor`` of the case's largest: median and max %,
    and the fraction of entries whose ladder is not monotone (a step against the others' sign,
    steps below 0.1 % not counted)."""
    rows = []
    for (load, depth), g in df.groupby(["load_kn", "depth_um"]):
        w = g.pivot_table(index=["node", "j"], columns="gdy_um", values=value)
        w = w[sorted(w.columns, reverse=True)]
        w = w[(w.abs().max(axis=1) >= floor * w.abs().max().max())]
        steps = w.T.pct_change().T.iloc[:, 1:] * 100.0
        for a, b in zip(w.columns[:-1], w.columns[1:]):
            d = steps[b].abs()
            rows.append({"case": f"{load:g} kN / {depth:g} um", "step": f"{a:g} -> {b:g}",
                         "median %": d.median(), "90th pct %": d.quantile(0.9),
                         "max %": d.max()})
        sig = np.sign(steps.where(steps.abs() >= 0.1))
        osc = ((sig > 0).any(axis=1) & (sig < 0).any(axis=1)).mean()
        rows.append({"case": f"{load:g} kN / {depth:g} um", "step": "not monotone",
                     "median %": 100.0 * osc, "90th pct %": np.nan, "max %": np.nan})
    return pd.DataFrame(rows)


def report(paths) -> None:
    """Ladders of the removed force (``rf``) and the table's pressure (``w0 x ratio``) per file
    written by ``tables``, and the tables' CPU seconds."""
    for p in paths:
        df = pd.read_csv(p)
        df["p_window"] = df["w0_pa"] * df["ratio"]
        print(f"## {p}")
        for v in ("rf", "p_window"):
            print(f"### {v}")
            print(ladder(df, v).to_markdown(index=False, floatfmt=".3g"))
        cpu = df.groupby(["load_kn", "depth_um", "gdy_um"])["table_cpu_s"].first().unstack()
        print("### table CPU s")
        print(cpu.to_markdown(floatfmt=".1f"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("probe")
    p.add_argument("--load", type=float, default=500.0)
    p.add_argument("--depth", type=float, default=50.0)
    p.add_argument("--gdy", type=float, nargs="+", default=[80.0, 40.0, 20.0, 10.0])
    p.add_argument("--ldy", type=float, nargs="+", default=[40.0])
    p.add_argument("--y-d-mm", type=float, nargs="+", default=[0.0],
                   help="the defect's axial positions (its sub-cell position in the window)")
    p.add_argument("--end-dy", type=float, default=None, help="axial end strips (um)")
    p.add_argument("--sy", type=int, default=None, help="gap sub-points per cell along y")
    p.add_argument("--xi", type=float, nargs="+", default=[0.0, 0.5, 0.9])
    p.add_argument("--preset", default="standard")
    p.add_argument("--rim", action="store_true")
    p.add_argument("--out", type=Path, required=True)
    t = sub.add_parser("tables")
    t.add_argument("--cases", default="[[500, 50], [750, 20]]", help="JSON [[kN, um], ...]")
    t.add_argument("--gdy", type=float, nargs="+", default=[80.0, 40.0, 20.0, 10.0])
    t.add_argument("--ldy", type=float, default=40.0)
    t.add_argument("--preset", default="standard")
    t.add_argument("--out", type=Path, required=True)
    r = sub.add_parser("report")
    r.add_argument("files", type=Path, nargs="+")
    a = ap.parse_args(argv)
    if a.cmd == "report":
        return report(a.files)
    if a.cmd == "tables":
        df = tables(json.loads(a.cases), a.gdy, a.ldy, a.preset)
    else:
        df = probe(a.load, a.depth, a.gdy, a.ldy, a.xi, a.preset, a.rim, a.sy, a.y_d_mm, a.end_dy)
    a.out.parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(a.out, index=False)


if __name__ == "__main__":
    main()
