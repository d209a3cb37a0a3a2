"""The dynamic rig's OR 3:00 events against the operating clearance (issue 42 part 5;
docs/virtual_rig.md, "The load zone with the dynamic excitation").

    python -m benchmarks rig_clearance runs/Z_c-6=runs/Z_config_c-6.yaml runs/Z_c0=... \\
        [--records DATA/cwru_de12 DATA/cwru_de48] [--b-inner 0.35]

Each argument is a scored dynamic rig run and its config (``RUN=CONFIG``), one clearance each
(``bearing-envelope rig ...OR007at{3,6}... --config CONFIG -o RUN``). Per run:

- the 3:00 ball's static load (the scene's load distribution at 90 deg, outer race, the first
  12 kHz 3:00 record) and, in the dynamic runs of the 3:00 records, the least load of the
  element nearest the pit (``roller_load``) and the defect contact's peak;
- secondary events per 3:00 ball passage (``event_shape.csv``, simulated; 12 kHz and 48 kHz);
- OR 3:00 re 6:00, dB: the written rule (``outer_race.csv``, each record's best band; passes)
  and read in fs/4-3fs/8 on both (``outer_race_bands.csv``);
- the outer exponent measured on the run's pairs
  (:func:`~bearing_envelope.study.rig.load_zone.removed_force_exponent`) and the inner-race fr
  sideband the clearance implies (:func:`~bearing_envelope.study.rig.load_zone.directional_modulation`
  at the run's settings, ``--b-inner``, that median outer exponent).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np
import pandas as pd

DATA = "/work/shared/data/real"


def _fmt(values, nd=1) -> str:
    """Values joined by " / "; one not read (NaN: the rule's contrast floor) as "n/a"."""
    return " / ".join(f"{x:.{nd}f}" if np.isfinite(x) else "n/a" for x in values) or "-"


def clearance_row(run: Path, config: str, conds, b_inner: float) -> dict:
    """The figures of one run (see the module's docstring)."""
    from bearing_envelope.physics.loads import scene_load_distribution
    from bearing_envelope.study import rig
    from bearing_envelope.study.rig.dynamic import dynamic_path
    from bearing_envelope.study.rig.load_zone import (directional_modulation,
                                                      removed_force_exponent)

    s = rig.read_rig_config(config)
    by = {c.name: c for c in conds}
    ratios = pd.read_csv(run / "outer_race.csv")
    bands = pd.read_csv(run / "outer_race_bands.csv")
    ev = pd.read_csv(run / "event_shape.csv")
    at3 = ev[(ev.location == "outer_race") & (ev.position_deg == 90.0)]
    or3 = [by[n] for n in ratios.record_3]
    least, peak = [], []
    for c in or3:
        with np.load(dynamic_path(run / "contact", c)) as z:
            least.append(float(np.min(z["roller_load"])))
            peak.append(float(z["defect_force_peak"]))
    b_out = [removed_force_exponent(str(dynamic_path(run / "contact", by[r.record_3])),
                                    str(dynamic_path(run / "contact", by[r.record_6])),
                                    by[r.record_3].rates["bpfo"]) for _, r in ratios.iterrows()]
    static = float(scene_load_distribution(rig.condition_scene(or3[0], s))
                   .load_at(math.pi / 2, "outer"))
    ir = [c for c in conds if c.location == "inner_race" and c.fs_hz == or3[0].fs_hz]
    sb1 = directional_modulation(s, ir[0], or3[0], b_inner, float(np.median(b_out)))["sb1_db"] \
        if ir else np.nan
    fixed = bands[bands.band == "fs4_3fs8"]
    return {"clearance_um": s.scene["bearing"]["radial_clearance_um"], "static_3_n": static,
            "least_3_n": min(least), "defect_peak_3_n": max(peak),
            "secondary": {fs: list(at3[at3.fs_hz == fs].sim_secondary_events)
                          for fs in sorted(set(at3.fs_hz))},
            "meas_secondary": {fs: list(at3[at3.fs_hz == fs].meas_secondary_events)
                               for fs in sorted(set(at3.fs_hz))},
            "rule_db": list(ratios.sim_db), "meas_db": list(ratios.meas_db),
            "passes": int((ratios.rule == "PASS").sum()), "pairs": int(len(ratios)),
            "fixed_db": list(fixed.sim_db), "meas_fixed_db": list(fixed.meas_db),
            "b_outer": b_out, "sb1_db": sb1}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks rig_clearance", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="RUN=CONFIG, one per clearance")
    ap.add_argument("--records", nargs="+", default=[f"{DATA}/cwru_de12", f"{DATA}/cwru_de48"])
    ap.add_argument("--b-inner", type=float, default=0.35,
                    help="inner-race event exponent (the dynamic rig's, rig --identify)")
    args = ap.parse_args(argv)
    from bearing_envelope.study import rig

    conds = rig.record_conditions(args.records)
    rows = [clearance_row(Path(r.split("=")[0]), r.split("=")[1], conds, args.b_inner)
            for r in args.runs]
    rows.sort(key=lambda r: r["clearance_um"])
    m = rows[0]
    print(f"measured: secondary events per 3:00 passage "
          f"{ {fs: _fmt(v, 2) for fs, v in m['meas_secondary'].items()} }; OR 3:00 re 6:00 "
          f"(rule) {_fmt(m['meas_db'])} dB; in fs/4-3fs/8 {_fmt(m['meas_fixed_db'])} dB\n")
    print("| clearance um | 3:00 static load N | least load over the pit N | defect contact "
          "peak N | secondary events per 3:00 passage | OR 3:00 re 6:00, rule, dB (passes) | "
          "in fs/4-3fs/8, dB | b_outer | IR fr sideband dB |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        sec = "; ".join(f"{fs / 1e3:g} kHz {_fmt(v, 2)}" for fs, v in r["secondary"].items())
        print(f"| {r['clearance_um']:+g} | {r['static_3_n']:.2f} | {r['least_3_n']:.2f} | "
              f"{r['defect_peak_3_n']:.1f} | {sec} | {_fmt(r['rule_db'])} ({r['passes']}/"
              f"{r['pairs']}) | {_fmt(r['fixed_db'])} | {_fmt(r['b_outer'], 3)} | "
              f"{r['sb1_db']:.1f} |")
    return 0


def smoke() -> None:
    import tempfile

    from bearing_envelope.study.rig.dynamic import DYNAMIC_MODEL

    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        for name in ("ir", "or3", "or6"):
            np.savez(d / f"{name}.npz", x=np.zeros(1200), fs=np.float64(12e3))
        (d / "manifest.csv").write_text(
            "file,location,length_um,depth_um,position_deg,load,shaft_hz,bearing\n"
            "ir.npz,inner_race,177.8,279.4,,0,29.95,6205\n"
            "or3.npz,outer_race,177.8,279.4,90,0,29.95,6205\n"
            "or6.npz,outer_race,177.8,279.4,0,0,29.95,6205\n")
        (d / "rig.yaml").write_text("scene: {bearing: {designation: SKF 6205-2RS, "
                                    "radial_clearance_um: 2.0}}\nrig: {load_kN: 0.1, "
                                    "fidelity: draft, dynamics: dynamic}\n")
        run = d / "run"
        (run / "contact").mkdir(parents=True)
        t = np.arange(12_000) / 12e3
        for name, q in (("or3", 20.0), ("or6", 50.0)):
            f = np.zeros(t.size)
            f[np.arange(100, t.size - 200, 112)] = 0.1 * q ** 0.3
            np.savez(run / "contact" / f"{name}_dynamic.npz", fs=np.float64(12e3), time=t,
                     model=np.str_(DYNAMIC_MODEL), removed_force=np.convolve(
                         f, np.sin(np.arange(12) * 2.0), "same"),
                     roller_load=np.full(t.size, q), defect_force_peak=np.float64(q))
        pd.DataFrame({"record_3": ["or3"], "record_6": ["or6"], "meas_db": [-12.0],
                      "sim_db": [-10.0], "rule": ["PASS"]}).to_csv(run / "outer_race.csv",
                                                                   index=False)
        pd.DataFrame({"record_3": ["or3"], "record_6": ["or6"], "band": ["fs4_3fs8"],
                      "meas_db": [-12.0], "sim_db": [-11.0]}).to_csv(
            run / "outer_race_bands.csv", index=False)
        pd.DataFrame({"record": ["or3"], "location": ["outer_race"], "position_deg": [90.0],
                      "fs_hz": [12e3], "meas_secondary_events": [1.5],
                      "sim_secondary_events": [0.0]}).to_csv(run / "event_shape.csv",
                                                             index=False)
        main([f"{run}={d / 'rig.yaml'}", "--records", str(d)])


if __name__ == "__main__":
    raise SystemExit(main())
