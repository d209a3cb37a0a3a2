"""Outer-race pits outside the radial load zone (CWRU 3:00, 12:00) against 6:00: which mechanism
loads them, the events it makes, the BPFO level relative to 6:00 (docs/scene.md, "Elements
loaded outside the load zone").

    nice -n 10 python -m benchmarks outside_zone --fidelity standard --revolutions 20 --hp 0 3

Scene: config_cwru.yaml (SKF 6205, assumed 1 kN, 0.007 in x 0.011 in pit) at the four CWRU
speeds (0-3 hp), the pit at 0 / 90 / 180 deg from the load direction, for each mechanism:
``radial`` (radial load only, 10 um clearance: the model before), ``centrifugal`` (plus
load.centrifugal), ``preload`` (plus an operating clearance of -5 um: fits and a warm inner ring,
``loads.operating_clearance``). Per case: the element load at the pit, the baseline and extreme
``p_max``, the largest removed force, the envelope 1 x BPFO amplitude of ``p_max`` and of the
removed force (band fs/4 - 3 fs/8, Hann, amplitude of the nearest line within 1 %), the CPU
seconds, the exposure note. Writes ``outside_zone.csv`` and prints the table.
"""

from __future__ import annotations

import argparse
import copy
import csv
import math
import os
import time

import numpy as np
import yaml

from bearing_envelope.physics.history import simulate
from bearing_envelope.physics.locations import scene_event_frequencies
from bearing_envelope.physics.scene import Scene
from bearing_envelope.signal.envelope import envelope_spectrum
from bearing_envelope.signal.spectrum import amplitude_at

HERE = os.path.dirname(os.path.abspath(__file__))
#: The 0.007 in EDM pit (diameter; the sweep's widths_um in config_cwru.yaml).
PIT_UM = 177.8
RPM = {0: 1797.0, 1: 1772.0, 2: 1750.0, 3: 1730.0}
MECHANISMS = {"radial": {}, "centrifugal": {"centrifugal": True},
              "preload": {"centrifugal": True, "clearance_um": -5.0}}


def scene_for(base: dict, hp: int, position: float, mech: dict) -> Scene:
    m = copy.deepcopy(base)
    for k in ("operation", "defect", "load", "bearing"):
        m.setdefault(k, {})
    m["operation"]["shaft_rate_hz"] = RPM[hp] / 60.0
    m["defect"].update(location="outer_race", position_deg=position, width_um=PIT_UM)
    m["load"]["centrifugal"] = bool(mech.get("centrifugal", False))
    if "clearance_um" in mech:
        m["bearing"]["radial_clearance_um"] = mech["clearance_um"]
    return Scene.from_mapping(m, load_kN=1.0, depth_um=279.4)


def bpfo_level(x: np.ndarray, fs: float, bpfo: float) -> float:
    f, a = envelope_spectrum(x - np.mean(x), fs, (0.25 * fs, 0.375 * fs))
    return float(amplitude_at(f, a, bpfo, 0.01 * bpfo)[1])


def run_case(sc: Scene, fidelity: str) -> dict:
    t0 = time.process_time()
    h = simulate(sc, fidelity)
    cpu = time.process_time() - t0
    fs, bpfo = sc.operation.fs_hz, scene_event_frequencies(sc)["bpfo"]
    p, rf = h.signals["p_max"], h.signals["removed_force"]
    base = float(np.median(p))
    return {"Q_N": float(h.roller_load.max()), "p_base_GPa": base / 1e9,
            "p_min_GPa": float(p.min()) / 1e9, "p_max_GPa": float(p.max()) / 1e9,
            "removed_N": float(rf.max()), "env_bpfo_p_MPa": bpfo_level(p, fs, bpfo) / 1e6,
            "env_bpfo_force_N": bpfo_level(rf, fs, bpfo), "n_solves": h.stats["n_solves"],
            "cpu_s": cpu, "note": h.stats.get("exposure_note") or ""}


def main(argv=None) -> int:
    """Run the measurement (module docstring); ``argv`` as on the command line."""
    ap = argparse.ArgumentParser(prog="python -m benchmarks outside_zone",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--fidelity", default="standard")
    ap.add_argument("--hp", type=int, nargs="*", default=[0, 1, 2, 3])
    ap.add_argument("--revolutions", type=float, default=100)
    ap.add_argument("--out", default="results_bench/outside_zone")
    ap.add_argument("--mechanisms", nargs="*", default=list(MECHANISMS))
    args = ap.parse_args(argv)
    with open(os.path.join(HERE, "..", "config_cwru.yaml")) as fh:
        base = yaml.safe_load(fh)["scene"]
    base.setdefault("operation", {})["revolutions"] = args.revolutions
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for mname, mech in ((k, MECHANISMS[k]) for k in args.mechanisms):
        for hp in args.hp:
            for pos in (0.0, 90.0, 180.0):
                r = {"mechanism": mname, "hp": hp, "position_deg": pos,
                     **run_case(scene_for(base, hp, pos, mech), args.fidelity)}
                rows.append(r)
                print(", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                                for k, v in r.items()), flush=True)
    ref = {(r["mechanism"], r["hp"]): r for r in rows if r["position_deg"] == 0.0}
    for r in rows:
        r6 = ref[(r["mechanism"], r["hp"])]
        for key in ("env_bpfo_p_MPa", "env_bpfo_force_N"):
            v, v6 = r[key], r6[key]
            r[key + "_dB_re_6"] = 20 * math.log10(v / v6) if v > 0 and v6 > 0 else float("-inf")
    with open(os.path.join(args.out, "outside_zone.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    for r in rows:
        print(f"{r['mechanism']:12s} {r['hp']} hp {r['position_deg']:5.0f} deg  Q {r['Q_N']:8.3f} N  "
              f"p {r['p_base_GPa']:.3f} [{r['p_min_GPa']:.3f}, {r['p_max_GPa']:.3f}] GPa  "
              f"dF {r['removed_N']:.4g} N  BPFO p {r['env_bpfo_p_MPa_dB_re_6']:+.1f} dB  "
              f"force {r['env_bpfo_force_N_dB_re_6']:+.1f} dB  {r['cpu_s']:.1f} CPU s")
    return 0


def smoke() -> None:
    """The same path on a tiny case: draft, a tenth of a revolution, 0 hp, centrifugal."""
    main(["--fidelity", "draft", "--revolutions", "0.1", "--hp", "0", "--mechanisms",
          "centrifugal", "--out", "outside_zone_smoke"])


if __name__ == "__main__":
    raise SystemExit(main())
