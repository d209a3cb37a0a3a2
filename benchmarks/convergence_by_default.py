"""Issue 25 "Right and converged by default, at today's cost": the measurements of
``docs/benchmarks.md``, section "Convergence by default (issue 25)".

    nice -n 5 python benchmarks/convergence_by_default.py amplitudes [--fidelity draft]
    nice -n 5 python benchmarks/convergence_by_default.py cache --fidelity draft standard \\
        --depths 15 50 100 --load 500 [--cache DIR] [--revolutions 100]
    nice -n 5 python benchmarks/convergence_by_default.py margin --load 500 --depth 50 \\
        --margins 400 1600 6400 whole

``amplitudes``: one simulated case (500 kN / 50 um, 100 revolutions) analysed with
``analysis.amplitude: peak_bin`` and ``interpolated`` side by side (config.yaml's bands): the
ratio interpolated / peak bin of every envelope 1 x and 2 x BPFI and raw line.

``cache``: CPU seconds (``time.process_time``) of ``simulate`` per case of a mini-sweep (one
load, a few depths, each fidelity), in one process, cases in sweep order, after a warm-up case
(numba compilation); with ``--cache DIR`` the no-defect solves are shared through the
content-addressed cache (start from an empty DIR to include the misses). Prints the sha256 of
each case's signals, to compare with a run without the cache.

``margin``: the removed force at the table's largest load and the centred defect (x = 0) for
the window's axial margins (um; ``whole``: a window over the whole roller), from a direct zoom
solve (:func:`bearing_envelope.physics.table.direct_pressure`'s route).
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import inspect
import platform
import sys
import time
from datetime import datetime, timezone

import numpy as np

from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.history import CONTACT_SIGNALS, simulate
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene
from bearing_envelope.physics.solves import SolveStats, defect_solve, solve_load
from bearing_envelope.study.pipeline import case_bands, case_harmonics, history_case
from bearing_envelope.study.settings import CaseId, load_settings

#: The warm-up case (compiles the numba kernels before the timed cases): draft, healthy.
WARMUP_REVOLUTIONS = 2


def _stamp() -> str:
    return (f"{datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC, {platform.node()}, "
            f"{platform.processor() or platform.machine()}, Python {platform.python_version()}")


def signals_sha256(hist) -> str:
    """sha256 over every contact signal of a case (float64 bytes, in CONTACT_SIGNALS order)."""
    h = hashlib.sha256()
    for k in CONTACT_SIGNALS:
        h.update(np.ascontiguousarray(hist.signals[k], dtype=np.float64).tobytes())
    return h.hexdigest()


def _simulate(scene, fid, cache):
    if cache is None:
        return simulate(scene, fid)
    if "nodefect_cache" not in inspect.signature(simulate).parameters:
        sys.exit("this tree's simulate() has no nodefect_cache (run without --cache)")
    return simulate(scene, fid, nodefect_cache=cache)


def run_cache(args) -> None:
    print(f"# cache mini-sweep: {_stamp()}; cache: {args.cache}; revolutions {args.revolutions}")
    op = {"operation": {"revolutions": args.revolutions}}
    _simulate(Scene.from_mapping({"operation": {"revolutions": WARMUP_REVOLUTIONS}},
                                 load_kN=args.load, depth_um=0.0), fidelity_from("draft"), None)
    print("| fidelity | case | CPU s | solves | cache hits / misses | sha256 of the signals |")
    print("|---|---|---|---|---|---|")
    for name in args.fidelity:
        fid = fidelity_from(name)
        total = 0.0
        for depth in args.depths:
            sc = Scene.from_mapping(op, load_kN=args.load, depth_um=depth)
            c0 = time.process_time()
            hist = _simulate(sc, fid, args.cache)
            dt = time.process_time() - c0
            total += dt
            st = hist.stats
            hm = f"{st.get('nodefect_cache_hits', '-')} / {st.get('nodefect_cache_misses', '-')}"
            print(f"| {name} | F{args.load:g}kN_h{depth:g}um | {dt:.2f} | {st['n_solves']} | {hm} "
                  f"| {signals_sha256(hist)[:16]} |", flush=True)
        print(f"| {name} | mean of {len(args.depths)} | {total / len(args.depths):.2f} | | | |",
              flush=True)


def run_amplitudes(args) -> None:
    st = load_settings(args.config)
    sc = st.scene(CaseId(args.load, args.depth))
    hist = simulate(sc, fidelity_from(args.fidelity))
    case = history_case(hist)
    print(f"# amplitudes: {_stamp()}; F{args.load:g}kN_h{args.depth:g}um, {args.fidelity}, "
          f"signal {st.analysis.signal}")
    tables = {}
    for est in ("peak_bin", "interpolated"):
        an = dataclasses.replace(st.analysis, amplitude=est)
        bands, _ = case_bands(case, an)
        tables[est] = case_harmonics(case, an, bands).set_index(
            ["band", "quantity", "order", "sideband"])
    print("| band | quantity | order | peak bin | interpolated | interpolated / peak bin |")
    print("|---|---|---|---|---|---|")
    a, b = tables["peak_bin"], tables["interpolated"]
    for key in a.index:
        band, q, k, m = key
        if m != 0 or q not in ("raw_fr", "raw_bpfi", "envelope_bpfi") or k > 2:
            continue
        va, vb = float(a.loc[key, "amplitude"]), float(b.loc[key, "amplitude"])
        print(f"| {band} | {q} | {k} | {va:.4g} | {vb:.4g} | {vb / va:.4f} |")


#: A window margin (um) beyond either roller end from the roller's centre: the whole roller.
WHOLE_ROLLER_MARGIN_UM = 1e6


def removed_force(scene, fid, q, x_d=0.0):
    """``(removed force N, approach m, p_max Pa, window solves CPU s)`` of one direct zoom solve
    at roller load ``q`` and offset ``x_d``."""
    stats = SolveStats()
    c0 = time.process_time()
    node = solve_load(scene, fid, q, 1.0, stats)
    ds = defect_solve(scene, fid, node, x_d, stats)
    return ds.removed_force, node.approach, ds.P, time.process_time() - c0


def run_margin(args) -> None:
    sc = Scene.from_mapping(None, load_kN=args.load, depth_um=args.depth)
    q = scene_load_distribution(sc).q_max
    print(f"# margin: {_stamp()}; F{args.load:g}kN_h{args.depth:g}um, Q_max = {q:.6g} N, "
          f"x = 0, {args.fidelity}")
    print("| far field | margin um | removed force N | approach um | p_max GPa | CPU s |")
    print("|---|---|---|---|---|---|")
    for far in args.far_field:
        for mg in args.margins:
            margin = WHOLE_ROLLER_MARGIN_UM if mg == "whole" else float(mg)
            fid = fidelity_from({"preset": args.fidelity, "window_margin_um": margin,
                                 "far_field": far})
            dF, d0, P, dt = removed_force(sc, fid, q)
            print(f"| {far} | {mg} | {dF:.4g} | {1e6 * d0:.5f} | {1e-9 * P:.5g} | {dt:.1f} |",
                  flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("cache")
    c.add_argument("--fidelity", nargs="+", default=["draft", "standard"])
    c.add_argument("--depths", type=float, nargs="+", default=[15.0, 50.0, 100.0])
    c.add_argument("--load", type=float, default=500.0)
    c.add_argument("--revolutions", type=float, default=100.0)
    c.add_argument("--cache", default=None)
    a = sub.add_parser("amplitudes")
    a.add_argument("--config", default="config.yaml")
    a.add_argument("--fidelity", default="draft")
    a.add_argument("--load", type=float, default=500.0)
    a.add_argument("--depth", type=float, default=50.0)
    g = sub.add_parser("margin")
    g.add_argument("--fidelity", default="standard")
    g.add_argument("--load", type=float, default=500.0)
    g.add_argument("--depth", type=float, default=50.0)
    g.add_argument("--margins", nargs="+", default=["400", "1600", "6400", "whole"])
    g.add_argument("--far-field", nargs="+", default=["frozen", "responds"])
    args = ap.parse_args(argv)
    {"cache": run_cache, "amplitudes": run_amplitudes, "margin": run_margin}[args.cmd](args)


if __name__ == "__main__":
    main()
