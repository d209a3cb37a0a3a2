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
solve (:func:`bearing_envelope.physics.table.direct_pressure`'s route), far field frozen and
responding.

``dump`` / ``diff``: the sweep's numbers before and after: ``dump`` (run once with each tree on
``PYTHONPATH``) stores the signals of a few cases; ``diff`` (this tree) reads the main envelope
and raw lines of both with the same bands and prints after / before per signal (physics at the
peak bin, estimator, both)::

    PYTHONPATH=old/src python benchmarks/convergence_by_default.py dump --out /tmp/before
    PYTHONPATH=src python benchmarks/convergence_by_default.py dump --out /tmp/after
    PYTHONPATH=src python benchmarks/convergence_by_default.py diff --before /tmp/before \
        --after /tmp/after

``acquisition``: the post-event undershoot of p_max, its peak and the kurtogram's best cell for
point samples, today's Kaiser FIR and three non-negative decimation kernels.

Run 2026-11-26 for ``docs/benchmarks.md``, "Convergence by default (issue 25)".
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
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from bearing_envelope.physics.acquisition import antialias_filter
from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.history import CONTACT_SIGNALS, evaluate_signals, simulate
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene
from bearing_envelope.physics.solves import SolveStats, defect_solve, solve_load
from bearing_envelope.physics.table import build_table
from bearing_envelope.signal import fast_kurtogram
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


def run_dump(args) -> None:
    """Simulate cases with this tree's code and store their signals (to compare trees)."""
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for spec in args.cases:
        load, depth = (float(v) for v in spec.split(":"))
        sc = Scene.from_mapping(None, load_kN=load, depth_um=depth)
        c0 = time.process_time()
        hist = simulate(sc, fidelity_from(args.fidelity))
        dt = time.process_time() - c0
        ff = sc.frequencies()
        np.savez(out / f"F{load:g}kN_h{depth:g}um.npz", fs=sc.operation.fs_hz,
                 fr=sc.operation.shaft_rate_hz, bpfi=sc.bpfi_hz, bpfo=ff.bpfo, ftf=ff.ftf,
                 bsf=ff.bsf, load_kN=load, depth_um=depth, cpu_s=dt,
                 **{k: hist.signals[k] for k in CONTACT_SIGNALS})
        print(f"{spec}: {dt:.1f} s CPU", flush=True)


def _dumped_case(path):
    z = np.load(path)
    sig = {k: z[k] for k in CONTACT_SIGNALS if k in z}
    return SimpleNamespace(signals=sig, fs=float(z["fs"]), fr=float(z["fr"]),
                           bpfi=float(z["bpfi"]), bpfo=float(z["bpfo"]), ftf=float(z["ftf"]),
                           bsf=float(z["bsf"]), load_kN=float(z["load_kN"]),
                           depth_um=float(z["depth_um"]), attrs={}, scene=None)


def _lines(case, analysis, signal, estimator):
    an = dataclasses.replace(analysis, signal=signal, amplitude=estimator)
    bands, _ = case_bands(case, an)
    df = case_harmonics(case, an, bands)
    keep = df["quantity"].isin(["raw_bpfi", "envelope_bpfi"]) & (df["sideband"] == 0) & \
        (df["order"] <= 2)
    return df[keep].set_index(["band", "quantity", "order"])["amplitude"]


def run_diff(args) -> None:
    """Ratios of the main amplitudes after / before (same bands, per signal): the physics
    change (both read at the peak bin), the estimator change, and both."""
    analysis = load_settings(args.config).analysis
    print(f"# diff: {_stamp()}; before {args.before}, after {args.after}")
    print("| case | signal | quantity | physics (after / before, peak bin) | estimator "
          "(interpolated / peak bin, after) | both |")
    print("|---|---|---|---|---|---|")
    for path in sorted(Path(args.before).glob("*.npz")):
        before, after = _dumped_case(path), _dumped_case(Path(args.after) / path.name)
        if before.depth_um == 0:
            continue
        for signal in args.signals:
            b = _lines(before, analysis, signal, "peak_bin")
            a = _lines(after, analysis, signal, "peak_bin")
            ai = _lines(after, analysis, signal, "interpolated")
            for q, k in (("envelope_bpfi", 1), ("envelope_bpfi", 2), ("raw_bpfi", 1)):
                sel = [i for i in b.index if i[1] == q and i[2] == k]
                phys = np.array([a[i] / b[i] for i in sel])
                est = np.array([ai[i] / a[i] for i in sel])
                both = np.array([ai[i] / b[i] for i in sel])
                def rng(v):
                    return f"{v.min():.3f}-{v.max():.3f}" if v.size > 1 else f"{v[0]:.3f}"
                print(f"| {path.stem} | {signal} | {k} x BPFI {q.split('_')[0]} "
                      f"({len(sel)} bands) | {rng(phys)} | {rng(est)} | {rng(both)} |",
                      flush=True)


def _kernels(n: int) -> dict[str, np.ndarray]:
    """Decimation kernels at ``n x fs`` compared by ``acquisition``: today's Kaiser FIR and
    three non-negative ones (a box over 1/fs: an integrating ADC; a triangle over 2/fs; a
    Gaussian of sigma 1/(2 fs))."""
    g = np.exp(-0.5 * (np.arange(-4 * n, 4 * n + 1) / (0.5 * n)) ** 2)
    return {"kaiser FIR (today)": antialias_filter(n), "box 1/fs": np.ones(n) / n,
            "triangle 2/fs": np.convolve(np.ones(n), np.ones(n)) / n ** 2,
            "gaussian sigma 1/(2 fs)": g / g.sum()}


def _acquired(x: np.ndarray, k: np.ndarray, n: int, lead: int, n_out: int) -> np.ndarray:
    """``x`` (internal samples from ``-lead``) filtered by the centred kernel ``k`` at every
    ``n``-th sample from 0."""
    c = (k.size - 1) // 2
    return np.convolve(x, k, mode="full")[c + lead: c + lead + n * n_out: n][:n_out]


def run_acquisition(args) -> None:
    """Post-event undershoot of p_max below the healthy race's (same acquisition, load-zone
    samples where the healthy p_max exceeds half its maximum), the peak against the internal
    maximum, the response at fs/4 and fs/2, and the kurtogram's best cell, per kernel."""
    fid = fidelity_from(args.fidelity)
    n = args.oversample
    lead = (antialias_filter(n).size - 1) // 2
    print(f"# acquisition: {_stamp()}; {args.load:g} kN, {args.fidelity}, "
          f"{args.revolutions:g} revolutions, internal rate {n} x fs")
    print("| depth um | kernel | |H| at fs/4, fs/2 | undershoot below healthy % | peak / internal "
          "max | kurtogram best cell Hz (kurtosis) |")
    print("|---|---|---|---|---|---|")
    healthy = {}
    for depth in args.depths:
        sc = Scene.from_mapping({"operation": {"revolutions": args.revolutions}},
                                load_kN=args.load, depth_um=depth)
        ld = scene_load_distribution(sc)
        table, _, _ = build_table(sc, fid, q_max=ld.q_max, stats=SolveStats())
        fs, n_out = sc.operation.fs_hz, sc.n_samples
        j = np.arange(-lead, n * n_out + lead + 1)
        x = evaluate_signals(sc, table, ld, j / (n * fs))["p_max"]
        kern = {**_kernels(n), "point": None}
        for name, k in kern.items():
            y = x[lead::n][:n_out] if k is None else _acquired(x, k, n, lead, n_out)
            if depth == 0:
                healthy[name] = y
            h0 = healthy[name]
            sel = h0 > 0.5 * h0.max()
            under = 100 * float(((y[sel] - h0[sel]) / h0[sel]).min())
            kg = fast_kurtogram(y - y.mean(), fs, args.nlevel)
            resp = "-" if k is None else ", ".join(
                f"{abs(np.sum(k * np.exp(-2j * np.pi * f * np.arange(k.size) / n))):.3g}"
                for f in (0.25, 0.5))
            print(f"| {depth:g} | {name} | {resp} | {under:.2f} | {y.max() / x.max():.4f} | "
                  f"{kg.fc - kg.bandwidth / 2:.0f}-{kg.fc + kg.bandwidth / 2:.0f} "
                  f"({kg.kurtosis:.3g}) |", flush=True)


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
    d = sub.add_parser("dump")
    d.add_argument("--out", required=True)
    d.add_argument("--fidelity", default="standard")
    d.add_argument("--cases", nargs="+", default=["500:0", "500:15", "500:50", "500:100"])
    f = sub.add_parser("diff")
    f.add_argument("--before", required=True)
    f.add_argument("--after", required=True)
    f.add_argument("--config", default="config.yaml")
    f.add_argument("--signals", nargs="+", default=["p_max", "removed_force",
                                                     "approach_change"])
    q = sub.add_parser("acquisition")
    q.add_argument("--fidelity", default="standard")
    q.add_argument("--load", type=float, default=500.0)
    q.add_argument("--depths", type=float, nargs="+", default=[0.0, 15.0, 50.0, 100.0])
    q.add_argument("--revolutions", type=float, default=10.0)
    q.add_argument("--oversample", type=int, default=8)
    q.add_argument("--nlevel", type=int, default=8)
    args = ap.parse_args(argv)
    {"cache": run_cache, "amplitudes": run_amplitudes, "margin": run_margin, "dump": run_dump,
     "diff": run_diff, "acquisition": run_acquisition}[args.cmd](args)


if __name__ == "__main__":
    main()
