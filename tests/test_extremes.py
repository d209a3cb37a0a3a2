"""Numerical stability at the extremes (issue 6, item 4).

Each test asserts finite, physically sane results or a clear error. Every contact solve made
here, directly or inside :func:`bearing_envelope.physics.history.simulate`, goes through
:func:`checked_solve`, which asserts force balance (``sum(p) dx dy == F`` to 1e-9 relative
under force control; the returned force equals ``sum(p) dx dy`` under displacement control),
``p >= 0``, no pressure on cells without material, and complementarity (``|h| <= tol max(u)``
where ``p > 0``, ``h >= -tol max(u)`` everywhere, ``h`` the deformed gap recomputed from the
returned pressure). Draft fidelity, one revolution or less, tiny grids.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import bearing_envelope.contact as contact
import bearing_envelope.physics.solves.stats as solves
from bearing_envelope.contact import hertz
from bearing_envelope.physics.geometry import defect_depth
from bearing_envelope.physics.history import simulate
from bearing_envelope.study.pipeline import case_bands, case_harmonics, history_case
from bearing_envelope.physics.scene import Defect, Scene, default_scene_mapping
from bearing_envelope.diagnosis import AnalysisOptions, analyze_signal
from bearing_envelope.signal import fast_kurtogram
from bearing_envelope.study.tradeoff import DEFAULT_BANDS
from bearing_envelope.study.pipeline import case_frequencies
from bearing_envelope.study.sections import AnalysisSettings

E_STAR = 115.4e9
_REAL_SOLVE = contact.solve_contact
ANALYSIS = {"signal": "p_max", "nlevel": 8, "filter_order": 4, "harmonics": 2, "sidebands": 1,
            "raw_orders_fr": 1, "bands": DEFAULT_BANDS}


def typed(analysis, case):
    """The pipeline takes typed settings: build them for this (synthetic) case."""
    return AnalysisSettings.from_mapping(analysis, fs=float(case.fs), freqs=case_frequencies(case),
                                         has_sensor=True)


# ------------------------------------------------------------------------------------ checks


def check_solution(sol, gap, dx, dy, force, tol):
    """Force balance, p >= 0 and complementarity of one contact solution (module docstring)."""
    g = np.asarray(gap, dtype=float)
    p = sol.pressure
    fin = np.isfinite(g)
    assert p.shape == g.shape
    assert np.isfinite(p).all() and (p >= 0).all()
    assert (p[~fin] == 0).all(), "pressure on cells without material"
    f = float(p.sum()) * dx * dy
    assert f > 0 and math.isfinite(sol.approach)
    if force is not None:
        assert abs(f - force) <= 1e-9 * force, (f, force)
    assert abs(sol.force - f) <= 1e-9 * f
    u = sol.displacement
    h = np.where(fin, g, 0.0) + u - sol.approach
    slack = 1.01 * tol * float(u.max()) + 1e-15
    assert (h[fin] >= -slack).all(), f"interpenetration {-h[fin].min():.3g} m > {slack:.3g} m"
    closed = fin & (p > 0)
    assert (np.abs(h[closed]) <= slack).all(), f"gap open under pressure {np.abs(h[closed]).max():.3g} m"
    assert sol.converged


def checked_solve(gap, dx, dy, force, e_star, **kw):
    """``solve_contact`` followed by :func:`check_solution`."""
    sol = _REAL_SOLVE(gap, dx, dy, force, e_star, **kw)
    check_solution(sol, gap, dx, dy, None if kw.get("approach") is not None else force,
                   kw.get("tol", 1e-8))
    checked_solve.count += 1
    return sol


checked_solve.count = 0


@pytest.fixture(autouse=True)
def _every_solve_checked(monkeypatch):
    """Every contact solve of the physics goes through physics.solves (SolveStats.solve): route
    it here, and the package's own name too."""
    monkeypatch.setattr(contact, "solve_contact", checked_solve)
    monkeypatch.setattr(solves, "solve_contact", checked_solve)


def scene(load_kN=250.0, depth_um=15.0, revolutions=1.0, **over):
    m = default_scene_mapping()
    m["operation"]["revolutions"] = revolutions
    for key, v in over.items():
        sec, k = key.split("__")
        m[sec][k] = v
    return Scene.from_mapping(m, load_kN=load_kN, depth_um=depth_um)


#: Draft fidelity without the interpolation checks and snapshot solves (they do not change the
#: history; every table solve is still made and checked).
DRAFT = {"preset": "draft", "n_checks": 0, "n_snapshot_offsets": 0}


def run(sc, fid=DRAFT):
    n0 = checked_solve.count
    h = simulate(sc, fid)
    assert checked_solve.count - n0 == h.stats["n_solves"] > 0   # every solve was checked
    for name in ("p_max", "p_max_defect", "roller_load", "defect_offset"):
        x = getattr(h, name)
        assert x.size == sc.n_samples and np.isfinite(x).all(), name
    acq = h.acquisition
    if acq["mode"] == "point":
        assert (h.p_max >= 0).all() and (h.p_max_defect <= h.p_max * (1 + 1e-12) + 1e-6).all()
    else:
        # physics on the internal samples (before the anti-alias filter): pressures >= 0 and the
        # defect neighbourhood's maximum never above the whole contact's
        lo, hi = acq["internal_range"]["p_max"]
        lo_d, hi_d = acq["internal_range"]["p_max_defect"]
        assert lo >= 0 and lo_d >= 0 and hi_d <= hi * (1 + 1e-12)
        # the linear filter's bound on its output (history.antialias_undershoot)
        u = acq["undershoot_bound"]
        assert 0 < u < 1
        for x, top in ((h.p_max, hi), (h.p_max_defect, hi_d)):
            assert x.min() >= -u * top * (1 + 1e-9) and x.max() <= (1 + u) * top * (1 + 1e-9)
    assert np.isfinite(h.table.p0).all() and (np.diff(h.table.p0) > 0).all()
    return h


def analyse(h, analysis=ANALYSIS):
    case = history_case(h)
    doc, _ = case_bands(case, typed(analysis, case))
    df = case_harmonics(case, typed(analysis, case), doc)
    assert np.isfinite(df["amplitude"].astype(float)).all()
    assert (df[df["band"] != "raw"]["band_high_hz"] < case.fs / 2).all()
    return doc, df


def hertz_p0(h):
    """Hertz p0 (unbounded crown) at the largest roller load of a history."""
    b = h.scene.bearing
    return hertz.elliptical(float(h.roller_load.max()), b.rx_m, b.ry_m, h.scene.material.e_star_pa).p0


# ------------------------------------------------------------------------------------ loads


def test_small_load_resolved_is_hertzian():
    # 0.5 kN on the bearing: ~60 N on the most loaded roller, contact ~2 mm x 60 um
    h = run(scene(0.5, 15.0))
    assert 0.9 < h.table.p0[-1] / hertz_p0(h) < 1.2      # no-defect peak: Hertz
    assert h.table.p0[-1] < h.p_max.max() < 10 * h.table.p0[-1]   # the rim raises it, finitely


def test_load_near_zero():
    # 10 N on the bearing: ~1 N on the most loaded roller, a contact smaller than one cell of
    # the draft grids. The grid averages the pressure over the cell: finite, below Hertz p0.
    h = run(scene(0.01, 15.0))
    assert 0 < h.table.p0[-1] <= 1.01 * hertz_p0(h)
    assert 0 < h.p_max.max() < 10 * hertz_p0(h)


def test_subcell_contact():
    # sphere whose Hertz contact is much smaller than a cell: the exact discrete answer is the
    # whole force on the centre cell(s)
    R, F = 0.01, 1.0
    a = hertz.sphere(F, R, E_STAR).a
    d = 5 * a
    x = (np.arange(8) - 4) * d
    g = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * R)
    s = checked_solve(g, d, d, F, E_STAR, boundary="ignore")
    assert s.pressure[4, 4] == pytest.approx(F / d ** 2, rel=1e-9)


def test_load_one_and_a_half_C0():
    h = run(scene(1125.0, 100.0))
    h750 = run(scene(750.0, 0.0))
    assert h.table.p0[-1] > h750.table.p0[-1]          # more load, more pressure
    assert h.p_max.max() < 50e9                         # finite and not absurd
    assert h.p_max.max() > h.table.p0[-1]               # the defect rim raises the peak


# ------------------------------------------------------------------------------------ defects


def test_depth_zero_is_the_smooth_load_zone_signal():
    h = run(scene(750.0, 0.0))
    # healthy: p_max follows P0(Q(t)) only; no defect neighbourhood pressure is read
    assert h.acquisition["internal_range"]["p_max"][1] <= h.table.p0.max() * (1 + 1e-9)
    # the slow load-zone modulation lies in the anti-alias filter's pass band (ripple < 1e-4)
    assert h.p_max.max() <= h.table.p0.max() * (1 + 1e-4)
    assert h.p_max.max() == pytest.approx(hertz_p0(h), rel=0.25)


def test_depth_200um():
    h = run(scene(750.0, 200.0))
    h0 = run(scene(750.0, 0.0))
    assert h.p_max.max() > h0.p_max.max()
    assert h.p_max.max() < 50e9
    # a local event: most of the time the defect is outside the contact
    assert np.median(h.p_max) == pytest.approx(np.median(h0.p_max), rel=0.02)


def test_defect_wider_than_the_contact():
    # 2 mm along rolling at 250 kN (contact width ~0.7 mm): the roller bridges the pit
    h = run(scene(250.0, 20.0, defect__width_um=2000.0))
    a = h.table.info["half_width"].max()
    assert 2e-3 > 2 * a
    assert h.p_max.max() > h.table.p0.max()     # load carried by the rims
    # while the whole contact sits over the pit floor, the defect neighbourhood carries the
    # load of the two flanks only where they are: the neighbourhood maximum stays finite
    assert np.isfinite(h.table.ratio_defect).all()


def test_defect_at_the_roller_end():
    # touches the end of the 34 mm roller; at the low table loads the contact does not reach it
    sc = scene(750.0, 100.0, defect__axial_position_mm=16.75)
    h = run(sc)
    h0 = run(scene(750.0, 0.0))
    # the pit sits in the end relief, under the roller-end overpressure: finite, the same order
    assert h.p_max.max() == pytest.approx(h0.p_max.max(), rel=0.5)
    assert np.median(h.p_max) == pytest.approx(np.median(h0.p_max), rel=0.02)


# ------------------------------------------------------------------------------------ edges


def _cylinder(n_y, *, end_radius=0.0, n_x=16):
    """A 2 mm roller (R 5 mm) on a flat, cut square (or rounded) at its ends, on a box that
    holds the +inf cells beyond the ends."""
    R, L = 5e-3, 2e-3
    F = 2000.0
    b = 4 * F * R / (math.pi * L * E_STAR)   # line-contact half-width (2D Hertz)
    b = math.sqrt(b)
    dx = 3 * b / n_x
    dy = 1.2 * L / n_y
    x = (np.arange(2 * n_x) - n_x + 0.5) * dx
    y = (np.arange(n_y) - n_y / 2 + 0.5) * dy
    ay = np.abs(y)
    s = np.zeros_like(y)
    if end_radius > 0:
        u = np.clip(ay - (L / 2 - end_radius), 0, end_radius)
        s = end_radius - np.sqrt(end_radius ** 2 - u ** 2)
    s = np.where(ay <= L / 2, s, np.inf)
    g = x[:, None] ** 2 / (2 * R) + s[None, :]
    sol = checked_solve(g, dx, dy, F, E_STAR, tol=1e-8, boundary="ignore")
    mid = sol.pressure[:, n_y // 2].max()
    return sol.pressure.max(), mid


def test_sharp_roller_end_peak_grows_with_refinement():
    peaks, mids = zip(*[_cylinder(n) for n in (24, 48, 96)])
    assert all(np.isfinite(peaks))
    assert peaks[0] < peaks[1] < peaks[2]                          # singular: grows each time
    assert peaks[2] > 1.5 * mids[2]                                 # edge overpressure
    # the centre of the roller is not affected by the refinement at the ends
    assert np.ptp(mids) < 0.05 * mids[2]


def test_rounded_roller_end_converges():
    # a 0.5 mm corner radius, resolved from 48 cells along the roller (dy = 50 um) on
    peaks, mids = zip(*[_cylinder(n, end_radius=0.5e-3) for n in (48, 96, 192)])
    assert abs(peaks[2] - peaks[1]) < 0.5 * abs(peaks[1] - peaks[0])
    assert abs(peaks[2] / peaks[1] - 1) < 0.05
    assert peaks[2] < 4 * mids[2]


def _pit(n, edge_radius_um):
    """Sphere (R 10 mm, 5 N, a = 69 um) on a flat with a 60 um square, 2 um deep pit at the
    centre (the pit floor carries no load)."""
    R, F = 10e-3, 5.0
    a = hertz.sphere(F, R, E_STAR).a
    d = 3 * a / n
    x = (np.arange(n) - n / 2 + 0.5) * d
    dfct = Defect(depth_um=2.0, length_um=60.0, width_um=60.0, shape="flat",
                  edge_radius_um=edge_radius_um, axial_position_mm=0.0, orientation="axial")
    g = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * R) + defect_depth(dfct, x[:, None], x[None, :])
    sol = checked_solve(g, d, d, F, E_STAR, tol=1e-8, boundary="ignore")
    return sol.pressure.max(), hertz.sphere(F, R, E_STAR).p0


def test_sharp_defect_rim_peak_grows_with_refinement():
    peaks, p0 = zip(*[_pit(n, 0.0) for n in (32, 64, 128)])
    assert all(np.isfinite(peaks))
    assert peaks[0] < peaks[1] < peaks[2]          # no grid limit
    # p ~ r^-1/2 at a sharp rim (punch edge): halving the cell raises the peak by ~sqrt(2)
    assert 1.2 < peaks[2] / peaks[1] < 1.6
    assert peaks[2] > 1.2 * p0[0]


def test_rounded_defect_rim_converges():
    # 40 um rim radius: converging once the cell is a small fraction of the radius
    peaks, _ = zip(*[_pit(n, 40.0) for n in (64, 128, 256)])
    assert abs(peaks[2] - peaks[1]) < 0.5 * abs(peaks[1] - peaks[0])
    assert abs(peaks[2] / peaks[1] - 1) < 0.1


def test_sharp_rim_and_sharp_roller_end_in_the_scene_stay_finite():
    h = run(scene(750.0, 100.0, defect__edge_radius_um=0.0,
                  bearing__end_relief={"kind": "radius", "radius_mm": 1e-3}))
    assert h.p_max.max() < 100e9


# ------------------------------------------------------------------------------------ grids


def test_very_coarse_grid_hertz():
    R, F = 0.01, 100.0
    hz = hertz.sphere(F, R, E_STAR)
    n, d = 8, hz.a / 2                      # 4 cells across the contact diameter
    x = (np.arange(n) - n // 2) * d
    g = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * R)
    s = checked_solve(g, d, d, F, E_STAR, boundary="ignore")
    assert 0.7 < s.p_max / hz.p0 < 1.3


def test_very_fine_grid_tiny_domain_hertz():
    R, F = 0.01, 1e-6                       # a ~ 0.4 um: nanometre cells
    hz = hertz.sphere(F, R, E_STAR)
    n = 64
    d = 6 * hz.a / n
    assert d < 1e-7
    x = (np.arange(n) - n // 2) * d
    g = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * R)
    s = checked_solve(g, d, d, F, E_STAR)
    assert s.p_max / hz.p0 == pytest.approx(1.0, abs=2e-3)


def test_very_coarse_history():
    fid = {**DRAFT, "global_dx_um": 80.0, "global_dy_um": 2000.0, "local_dx_um": 40.0,
           "local_dy_um": 200.0}
    h = run(scene(750.0, 100.0), fid)
    assert 0.5 < h.table.p0[-1] / hertz_p0(h) < 2.0


# ------------------------------------------------------------------------------------ signals


def _noise(n=32768, seed=0):
    return np.random.default_rng(seed).standard_normal(n)


def test_band_past_nyquist_raises_or_clamps():
    fs = 65000.0
    x = _noise()
    with pytest.raises(ValueError, match="Nyquist"):
        analyze_signal(
            x,
            fs,
            fr=15.8,
            bpfi=231.9,
            options=AnalysisOptions(
                bands=[{"name": "hi", "strategy": "fixed", "low_hz": 30000, "high_hz": 40000}]
            ),
        )
    df = analyze_signal(
        x,
        fs,
        fr=15.8,
        bpfi=231.9,
        options=AnalysisOptions(
            bands=[
                {
                    "name": "hi",
                    "strategy": "fixed",
                    "low_hz": 30000,
                    "high_hz": 40000,
                    "clamp": True,
                },
                {
                    "name": "ord",
                    "strategy": "orders",
                    "low": 130,
                    "high": 200,
                    "base": "bpfi",
                    "clamp": True,
                },
            ]
        ),
    )
    bands = df[df["band_strategy"] != "raw"]
    assert bands["clamped"].all() and (bands["band_high_hz"] < fs / 2).all()
    assert np.isfinite(df["amplitude"].astype(float)).all()
    # a band entirely above Nyquist cannot be clamped: clear error
    with pytest.raises(ValueError, match="Nyquist"):
        analyze_signal(x, fs, fr=15.8, bpfi=231.9, options=AnalysisOptions(bands=[
            {"name": "hi", "strategy": "fixed", "low_hz": 33000, "high_hz": 40000, "clamp": True}]))


def test_kurtogram_band_at_nyquist_is_clamped():
    fs = 65000.0
    x = _noise(65536)
    ring = np.hanning(64) * np.cos(np.pi * 0.8 * np.arange(64))   # bursts at 26 kHz
    for i in range(200, x.size - 64, 280):
        x[i:i + 64] += 3 * ring
    # the guard keeps the best cell at level <= 1: the top band [fs/4, fs/2] wins
    df = analyze_signal(
        x,
        fs,
        fr=15.8,
        bpfi=231.9,
        options=AnalysisOptions(
            bands=[{"name": "kurtogram", "strategy": "kurtogram", "max_level": 1}]
        ),
    )
    row = df[df["band_strategy"] == "kurtogram"].iloc[0]
    assert row["band_high_hz"] < fs / 2 and bool(row["clamped"])
    assert np.isfinite(df["amplitude"].astype(float)).all()


def test_constant_signal():
    fs = 65000.0
    x = np.full(65000, 3.0e9)
    with pytest.raises(ValueError, match="constant"):
        fast_kurtogram(x, fs, 6)
    df = analyze_signal(
        x, fs, fr=15.8, bpfi=231.9, options=AnalysisOptions(bands=DEFAULT_BANDS[1:])
    )
    amp = df["amplitude"].astype(float)
    assert np.isfinite(amp).all()
    raw_dc = df[(df["quantity"] == "raw_spectrum") & (df["base"] == "dc")]["amplitude"].iloc[0]
    assert raw_dc == pytest.approx(3.0e9)
    assert (amp[df["quantity"] != "raw_spectrum"] < 1e-12 * 3.0e9).all()   # nothing to demodulate


def test_history_shorter_than_two_bpfi_periods():
    sc = scene(250.0, 100.0, revolutions=0.1)
    assert sc.n_samples < 2 * sc.operation.fs_hz / sc.bpfi_hz
    h = run(sc)
    an = dict(ANALYSIS, nlevel=8)
    doc, df = analyse(h, an)
    assert doc.kurtogram["level"] <= 2           # depth limited by the few samples


def test_shortest_history_allowed_and_below():
    with pytest.raises(ValueError, match="revolutions"):
        scene(250.0, 15.0, revolutions=1e-4)        # fewer than 16 samples


def test_fs_well_below_65kHz():
    with pytest.raises(ValueError, match="fs_hz"):
        scene(250.0, 100.0, operation__fs_hz=5000.0)   # 13 x BPFI above Nyquist
    h = run(scene(250.0, 100.0, operation__fs_hz=6100.0))
    with pytest.raises(ValueError, match="Nyquist"):   # the 8-16 kHz band cannot exist
        analyse(h, dict(ANALYSIS, nlevel=6))
    doc, df = analyse(h, dict(ANALYSIS, nlevel=6, bands=DEFAULT_BANDS[:4]))
    assert doc.band("bpfi_10_13").high_hz == pytest.approx(13 * 231.9) and 13 * 231.9 < 3050.0


def test_fs_well_above_65kHz():
    h = run(scene(250.0, 100.0, revolutions=0.5, operation__fs_hz=1.0e6))
    h65 = run(scene(250.0, 100.0, revolutions=0.5))
    assert h.p_max.size > 15 * h65.p_max.size
    # same physics, only sampled more densely
    assert h.p_max.max() == pytest.approx(h65.p_max.max(), rel=0.02)
    doc, df = analyse(h, dict(ANALYSIS, nlevel=8))
    assert doc.fs == 1.0e6
