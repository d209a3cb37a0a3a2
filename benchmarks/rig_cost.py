"""Cost of the virtual rig with the dynamics (docs/virtual_rig.md, "With the dynamics").

    nice -n 5 python -m benchmarks rig_cost                          # dynamic records, per preset
    nice -n 5 python -m benchmarks rig_cost --whole DATA/cwru_de12 DATA/cwru_de48

1. A dynamic rig record per preset (``draft``, ``standard`` defect table): the CWRU records'
   scenes of ``config_rig.yaml`` (the rig's load, clearance, structure, sensor), each record's
   length at its fs; CPU s (process time) of the defect table (cold, once per pit in a process)
   and of the dynamic run (:func:`bearing_envelope.study.rig.dynamic.simulate_dynamic_record`).
   The records are synthetic conditions of the development records' scenes (no data needed):
   OR 0.007 in at 6:00 and at 3:00, IR 0.007 in, OR 0.014 in at 6:00, IR 0.028 in, ball
   0.007 in; 10 s at 12 kHz, 29.95 Hz shaft rate.
2. ``--whole``: the whole rig (``bearing-envelope rig RECORDS --config config_rig.yaml``) run
   from empty scratch folders, ``rig.dynamics: quasi_static`` then ``dynamic``, one after the
   other in this process's children: user + system CPU s of each and their ratio.
"""

from __future__ import annotations

import argparse
import datetime
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

from bearing_envelope.physics.defect_contact import defect_table
from bearing_envelope.study.rig import read_rig_config
from bearing_envelope.study.rig.dynamic import rig_params, simulate_dynamic_record
from bearing_envelope.study.rig.records import RigCondition, resolve_bearing
from bearing_envelope.study.rig.simulation import condition_scene

from .dynamics_cost import machine

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "config_rig.yaml"
#: The scenes measured: name -> (location, pit diameter um, depth um, position deg).
SCENES = {"OR007at6": ("outer_race", 177.8, 279.4, 0.0),
          "OR007at3": ("outer_race", 177.8, 279.4, 90.0),
          "IR007": ("inner_race", 177.8, 279.4, 0.0),
          "OR014at6": ("outer_race", 355.6, 279.4, 0.0),
          "IR028": ("inner_race", 711.2, 1270.0, 0.0),
          "B007": ("rolling_element", 177.8, 279.4, 0.0)}


def condition(name: str, duration_s: float, fs_hz: float = 12_000.0,
              shaft_hz: float = 29.95) -> RigCondition:
    """A synthetic rig condition of one of :data:`SCENES` (no record behind it)."""
    loc, d, h, pos = SCENES[name]
    return RigCondition(name, "", loc, d, d, h, pos, 0.0, shaft_hz, fs_hz,
                        int(round(duration_s * fs_hz)), resolve_bearing("SKF 6205-2RS"))


def record_costs(presets=("draft", "standard"), names=tuple(SCENES), duration_s: float = 10.0,
                 out=None) -> list:
    """CPU s of the defect table and of the dynamic run of each scene, per preset."""
    base = read_rig_config(CONFIG)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for preset in presets:
            s = type(base)(**{**base.__dict__, "fidelity": preset, "dynamics": "dynamic"})
            for name in names:
                c = condition(name, duration_s)
                scene = condition_scene(c, s)
                t0 = time.process_time()
                defect_table(scene, preset)
                table = time.process_time() - t0
                info = simulate_dynamic_record(c, scene, s,
                                               Path(out or tmp) / f"{name}_{preset}.npz")
                p = rig_params(scene, s, None)
                rows.append({"preset": preset, "scene": name, "table": table,
                             "run": info["run_cpu_s"], "step_us": 1e6 * info["step_s"],
                             "steps": info["steps"], "peak": info["defect_force_peak_n"],
                             "load": p.force_n})
    return rows


def whole_rig(records, out: Path) -> list:
    """CPU s (children's user + system) of the whole rig, quasi-static then dynamic."""
    raw = yaml.safe_load(CONFIG.read_text())
    rows = []
    for mode in ("quasi_static", "dynamic"):
        raw["rig"]["dynamics"] = mode
        cfg = out / f"config_{mode}.yaml"
        cfg.write_text(yaml.safe_dump(raw, sort_keys=False))
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.time()
        subprocess.run([sys.executable, "-m", "bearing_envelope", "rig", *map(str, records),
                        "--config", str(cfg), "-o", str(out / mode)], check=True,
                       stdout=subprocess.DEVNULL)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        rows.append({"mode": mode, "user": after.ru_utime - before.ru_utime,
                     "system": after.ru_stime - before.ru_stime, "wall": time.time() - t0})
    return rows


def print_records(rows) -> None:
    print("| preset | scene | defect table CPU s | dynamic run CPU s | record CPU s | step us |"
          " steps | defect contact peak N |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['preset']} | {r['scene']} | {r['table']:.1f} | {r['run']:.1f} | "
              f"{r['table'] + r['run']:.1f} | {r['step_us']:.3f} | {r['steps']} | "
              f"{r['peak']:.1f} |")


def print_whole(rows) -> None:
    print("| rig.dynamics | user CPU s | system CPU s | CPU s | wall s |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['mode']} | {r['user']:.1f} | {r['system']:.1f} | "
              f"{r['user'] + r['system']:.1f} | {r['wall']:.0f} |")
    if len(rows) == 2:
        q, d = (r["user"] + r["system"] for r in rows)
        print(f"\ndynamic / quasi-static: {d / q:.2f}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks rig_cost", description=__doc__)
    ap.add_argument("--presets", nargs="+", default=["draft", "standard"])
    ap.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    ap.add_argument("--duration", type=float, default=10.0, help="record length, s")
    ap.add_argument("--whole", nargs="+", metavar="RECORDS",
                    help="also run the whole rig on these records, both models")
    ap.add_argument("-o", "--output", help="scratch folder of --whole (default: a temporary one)")
    args = ap.parse_args(argv)
    print(f"{datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, {machine()}, "
          f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}\n")
    print_records(record_costs(args.presets, args.scenes, args.duration))
    if args.whole:
        if args.output:
            Path(args.output).mkdir(parents=True, exist_ok=True)
            print(), print_whole(whole_rig(args.whole, Path(args.output)))
        else:
            with tempfile.TemporaryDirectory() as tmp:
                print(), print_whole(whole_rig(args.whole, Path(tmp)))
    return 0


def smoke() -> None:
    print_records(record_costs(("draft",), ("OR007at6",), duration_s=0.02))


if __name__ == "__main__":
    raise SystemExit(main())
