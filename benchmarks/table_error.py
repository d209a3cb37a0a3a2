"""Interpolation error of the P(Q, x) table against direct solves, per table layout (issue 13.3).

    nice -n 5 python benchmarks/table_error.py > results/table_error.jsonl

For each case and fidelity variant (``standard`` plus overrides), side by side in one process:

- CPU seconds of the whole case (``simulate``, 100 revolutions, ``time.process_time``);
- the table's error against direct zoom solves (``direct_pressure`` at the same fidelity and
  ``kappa``) at every sample of one shaft revolution at which the defect is inside a loaded
  contact (``|x| < s(Q)``), with the offset snapped to the window grid (the table's own error,
  without the sub-cell jitter of an under-resolved rim; see docs/benchmarks.md): max and rms of
  ``|P_table - P_direct| / P_direct``, and the same on the subset the lead measured last time
  (two BPFI periods centred on the load-zone centre).

Direct solves are cached per (kappa, Q, x): variants that only change the table's nodes share
them when their kappa agrees.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.history import kinematics, simulate
from bearing_envelope.physics.table import direct_pressure
from bearing_envelope.physics.scene import Scene

VARIANTS = {
    "standard": {},
    "n_loads=7": {"n_loads": 7},
    "n_loads=9": {"n_loads": 9},
    "offsets x2": {"offsets_per_width": 8.0, "offset_step_um": 6.0},
    "n_loads=7, offsets x2": {"n_loads": 7, "offsets_per_width": 8.0, "offset_step_um": 6.0},
    "n_loads=9, offsets x2": {"n_loads": 9, "offsets_per_width": 8.0, "offset_step_um": 6.0},
    "rim strips 0.5 um": {"rim_dx_um": 0.5},
    "rim strips 0.5 um, offsets x2": {"rim_dx_um": 0.5, "offsets_per_width": 8.0, "offset_step_um": 6.0},
    "rim strips 0.5 um, n_loads=7": {"rim_dx_um": 0.5, "n_loads": 7},
    # the candidates of benchmarks/accuracy.py (issue 13 part 4)
    "rim strips 0.5 um, n_loads=7, offsets x2": {
        "rim_dx_um": 0.5, "n_loads": 7, "n_offsets": 28, "offsets_per_width": 8.0,
        "offset_step_um": 6.0, "max_offsets": 240},
    "rim strips 0.5 um, n_loads=9, offsets x3": {
        "rim_dx_um": 0.5, "n_loads": 9, "n_offsets": 42, "offsets_per_width": 12.0,
        "offset_step_um": 4.0, "max_offsets": 360},
}

#: Fidelity fields that only change the table's nodes (direct solves are shared across them).
TABLE_ONLY = {"name", "n_loads", "n_offsets", "offsets_per_width", "offset_step_um", "max_offsets",
              "n_checks", "n_snapshot_offsets"}


def samples(s, h):
    """(Q, x snapped, centre-subset mask) of one revolution's samples with the defect in contact."""
    fs, fr, bpfi = s.operation.fs_hz, s.operation.shaft_rate_hz, s.bpfi_hz
    k0 = round(bpfi / fr)
    c = int(round(k0 * fs / bpfi))           # an event at the load-zone centre, one revolution in
    idx = np.arange(c - int(round(0.5 * fs / fr)), c + int(round(0.5 * fs / fr)))
    kin = kinematics(s, h.time[idx])
    q = h.load_distribution.load_at(kin["theta_shaft"])
    x = kin["offset"]
    dx = h.table.info["window_dx"]
    near = (q > 0) & (np.abs(x) < h.table.scale(np.maximum(q, 1.0)))
    half = int(round(fs / bpfi))              # two BPFI periods around the centre event
    centre = np.abs(idx - c) <= half
    return q[near], np.round(x[near] / dx) * dx, centre[near]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+", default=["500:50", "750:15"])
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS))
    ap.add_argument("--revolutions", type=float, default=100.0)
    a = ap.parse_args(argv)
    cache: dict = {}
    for case in a.cases:
        load, depth = (float(v) for v in case.split(":"))
        s = Scene.from_mapping({"operation": {"revolutions": a.revolutions}}, load_kN=load,
                               depth_um=depth)
        ref_samples = None
        for name in a.variants:
            fid = fidelity_from({"preset": "standard", **VARIANTS[name]})
            t0 = time.process_time()
            h = simulate(s, fid)
            cpu = time.process_time() - t0
            if ref_samples is None:
                ref_samples = samples(s, h)
            q, x, centre = ref_samples
            kappa = h.table.kappa
            direct = []
            t1 = time.process_time()
            for qq, xx in zip(q, x):
                solve_spec = tuple(sorted((k, v) for k, v in fid.to_dict().items()
                                          if k not in TABLE_ONLY))
                key = (load, depth, solve_spec, round(kappa, 12), float(qq), float(xx))
                if key not in cache:
                    cache[key] = direct_pressure(s, fid, float(qq), float(xx), kappa=kappa)[0]
                direct.append(cache[key])
            t_direct = time.process_time() - t1
            direct = np.array(direct)
            tab = h.table.evaluate(q, x)[0]
            e = np.abs(tab - direct) / direct
            w = int(np.argmax(e))
            out = {
                "load_kN": load, "depth_um": depth, "variant": name, "cpu_case_s": cpu,
                "table_nodes": list(h.table.ratio.shape), "kappa": kappa,
                "samples": int(q.size), "max_err": float(e.max()),
                "rms_err": float(np.sqrt(np.mean(e ** 2))),
                "centre_samples": int(centre.sum()),
                "centre_max_err": float(e[centre].max()) if centre.any() else 0.0,
                "worst_Q_over_Qmax": float(q[w] / h.load_distribution.q_max),
                "worst_x_over_s": float(x[w] / h.table.scale(q[w])),
                "build_table_check_max": h.table.info.get("interp_max_rel_error_p_max", 0.0),
                "n_solves": h.stats["n_solves"],
                "cpu_direct_s": t_direct,
            }
            print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
