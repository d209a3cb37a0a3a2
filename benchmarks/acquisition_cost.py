"""CPU cost of the anti-aliased acquisition against point samples, side by side (issue 12 part 6).

    nice -n 5 python benchmarks/acquisition_cost.py [--load 750 --depth 100] [--repeat 3]

One case at ``standard`` (100 revolutions, 411,392 samples; checks and snapshots as in the
sweep): the contact table is built once (its CPU time reported), then the synthesis of every
signal from it with ``{mode: point}`` and ``{mode: antialiased, oversample: auto}`` is timed
alternately, ``--repeat`` times each (process CPU seconds, best and median: the machine is
shared). Prints one markdown table.
"""

from __future__ import annotations

import argparse
import statistics
import time

from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.acquisition import acquisition_settings
from bearing_envelope.physics.history import synthesize_case
from bearing_envelope.physics.solves import SolveStats
from bearing_envelope.physics.table import build_table
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--load", type=float, default=750.0)
    ap.add_argument("--depth", type=float, default=100.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    sc = Scene.from_mapping(None, load_kN=args.load, depth_um=args.depth)
    fid = fidelity_from("standard")
    ld = scene_load_distribution(sc)
    c0 = time.process_time()
    table, _, _ = build_table(sc, fid, q_max=ld.q_max, stats=SolveStats(), progress=None)
    t_table = time.process_time() - c0
    acqs = {"point": {"mode": "point", "oversample": 1},
            "antialiased": acquisition_settings(sc, fid)}     # the default: antialiased, auto
    synthesize_case(sc, table, ld, fid, acquisition=acqs["point"])      # numba compile
    times = {k: [] for k in acqs}
    info = {}
    for _ in range(args.repeat):
        for k, acq in acqs.items():
            c0 = time.process_time()
            _, sig, meta = synthesize_case(sc, table, ld, fid, acquisition=acq)
            times[k].append(time.process_time() - c0)
            info[k] = meta
    n = acqs["antialiased"]
    print(f"case F{args.load:g}kN_h{args.depth:g}um, standard, {len(sig['p_max'])} samples; "
          f"table {t_table:.1f} s CPU; antialiased: oversample {n['oversample']}, "
          f"{n['filter_taps']} taps")
    print("| acquisition | synthesis CPU s, best / median | case CPU (table + best synthesis) "
          "| ratio to point |")
    print("|---|---|---|---|")
    base = t_table + min(times["point"])
    for k, t in times.items():
        tot = t_table + min(t)
        print(f"| {k} | {min(t):.2f} / {statistics.median(t):.2f} | {tot:.1f} | "
              f"{tot / base:.2f} (synthesis alone {min(t) / min(times['point']):.1f}x) |")


if __name__ == "__main__":
    main()
