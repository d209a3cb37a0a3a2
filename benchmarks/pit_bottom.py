"""Depth below which the pit bottom carries load, per load (issue 12 part 4), by hand.

    nice -n 5 python benchmarks/pit_bottom.py --out results_bench/pit_bottom

For each bearing load (250/500/750 kN, the most loaded roller's Q_max, defect at the centre of
its contact and at 1/4, 1/2 of the Hertz half-width), :func:`bearing_envelope.physics.pit.depth_threshold`
bisects the depth (1 % bracket) at which the pit's deepest cells first carry pressure, for the
default width rule w = 2 h and for fixed widths (60 um, 200 um), at ``standard`` and with the
defect window's spacing halved (1 um). Next to it the plane-strain estimate of how far the
roller sinks into a traction-free slot of width w in a contact at pressure p0 (the face
displacement of a Griffith crack, ``2 p0 c / E*`` with c = w/2; rounded rims make the free slot
narrower; p0 = the no-defect pressure at the defect's axial position, scaled by
sqrt(1 - (x/a)^2) off the contact centre); with w = 2 h (a round trough of radius r for h < r)
the depth at which the trough is as deep as that (``pit.slot_estimate``). Writes
``pit_bottom.csv`` and prints a markdown table (``--report-only`` re-prints it from the csv).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import pandas as pd

from bearing_envelope.physics.pit import depth_threshold, pit_scene, slot_estimate

LOADS = (250.0, 500.0, 750.0)
WIDTHS = (None, 60.0, 200.0)
FIDS = {"standard": {"preset": "standard"}, "dx 1 um": {"preset": "standard", "local_dx_um": 1.0}}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--offsets", type=float, nargs="+", default=[0.0, 0.25, 0.5],
                    help="defect offsets as fractions of the Hertz half-width a")
    ap.add_argument("--report-only", action="store_true")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.report_only:
        print(markdown(pd.read_csv(args.out / "pit_bottom.csv")))
        return
    rows = []
    for fname, fid in FIDS.items():
        for load in LOADS:
            e_star = pit_scene(None, load, 50.0, None).material.e_star_pa
            for w in WIDTHS:
                for off in args.offsets:
                    c0 = time.process_time()
                    # offsets in m need a: take it from the first solve at offset 0
                    x_d = 0.0
                    if off:
                        a = next(r for r in rows if r["load_kN"] == load)["a_um"] * 1e-6
                        x_d = off * a
                    h_lo = 0.5 if w is None else 0.05
                    h, log = depth_threshold(load, w, fid, x_d=x_d, h_lo=h_lo, h_hi=200.0)
                    p0, a_h = log[0].p_centre, log[0].a_hertz
                    rows.append({"fidelity": fname, "load_kN": load,
                                 "width": "2 h" if w is None else f"{w:g} um",
                                 "offset_a": off, "q_max_kN": 1e-3 * log[0].q_load,
                                 "p_centre_GPa": 1e-9 * p0, "a_um": 1e6 * a_h, "h_star_um": h,
                                 "slot_estimate_um": slot_estimate(
                                     p0 * math.sqrt(1 - off ** 2), e_star, w),
                                 "bottom_depth_at_h_star_um": min(
                                     (r.max_cell_depth_um for r in log
                                      if abs(math.log(r.depth_um / h)) < 0.02), default=math.nan),
                                 "solves": len(log), "cpu_s": time.process_time() - c0})
                    r = rows[-1]
                    print(f"{fname} F{load:g} w={r['width']} x={off}a: h* = {h:.3g} um "
                          f"(estimate {r['slot_estimate_um']:.3g} um), {r['cpu_s']:.1f} s CPU",
                          flush=True)
    df = pd.DataFrame(rows)
    df.to_csv(args.out / "pit_bottom.csv", index=False)
    print(markdown(df))


def markdown(df):
    """Per fidelity x load x width: h* at each offset, the largest, and the estimate at x = 0."""
    out = ["| fidelity | load (kN) | Q_max (kN) | p at the defect, x = 0 (GPa) | width | h* (um) at x = "
           + " / ".join(f"{o:g} a" for o in sorted(df.offset_a.unique()))
           + " | deepest cell depth at h* (um), x = 0 | slot estimate of h* (um), x = 0 |",
           "|---|---|---|---|---|---|---|---|"]
    for (f, load, w), g in df.groupby(["fidelity", "load_kN", "width"], sort=False):
        g = g.sort_values("offset_a")
        g0 = g.iloc[0]
        out.append(f"| {f} | {load:g} | {g0.q_max_kN:.2f} | {g0.p_centre_GPa:.2f} | {w} | "
                   + " / ".join(f"{v:.3g}" for v in g.h_star_um)
                   + f" | {g0.bottom_depth_at_h_star_um:.3g} | {g0.slot_estimate_um:.3g} |")
    return "\n".join(out)


if __name__ == "__main__":
    main()
