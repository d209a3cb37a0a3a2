"""What the roller-load handover adds at 1 x BPFI (issue 12 part 5), by hand.

    nice -n 5 python benchmarks/roller_load.py --out results/roller_load

For the healthy and the 50 um cases at 250/500/750 kN (standard fidelity, no checks/snapshots,
default anti-aliased acquisition, 100 revolutions), one table per case, then the history with
``load.roller_load: smooth`` (load-zone law at the defect's angle) and ``discrete`` (the load of
the roller over the defect: steps half-way between rollers). Per signal (p_max, contact_force):
the raw amplitude at 1 x BPFI and the envelope 1 x BPFI in the four fixed bands, both models
and the discrete/smooth ratio. Writes ``roller_load.csv`` and prints it.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pandas as pd

from bearing_envelope.physics.history import synthesize_case
from bearing_envelope.physics.table import build_table
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.scene import Scene
from bearing_envelope.diagnosis import harmonic_amplitudes
from bearing_envelope.signal import amplitude_at, amplitude_spectrum, envelope_spectrum

FID = {"preset": "standard", "n_checks": 0, "n_snapshot_offsets": 0}


def amplitudes(x, fs, bpfi):
    x = np.asarray(x, float) - np.mean(x)
    f, a = amplitude_spectrum(x, fs)
    out = {"raw_1x": amplitude_at(f, a, bpfi, 0.5)[1]}
    for name, band in {"fs4_3fs8": (0.25 * fs, 0.375 * fs), "bpfi_3_6": (3 * bpfi, 6 * bpfi),
                       "bpfi_10_13": (10 * bpfi, 13 * bpfi), "fixed": (8125.0, 16250.0)}.items():
        fe, ae = envelope_spectrum(x, fs, band)
        out[f"env1x_{name}"] = harmonic_amplitudes(fe, ae, bpfi, n_harmonics=1,
                                                   n_sidebands=0)[0]["amplitude"]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--loads", type=float, nargs="+", default=[250.0, 500.0, 750.0])
    ap.add_argument("--depths", type=float, nargs="+", default=[0.0, 50.0])
    ap.add_argument("--revolutions", type=float, default=100.0)
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for load in args.loads:
        for depth in args.depths:
            t0 = time.time()
            base = Scene.from_mapping({"operation": {"revolutions": args.revolutions}},
                                      load_kN=load, depth_um=depth)
            ld = scene_load_distribution(base)
            table, _, _ = build_table(base, FID, q_max=ld.q_max, progress=None)
            res = {}
            for model in ("smooth", "discrete"):
                sc = Scene.from_mapping({"operation": {"revolutions": args.revolutions},
                                         "load": {"roller_load": model}},
                                        load_kN=load, depth_um=depth)
                _, sig, _ = synthesize_case(sc, table, ld, FID)
                for name in ("p_max", "contact_force"):
                    res[(model, name)] = amplitudes(sig[name], sc.operation.fs_hz, sc.bpfi_hz)
            for name in ("p_max", "contact_force"):
                for q, v in res[("smooth", name)].items():
                    d = res[("discrete", name)][q]
                    rows.append({"load_kN": load, "depth_um": depth, "signal": name,
                                 "quantity": q, "smooth": v, "discrete": d,
                                 "ratio": d / v if v else float("inf")})
            print(f"F{load:g}kN h{depth:g}um: {time.time() - t0:.1f} s", flush=True)
    df = pd.DataFrame(rows)
    df.to_csv(args.out / "roller_load.csv", index=False)
    pd.set_option("display.width", 200)
    pd.set_option("display.max_rows", 200)
    print(df.to_string(index=False, float_format=lambda v: f"{v:.4g}"))


if __name__ == "__main__":
    main()
