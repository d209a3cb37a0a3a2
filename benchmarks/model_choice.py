"""Model only what the scene needs: the criterion's verdict against where the two models' answers
differ (docs/dynamics.md, "Model only what the scene needs").

    nice -n 5 python -m benchmarks model_choice --fidelity draft --duration 0.5

For each scene, both models on the same scene, fs and record length:

- quasi-static (``physics.history.simulate``): the removed force (N), the surrogate of the
  defect's action, along the direction of the defect's contact (``defect_angle``);
- dynamic (``physics.dynamics.case.simulate_dynamic``): the force the bearing passes to the
  housing (N) along the same direction, less that of the same scene without its pit (the same
  model, start and step): the pit's part. The healthy bearing's own varying compliance has its
  lines at multiples of Z f_c (BPFO): for the default bearing (22 rollers, f_c/f_r = 0.333)
  2 BPFO = 231.4 Hz falls in the BPFI bin (231.9 Hz) of any record shorter than a few seconds,
  and an outer-race pit's line is BPFO itself; the removed force holds no healthy part.

Per scene: the criterion's ``share`` (drop / static approach), ``event_over_period`` and verdict;
the envelope line at 1 x the event rate of each force in the band fs/4 - 3 fs/8 (Hann, largest
bin within 1 % of the rate) and their ratio in dB; the peak force of the element contact over the pit against the static element load; and
whether that contact opens over the pit (a second dynamic run, point samples at 1 MHz over two
passages: the least outer-contact load of the element whose contact centre is within the pit's
middle half, against the static load). Where the element follows the pit quasi-statically, the
housing receives the blocked (removed) force through the element's two contacts in series:
``k_other / (k + k_other)`` of it (``defect_scales``' stiffnesses; about -6 dB for a ball). In
the band the element between its two linearised contacts (the model's stiffnesses at the
static loads, its mass and contact damping) changes that (:func:`element_path`: the force of
its **outer** contact, the housing's): an inner-race pit's reaches the housing through the
other contact, ``k_o / (k + k_o - m w^2)`` (+4.0 / +3.1 dB at 250 / 750 kN for the default
roller, whose 30-35 kHz mode sits just above fs/4 - 3fs/8 at 65 kHz); an outer-race pit's
through its own contact, ``(k_o - m w^2) / (k + k_o - m w^2)``, falling to 0 at the
anti-resonance ``sqrt(k_o / m)`` (25 kHz for the 6205's ball at 51 N: 1.3-4.0 dB below the
static ratio in 12-18 kHz at 48 kHz, 0.1 dB at 12 kHz). The expected ratio is the removed
force's line through that linear element over its own. The answers differ where the line ratio
leaves that value by more than 3 dB, the contact over the pit strikes (peak above 1.5 x its
static load; the quasi-static contact never exceeds it), or the contact opens. Prints a markdown table; CPU seconds are process time.

``--decompose`` (the default-sweep scenes, or those named by ``--only``): the pit's part of the
housing force's line taken apart (:func:`decompose`): the table's pit ratio at the ends of its
``x`` range, the healthy bearing's line, the whole and the pit's part, the pit's ratio read at
the model's approach (the join before 2026-12-06), a pit-free table, half the step, and the
element's mass / 16 (its mode four times higher, out of the band). ``--speeds 1 2 3 5 10``: the
rig's 0.021 in pit at 6:00 at those multiples of 1797 rpm, all at 48 kHz (the band fixed, the
event's duration varied). ``--causes 1``: the same pit at that speed, each candidate for its
departure switched alone (:func:`causes`: fidelity, both tables' offsets, the acquisition's
oversampling, the record length, the step, the element's mass). ``--transfer 10``: that
pit's part of the housing force over the removed force, band by band (:func:`transfer`).
``--separate 8``: the default sweep's 250 kN, 50 um case (pit joined at the load, no healthy
run subtracted) over an 8 s record: its envelope lines at 2 BPFO and at BPFI, apart.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from bearing_envelope.physics.defect_contact import defect_scales, defect_table
from bearing_envelope.physics.dynamics.case import joined_law, scene_params, simulate_dynamic
from bearing_envelope.physics.dynamics.criterion import model_choice
from bearing_envelope.physics.dynamics.model import simulate_dynamics
from bearing_envelope.physics.dynamics.params import STEPS_PER_PERIOD, contact_stiffness
from bearing_envelope.physics.history import defect_angle, simulate
from bearing_envelope.physics.locations import scene_event_frequencies
from bearing_envelope.physics.scene import Scene
from bearing_envelope.signal.envelope import envelope_spectrum
from bearing_envelope.signal.spectrum import amplitude_at

INCH_UM = 25400.0
#: The rig's scene (config_rig.yaml): its load, its identified preload, centrifugal force on.
RIG = {"load_kN": 0.1, "clearance_um": -3.94}
#: Departure of the two models' line ratio from its quasi-static value beyond which their
#: answers differ, dB.
DIFFER_DB = 3.0
#: Peak force of the contact over the pit, over its static load, above which it is a strike
#: (the quasi-static contact never exceeds its static load).
STRIKE = 1.5


def cwru(pit_in: float, position_deg: float, clearance_um: float, *, fs_hz: float,
         duration_s: float, load_kN: float = RIG["load_kN"], rpm: float = 1797.0,
         oversample: int | None = None) -> Scene:
    """The CWRU 6205 (1797 rpm unless ``rpm``) with a round 0.28 mm deep outer-race pit
    (``oversample``: the acquisition's, else ``auto``)."""
    fr = rpm / 60.0
    dia = pit_in * INCH_UM
    m = {"bearing": {"designation": "SKF 6205-2RS", "radial_clearance_um": clearance_um},
         "operation": {"shaft_rate_hz": fr, "fs_hz": fs_hz, "revolutions": duration_s * fr},
         "load": {"centrifugal": True},
         "defect": {"location": "outer_race", "shape": "cylinder", "length_um": dia,
                    "width_um": dia, "position_deg": position_deg},
         "dynamics": {"model": "auto"}}
    if oversample is not None:
        m["operation"]["acquisition"] = {"oversample": int(oversample)}
    return Scene.from_mapping(m, load_kN=load_kN, depth_um=279.4)


def default_sweep(load_kN: float, depth_um: float, *, duration_s: float) -> Scene:
    """A default-sweep case (config.yaml's scene), shortened to ``duration_s``."""
    m = {"operation": {"revolutions": duration_s * 15.8}, "dynamics": {"model": "auto"}}
    return Scene.from_mapping(m, load_kN=load_kN, depth_um=depth_um)


def scenes(fs_hz: float, duration_s: float) -> list[tuple[str, Scene]]:
    """The measured scenes: the rig's (preload), the catalogue's clearance at 3:00 and 6:00, and
    default-sweep cases."""
    out = []
    for pit in (0.007, 0.021):
        out.append((f"rig OR 6:00 {pit} in", cwru(pit, 0.0, RIG["clearance_um"], fs_hz=fs_hz,
                                                 duration_s=duration_s)))
    out.append(("rig OR 3:00 0.021 in", cwru(0.021, 90.0, RIG["clearance_um"], fs_hz=fs_hz,
                                             duration_s=duration_s)))
    for pit in (0.007, 0.014, 0.021):
        out.append((f"10 um clearance OR 3:00 {pit} in",
                    cwru(pit, 90.0, 10.0, fs_hz=fs_hz, duration_s=duration_s)))
    out.append(("10 um clearance OR 6:00 0.021 in", cwru(0.021, 0.0, 10.0, fs_hz=fs_hz,
                                                         duration_s=duration_s)))
    # events near and under the natural period (fs at least 2 x 13 x BPFI: 4, 8, 12 x fs)
    for pit, pos, speed in ((0.014, 90.0, 10), (0.021, 0.0, 10), (0.021, 90.0, 10),
                            (0.021, 0.0, 15), (0.021, 90.0, 15), (0.021, 90.0, 20),
                            (0.021, 0.0, 30), (0.021, 90.0, 30)):
        clock = "3:00" if pos else "6:00"
        f = (4 if speed <= 10 else 8 if speed <= 20 else 12) * fs_hz
        out.append((f"rig OR {clock} {pit} in, {speed} x speed, {f / 1e3:g} kHz",
                    cwru(pit, pos, RIG["clearance_um"], fs_hz=f, duration_s=duration_s,
                         rpm=1797.0 * speed)))
    for load, depth in ((250.0, 50.0), (750.0, 100.0)):
        out.append((f"default sweep {load:g} kN h {depth:g} um",
                    default_sweep(load, depth, duration_s=duration_s)))
    return out


def line(x: np.ndarray, fs: float, rate: float) -> float:
    """Envelope line at 1 x ``rate`` of ``x`` in the band fs/4 - 3 fs/8 (mean removed, Hann,
    largest bin within 1 %): above the shaft's mode on the bearing, where the housing receives
    an internal force pulse whole (at the event rate itself the shaft's motion cancels it: the
    mean force through a bearing is the applied load)."""
    f, a = envelope_spectrum(x - np.mean(x), fs, (0.25 * fs, 0.375 * fs))
    return float(amplitude_at(f, a, rate, 0.01 * rate)[1])


def element_path(x: np.ndarray, fs: float, scene: Scene,
                 mass_kg: float | None = None) -> np.ndarray:
    """``x`` (a blocked force on the pitted contact, N) through the element between its two
    linearised contacts, rings held: the change of the force the element's **outer** contact
    passes to the outer ring (the housing force's contact). With ``k, k_o`` the model's
    stiffnesses of the pitted and the other contact at the static loads of ``defect_scales``,
    ``c`` its contact damping (``c_o = 0`` on an other contact that carries nothing), ``m`` the
    element's mass and ``D = k + k_o - m w^2 + i w (c + c_o)``:

    - inner-race pit (the outer contact is the other one): ``H = (k_o + i w c_o) / D``,
      falling to 0 above the element's mode;
    - outer-race pit (the outer contact is the pitted one): ``H = (k_o - m w^2 + i w c_o) / D``,
      the pitted contact's own change: 0 at the anti-resonance ``sqrt(k_o / m)`` (the element's
      inertia cancels the other contact's spring) and the whole blocked force above the mode,
      where the element cannot follow the pit.

    Both are ``k_o / (k + k_o)`` at low frequency. Until 2026-12-06 the outer-race pit was given
    the inner-race form (the other contact's force: 3-6 dB too high in 12-18 kHz for the 6205
    at 48 kHz). ``mass_kg``: the element's mass, if not the model's.
    """
    sc = defect_scales(scene)
    p = scene_params(scene)
    outer = sc_race(scene) == "outer"
    k_p, k_q = (p.k_outer, p.k_inner) if outer else (p.k_inner, p.k_outer)
    k = contact_stiffness(k_p, sc.element_load_n, p.exponent)
    loaded = sc.other_stiffness_n_m > 0
    ko = contact_stiffness(k_q, sc.other_load_n, p.exponent) if loaded else 0.0
    w = 2 * math.pi * np.fft.rfftfreq(x.size, 1.0 / fs)
    c, c_o = p.contact_damping_ns_m, (p.contact_damping_ns_m if loaded else 0.0)
    mw2 = (p.element_mass_kg if mass_kg is None else mass_kg) * w ** 2
    h = (ko - (mw2 if outer else 0.0) + 1j * w * c_o) / (k + ko - mw2 + 1j * w * (c + c_o))
    return np.fft.irfft(h * np.fft.rfft(x - np.mean(x)), x.size)


def sc_race(scene: Scene) -> str:
    """The race whose contact holds the pit (its table's)."""
    return "outer" if scene.defect.location == "outer_race" else "inner"


def healthy_housing_force(scene: Scene) -> np.ndarray:
    """The housing force ``(n, 2)`` of ``scene`` without its pit: the dynamic case's model,
    start, step and acquisition, no defect law."""
    op = scene.operation
    over = None if op.acquisition.oversample == "auto" else int(op.acquisition.oversample)
    r = simulate_dynamics(scene_params(scene), scene.n_samples / op.fs_hz, op.fs_hz,
                          acquisition_mode=op.acquisition.mode, oversample=over)
    return r.housing_force_n


def opening(scene: Scene, fidelity: str, q_static: float) -> float:
    """Least outer-contact load of an element whose contact centre is within the pit's middle
    half, over two passages at 1 MHz point samples, over the static load (outer race only)."""
    if scene.defect.location != "outer_race":
        return float("nan")
    p = scene_params(scene)
    p = p.with_(defect=joined_law(defect_table(scene, fidelity), p))
    bpfo = scene_event_frequencies(scene)["bpfo"]
    r = simulate_dynamics(p, 2.0 / bpfo, 1e6, acquisition_mode="point")
    theta = 2 * math.pi * p.cage_rate_hz * r.t_s[:, None] + 2 * math.pi * np.arange(p.z) / p.z
    x = p.outer_race_radius_m * np.angle(np.exp(1j * (theta - p.defect_angle_rad)))
    inside = np.abs(x) < 0.25 * scene.defect.extent_x_m
    return float(r.element_load_n[inside].min() / q_static) if inside.any() else float("nan")


def measure(name: str, scene: Scene, fidelity: str) -> dict:
    """Both models on ``scene``: the lines, their ratio, the strike and the opening."""
    ch = model_choice(scene)
    sc = defect_scales(scene)
    ev = scene_event_frequencies(scene)
    rate = ev["bpfo"] if scene.defect.location == "outer_race" else ev["bpfi"]
    fs = scene.operation.fs_hz
    c0 = time.process_time()
    h = simulate(scene, fidelity)
    c_qs = time.process_time() - c0
    c0 = time.process_time()
    d = simulate_dynamic(scene, fidelity)
    ang = defect_angle(scene, h.time)   # the removed force's direction; the housing force's:
    phi = math.radians(scene.defect.position_deg) if scene.defect.location == "outer_race" else 0.0
    removed = h.signals["removed_force"] * np.cos(ang - phi)
    qs = line(removed, fs, rate)
    hf = healthy_housing_force(scene)
    c_dyn = time.process_time() - c0
    f_dir = d.signals["housing_force_x"] * math.cos(phi) + d.signals["housing_force_y"] * math.sin(phi)
    h_dir = hf[:, 0] * math.cos(phi) + hf[:, 1] * math.sin(phi)
    healthy = line(h_dir, fs, rate)
    dyn = line(f_dir - h_dir, fs, rate)
    ratio = 20 * math.log10(dyn / qs) if qs > 0 and dyn > 0 else float("inf")
    least = opening(scene, fidelity, sc.element_load_n)
    k, ko = sc.stiffness_n_m, sc.other_stiffness_n_m
    static = 20 * math.log10(ko / (k + ko)) if ko > 0 else float("-inf")
    through = line(element_path(removed, fs, scene), fs, rate)
    expected = 20 * math.log10(through / qs) if through > 0 and qs > 0 else float("-inf")
    peak = d.model["defect_force_peak_n"] / sc.element_load_n
    differ = not abs(ratio - expected) <= DIFFER_DB or peak > STRIKE or least <= 0.0
    return {"scene": name, "Q_N": sc.element_load_n, "share": ch.share,
            "event_periods": ch.event_over_period, "verdict": ch.verdict,
            "qs_line_N": qs, "healthy_line_N": healthy, "dyn_line_N": dyn, "ratio_dB": ratio,
            "static_dB": static, "expected_dB": expected,
            "peak_over_Q": peak,
            "least_over_Q": least, "differ": differ,
            "agrees": (ch.verdict == "dynamic") == differ, "cpu_qs": c_qs, "cpu_dyn": c_dyn}


def table(rows: list[dict]) -> str:
    """The markdown table of :func:`measure`'s rows."""
    head = ("| scene | Q N | drop/approach | event / T_n | verdict | QS removed-force env. line N | "
            "healthy housing-force env. line N | dynamic housing-force env. line, pit's part N | "
            "ratio dB | k_o/(k+k_o) dB | expected dB (through the element) | peak / Q | "
            "least load over pit / Q | answers differ | verdict agrees | CPU s QS, dyn |")
    out = [head, "|" + "---|" * 16]
    for r in rows:
        out.append(f"| {r['scene']} | {r['Q_N']:.3g} | {r['share']:.3g} | "
                   f"{r['event_periods']:.3g} | {r['verdict']} | {r['qs_line_N']:.3g} | "
                   f"{r['healthy_line_N']:.3g} | "
                   f"{r['dyn_line_N']:.3g} | {r['ratio_dB']:+.1f} | {r['static_dB']:+.1f} | "
                   f"{r['expected_dB']:+.1f} | {r['peak_over_Q']:.3g} | "
                   f"{r['least_over_Q']:.3g} | {'yes' if r['differ'] else 'no'} | "
                   f"{'yes' if r['agrees'] else 'NO'} | {r['cpu_qs']:.1f}, {r['cpu_dyn']:.1f} |")
    return "\n".join(out)


def _pit_part(scene: Scene, law, fs: float, rate: float, **kw) -> tuple[float, float]:
    """Line of the housing force along x with ``law`` and of its pit's part (less the healthy
    run with the same changes ``kw`` of the parameters and step), N."""
    op = scene.operation
    spp = kw.pop("steps_per_period", None)
    p = scene_params(scene).with_(**kw)
    run = {"acquisition_mode": op.acquisition.mode, "steps_per_period": spp,
           "oversample": None if op.acquisition.oversample == "auto" else int(op.acquisition.oversample)}
    healthy = simulate_dynamics(p, scene.n_samples / fs, fs, **run).housing_force_n[:, 0]
    pit = simulate_dynamics(p.with_(defect=law), scene.n_samples / fs, fs, **run).housing_force_n[:, 0]
    return line(pit, fs, rate), line(pit - healthy, fs, rate)


def decompose(name: str, scene: Scene, fidelity: str) -> list[str]:
    """The default-sweep line taken apart (inner-race pit): one printed line per variant."""
    tab = defect_table(scene, fidelity)
    p = scene_params(scene)
    fs, rate = scene.operation.fs_hz, scene_event_frequencies(scene)["bpfi"]
    h, f = np.asarray(tab.healthy_force_n), np.asarray(tab.force_n)
    ok = h > 0
    ends = max(float(np.max(np.abs(f[i, ok] / h[ok] - 1.0))) for i in (0, -1))
    out = [f"{name}: table {len(tab.x_m)} x {len(tab.delta_m)}, largest |ratio - 1| at the x "
           f"range's ends {ends:.3g}"]
    print(out[0], flush=True)
    k = p.k_inner if tab.race == "inner" else p.k_outer
    at_approach = joined_law(type("T", (), {"race": tab.race, "x_m": tab.x_m, "delta_m": tab.delta_m,
                                            "healthy_force_n": k * np.asarray(tab.delta_m) ** p.exponent,
                                            "force_n": f / np.where(ok, h, 1.0)[None, :]
                                            * (k * np.asarray(tab.delta_m) ** p.exponent)[None, :]}), p)
    none = joined_law(type("T", (), {"race": tab.race, "x_m": tab.x_m, "delta_m": tab.delta_m,
                                     "healthy_force_n": h, "force_n": np.tile(h, (len(tab.x_m), 1))}), p)
    law = joined_law(tab, p)
    for what, lw, kw in (("pit (joined at the load)", law, {}),
                         ("pit ratio read at the model's approach", at_approach, {}),
                         ("table without its pit (ratio 1)", none, {}),
                         ("half the step", law, {"steps_per_period": 80.0}),
                         ("element mass / 16", law, {"element_mass_kg": p.element_mass_kg / 16})):
        c0 = time.process_time()
        whole, part = _pit_part(scene, lw, fs, rate, **kw)
        out.append(f"  {what}: line {whole:.4g} N, pit's part {part:.4g} N "
                   f"({time.process_time() - c0:.1f} CPU s)")
        print(out[-1], flush=True)
    return out


def _departure(scene: Scene, fidelity, **kw) -> float:
    """:func:`measure`'s departure (ratio less expected, dB) of ``scene`` with the dynamic runs'
    ``steps_per_period`` and ``element_mass_kg`` of ``kw`` (the expected path's mass with it)."""
    fs, rate = scene.operation.fs_hz, scene_event_frequencies(scene)["bpfo"]
    h = simulate(scene, fidelity)
    removed = h.signals["removed_force"] * np.cos(defect_angle(scene, h.time))
    mass = kw.get("element_mass_kg")
    _, part = _pit_part(scene, joined_law(defect_table(scene, fidelity), scene_params(scene)),
                        fs, rate, **kw)
    qs = line(removed, fs, rate)
    return 20 * math.log10(part / qs) - 20 * math.log10(
        line(element_path(removed, fs, scene, mass), fs, rate) / qs)


def causes(speed: float, fs: float, duration_s: float, fidelity: str) -> list[str]:
    """The candidates for the departure of the rig's 0.021 in pit at 6:00 (``speed`` x 1797 rpm,
    ``fs``), each switched alone: the departure (ratio less expected, dB) per candidate, one
    printed line each."""
    def scene(**kw):
        return cwru(0.021, 0.0, RIG["clearance_um"], fs_hz=fs, rpm=1797.0 * speed,
                    duration_s=kw.pop("duration_s", duration_s), **kw)

    fine = {"preset": fidelity, "offset_step_um": 10.0, "max_offsets": 200}
    m = scene_params(scene()).element_mass_kg
    cases = (("as in the table", lambda: _departure(scene(), fidelity)),
             ("fidelity standard", lambda: _departure(scene(), "standard")),
             ("both tables' offsets every 10 um", lambda: _departure(scene(), fine)),
             ("acquisition oversample 8 (both models)",
              lambda: _departure(scene(oversample=8), fidelity)),
             ("record twice as long", lambda: _departure(scene(duration_s=2 * duration_s), fidelity)),
             ("half the step",
              lambda: _departure(scene(), fidelity, steps_per_period=2 * STEPS_PER_PERIOD)),
             ("element mass / 16 (its mode 4 x higher)",
              lambda: _departure(scene(), fidelity, element_mass_kg=m / 16)))
    out = []
    for what, run in cases:
        c0 = time.process_time()
        out.append(f"{what}: departure {run():+.2f} dB ({time.process_time() - c0:.1f} CPU s)")
        print(out[-1], flush=True)
    return out


def transfer(speed: float, fs: float, duration_s: float, fidelity: str) -> list[str]:
    """The dynamic model's pit part of the housing force over the removed force, band by band
    (1.5 kHz at 48 kHz, the bins where the removed force holds 5 % of its band's peak), against
    the element's linear path (undamped) through its outer contact (:func:`element_path`) and
    through the other one, for the rig's 0.021 in pit at 6:00 at ``speed`` x 1797 rpm: one printed line
    per band."""
    sc = cwru(0.021, 0.0, RIG["clearance_um"], fs_hz=fs, duration_s=duration_s,
              rpm=1797.0 * speed)
    h = simulate(sc, fidelity)
    x = h.signals["removed_force"] * np.cos(defect_angle(sc, h.time))
    p = scene_params(sc)
    law = joined_law(defect_table(sc, fidelity), p)
    run = {"acquisition_mode": sc.operation.acquisition.mode}
    y = (simulate_dynamics(p.with_(defect=law), x.size / fs, fs, **run).housing_force_n[:, 0]
         - simulate_dynamics(p, x.size / fs, fs, **run).housing_force_n[:, 0])
    f = np.fft.rfftfreq(x.size, 1.0 / fs)
    X, Y = np.fft.rfft(x - x.mean()), np.fft.rfft(y - y.mean())
    sd = defect_scales(sc)
    k = contact_stiffness(p.k_outer, sd.element_load_n, p.exponent)
    ko = contact_stiffness(p.k_inner, sd.other_load_n, p.exponent)
    out = []
    for lo in np.arange(0.0, fs / 2, fs / 32):
        sel = (f >= lo) & (f < lo + fs / 32) & (f > 0)
        top = sel & (np.abs(X) > 0.05 * np.abs(X[sel]).max())
        r = np.sum(Y[top] * np.conj(X[top])) / np.sum(np.abs(X[top]) ** 2)
        w = 2 * math.pi * (lo + fs / 64)
        d = k + ko - p.element_mass_kg * w ** 2
        out.append(f"{lo / 1e3:5.1f}-{(lo + fs / 32) / 1e3:5.1f} kHz: measured "
                   f"{20 * math.log10(abs(r)):+.1f} dB ({math.degrees(np.angle(r)):+.0f} deg), "
                   f"outer contact {20 * math.log10(abs((ko - p.element_mass_kg * w ** 2) / d)):+.1f}"
                   f" dB, inner contact {20 * math.log10(abs(ko / d)):+.1f} dB")
        print(out[-1], flush=True)
    return out


def separate(duration_s: float, fidelity: str) -> dict:
    """The default sweep's 250 kN, 50 um housing force over ``duration_s`` (no healthy run
    subtracted): its envelope line (fs/4 - 3fs/8, largest bin within one bin) at 2 BPFO and at
    BPFI, N, and the bin width, Hz (fine enough bins part the two)."""
    sc = default_sweep(250.0, 50.0, duration_s=duration_s)
    fs, ev = sc.operation.fs_hz, scene_event_frequencies(sc)
    p = scene_params(sc)
    p = p.with_(defect=joined_law(defect_table(sc, fidelity), p))
    x = simulate_dynamics(p, sc.n_samples / fs, fs,
                          acquisition_mode=sc.operation.acquisition.mode).housing_force_n[:, 0]
    f, a = envelope_spectrum(x - np.mean(x), fs, (0.25 * fs, 0.375 * fs))
    df = float(f[1] - f[0])
    out = {"bin_hz": df}
    for name, rate in (("2 BPFO", 2 * ev["bpfo"]), ("BPFI", ev["bpfi"])):
        hz, amp = amplitude_at(f, a, rate, 0.6 * df)
        out[f"{name} {rate:.2f} Hz"] = (float(hz), float(amp))
    return out


def main(argv=None) -> int:
    """Measure the criterion on the scenes of :func:`scenes` (or those named)."""
    ap = argparse.ArgumentParser(prog="python -m benchmarks model_choice", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fidelity", default="draft")
    ap.add_argument("--duration", type=float, default=0.5, help="record length, s")
    ap.add_argument("--fs", type=float, default=12000.0, help="CWRU scenes' fs, Hz")
    ap.add_argument("--only", nargs="*", default=None, help="scene names containing these")
    ap.add_argument("--decompose", action="store_true",
                    help="take the default-sweep line apart (decompose) instead of the table")
    ap.add_argument("--speeds", nargs="*", type=float, default=None,
                    help="the rig's 0.021 in pit at 6:00 at these multiples of 1797 rpm, 48 kHz")
    ap.add_argument("--causes", type=float, default=None,
                    help="speed multiple: the rig's 0.021 in pit at 6:00, 4 x fs, each candidate "
                         "for its departure switched alone")
    ap.add_argument("--transfer", type=float, default=None,
                    help="speed multiple: the rig's 0.021 in pit at 6:00, 4 x fs, the pit part "
                         "over the removed force band by band")
    ap.add_argument("--separate", type=float, default=None,
                    help="record length, s: the default 250 kN case's lines near BPFI apart")
    a = ap.parse_args(argv)
    if a.transfer:
        transfer(a.transfer, 4 * a.fs, a.duration, a.fidelity)
        return 0
    if a.causes:
        causes(a.causes, 4 * a.fs, a.duration, a.fidelity)
        return 0
    if a.separate:
        for k, v in separate(a.separate, a.fidelity).items():
            print(k, v)
        return 0
    if a.speeds:
        rows = []
        for k in a.speeds:
            sc = cwru(0.021, 0.0, RIG["clearance_um"], fs_hz=4 * a.fs, duration_s=a.duration,
                      rpm=1797.0 * k)
            rows.append(measure(f"rig OR 6:00 0.021 in, {k:g} x speed, {4 * a.fs / 1e3:g} kHz", sc,
                                a.fidelity))
            print(table(rows[-1:]).splitlines()[-1], flush=True)
        return 0
    if a.decompose:
        for name, sc in scenes(a.fs, a.duration):
            if (a.only and any(o in name for o in a.only)) or (not a.only and "default" in name):
                decompose(name, sc, a.fidelity)
        return 0
    rows = []
    for name, sc in scenes(a.fs, a.duration):
        if a.only and not any(o in name for o in a.only):
            continue
        rows.append(measure(name, sc, a.fidelity))
        print(table(rows[-1:]).splitlines()[-1], flush=True)
    print()
    print(table(rows))
    return 0


def smoke() -> None:
    """The same path on one short scene."""
    main(["--duration", "0.05", "--only", "rig OR 6:00 0.007"])


if __name__ == "__main__":
    raise SystemExit(main())
