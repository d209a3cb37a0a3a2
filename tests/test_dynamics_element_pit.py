"""A pit on a rolling element in the dynamic model (docs/dynamics.md, "A pit on a rolling
element"), against answers computed without it: the spin kinematics (closed-form BSF, FTF), the
strike of an element held between rings that do not move in the event (Hertz in series with the
pit's law), zero force where the element carries nothing, the envelope's 2 x BSF line with FTF
sidebands, momentum, the time step, and the location's own wandering-axis rule."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy.optimize import brentq

from bearing_envelope.physics.defect_contact import defect_table
from bearing_envelope.physics.dynamics import (DefectLaw, ElementPit, params_from_scene,
                                               simulate_dynamics, slot_drop, slot_law)
from bearing_envelope.physics.dynamics import element_pit_from_scene
from bearing_envelope.physics.dynamics.params import STEPS_PER_PERIOD
from bearing_envelope.physics.geometry import hertz_estimate
from bearing_envelope.physics.loads import scene_load_distribution
from bearing_envelope.physics.locations.rolling_element import on_track, rolling_element_kinematics
from bearing_envelope.physics.scene import Scene
from bearing_envelope.signal.envelope import envelope_spectrum
from bearing_envelope.signal.spectrum import amplitude_at
from test_dynamics_oracles import cwru_scene

#: The 0.007 in CWRU pit as a slot (m) and its depth.
W7, DEPTH = 177.8e-6, 279.4e-6
FS = 1e6


def ball_scene(**defect):
    return cwru_scene(location="rolling_element", **defect)


def scene_from(depth_um=0.0, clearance_um=None, **defect):
    """The CWRU scene (config_cwru.yaml, 1 kN) with a pit on a ball."""
    m = yaml.safe_load((Path(__file__).resolve().parents[1] / "config_cwru.yaml").read_text())["scene"]
    m["defect"].update(location="rolling_element", **defect)
    if clearance_um is not None:
        m.setdefault("bearing", {})["radial_clearance_um"] = clearance_um
    return Scene.from_mapping(m, load_kN=1.0, depth_um=depth_um)


def rates(scene):
    """Closed-form BSF and FTF (Hz) of the scene's bearing (Harris & Kotzalas 2007, ch. 8)."""
    b, fr = scene.bearing, scene.operation.shaft_rate_hz
    g = b.roller_diameter_mm * math.cos(b.contact_angle_rad) / b.pitch_diameter_mm
    bsf = b.pitch_diameter_mm / (2 * b.roller_diameter_mm) * fr * (1 - g * g)
    return bsf, 0.5 * fr * (1 - g)


def slot_params(scene=None, width=W7, **kw):
    """The 6205 (1 kN, 10 um clearance, 1797 rpm) with a slot on element 0: the geometric law of
    each contact (its own Hertz constant)."""
    p = params_from_scene(scene or ball_scene(), **kw)
    lo = slot_law(p.element_radius_m, width, DEPTH, p.k_outer, 1.5, 30e-6)
    li = slot_law(p.element_radius_m, width, DEPTH, p.k_inner, 1.5, 30e-6)
    return p.with_(defect=lo, element_pit=replace(p.pit, inner=li))


def runs(mask):
    """``(start, stop)`` index pairs of the runs of True in ``mask``."""
    m = np.diff(np.r_[0, np.asarray(mask, dtype=int), 0])
    return list(zip(np.flatnonzero(m == 1), np.flatnonzero(m == -1)))


@pytest.fixture(scope="module")
def passes():
    p = slot_params()
    return p, simulate_dynamics(p, 0.03, FS, acquisition_mode="point")


def test_the_pit_meets_outer_and_inner_race_alternately_at_the_spin_times(passes):
    p, r = passes
    bsf, _ = rates(ball_scene())
    v = 2 * math.pi * bsf * p.element_radius_m          # the pit's speed through a contact
    events = [(a, b) for a, b in runs(r.defect_contact != 0) if a > 0 and b < r.t_s.size]
    assert len(events) == 4
    for a, b in events:
        centre = 0.5 * (r.t_s[a] + r.t_s[b - 1])
        k = round(centre * 2 * bsf)
        print(f"event {k}: centre {1e6 * centre:.2f} us (k/(2 BSF) {1e6 * k / (2 * bsf):.2f} us), "
              f"{'outer' if r.defect_contact[a] > 0 else 'inner'}, {1e6 * (b - a) / FS:.0f} us "
              f"(w/v {1e6 * W7 / v:.1f} us)")
        assert abs(centre - k / (2 * bsf)) <= 1 / FS + r.step_s
        assert r.defect_contact[a] == (1 if k % 2 == 0 else -1)   # even: outer, odd: inner
        assert np.all(r.defect_contact[a:b] == r.defect_contact[a])
        assert abs((b - a) / FS - W7 / v) <= 2 / FS


def held_strike(p, q_entry, side, h):
    """The load of the pitted contact over the pit centre, the rings held where they were at
    entry (the event is short against the shaft's motion): the element's two contacts in series,
    Hertz on the other side, ``K <delta - h>^1.5`` on the pit's; the outer one carries ``F_c`` more.
    ``q_entry``: the pitted contact's load at entry. Returns 0 when the element leaves the race."""
    fc = p.centrifugal_n
    qi0 = q_entry if side < 0 else q_entry - fc
    total = (qi0 / p.k_inner) ** (2 / 3) + ((qi0 + fc) / p.k_outer) ** (2 / 3)

    def gap(qi):
        return (qi / p.k_inner) ** (2 / 3) + ((qi + fc) / p.k_outer) ** (2 / 3) + h - total

    if gap(0.0) >= 0:
        return 0.0 if side < 0 else fc
    qi = brentq(gap, 0.0, qi0, xtol=1e-9)
    return qi if side < 0 else qi + fc


def test_strike_strength_follows_the_element_load(passes):
    p, r = passes
    h = float(slot_drop(0.0, p.element_radius_m, W7, DEPTH))
    drops = []
    for a, b in runs(r.defect_contact != 0):
        f = r.defect_force_n[a:b]
        if a == 0 or f[0] < 20.0:                  # truncated by the record, or out of the zone
            continue
        side = int(r.defect_contact[a])
        expect = f[0] - held_strike(p, f[0], side, h)
        drops.append((f[0], f[0] - f.min(), expect))
        print(f"{'outer' if side > 0 else 'inner'}: entry {f[0]:.1f} N, drop {f[0] - f.min():.2f} N "
              f"(held rings {expect:.2f} N)")
        assert f[0] - f.min() == pytest.approx(expect, rel=0.06)
    assert len(drops) == 2
    (q1, d1, _), (q2, d2, _) = sorted(drops)
    assert q1 < 0.5 * q2 and d1 < d2                 # a lighter element strikes less


def test_no_strike_where_the_element_carries_nothing():
    p = slot_params(centrifugal=False)
    fc = p.cage_rate_hz

    def run(q):                                       # element 0 from 116 to 266 deg
        return simulate_dynamics(q.with_(cage_angle=lambda t: math.pi + 2 * math.pi * fc * t),
                                 0.02, 2e5, acquisition_mode="point", settle_s=0.015)
    r, h = run(p), run(p.with_(defect=None))
    met = runs(r.defect_contact != 0)
    print(f"{len(met)} passes of the pit through a contact, largest force "
          f"{r.defect_force_n.max():.3g} N")
    assert len(met) >= 3 and {int(r.defect_contact[a]) for a, _ in met} == {-1, 1}
    assert np.all(r.defect_force_n == 0.0)
    assert np.array_equal(r.housing_force_n, h.housing_force_n)
    # with its centrifugal force the element still touches the outer race: the pit strikes
    # there, never on the open inner contact
    c = slot_params()
    rc = simulate_dynamics(c.with_(cage_angle=lambda t: math.pi + 2 * math.pi * fc * t), 0.02, 2e5,
                           acquisition_mode="point", settle_s=0.015)
    outer = [rc.defect_force_n[a:b].max() for a, b in runs(rc.defect_contact > 0)]
    inner = [rc.defect_force_n[a:b].max() for a, b in runs(rc.defect_contact < 0)]
    print(f"F_c {c.centrifugal_n:.3f} N: outer strikes {np.round(outer, 3)} N, inner {inner}")
    assert len(inner) >= 1 and max(inner) == 0 and len(outer) >= 2 and min(outer) > 0


@pytest.fixture(scope="module")
def envelope_runs():
    p = slot_params()
    return p, {s: simulate_dynamics(p, 0.5, 12000.0, steps_per_period=s)
               for s in (STEPS_PER_PERIOD, 2 * STEPS_PER_PERIOD)}


def envelope_lines(r, fs=12000.0):
    """Envelope lines (band fs/4-3fs/8) of the resonator acceleration and the housing force at
    2 BSF - FTF, 2 BSF, 2 BSF + FTF, and each spectrum's floor (median, 20-500 Hz) and its
    strongest line there."""
    bsf, ftf = rates(ball_scene())
    out = []
    for x in (r.resonator_acceleration_m_s2, r.housing_force_n[:, 0]):
        f, a = envelope_spectrum(x - x.mean(), fs, (0.25 * fs, 0.375 * fs))
        sel = (f > 20) & (f < 500)
        out.append(([amplitude_at(f, a, q, 1.0)[1] for q in (2 * bsf - ftf, 2 * bsf, 2 * bsf + ftf)],
                    float(np.median(a[sel])), float(f[sel][np.argmax(a[sel])])))
    return out


def test_envelope_line_at_twice_bsf_with_ftf_sidebands_and_momentum(envelope_runs):
    p, runs_ = envelope_runs
    r = runs_[STEPS_PER_PERIOD]
    bsf, _ = rates(ball_scene())
    for lines, floor, top in envelope_lines(r):
        print(f"2BSF-FTF, 2BSF, 2BSF+FTF: {np.round(np.array(lines) / floor, 1)} x the floor; "
              f"strongest line {top:.1f} Hz (2 BSF {2 * bsf:.2f} Hz)")
        assert abs(top - 2 * bsf) <= 2.0                 # the bin (2 Hz) nearest 2 BSF
        assert lines[1] > 30 * floor and min(lines[0], lines[2]) > 15 * floor
    mean = r.housing_force_n.mean(axis=0)
    print(f"mean housing force {mean} N for {p.force_n} N")
    assert mean[0] == pytest.approx(p.force_n, rel=2e-4) and abs(mean[1]) < 2e-4 * p.force_n


def test_envelope_lines_change_under_one_percent_when_the_step_halves(envelope_runs):
    _, runs_ = envelope_runs
    a, b = (np.ravel([ln for ln, *_ in envelope_lines(runs_[s])])
            for s in (STEPS_PER_PERIOD, 2 * STEPS_PER_PERIOD))
    change = np.max(np.abs(a - b) / b)
    print(f"largest change of the 2 BSF lines when the step halves: {change:.2e}")
    assert change <= 0.01


def wandering_prediction(scene, t, width):
    """Per pass of the pit through each contact (the location's kinematics), whether the
    location's rule strikes there: on the track within the contact's Hertz semi-axis at the
    quasi-static load (:func:`on_track`), and the ratio |offset| / b (None: never on track)."""
    ld = scene_load_distribution(scene)
    kin = rolling_element_kinematics(scene, 2 * math.pi * scene.cage_rate_hz * t, redraw=True)
    out = []
    for race, key, sign in (("outer", "offset_outer", 1), ("inner", "offset_inner", -1)):
        q = ld.load_at(kin["psi"], race)
        b = hertz_estimate(scene.for_race(race), 1.0).b * np.cbrt(q)
        for a, e in runs(np.abs(kin[key]) <= 0.5 * width):
            m = (a + e) // 2
            ratio = abs(kin["track_offset"][m]) / b[m] if b[m] > 0 else math.inf
            out.append((sign, a, e, bool(on_track(scene, race, q[m:m + 1],
                                                  kin["track_offset"][m:m + 1])[0]), ratio))
    return out


def test_wandering_axis_strikes_only_the_passes_the_location_rule_puts_on_track():
    scene = ball_scene(spin_axis="wandering", spin_seed=2)
    p = slot_params(scene)
    fs = 2e5
    r = simulate_dynamics(p, 0.5, fs, acquisition_mode="point")
    pred = wandering_prediction(scene, r.t_s, W7)
    checked = {True: 0, False: 0}
    for sign, a, e, strikes, ratio in pred:
        if a == 0 or e == r.t_s.size or 0.8 < ratio < 1.25:      # cut, or at the ellipse's edge
            continue
        got = bool(np.any(r.defect_contact[a:e] == sign) and r.defect_force_n[a:e].max() > 0)
        assert got == strikes, (sign, r.t_s[a], ratio)
        checked[strikes] += 1
    print(f"passes checked: {checked[True]} striking, {checked[False]} missing the contact")
    assert checked[True] >= 3 and checked[False] >= 10
    # a turn whose draw puts the pit off the ellipse at the largest load: no strike in it at all
    f_c = p.cage_rate_hz
    q_max = scene_load_distribution(scene).load_at(np.zeros(1), "outer")[0]
    b_max = hertz_estimate(scene.for_race("outer"), 1.0).b * np.cbrt(1.5 * q_max)
    k = np.arange(1, int(0.5 * f_c))
    off = np.abs(rolling_element_kinematics(scene, 2 * math.pi * k)["track_offset"])
    assert np.count_nonzero(off > b_max) >= 2
    for kk in k[off > b_max]:
        sel = (r.t_s >= (kk - 0.5) / f_c) & (r.t_s < (kk + 0.5) / f_c)
        assert np.all(r.defect_force_n[sel] == 0) and np.all(r.defect_contact[sel] == 0)
    again = simulate_dynamics(p, 0.05, fs, acquisition_mode="point")
    assert np.array_equal(again.defect_force_n, r.defect_force_n[:again.t_s.size])


def test_orientation_is_redrawn_only_where_the_ball_is_free():
    free = element_pit_from_scene(ball_scene(spin_axis="wandering", spin_seed=2))
    rows = free.table(-1, 6)
    kin = rolling_element_kinematics(ball_scene(spin_axis="wandering", spin_seed=2),
                                     2 * math.pi * np.arange(-1, 7))
    assert np.array_equal(rows[:, 0], kin["track_offset"])
    assert len(np.unique(rows[:, 0])) == 8
    # a 40 um preload loads every ball all round: the contacts hold the spin axis
    held = element_pit_from_scene(scene_from(clearance_um=-40.0, spin_axis="wandering",
                                             spin_seed=2)).table(-1, 6)
    assert np.all(held[:, 0] == held[0, 0]) and np.allclose(held[:, 1], held[0, 1], atol=1e-9)
    assert np.all(element_pit_from_scene(ball_scene()).table(-1, 6) == [[0.0, 0.0]])


def test_the_defect_contact_tables_of_a_ball_pit_drive_the_element_pit():
    """The project's non-Hertzian tables of the round 0.021 in pit on a ball, one per contact:
    over the pit centre the loaded element carries what the held-rings series solve gives from
    the same tables (the kernel's reading against the tables' own), the rings where the healthy
    bearing has them at that instant (the load zone's drift removed). The event (~460 us) is
    not short against the shaft's mode on the bearing, so the rings are made 1000 times heavier
    (their support scaled alike): held through the event."""
    scene = scene_from(279.4, width_um=533.4, length_um=533.4)
    to, ti = defect_table(scene, "draft", race="outer"), defect_table(scene, "draft", race="inner")
    assert (to.race, ti.race) == ("outer", "inner")
    p = params_from_scene(scene, defect=DefectLaw.from_table(to), defect_inner=DefectLaw.from_table(ti))
    assert p.defect_race == "element" and p.pit.inner is not None
    base = p
    p = p.with_(shaft_mass_kg=1e3 * p.shaft_mass_kg, housing_mass_kg=1e3 * p.housing_mass_kg,
                housing_stiffness_n_m=1e3 * p.housing_stiffness_n_m,
                housing_damping_ns_m=1e3 * p.housing_damping_ns_m)
    r = simulate_dynamics(p, 0.016, FS, acquisition_mode="point")
    h = simulate_dynamics(p.with_(defect=None), 0.016, FS, acquisition_mode="point")
    n = 0
    for a, b in runs(r.defect_contact != 0):
        if a == 0:
            continue
        side = int(r.defect_contact[a])
        tab, k_pit, k_other = (to, p.k_outer, p.k_inner) if side > 0 else (ti, p.k_inner, p.k_outer)
        m = (a + b) // 2
        q_h = h.element_load_n[m, 0] - (0.0 if side > 0 else p.centrifugal_n)   # healthy, pitted side
        fc = -p.centrifugal_n if side > 0 else p.centrifugal_n                   # other = q + fc
        total = (q_h / k_pit) ** (2 / 3) + ((q_h + fc) / k_other) ** (2 / 3)
        expect = brentq(lambda q: float(tab.approach(0.0, q)) + ((q + fc) / k_other) ** (2 / 3)
                        - total, 0.05 * q_h, q_h)
        print(f"{'outer' if side > 0 else 'inner'}: healthy {q_h:.1f} N, over the pit centre "
              f"{r.defect_force_n[m]:.1f} N (held rings {expect:.1f} N)")
        assert r.defect_force_n[m] == pytest.approx(expect, abs=0.1 * (q_h - expect))
        n += 1
    assert n == 2
    # with the assumed rings the shaft's mode takes part: less is removed than held rings give
    light = p.with_(**{k: getattr(base, k) for k in ("shaft_mass_kg", "housing_mass_kg",
                                                     "housing_stiffness_n_m", "housing_damping_ns_m")})
    r, h = (simulate_dynamics(q, 0.009, FS, acquisition_mode="point") for q in (light, light.with_(defect=None)))
    a, b = next((a, b) for a, b in runs(r.defect_contact < 0) if a > 0)
    m = (a + b) // 2
    q_h = h.element_load_n[m, 0] - p.centrifugal_n
    total = (q_h / p.k_inner) ** (2 / 3) + ((q_h + p.centrifugal_n) / p.k_outer) ** (2 / 3)
    held = brentq(lambda q: float(ti.approach(0.0, q)) + ((q + p.centrifugal_n) / p.k_outer) ** (2 / 3)
                  - total, 0.05 * q_h, q_h)
    print(f"assumed rings, inner strike: removes {q_h - r.defect_force_n[m]:.1f} N of {q_h:.1f} N "
          f"(held rings {q_h - held:.1f} N)")
    assert 0 < q_h - r.defect_force_n[m] < q_h - held


def test_element_pit_refuses_bad_values():
    with pytest.raises(ValueError, match="spin_per_cage: got -1"):
        ElementPit(spin_per_cage=-1.0)
    with pytest.raises(ValueError, match="semi_axis_outer_m: got nan"):
        ElementPit(semi_axis_outer_m=float("nan"))
    p = slot_params()
    with pytest.raises(ValueError, match="defect_race: got 'ball'; allowed: outer | inner | element"):
        p.with_(defect_race="ball")
    with pytest.raises(ValueError, match="wandering orientation needs a point contact"):
        p.with_(exponent=10 / 9, element_pit=ElementPit(orientation=lambda k: (k * 0.0, k * 0.0)))
