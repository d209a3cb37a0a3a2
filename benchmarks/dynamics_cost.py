"""The dynamic bearing model's integrator, step rule and cost (docs/dynamics.md, "Integrator").

    nice -n 5 python -m benchmarks dynamics_cost              # all three parts, ~3 CPU min
    nice -n 5 python -m benchmarks dynamics_cost --full       # plus a measured 10 s record

Scene: the CWRU 6205 (config_cwru.yaml: 1 kN assumed, 10 um clearance, 1797 rpm, centrifugal
force, the assumed structure of ``STRUCTURE_DEFAULTS``), an outer-race slot of the geometric law
(``slot_law``, 0.011 in deep).

1. Integrators on one short scene (10 ms from the quasi-static state, the 0.007 in slot 2 deg
   from the load: one element crosses it): the numba RK4 kernel at 10-80 steps per period of the
   highest frequency (``S``; the step is rounded down to divide the 1 us record interval)
   against scipy's ``solve_ivp`` (Radau, BDF, LSODA, DOP853) on the same
   right-hand side; error of the end state (of the largest displacement) and of the resonator's
   displacement (RMS, of its RMS) against DOP853 at rtol 1e-12; CPU s and CPU ratio to RK4 at
   the step rule.
2. Step rule: envelope lines of the defect (1-3 x BPFO, 1-3 x BPFI, 2 BSF -+ FTF and 2 BSF) of
   the resonator acceleration and of the housing force along x and y (band fs/4-3fs/8, 1 s)
   for 20-80 steps per period (:data:`RULE_STEPS`, ``--rule-steps``); the largest change of a
   line from ``S`` steps to ``2 S``. Scenes: the 0.007 in slot at 6:00 (loaded), the 0.021 in
   slot at 3:00 (an element bouncing at the load zone's edge), both at 12 kHz (``--no-edge``
   leaves them out), and the rig's OR 0.007 in at 6:00 and at 3:00, IR 0.007 in and the ball
   0.007 in (:data:`RIG_SCENES`, ``--rule-scenes``: config_rig.yaml's 0.1 kN, preload and
   structure, the standard table, a ball's axis fixed) at 12 and 48 kHz (:data:`RIG_FS`).
3. Cost: CPU s of 0.5 s and 1 s records at 12 kHz at the step rule; 10 s extrapolated linearly
   (and measured with ``--full``).
4. Ball pit (``--parts ball``): the 0.007 in slot on element 0 (each contact's geometric law),
   envelope lines at 2 BSF and 2 BSF -+ FTF of the resonator acceleration and the housing force
   (fs/4-3fs/8, 12 kHz, 1 s) for 20-80 steps per period, their height over the spectrum's
   median (20-500 Hz), the largest change when the step halves, and the CPU s of each record.
5. Kernel (``--parts kernel``): a 1 s record of the 0.007 in slot at 6:00 by the fused RK4 loop
   (``kernel="fast"``) and by the step-by-step reference, alternately three times; CPU s, ns
   per step and whether the two agree to the bit.
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import math
import platform
import time
from pathlib import Path

import numpy as np
import yaml
from scipy.integrate import solve_ivp

from bearing_envelope.physics.dynamics import (StateLayout, initial_state, params_from_scene, rhs,
                                               simulate_dynamics, slot_law)
from bearing_envelope.physics.dynamics.model import arrays
from bearing_envelope.physics.dynamics.params import STEPS_PER_PERIOD, rule_steps
from bearing_envelope.physics.kinematics import bearing_rates
from bearing_envelope.physics.scene import Scene
from bearing_envelope.signal.envelope import envelope_spectrum
from bearing_envelope.signal.spectrum import amplitude_at

ROOT = Path(__file__).resolve().parents[1]
DEPTH_M = 279.4e-6
INCH = 25.4e-3


def machine() -> str:
    name = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                name = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{name}, {platform.python_implementation()} {platform.python_version()}"


def scene_params(width_in: float | None, position_deg: float = 0.0):
    m = yaml.safe_load((ROOT / "config_cwru.yaml").read_text(encoding="utf-8"))["scene"]
    p = params_from_scene(Scene.from_mapping(m, load_kN=1.0, depth_um=0.0))
    if width_in is None:
        return p
    law = slot_law(p.element_radius_m, width_in * INCH, DEPTH_M, p.k_outer, p.exponent, 30e-6)
    return p.with_(defect=law, defect_angle_rad=math.radians(position_deg), defect_race="outer")


def reference_run(p, y0, t_end, t_eval):
    lay = StateLayout(p.z)
    atol = np.r_[np.full(lay.n_dof, 1e-15), np.full(lay.n_dof, 1e-11)]
    a = arrays(p, -1e-3, t_end + 1e-3)
    return solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", args=(p, a), rtol=1e-12, atol=atol,
                     t_eval=t_eval)


def integrators(duration: float = 1e-2, steps=(10, 20, 40, 80),
                methods=(("Radau", 1e-6), ("BDF", 1e-6), ("LSODA", 1e-6), ("LSODA", 1e-9),
                         ("DOP853", 1e-9))) -> list[dict]:
    p = scene_params(0.007, 2.0)
    lay = StateLayout(p.z)
    y0 = initial_state(p)
    fs = 1e6
    r0 = simulate_dynamics(p, duration, fs, acquisition_mode="point", settle_s=0.0, y0=y0)
    t_eval = r0.t_s
    ref = reference_run(p, y0, r0.t_end_s, np.r_[t_eval, r0.t_end_s])
    scale = np.abs(y0[:lay.n_dof]).max()
    res_ref = ref.y[lay.RES, :-1]

    def errors(y_end, res):
        e_end = np.abs(y_end[:lay.n_dof] - ref.y[:lay.n_dof, -1]).max() / scale
        e_res = math.sqrt(np.mean((res - res_ref) ** 2)) / math.sqrt(np.mean((res_ref - res_ref.mean()) ** 2))
        return e_end, e_res

    rows = []
    for s in steps:
        c0 = time.process_time()
        r = simulate_dynamics(p, duration, fs, acquisition_mode="point", settle_s=0.0, y0=y0,
                              steps_per_period=float(s))
        cpu = time.process_time() - c0
        rows.append(dict(method=f"RK4 numba, S = {s} (dt {1e6 * r.step_s:.2f} us)", cpu=cpu, steps=r.steps,
                         **dict(zip(("e_end", "e_res"), errors(r.state_end, r.resonator_displacement_m)))))
    a = arrays(p, -1e-3, r0.t_end_s + 1e-3)
    for method, rtol in methods:
        atol = np.r_[np.full(lay.n_dof, rtol * 1e-6 * scale), np.full(lay.n_dof, rtol * 1e-2)]
        c0 = time.process_time()
        sol = solve_ivp(rhs, (0.0, r0.t_end_s), y0, method=method, args=(p, a), rtol=rtol,
                        atol=atol, t_eval=np.r_[t_eval, r0.t_end_s])
        cpu = time.process_time() - c0
        e = errors(sol.y[:, -1], sol.y[lay.RES, :-1]) if sol.success else (math.nan, math.nan)
        rows.append(dict(method=f"solve_ivp {method}, rtol {rtol:g}", cpu=cpu, steps=sol.nfev,
                         e_end=e[0], e_res=e[1]))
    rule = next((r["cpu"] for r in rows if f"S = {int(STEPS_PER_PERIOD)} " in r["method"]),
                rows[0]["cpu"])
    for r in rows:
        r["ratio"] = r["cpu"] / rule
    return rows


#: Steps per period measured by the step rule's parts (each against twice as many).
RULE_STEPS = (20, 30, 40, 60, 80)
#: The rig's scenes of the step rule (``benchmarks.rig_cost.SCENES``: config_rig.yaml's load,
#: preload, structure and sensor, the standard table).
RIG_SCENES = ("OR007at6", "OR007at3", "IR007", "B007")
#: The sampling rates of the rig's scenes in the step rule (the 12 and 48 kHz records), Hz.
RIG_FS = (12000.0, 48000.0)


def fault_hz(p) -> tuple[float, float, float]:
    """The three lines of ``p``'s defect: 1-3 x BPFO (outer race), 1-3 x BPFI (inner race),
    2 BSF -+ FTF and 2 BSF (an element pit)."""
    if p.element_pit is not None:
        r = bearing_rates(p.shaft_rate_hz, p.z, 2e3 * p.element_radius_m,
                          1e3 * (p.outer_race_radius_m + p.inner_race_radius_m),
                          math.degrees(p.contact_angle_rad))
        return 2 * r["bsf"] - r["ftf"], 2 * r["bsf"], 2 * r["bsf"] + r["ftf"]
    f1 = p.z * (p.shaft_rate_hz - p.cage_rate_hz if p.defect_race == "inner" else p.cage_rate_hz)
    return f1, 2 * f1, 3 * f1


def lines(p, steps: float, duration: float, fs: float = 12000.0):
    """Envelope lines of the defect (:func:`fault_hz`; band fs/4-3fs/8) of the resonator
    acceleration and of the housing force along x and y."""
    r = simulate_dynamics(p, duration, fs, steps_per_period=steps)
    freqs = fault_hz(p)
    out = []
    for x in (r.resonator_acceleration_m_s2, r.housing_force_n[:, 0], r.housing_force_n[:, 1]):
        f, a = envelope_spectrum(x - x.mean(), fs, (0.25 * fs, 0.375 * fs))
        out += [amplitude_at(f, a, q, 0.01 * freqs[0])[1] for q in freqs]
    return np.array(out)


def halving(got: dict) -> dict:
    """Largest relative change of a line from ``S`` steps per period to ``2 S``, per ``S``."""
    return {s: float(np.max(np.abs(got[s] - got[2 * s]) / np.abs(got[2 * s])))
            for s in got if 2 * s in got}


def rig_scene_params(name: str, preset: str = "standard", fs_hz: float = 12000.0):
    """The dynamic model of a rig scene (:data:`RIG_SCENES`) recorded at ``fs_hz``, as the rig
    builds it; a ball's spin axis fixed (its pit meets a contact every turn, not only while the
    wandering axis holds it on the track)."""
    from bearing_envelope.physics.dynamics.case import case_params
    from bearing_envelope.study.rig import read_rig_config
    from bearing_envelope.study.rig.dynamic import rig_scene
    from bearing_envelope.study.rig.simulation import condition_scene

    from .rig_cost import CONFIG, condition
    base = read_rig_config(CONFIG)
    s = type(base)(**{**base.__dict__, "fidelity": preset, "dynamics": "dynamic",
                      "ball_spin_axis": "fixed"})
    return case_params(rig_scene(condition_scene(condition(name, 1.0, fs_hz), s), s), preset)[0]


def step_rule(duration: float = 1.0, steps=RULE_STEPS, rig=RIG_SCENES, rig_fs=RIG_FS,
              edge: bool = True) -> list[dict]:
    scenes = [(f"{w} in at {clock}", 12000.0, lambda w=w, pos=pos: scene_params(w, pos))
              for w, pos, clock in ((0.007, 0.0, "6:00"), (0.021, 90.0, "3:00"))] if edge else []
    scenes += [(f"rig {name} {fs / 1e3:g} kHz", fs, lambda name=name, fs=fs: rig_scene_params(name, fs_hz=fs))
               for name in rig for fs in rig_fs]
    rows = []
    for label, fs, make in scenes:
        p = make()
        got, cpu = {}, {}
        for s in steps:
            c0 = time.process_time()
            got[s] = lines(p, float(s), duration, fs)
            cpu[s] = time.process_time() - c0
        change = halving(got)
        rows += [dict(scene=label, steps=s, lines=got[s], change=change.get(s, math.nan),
                      cpu=cpu[s], rule=rule_steps(p)) for s in steps]
    return rows


def cost(durations=(0.5, 1.0), full: bool = False) -> list[dict]:
    rows = []
    for label, p in (("healthy", scene_params(None)), ("0.007 in at 6:00", scene_params(0.007, 0.0))):
        got = []
        for d in durations + ((10.0,) if full else ()):
            c0 = time.process_time()
            r = simulate_dynamics(p, d, 12000.0)
            got.append((d, time.process_time() - c0, r.steps, r.oversample))
        (d0, c0_, *_), (d1, c1, *_) = got[0], got[1]
        per_s = (c1 - c0_) / (d1 - d0)
        rows.append(dict(scene=label, runs=got, per_s=per_s, ten_s=c1 + per_s * (10.0 - d1),
                         measured_10=got[2][1] if full else math.nan))
    return rows


def kernels(duration: float = 1.0, repeats: int = 3) -> list[dict]:
    """CPU s of a record at 12 kHz by the fused loop and by the step-by-step reference, on
    the 0.007 in slot at 6:00 (alternately, ``repeats`` times each), and whether they agree to
    the bit."""
    p = scene_params(0.007, 0.0)
    rows = []
    for k in range(repeats):
        for kernel in ("fast", "reference"):
            c0 = time.process_time()
            r = simulate_dynamics(p, duration, 12000.0, kernel=kernel)
            rows.append(dict(kernel=kernel, cpu=time.process_time() - c0, steps=r.steps,
                             force=r.housing_force_n, end=r.state_end))
    same = all(np.array_equal(a["force"], b["force"]) and np.array_equal(a["end"], b["end"])
               for a, b in zip(rows[::2], rows[1::2]))
    for r in rows:
        r["same"] = same
    return rows


def print_kernels(rows) -> None:
    print("\n| kernel | CPU s per run | steps | ns per step | housing force and end state equal to the bit |")
    print("|---|---|---|---|---|")
    for kernel in ("fast", "reference"):
        got = [r for r in rows if r["kernel"] == kernel]
        cpu = [r["cpu"] for r in got]
        print(f"| {kernel} | {' / '.join(f'{c:.2f}' for c in cpu)} | {got[0]['steps']} | "
              f"{1e9 * min(cpu) / got[0]['steps']:.0f} | {got[0]['same']} |")


def ball_params(width_in: float = 0.007):
    """The CWRU scene with the slot on element 0 (outer and inner contact laws)."""
    m = yaml.safe_load((ROOT / "config_cwru.yaml").read_text(encoding="utf-8"))["scene"]
    m["defect"]["location"] = "rolling_element"
    p = params_from_scene(Scene.from_mapping(m, load_kN=1.0, depth_um=0.0))
    lo, li = (slot_law(p.element_radius_m, width_in * INCH, DEPTH_M, k, p.exponent, 30e-6)
              for k in (p.k_outer, p.k_inner))
    return p.with_(defect=lo, element_pit=dataclasses.replace(p.pit, inner=li))


def ball(duration: float = 1.0, steps=RULE_STEPS, fs: float = 12000.0) -> list[dict]:
    p = ball_params()
    r = bearing_rates(p.shaft_rate_hz, p.z, 2e3 * p.element_radius_m,
                      1e3 * (p.outer_race_radius_m + p.inner_race_radius_m),
                      math.degrees(p.contact_angle_rad))
    freqs = (2 * r["bsf"] - r["ftf"], 2 * r["bsf"], 2 * r["bsf"] + r["ftf"])
    rows = []
    for s in steps:
        c0 = time.process_time()
        res = simulate_dynamics(p, duration, fs, steps_per_period=float(s))
        cpu = time.process_time() - c0
        lines, over = [], []
        for x in (res.resonator_acceleration_m_s2, res.housing_force_n[:, 0]):
            f, a = envelope_spectrum(x - x.mean(), fs, (0.25 * fs, 0.375 * fs))
            floor = np.median(a[(f > 20) & (f < 500)])
            lines += [amplitude_at(f, a, q, 1.0 / duration)[1] for q in freqs]
            over += [lines[-2] / floor]
        rows.append(dict(steps=s, cpu=cpu, lines=np.array(lines), over=over,
                         mean=res.housing_force_n[:, 0].mean() / p.force_n - 1))
    change = halving({r["steps"]: r["lines"] for r in rows})
    for r in rows:
        r["change"] = change.get(r["steps"], math.nan)
    return rows


def print_ball(rows) -> None:
    print("\n| steps/period | CPU s | lines 2BSF-FTF, 2BSF, 2BSF+FTF (res; force) | 2BSF / floor (res, force) | mean force / load - 1 | largest change when the step halves |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['steps']} | {r['cpu']:.2f} | {' '.join(f'{v:.4g}' for v in r['lines'])} | "
              f"{r['over'][0]:.0f}, {r['over'][1]:.0f} | {r['mean']:.1e} | {100 * r['change']:.3f} % |")


def print_tables(ints, rule, costs) -> None:
    print(f"# dynamics_cost, {datetime.date.today().isoformat()}, {machine()}\n")
    print("| integrator | CPU s | CPU / RK4 at the rule | RK4 steps or solve_ivp nfev | end state error | resonator error |")
    print("|---|---|---|---|---|---|")
    for r in ints:
        print(f"| {r['method']} | {r['cpu']:.3f} | {r['ratio']:.1f} | {r['steps']} | {r['e_end']:.1e} | {r['e_res']:.1e} |")
    print("\n| scene (its rule's steps/period) | steps/period | CPU s | lines (res, force x, force y: 3 each) | largest change when the step halves |")
    print("|---|---|---|---|---|")
    for r in rule:
        print(f"| {r['scene']} ({r['rule']:g}) | {r['steps']} | {r['cpu']:.2f} | {' '.join(f'{v:.4g}' for v in r['lines'])} | {100 * r['change']:.3f} % |")
    print("\n| scene | record s: CPU s (steps, oversample) | CPU s per record s | 10 s extrapolated | 10 s measured |")
    print("|---|---|---|---|---|")
    for r in costs:
        runs = "; ".join(f"{d:g} s: {c:.2f} ({n}, {o})" for d, c, n, o in r["runs"])
        print(f"| {r['scene']} | {runs} | {r['per_s']:.2f} | {r['ten_s']:.1f} | {r['measured_10']:.1f} |")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks dynamics_cost", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--full", action="store_true", help="also measure a 10 s record")
    ap.add_argument("--rule-duration", type=float, default=1.0, help="record length of part 2, s")
    ap.add_argument("--rule-steps", type=int, nargs="+", default=list(RULE_STEPS),
                    help="steps per period of part 2 (each against twice as many when listed)")
    ap.add_argument("--rule-scenes", nargs="+", default=list(RIG_SCENES), help="rig scenes of part 2")
    ap.add_argument("--no-edge", action="store_true", help="part 2 without the two 1 kN scenes")
    ap.add_argument("--parts", nargs="+", default=["integrators", "rule", "cost", "ball"],
                    choices=["integrators", "rule", "cost", "ball", "kernel"],
                    help="the parts to run (kernel: the fused loop against the reference)")
    args = ap.parse_args(argv)
    simulate_dynamics(scene_params(None), 0.01, 12000.0)          # compile outside the clocks
    print_tables(integrators() if "integrators" in args.parts else [],
                 step_rule(args.rule_duration, tuple(args.rule_steps), tuple(args.rule_scenes),
                           edge=not args.no_edge) if "rule" in args.parts else [],
                 cost(full=args.full) if "cost" in args.parts else [])
    if "ball" in args.parts:
        print_ball(ball())
    if "kernel" in args.parts:
        print_kernels(kernels())
    return 0


def smoke() -> None:
    ints = integrators(duration=2e-4, steps=(20, 40), methods=(("LSODA", 1e-6),))
    rule = step_rule(duration=0.02, steps=(20, 40), rig=RIG_SCENES[:1])
    print_tables(ints, rule, cost(durations=(0.01, 0.02)))
    print_ball(ball(duration=0.02, steps=(20, 40)))
    print_kernels(kernels(duration=0.02, repeats=1))


if __name__ == "__main__":
    raise SystemExit(main())
