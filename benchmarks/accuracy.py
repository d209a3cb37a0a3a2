"""The reference's building blocks (a helper of ``benchmarks/reference.py``, not a benchmark).

- :func:`build`: the contact table of one case and fidelity run, built once from an empty kernel
  cache and cached (``tables/*.pkl`` under the output folder, with its process CPU);
- :func:`evaluate_run`: every metric of one run's signals (``p_max``, ``removed_force``,
  ``approach_change``: peak, rms and every amplitude of the analysis chain's tidy table in the
  bands of ``config.yaml``), synthesised at its own acquisition; the synthesis CPU is scaled to
  100 revolutions;
- :func:`richardson3`: the Richardson value of three levels of a ladder (observed order
  ``p = log2(|f1 - f2| / |f2 - f4|)``, used when the three are monotone and 0.5 <= p <= 4;
  otherwise the finest value, flagged);
- :func:`offsets_x`: the table's offset nodes of ``standard`` times a density factor (the trade
  study's ``offset_density`` knob, :func:`bearing_envelope.study.tradeoff.apply_knob`).

Checks and snapshots are off in every run (:data:`OFF`); the sweep adds them.
"""

from __future__ import annotations

import dataclasses
import math
import os
import pickle
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from bearing_envelope.contact.halfspace import clear_kernel_cache
from bearing_envelope.physics.fidelity import PRESETS, fidelity_from
from bearing_envelope.physics.acquisition import acquisition_settings
from bearing_envelope.physics.history import synthesize_case
from bearing_envelope.physics.solves import SolveStats
from bearing_envelope.physics.table import build_table
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.study.pipeline import case_bands, case_harmonics
from bearing_envelope.physics.scene import Scene
from bearing_envelope.study.settings import load_settings
from bearing_envelope.study.tradeoff import apply_knob

SIGNALS = ("p_max", "removed_force", "approach_change")
OFF = {"n_checks": 0, "n_snapshot_offsets": 0}


def offsets_x(factor: float) -> dict:
    """The offset-node fields of ``standard`` with the table density in offset times ``factor``
    (the trade study's ``offset_density`` knob)."""
    fid, _ = apply_knob(PRESETS["standard"], "offset_density", factor)
    return {k: getattr(fid, k) for k in ("n_offsets", "offsets_per_width", "offset_step_um",
                                         "max_offsets")}


def _fid(spec):
    """The fidelity mapping of a run (without the benchmark's own ``_`` keys)."""
    return {k: v for k, v in spec.items() if not k.startswith("_")}


def scene(load, depth, revolutions):
    return Scene.from_mapping({"operation": {"revolutions": revolutions}},
                              load_kN=load, depth_um=depth)


def table_path(out, load, depth, run):
    return out / "tables" / f"F{load:g}kN_h{depth:g}um_{run}.pkl"


def build(out, load, depth, run, spec):
    """The cached table of one case and run (built once; CPU of the build stored with it)."""
    path = table_path(out, load, depth, run)
    if path.exists():
        return pickle.loads(path.read_bytes())
    sc = scene(load, depth, 1.0)
    fid = fidelity_from(_fid(spec))
    ld = scene_load_distribution(sc)
    clear_kernel_cache()                        # every table from an empty kernel cache
    stats = SolveStats()
    c0 = time.process_time()
    table, _, _ = build_table(sc, fid, q_max=ld.q_max, stats=stats, progress=None)
    rec = {"table": table, "ld": ld, "fidelity": fid, "cpu_s": time.process_time() - c0,
           "n_solves": stats.n_solves}
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(f".tmp{os.getpid()}")
    tmp.write_bytes(pickle.dumps(rec))
    os.replace(tmp, path)
    return rec


def analysis_config() -> dict:
    st = load_settings(Path(__file__).resolve().parents[1] / "config.yaml")
    return st.analysis


def metrics(sc, sig, analysis) -> list[dict]:
    """Peak, rms and every amplitude of the tidy table, per signal."""
    ff = sc.frequencies()
    rows = []
    for name in SIGNALS:
        x = np.asarray(sig[name], float)
        whole = {"band": "", "band_strategy": "", "band_low_hz": np.nan, "band_high_hz": np.nan,
                 "order": 0, "sideband": 0}
        rows.append({"signal": name, **whole, "quantity": "peak", "value": float(x.max())})
        rows.append({"signal": name, **whole, "quantity": "rms",
                     "value": float(np.sqrt(np.mean((x - x.mean()) ** 2)))})
        if np.ptp(x) == 0:
            continue           # a healthy race removes no force: no spectrum to analyse
        case = SimpleNamespace(signals={name: x}, fs=sc.operation.fs_hz,
                               fr=sc.operation.shaft_rate_hz, bpfi=sc.bpfi_hz, bpfo=ff.bpfo,
                               ftf=ff.ftf, bsf=ff.bsf, load_kN=sc.load.load_kN,
                               depth_um=sc.defect.depth_um, scene=sc.to_mapping(), attrs={})
        an = dataclasses.replace(analysis, signal=name)
        doc, _ = case_bands(case, an)
        h = case_harmonics(case, an, doc)
        h = h[h["quantity"] != "kurtogram_kurtosis"]
        for _, r in h.iterrows():
            rows.append({"signal": name, "band": r["band"], "band_strategy": r["band_strategy"],
                         "band_low_hz": float(r["band_low_hz"]),
                         "band_high_hz": float(r["band_high_hz"]), "quantity": r["quantity"],
                         "order": int(r["order"]), "sideband": int(r["sideband"]),
                         "value": float(r["amplitude"])})
    return rows


def _warm_up(out, cases):
    """Compile the synthesis kernels once (untimed), so no run's CPU includes numba's JIT."""
    for load, depth in cases:
        path = table_path(out, load, depth, "standard")
        if path.exists():
            rec = pickle.loads(path.read_bytes())
            for n in (1, 3):
                synthesize_case(scene(load, depth, 0.2), rec["table"], rec["ld"], rec["fidelity"],
                                acquisition={"mode": "antialiased", "oversample": n})
            return


def evaluate_run(out, load, depth, run, spec, revolutions, ref_oversample, analysis):
    """The metrics of one case at one run (its cached table, its own acquisition; ``ref_*``
    runs at ``ref_oversample``), with the table's CPU and the synthesis of 100 revolutions."""
    sc = scene(load, depth, revolutions)
    path = table_path(out, load, depth, spec.get("_table", run))
    if not path.exists():
        return []
    rec = pickle.loads(path.read_bytes())
    if run.startswith("ref"):
        acq = {"mode": "antialiased", "oversample": ref_oversample}
    elif "_oversample" in spec:
        acq = {"mode": "antialiased", "oversample": int(spec["_oversample"])}
    else:
        acq = acquisition_settings(sc, rec["fidelity"])
    c0 = time.process_time()
    _, sig, _ = synthesize_case(sc, rec["table"], rec["ld"], rec["fidelity"], acquisition=acq)
    synth = (time.process_time() - c0) * 100.0 / revolutions
    return [{"load_kN": load, "depth_um": depth, "run": run, **r, "table_cpu_s": rec["cpu_s"],
             "synth_cpu_s_100rev": synth, "cpu_s": rec["cpu_s"] + synth,
             "n_solves": rec["n_solves"], "oversample": acq["oversample"]}
            for r in metrics(sc, sig, analysis)]


KEYS = ["load_kN", "depth_um", "signal", "band", "quantity", "order", "sideband"]


def richardson3(f1, f2, f4):
    """(value, order, status) from three values at spacings h, 2h, 4h (finest first)."""
    d21, d42 = f1 - f2, f2 - f4
    if d21 == 0:
        return f1, math.inf, "exact"
    if d21 * d42 <= 0:
        return f1, math.nan, "oscillatory: finest"
    p = math.log2(abs(d42) / abs(d21))
    if 0.5 <= p <= 4:
        return f1 + d21 / (2 ** p - 1), p, "richardson"
    return f1, p, "order out of [0.5, 4]: finest"


