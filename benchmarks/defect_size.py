"""Defect length from the entry-exit spacing (diagnosis.defect_size; docs/analysis.md, "Defect
length from the entry-exit spacing").

    nice -n 5 python -m benchmarks defect_size            # all four parts, ~20 CPU s
    nice -n 5 python -m benchmarks defect_size --part real

1. ``synthetic``: records whose spacing is known by construction (two modes, 3.5 and 9 kHz,
   excited by a negative step at each entry and an impulse with the load's return at each
   exit, at BPFO with 1 % period jitter, in white noise; ``tests/test_defect_size.py``'s
   generator): per fs, spacing and noise, the status, the estimate and whether the set spacing
   lies in the interval.
2. ``dynamic``: the dynamic model (``physics.dynamics``: the CWRU 6205 of config_cwru.yaml, an
   outer-race slot of the geometric law ``slot_law`` 0.007 / 0.014 / 0.021 in wide at 6:00,
   48 kHz, 0.5 s): the estimator on the defect contact force (the model's own events), on the
   force the outer ring passes to the housing and on the sensor's resonator acceleration,
   against ``w / v``.
3. ``real``: the CWRU 48 kHz drive-end records (``../shared/data/real/cwru_de48``) and the
   12 kHz ones (``cwru_de12``), each at its fault's own location with the shaft rate measured
   from the record (``diagnosis.speed``): the estimated length per record against the pit's
   diameter, and the Spearman rank correlation over the records estimated.
4. ``bands``: the 48 kHz records through five bands (:data:`SCAN_BANDS`): the length read in
   each (n.r.: not resolvable, with its shortest resolvable length).
"""

from __future__ import annotations

import argparse
import csv
import datetime
import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy.stats import spearmanr

from bearing_envelope.diagnosis.defect_size import (ESTIMATED, defect_length,
                                                    entry_exit_spacing, record_scene)
from bearing_envelope.diagnosis.speed import estimate_shaft_rate

ROOT = Path(__file__).resolve().parents[1]
#: The shared real records (``../shared/data/real`` of the checkout, or of its worktrees' parent).
DATA = next((d / "shared" / "data" / "real" for d in ROOT.parents
             if (d / "shared" / "data" / "real").is_dir()), ROOT.parent / "shared" / "data" / "real")
INCH = 25.4e-3
LOCATIONS = {"outer_race": "outer_race", "inner_race": "inner_race", "ball": "rolling_element"}


def _tests_generator():
    sys.path.insert(0, str(ROOT / "tests"))
    from test_defect_size import RATE, pit_record   # the tests' records of known spacing
    return RATE, pit_record


def synthetic(fss=(48000.0, 12000.0), dts_us=(101.0, 202.0, 303.0),
              noises=(0.02, 0.1, 0.3), duration_s: float = 3.0) -> list[dict]:
    """Part 1: records of known spacing; one row per fs x spacing x noise; spacing 0 is the
    control: the exit impulse alone, no entry step (nothing to find)."""
    rate, pit_record = _tests_generator()
    rows = []
    for fs in fss:
        for dt in (*dts_us, 0.0):
            for noise in noises:
                s = entry_exit_spacing(pit_record(fs, dt * 1e-6, noise=noise,
                                                  duration_s=duration_s,
                                                  entry=0.5 if dt else 0.0), fs, rate)
                iv = s.interval_s
                rows.append({"fs_khz": fs / 1e3, "dt_us": dt, "noise": noise, "status": s.status,
                             "estimate_us": None if s.dt_s is None else 1e6 * s.dt_s,
                             "interval_us": None if iv is None else (1e6 * iv[0], 1e6 * iv[1]),
                             "min_us": None if s.min_dt_s is None else 1e6 * s.min_dt_s,
                             "verdict": _verdict(s, dt * 1e-6),
                             "events": f"{s.n_events}/{s.n_periods}"})
    return rows


def _verdict(s, dt: float) -> str:
    """Right or wrong, for a spacing known by construction (0: the control, no entry)."""
    if s.status == ESTIMATED:
        if dt == 0:
            return "false estimate"
        return "inside" if s.interval_s[0] <= dt <= s.interval_s[1] else "outside"
    if dt == 0 or (s.min_dt_s is not None and dt < s.min_dt_s):
        return "right: none"
    return "missed"


def dynamic(widths_in=(0.007, 0.014, 0.021), duration_s: float = 0.5,
            fs: float = 48000.0) -> list[dict]:
    """Part 2: the dynamic model's records, one row per pit x signal."""
    from bearing_envelope.physics.dynamics import simulate_dynamics

    sys.path.insert(0, str(ROOT))
    from benchmarks.dynamics_cost import scene_params

    rows = []
    for w in widths_in:
        p = scene_params(w, 0.0)
        cpu = time.process_time()
        r = simulate_dynamics(p, duration_s, fs)
        cpu = time.process_time() - cpu
        v = 2.0 * math.pi * p.cage_rate_hz * p.outer_race_radius_m   # as speed_m_s (outer race)
        rate = p.z * p.cage_rate_hz
        for name, sig in (("defect contact force", r.defect_force_n),
                          ("housing force y", r.housing_force_n[:, 1]),
                          ("resonator acceleration", r.resonator_acceleration_m_s2)):
            x = sig + 1e-3 * np.std(sig) * np.random.default_rng(0).standard_normal(sig.size)
            s = entry_exit_spacing(x, fs, rate)
            iv = s.interval_s
            rows.append({"width_in": w, "signal": name, "truth_us": 1e6 * w * INCH / v,
                         "status": s.status,
                         "estimate_us": None if s.dt_s is None else 1e6 * s.dt_s,
                         "interval_us": None if iv is None else (1e6 * iv[0], 1e6 * iv[1]),
                         "sim_cpu_s": cpu})
    return rows


def real(folders=("cwru_de48", "cwru_de12")) -> list[dict]:
    """Part 3: every CWRU record of the folders at its fault's location."""
    rows = []
    for folder in folders:
        index = DATA / folder / "index.csv"
        if not index.exists():
            continue
        with open(index, newline="", encoding="utf-8") as fh:
            for rec in csv.DictReader(fh):
                d = np.load(DATA / folder / rec["file"])
                x, fs = np.asarray(d["x"], float), float(d["fs"])
                fr = estimate_shaft_rate(x, fs, float(rec["rpm_nominal"]) / 60.0).hz
                loc = LOCATIONS[rec["fault"]]
                res = defect_length(x, fs, record_scene("6205", fr, loc))
                rows.append({"file": rec["file"], "fs_khz": fs / 1e3, "location": loc,
                             "where": rec["outer_race_position"], "load_hp": rec["load_hp"],
                             "diameter_mm": float(rec["fault_diameter_mils"]) * 1e-3 * 25.4,
                             "status": res.status, "length_mm": res.length_mm,
                             "interval_mm": res.interval_mm,
                             "min_length_mm": res.min_length_mm,
                             "events": f"{res.spacing.n_events}/{res.spacing.n_periods}"})
    return rows


#: Bands of the scan (Hz) on the 48 kHz records.
SCAN_BANDS = ((500.0, 6000.0), (1500.0, 12000.0), (1500.0, 21600.0), (3000.0, 21600.0),
              (6000.0, 21600.0))


def band_scan(bands=SCAN_BANDS, folder: str = "cwru_de48") -> list[dict]:
    """Part 4: the 48 kHz records through each band: how much the reading depends on it."""
    rows = []
    with open(DATA / folder / "index.csv", newline="", encoding="utf-8") as fh:
        records = list(csv.DictReader(fh))
    for rec in records:
        d = np.load(DATA / folder / rec["file"])
        x, fs = np.asarray(d["x"], float), float(d["fs"])
        scene = record_scene("6205", estimate_shaft_rate(x, fs, float(rec["rpm_nominal"]) / 60.0)
                             .hz, LOCATIONS[rec["fault"]])
        row = {"file": rec["file"], "diameter_mm": float(rec["fault_diameter_mils"]) * 0.0254}
        for band in bands:
            res = defect_length(x, fs, scene, band=band)
            row[f"{band[0] / 1e3:g}-{band[1] / 1e3:g} kHz"] = (
                f"{res.length_mm:.3g}" if res.status == ESTIMATED else
                f"n.r. (>= {res.min_length_mm:.2g})" if res.min_length_mm else res.status)
        rows.append(row)
    return rows


def _f(v, fmt="{:.3g}"):
    if v is None:
        return "-"
    if isinstance(v, tuple):
        return "-".join(fmt.format(q) for q in v)
    return fmt.format(v) if isinstance(v, float) else str(v)


def table(rows: list[dict]) -> str:
    """Rows as a markdown table."""
    if not rows:
        return "(no rows)\n"
    keys = list(rows[0])
    out = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    out += ["| " + " | ".join(_f(r[k]) for k in keys) + " |" for r in rows]
    return "\n".join(out) + "\n"


def rank_summary(rows: list[dict]) -> str:
    """Spearman correlation of the estimated length with the diameter, per fs and location."""
    lines = []
    for fs in sorted({r["fs_khz"] for r in rows}, reverse=True):
        sel = [r for r in rows if r["fs_khz"] == fs]
        est = [r for r in sel if r["status"] == ESTIMATED]
        if len(est) >= 3 and len({r["diameter_mm"] for r in est}) > 1:
            rho = spearmanr([r["diameter_mm"] for r in est], [r["length_mm"] for r in est])[0]
            rho = f"{rho:+.2f}"
        else:
            rho = "n/a (fewer than 3 estimates of 2 sizes)"
        counts = {s: sum(r["status"] == s for r in sel) for s in sorted({r["status"] for r in sel})}
        lines.append(f"- {fs:g} kHz: {len(sel)} records, {counts}; Spearman rho(length, "
                     f"diameter) over the estimated: {rho}")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    """Run the parts asked; print markdown tables.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments (``--part synthetic|dynamic|real``, repeatable).

    Returns
    -------
    int
        0.
    """
    ap = argparse.ArgumentParser(prog="python -m benchmarks defect_size")
    ap.add_argument("--part", action="append",
                    choices=("synthetic", "dynamic", "real", "bands"))
    args = ap.parse_args(argv)
    parts = args.part or ["synthetic", "dynamic", "real", "bands"]
    from benchmarks.dynamics_cost import machine

    print(f"# defect_size, {datetime.date.today()}, {machine()}\n")
    cpu = time.process_time()
    if "synthetic" in parts:
        print("## Records of known spacing\n\n" + table(synthetic()))
    if "dynamic" in parts:
        print("## The dynamic model, outer-race slot at 6:00, 48 kHz\n\n" + table(dynamic()))
    if "real" in parts:
        rows = real()
        print("## CWRU records\n\n" + table(rows) + "\n" + rank_summary(rows))
    if "bands" in parts:
        print("## Estimated length (mm) per band, CWRU 48 kHz\n\n" + table(band_scan()))
    print(f"\nCPU {time.process_time() - cpu:.1f} s")
    return 0


def smoke() -> None:
    """The same code paths on tiny inputs (no figure checked)."""
    table(synthetic(fss=(48000.0,), dts_us=(202.0,), noises=(0.05,), duration_s=1.0))
    table(dynamic(widths_in=(0.014,), duration_s=0.1))
