"""The cost of one simulated case per fault location and fidelity, and the table against Hertz.

    nice -n 10 python -m benchmarks case_cost [--fidelity draft standard] [--revolutions 100]

1. The cost of a case: the CWRU bearing (SKF 6205-2RS, 1797 rpm, 48 kHz, 100 revolutions,
   the 0.007 in x 0.011 in EDM pit, 1 kN radial load -- config_cwru.yaml's case) at each fault
   location and fidelity; CPU seconds of :func:`bearing_envelope.physics.history.simulate`
   (``time.process_time``, this process only) and wall seconds.
2. The no-defect contact of the table against Hertz: the table's load-node pressure ``P0``
   (global + window solve) of the inner and outer contact at 100 N and at Q_max, against
   :func:`bearing_envelope.contact.hertz.elliptical`.

Prints markdown tables (docs/benchmarks.md, "Cost of one case"). This times ``simulate`` alone;
a Snakemake ``simulate`` job adds the interpreter, imports, the case's error model and the HDF5
write (measure it with ``/usr/bin/time`` on the job, see the docs).
"""

from __future__ import annotations

import argparse
import time

from bearing_envelope.contact.hertz import elliptical
from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.history import simulate
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene
from bearing_envelope.physics.solves import SolveStats, solve_load

INCH_UM = 25400.0
LOCATIONS = ("inner_race", "outer_race", "rolling_element")


def cwru_scene(location: str, revolutions: float = 100) -> Scene:
    """config_cwru.yaml's defect case at ``location`` (6:00 for the outer race)."""
    m = {"bearing": {"designation": "SKF 6205-2RS"},
         "operation": {"bpfi_override_hz": None, "shaft_rate_hz": 1797.0 / 60.0, "fs_hz": 48000.0,
                       "revolutions": revolutions},
         "defect": {"location": location, "position_deg": 0.0, "shape": "cylinder",
                    "width_um": 0.007 * INCH_UM}}
    return Scene.from_mapping(m, load_kN=1.0, depth_um=0.011 * INCH_UM)


def cost_table(fidelities: tuple[str, ...], revolutions: float = 100,
               locations: tuple[str, ...] = LOCATIONS) -> list[str]:
    rows = ["| location | fidelity | CPU s | wall s | contact solves | oversample N |",
            "|---|---|---|---|---|---|"]
    for fid in fidelities:
        for loc in locations:
            sc = cwru_scene(loc, revolutions)
            c0, w0 = time.process_time(), time.perf_counter()
            h = simulate(sc, fid)
            cpu, wall = time.process_time() - c0, time.perf_counter() - w0
            rows.append(f"| {loc} | {fid} | {cpu:.2f} | {wall:.2f} | {h.stats['n_solves']} | "
                        f"{h.acquisition.get('oversample', '-')} |")
    return rows


def hertz_table(fidelities: tuple[str, ...]) -> list[str]:
    sc0 = cwru_scene("inner_race")
    q_max = scene_load_distribution(sc0).q_max
    rows = ["| contact | fidelity | Q (N) | Hertz p0 (GPa) | table P0 (GPa) | difference |",
            "|---|---|---|---|---|---|"]
    for race in ("inner", "outer"):
        sc = sc0.for_race(race)
        for fid in fidelities:
            for q in (100.0, q_max):
                h = elliptical(q, sc.bearing.rx_m, sc.bearing.ry_m, sc.material.e_star_pa)
                node = solve_load(sc, fidelity_from(fid), q, 1.0, SolveStats())
                rows.append(f"| {race} | {fid} | {q:.1f} | {h.p0 / 1e9:.4f} | "
                            f"{node.p0 / 1e9:.4f} | {100 * (node.p0 / h.p0 - 1):+.3f} % |")
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fidelity", nargs="+", default=["draft", "standard"])
    ap.add_argument("--revolutions", type=float, default=100.0)
    ap.add_argument("--locations", nargs="+", default=list(LOCATIONS), choices=LOCATIONS)
    ap.add_argument("--no-hertz", action="store_true", help="the cost table only")
    args = ap.parse_args(argv)
    fids = tuple(args.fidelity)
    print("\n".join(cost_table(fids, args.revolutions, tuple(args.locations))))
    if not args.no_hertz:
        print()
        print("\n".join(hertz_table(fids)))
    return 0


def smoke() -> None:
    """One outer-race case at ``draft`` over two revolutions, and the Hertz table at draft."""
    main(["--fidelity", "draft", "--revolutions", "2", "--locations", "outer_race"])


if __name__ == "__main__":
    main()
