import math

import numpy as np
import pytest

from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.history import kinematics, simulate, synthesize, synthesize_numpy
from bearing_envelope.physics.table import direct_pressure
from bearing_envelope.physics.loads import palmgren_stiffness, solve_row
from bearing_envelope.physics.scene import Scene

FR = 15.8


def _scene(depth, load=500.0, **op):
    m = {"operation": {"revolutions": 2.0, **op}}
    return Scene.from_mapping(m, load_kN=load, depth_um=depth)


@pytest.fixture(scope="module")
def defect_case():
    # point samples: the events are compared sample by sample with the table
    s = _scene(50.0, acquisition={"mode": "point"})
    return s, simulate(s, "draft")


def _events(p, ref, tol=1e-6):
    """Index segments where p differs from the no-defect reference."""
    on = np.abs(p - ref) > tol * np.max(ref)
    edges = np.flatnonzero(np.diff(on.astype(int)))
    starts = list(edges[::2] + 1) if on[0] == 0 else [0] + list(edges[1::2] + 1)
    ends = list(edges[1::2]) if on[0] == 0 else list(edges[::2])
    return [(a, b) for a, b in zip(starts, ends)]


def test_no_defect_equals_p0_of_load_and_spectrum():
    fs = FR * 4096  # an integer number of samples per revolution: exact fr periodicity
    s = _scene(0.0, load=250.0, fs_hz=fs, revolutions=4.0, acquisition={"mode": "point"})
    h = simulate(s, "draft")
    # independent load: the load-zone equilibrium at the defect's angle 2 pi fr t
    b = s.bearing
    ld = solve_row(125e3, 22, b.contact_angle_deg, b.radial_clearance_um * 1e-6,
                   palmgren_stiffness(b.roller_length_mm * 1e-3))
    q = ld.load_at(2 * np.pi * FR * h.time)
    np.testing.assert_allclose(h.roller_load, q, rtol=1e-9, atol=1e-6)
    # P0(Q) = max(W0(Q), P_out(Q)): the no-defect maxima inside and outside the read strip,
    # each linear in Q^(1/3) between solved nodes (exact for Hertz), through 0 below the first
    t = h.table

    def lin(qn, v):
        out = np.interp(np.cbrt(q), np.cbrt(qn), v)
        below = np.cbrt(q) < np.cbrt(qn[0])
        out[below] = v[0] * np.cbrt(q[below]) / np.cbrt(qn[0])
        return out

    p0 = np.maximum(lin(t.q_nodes, t.w0), lin(t.q_out, t.p_out))
    np.testing.assert_allclose(h.p_max, p0, rtol=1e-12, atol=1.0)
    np.testing.assert_allclose(t.p0, np.maximum(t.w0, t.p_out_nodes), rtol=1e-12)
    # 250 kN is Hertzian: P0 at the largest node is the Hertz p0 within 1 %
    from bearing_envelope.contact import hertz

    hz = hertz.elliptical(t.q_nodes[-1], b.rx_m, b.ry_m, s.material.e_star_pa)
    assert t.p0[-1] == pytest.approx(hz.p0, rel=0.01)
    # spectrum: fr harmonics, nothing at BPFI
    amp = np.abs(np.fft.rfft(h.p_max)) / h.p_max.size
    df = fs / h.p_max.size
    k_fr = round(FR / df)
    k_bpfi = round(s.bpfi_hz / df)
    assert k_bpfi % k_fr != 0
    assert amp[k_fr] > 1e-2 * amp[0]
    near = [k for k in (k_bpfi - 1, k_bpfi, k_bpfi + 1) if k % k_fr]
    assert max(amp[near]) < 1e-9 * amp[k_fr]
    # the fr harmonics carry the signal: everything off them is numerical noise
    off = np.ones(amp.size, bool)
    off[::k_fr] = False
    assert amp[off].max() < 1e-9 * amp[k_fr]


def test_events_at_bpfi_spacing_in_load_zone(defect_case):
    s, h = defect_case
    t = h.table
    ref = t.evaluate(h.roller_load, np.full_like(h.time, 1.0))[0]  # the no-defect P0(Q(t))
    segs = [(a, b) for a, b in _events(h.p_max, ref) if a > 0 and b < h.time.size - 1]
    assert len(segs) >= 5
    fs, bpfi = s.operation.fs_hz, s.bpfi_hz
    centres = np.array([(a + b) / 2 for a, b in segs])
    # kinematics: the defect is centred on a roller at t_k = k / BPFI
    k = np.round(centres / fs * bpfi)
    assert np.all(np.abs(centres - k * fs / bpfi) <= 1.0)
    assert np.all(np.abs(np.diff(k)) >= 1)
    # events only in the load zone, and every roller passage inside it has an event
    ld = h.load_distribution
    psi = np.angle(np.exp(1j * 2 * np.pi * FR * centres / fs))
    assert np.all(np.abs(psi) < ld.half_angle)
    kk = np.arange(0, int(h.time[-1] * bpfi) + 1)
    psi_k = np.angle(np.exp(1j * 2 * np.pi * FR * kk / bpfi))
    inside = kk[(np.abs(psi_k) < 0.9 * ld.half_angle) & (kk > 0) & (kk < kk[-1])]
    assert set(inside) <= set(k.astype(int))
    assert np.all(h.p_max[h.roller_load == 0] == 0)


def test_defect_raises_peak(defect_case):
    s, h = defect_case
    h0 = simulate(_scene(0.0), "draft")
    assert h.p_max.max() > 1.2 * h0.p_max.max()
    assert h.p_max_defect.max() > h0.p_max_defect.max()


def test_contact_and_bearing_modes_agree(defect_case):
    s, h = defect_case
    q = h.load_distribution.q_max
    sc = Scene.from_mapping({"operation": {"revolutions": 2.0, "acquisition": {"mode": "point"}},
                             "load": {"mode": "contact"}},
                            load_kN=q / 1e3, depth_um=50.0)
    hc = simulate(sc, "draft")
    np.testing.assert_allclose(hc.roller_load, h.roller_load, rtol=1e-7, atol=1e-3)
    np.testing.assert_allclose(hc.p_max, h.p_max, rtol=1e-5)


def test_interpolated_table_within_stated_error():
    # a little denser than draft (draft's offset spacing w/3 under-resolves the steep exit of the
    # defect from small contacts; its stated error is then an underestimate)
    fid = fidelity_from({"preset": "draft", "offsets_per_width": 6.0, "n_loads": 4})
    s = _scene(50.0, revolutions=0.1)
    t = simulate(s, fid).table
    info = t.info
    assert info["interp_checks"].shape[0] == 3 * fid.n_checks
    stated = info["interp_max_rel_error_p_max"]          # offsets on the window grid
    stated_any = info["any_offset_max_rel_error_p_max"]  # adds the sub-cell jitter
    # the stated errors are maxima over random points: an estimate, hence the factor 2 for fresh
    # random points of the same distribution (Q uniform in Q^(1/3), x over the contact overlap)
    dx = info["window_dx"]
    rng = np.random.default_rng(7)
    q_lo, q_hi = np.cbrt(t.q_nodes[[0, -1]])
    for _ in range(3):
        q = float(rng.uniform(q_lo, q_hi) ** 3)
        reach = t.kappa * t.a_coef * np.cbrt(q) + 50e-6
        x = round(float(rng.uniform(0, reach)) / dx) * dx
        P, _ = direct_pressure(s, fid, q, x, kappa=t.kappa)
        Pi, _ = t.evaluate(q, x)
        assert abs(Pi - P) / P <= 2 * stated + 0.02
        x = float(rng.uniform(0, reach))
        P, _ = direct_pressure(s, fid, q, x, kappa=t.kappa)
        Pi, _ = t.evaluate(q, x)
        assert abs(Pi - P) / P <= 2 * stated_any + 0.02


def test_numba_matches_numpy(defect_case):
    s, h = defect_case
    a = synthesize(s, h.table, h.load_distribution, h.time)
    b = synthesize_numpy(s, h.table, h.load_distribution, h.time)
    for u, v in zip(a, b):
        np.testing.assert_allclose(u, v, rtol=1e-10, atol=1e-12 * max(1.0, np.abs(v).max()))


def test_kinematics_and_slip():
    s = _scene(50.0)
    t = np.arange(s.n_samples) / s.operation.fs_hz
    k0 = kinematics(s, t)
    # offset is the arc length on the raceway, |x| <= pi R_i / Z
    assert np.abs(k0["offset"]).max() <= math.pi * s.bearing.inner_race_radius_m / 22 + 1e-12
    ss = _scene(50.0, cage_slip_percent=2.0, slip_seed=3)
    k1 = kinematics(ss, t)
    k2 = kinematics(ss, t)
    np.testing.assert_array_equal(k1["offset"], k2["offset"])  # seeded
    # zero crossings of the offset (roller passages) jitter with slip, not without
    def passages(x):
        i = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
        return i - x[i] / (x[i + 1] - x[i])
    d0 = np.diff(passages(k0["offset"]))
    d1 = np.diff(passages(k1["offset"]))
    assert d0.std() < 1e-6 and d1.std() > 0.1
    # slip slows the cage: the defect meets rollers at Z (fr - fc (1 - s)) on average
    fc = ss.cage_rate_hz
    expect = ss.operation.fs_hz / (22 * (FR - fc * (1 - 0.02)))
    assert d1.mean() == pytest.approx(expect, rel=0.01)
    assert d0.mean() == pytest.approx(s.operation.fs_hz / s.bpfi_hz, rel=1e-9)


def test_noise_snr():
    s = _scene(0.0, load=250.0, noise_snr_db=10.0, noise_seed=5)
    h = simulate(s, "draft")
    clean = h.signals["p_max_clean"]
    n = h.signals["p_max"] - clean
    assert 10 * np.log10(np.var(clean) / np.var(n)) == pytest.approx(10.0, abs=0.2)


# ---------------------------------------------------------------------------------------------
# acquisition (issue 12 part 1)

from bearing_envelope.physics.acquisition import acquire, antialias_filter, auto_oversample  # noqa: E402

# an event every 280 samples (BPFI = 232.14 Hz, the study's 231.9 Hz gives 280.29): every event
# then has the same sub-sample phase, and shifting the train moves all of them alike
FS = 65000.0
BPFI = FS / 280
FIXED_BANDS = {"fs4_3fs8": (0.25 * FS, 0.375 * FS), "bpfi_3_6": (3 * BPFI, 6 * BPFI),
               "bpfi_10_13": (10 * BPFI, 13 * BPFI), "fixed": (8125.0, 16250.0)}


@pytest.mark.parametrize("n", [1, 7, 33])
def test_antialias_filter_stop_band_and_pass_band(n):
    from scipy.signal import freqz

    h = antialias_filter(n)
    assert h.size % 2 == 1 and np.allclose(h, h[::-1])          # linear phase, centred
    f = np.linspace(0.0, 0.5 * n, 20001)                         # in units of the output fs
    _, H = freqz(h, worN=2 * np.pi * f / n)
    mag = np.abs(H)
    assert mag[0] == pytest.approx(1.0, abs=1e-12)
    assert np.max(np.abs(mag[f <= 0.40] - 1.0)) < 1e-3           # pass band to 0.40 fs
    assert 20 * np.log10(mag[f >= 0.50].max()) <= -80.0          # >= 80 dB from Nyquist up


@pytest.mark.parametrize("n", [1, 2, 4, 7, 17, 33])
def test_antialias_filter_equals_scipy_firwin_to_the_bit(n):
    """The project's Kaiser design against scipy.signal's (kaiserord, kaiser_beta, firwin): the
    same taps, bit for bit, so the histories do not change with the implementation."""
    from scipy.signal import firwin, kaiser_beta as sp_beta, kaiserord

    from bearing_envelope.physics.acquisition import kaiser_beta

    atten = 85.0
    numtaps, beta = kaiserord(atten, 0.1 / (0.5 * n))
    assert kaiser_beta(atten) == beta == sp_beta(atten)
    assert [kaiser_beta(a) for a in (10.0, 30.0, 60.0)] == [sp_beta(a) for a in (10.0, 30.0, 60.0)]
    k = int(np.ceil((numtaps - 1) / (2.0 * n)))
    h = firwin(2 * k * n + 1, 0.45, fs=float(n), window=("kaiser", beta))
    np.testing.assert_array_equal(antialias_filter(n), h / h.sum())


@pytest.mark.parametrize("n", [1, 4, 9])
def test_decimate_centred_equals_upfirdn_and_direct_sum(n):
    """Every n-th output of the centred FIR (numba loop and numpy passes): bit for bit
    scipy.signal.upfirdn's, and the direct sum of h[j] x[.] written out per output (to
    rounding)."""
    from scipy.signal import upfirdn

    from bearing_envelope.physics.acquisition import decimate_centred

    rng = np.random.default_rng(7)
    h = antialias_filter(n)
    c = (h.size - 1) // 2
    count = 37
    x = rng.normal(size=(count - 1) * n + 2 * c + 1) * 1e9
    y = decimate_centred(h, x, n, count)
    np.testing.assert_array_equal(y, upfirdn(h, x, 1, n)[2 * c // n: 2 * c // n + count])
    np.testing.assert_array_equal(decimate_centred(h, x, n, count, use_numba=False), y)
    direct = [sum(h[j] * x[c + i * n + c - j] for j in range(h.size)) for i in range(count)]
    np.testing.assert_allclose(y, direct, rtol=0, atol=1e-12 * np.abs(x).max())
    with pytest.raises(ValueError, match="decimate_centred: x has"):
        decimate_centred(h, x[:-1], n, count)


def _event_train(shift):
    """A defect-like event per BPFI period: a broad bump (the contact, ~140 us) with two narrow
    rim spikes (~1 us, far below a sample), load-zone modulated at fr; shifted by ``shift`` s."""
    def ev(t):
        tau = (t - shift) * BPFI
        d = (tau - np.round(tau)) / BPFI                   # time from the nearest event
        amp = 1.0 + 0.5 * np.cos(2 * np.pi * 15.8 * t)
        x = amp * (np.exp(-0.5 * (d / 30e-6) ** 2)
                   + 2.0 * np.exp(-0.5 * ((d - 10e-6) / 1e-6) ** 2)
                   + 2.0 * np.exp(-0.5 * ((d + 10e-6) / 1e-6) ** 2))
        return {"x": x}
    return ev


def _envelope_1x(x):
    from bearing_envelope.diagnosis import harmonic_amplitudes
    from bearing_envelope.signal import envelope_spectrum

    out = {}
    for name, band in FIXED_BANDS.items():
        f, a = envelope_spectrum(x - x.mean(), FS, band)
        out[name] = harmonic_amplitudes(f, a, BPFI, n_harmonics=1, n_sidebands=0)[0]["amplitude"]
    return out


def test_antialiased_event_train_is_shift_invariant():
    n = int(0.5 * FS)
    shifts = np.array([0.0, 0.25, 0.5, 0.75]) / FS          # fractions of a sample
    spread = {}
    for mode, over in (("antialiased", 64), ("point", 1)):
        amps = [_envelope_1x(acquire(_event_train(d), n, FS, mode=mode, oversample=over)["x"])
                for d in shifts]
        spread[mode] = {b: (max(a[b] for a in amps) - min(a[b] for a in amps))
                        / np.mean([a[b] for a in amps]) for b in FIXED_BANDS}
    # the anti-aliased acquisition sees the same band-limited events whatever their sub-sample
    # phase; point samples hit or miss the 1 us rim spikes (report: docs/benchmarks.md)
    assert max(spread["antialiased"].values()) < 0.01, spread
    assert max(spread["point"].values()) > 0.05, spread


def test_acquire_point_equals_direct_samples_and_filters_only_named():
    ev = _event_train(0.0)
    n = 2000
    t = np.arange(n) / FS
    np.testing.assert_array_equal(acquire(ev, n, FS, mode="point")["x"], ev(t)["x"])

    def two(tt):
        return {"x": ev(tt)["x"], "state": tt}
    out = acquire(two, n, FS, mode="antialiased", oversample=8, filtered=("x",), block=300)
    np.testing.assert_allclose(out["state"], t, rtol=0, atol=1e-15)   # point-sampled, blocks exact
    whole = acquire(two, n, FS, mode="antialiased", oversample=8, filtered=("x",), block=n)
    np.testing.assert_allclose(out["x"], whole["x"], rtol=1e-12, atol=1e-12)
    # a tone in the pass band goes through unchanged (zero delay); one above Nyquist is removed
    tone = acquire(lambda tt: {"a": np.sin(2 * np.pi * 9000.0 * tt),
                               "b": np.sin(2 * np.pi * 40000.0 * tt)}, n, FS, oversample=8)
    np.testing.assert_allclose(tone["a"], np.sin(2 * np.pi * 9000.0 * t), atol=2e-4)
    assert np.abs(tone["b"]).max() < 1e-4


def test_acquisition_and_roller_load_bad_input():
    for acq, field in (({"oversample": 0}, "oversample"), ({"oversample": 2.5}, "oversample"),
                       ({"oversample": "fast"}, "oversample"), ({"mode": "box"}, "mode")):
        with pytest.raises(ValueError, match=f"operation.acquisition.{field}"):
            _scene(0.0, acquisition=acq)
    with pytest.raises(ValueError, match="load.roller_load"):
        Scene.from_mapping({"load": {"roller_load": "stepwise"}}, load_kN=500, depth_um=0)
    with pytest.raises(ValueError, match="oversample"):
        acquire(_event_train(0.0), 10, FS, oversample=0)


def test_auto_oversample_bounds_defect_travel():
    s = _scene(50.0)
    v = 2 * np.pi * (FR - s.cage_rate_hz) * s.bearing.inner_race_radius_m
    assert v == pytest.approx(4.24, abs=0.01)                   # defect speed past the rollers
    # the defect moves at most one table offset-node spacing per internal sample: 50 um deep,
    # w = 100 um: standard min(100/4, 12) = 12 um, paper min(100/8, 4) = 4 um
    for fid, dx, n_expected in (("standard", 12e-6, 6), ("paper", 4e-6, 17)):
        n = auto_oversample(s, fidelity_from(fid))
        assert v / (FS * n) <= dx * (1 + 1e-9) < v / (FS * (n - 1))
        assert n == n_expected


# ---------------------------------------------------------------------------------------------
# integral signals (issue 12 part 2)


def _table(depth, edge_radius_um=2.0, load=250.0):
    from bearing_envelope.physics.table import build_table
    from bearing_envelope.physics.loads import scene_load_distribution

    s = Scene.from_mapping({"operation": {"revolutions": 0.1},
                            "defect": {"edge_radius_um": edge_radius_um}},
                           load_kN=load, depth_um=depth)
    fid = fidelity_from({"preset": "draft", "n_checks": 0, "n_snapshot_offsets": 0})
    tb, nodes, _ = build_table(s, fid, q_max=scene_load_distribution(s).q_max, progress=None)
    return s, tb, nodes


def test_healthy_approach_and_area_follow_hertz():
    from bearing_envelope.contact import hertz

    s, tb, nodes = _table(0.0)
    b = s.bearing
    for q, d0, a0, nd in zip(tb.q_nodes, tb.approach0, tb.area0, nodes):
        hz = hertz.elliptical(q, b.rx_m, b.ry_m, s.material.e_star_pa)
        assert d0 == pytest.approx(hz.approach, rel=0.005)       # 250 kN: Hertzian contact
        # cells carrying pressure: the area is known to about one cell across the contact
        assert a0 == pytest.approx(hz.area, rel=nd.grid.dx / hz.a)
    # the rule c(q) q^2 reproduces Hertz (delta, A ~ Q^(2/3)) between and below the nodes
    q = np.array([0.2, 0.5, 0.9]) * tb.q_nodes[-1]
    hz = [hertz.elliptical(v, b.rx_m, b.ry_m, s.material.e_star_pa) for v in q]
    np.testing.assert_allclose(tb.approach_no_defect(q), [h.approach for h in hz], rtol=0.005)
    sig = tb.evaluate_integrals(q, np.zeros(3))
    assert np.all(sig["removed_force"] == 0) and np.all(sig["approach_change"] == 0)
    np.testing.assert_allclose(sig["contact_force"], q)


def test_dense_no_defect_approach_from_the_outside_solves():
    from bearing_envelope.contact import hertz

    s, tb, nodes = _table(15.0, load=750.0)
    b = s.bearing
    assert tb.approach_out.shape == tb.area_out.shape == tb.q_out.shape
    # at the load nodes the dense grid holds the nodes' own global solves
    at = [int(np.argmin(np.abs(tb.q_out - q))) for q in tb.q_nodes]
    np.testing.assert_allclose(tb.q_out[at], tb.q_nodes, rtol=1e-12)
    np.testing.assert_allclose(tb.approach_out[at], tb.approach0, rtol=1e-12)
    np.testing.assert_allclose(tb.area_out[at], tb.area0, rtol=1e-12)
    # between them solved values: Hertzian until the contact reaches the roller ends, then more
    # compliant, never below Hertz by more than the grid's 1 %; increasing with the load
    hz = np.array([hertz.elliptical(q, b.rx_m, b.ry_m, s.material.e_star_pa).approach
                   for q in tb.q_out])
    assert np.all(tb.approach_out >= 0.99 * hz)
    assert np.all(np.diff(tb.approach_out) > 0)


def test_removed_force_area_and_approach_change_of_a_defect():
    from bearing_envelope.contact import hertz

    forces = []
    for depth in (5.0, 15.0, 50.0):
        s, tb, nodes = _table(depth)
        b, d = s.bearing, s.defect
        q = tb.q_nodes[-1]
        hz = hertz.elliptical(q, b.rx_m, b.ry_m, s.material.e_star_pa)
        # Hertz load carried by the footprint before the defect was there
        xs = np.linspace(-d.extent_x_m / 2, d.extent_x_m / 2, 201)
        ys = np.linspace(-d.extent_y_m / 2, d.extent_y_m / 2, 201)
        X, Y = np.meshgrid(xs, ys, indexing="ij")
        f_foot = np.trapezoid(np.trapezoid(hz.pressure(X, Y), ys, axis=1), xs)
        sig = tb.evaluate_integrals(np.full(3, q), np.array([0.0, 0.5 * hz.a, 3 * hz.a]))
        dF = sig["removed_force"]
        # at fixed approach the footprint loses its load, the rims take part of it back
        assert 0 < dF[0] < f_foot and dF[1] > 0 and dF[2] == 0
        forces.append(dF[0] / f_foot)
        # area: the footprint leaves the contact (deep defect: at most its whole area)
        dA = tb.area0[-1] * tb.ratio_area[-1, 0]
        assert -dA == pytest.approx(d.extent_x_m * d.extent_y_m,
                                    rel=2 * nodes[-1].window.dx / d.extent_x_m)
        # approach change at fixed load: dF over the Hertz contact stiffness 3Q/(2 delta)
        assert sig["approach_change"][0] == pytest.approx(dF[0] * hz.approach / (1.5 * q), rel=0.01)
        assert sig["approach_change"][0] > 0 and sig["approach_change"][2] == 0
    # removed force -> 0 as the defect narrows (w = 2h here): faster than the footprint load
    assert forces[0] < forces[1] < forces[2] and forces[0] < 0.02


def test_integral_signals_in_the_history():
    s = _scene(50.0, load=250.0, acquisition={"mode": "point"})
    h = simulate(s, "draft")
    sig = h.signals
    inside = (np.abs(h.defect_offset) < 0.5 * h.table.scale(h.roller_load)) & (h.roller_load > 0)
    assert inside.sum() > 10
    assert np.all(sig["approach_change"][inside] > 0)
    assert np.all(sig["removed_force"][inside] > 0)
    np.testing.assert_allclose(sig["contact_force"] + sig["removed_force"], h.roller_load,
                               rtol=1e-12, atol=1e-9)
    far = np.abs(h.defect_offset) > 2 * h.table.scale(h.roller_load)
    assert np.all(sig["removed_force"][far] == 0)
    np.testing.assert_allclose(sig["approach"][far],
                               h.table.approach_no_defect(h.roller_load[far]), rtol=1e-12)


def test_discrete_roller_load_steps_between_rollers():
    s = _scene(0.0, acquisition={"mode": "point"})
    sd = Scene.from_mapping({"operation": {"revolutions": 2.0, "acquisition": {"mode": "point"}},
                             "load": {"roller_load": "discrete"}}, load_kN=500, depth_um=0)
    h, hd = simulate(s, "draft"), simulate(sd, "draft")
    ld = h.load_distribution
    kin = kinematics(s, h.time)
    # the load of the roller over the defect, at that roller's own angle
    np.testing.assert_allclose(hd.roller_load, ld.load_at(kin["theta_roller"]), rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(h.roller_load, ld.load_at(kin["theta_shaft"]), rtol=1e-9, atol=1e-6)
    # the discrete load is constant while one roller is over the defect and steps between them
    same = np.diff(kin["roller"]) == 0
    jump = np.abs(np.diff(hd.roller_load))
    assert jump[~same].max() > 50 * jump[same].max()


def test_hardness_bounds_global_and_window_solves():
    # the rim peak of a 50 um defect at an 80 kN roller load exceeds 8 GPa elastically (draft);
    # with H below it every solve (global, window, defect) stays <= H and the peak is H
    q, x = 80e3, 0.0
    P_el, _ = direct_pressure(_scene(50.0, revolutions=0.1), fidelity_from("draft"), q, x)
    H_GPa = 0.9 * P_el / 1e9
    s = Scene.from_mapping({"operation": {"revolutions": 0.1}, "material": {"hardness_GPa": H_GPa}},
                           load_kN=500.0, depth_um=50.0)
    P, Pd = direct_pressure(s, fidelity_from("draft"), q, x)
    assert P_el > s.material.hardness_pa
    assert P == pytest.approx(s.material.hardness_pa, rel=1e-12) and Pd <= P


def test_outside_peak_grid_is_refined_where_the_roller_end_peak_bends():
    # at 750 kN the roller-end peak sets in inside the load range: the P_out(Q) grid is bisected
    # there, and the linear reading between its points meets fresh global solves (at the
    # midpoint of the coarsest interval, not a point of the build)
    from bearing_envelope.physics import solves as hi
    from bearing_envelope.physics.fidelity import fidelity_from
    from bearing_envelope.physics.table import OUTSIDE_REFINE_TOL

    s = _scene(0.0, load=750.0, revolutions=0.1)
    fid = fidelity_from("draft")
    t = simulate(s, fid).table
    q = np.cbrt(t.q_out)
    assert q.size > t.out_density * (t.q_nodes.size - 1) + 1 and np.all(np.diff(q) > 0)
    assert np.all(np.isin(np.round(np.cbrt(t.q_nodes), 9), np.round(q, 9)))
    steps = np.diff(q)
    assert steps.min() < steps.max() / 4  # refined somewhere, not everywhere
    j = int(np.argmax(steps))
    qm = 0.5 * (q[j] + q[j + 1])
    pm = hi.outside_max(s, fid, qm ** 3, t.kappa, hi.SolveStats())
    assert abs(0.5 * (t.p_out[j] + t.p_out[j + 1]) - pm) <= OUTSIDE_REFINE_TOL * pm


@pytest.mark.parametrize("spec, field", [
    ({"local_dx_um": 2.0, "rim_dx_um": 4.0}, "fidelity.rim_dx_um"),     # coarser than its parent
    ({"local_dx_um": 2.0, "rim_dx_um": 2.0}, "fidelity.rim_dx_um"),     # not a refinement
    ({"local_dx_um": 2.0, "rim_dx_um": 0.75}, "fidelity.rim_dx_um"),    # not an integer ratio
    ({"local_dx_um": 2.0, "rim_dx_um": -0.5}, "fidelity.rim_dx_um"),
    ({"local_dx_um": 2.0, "rim_dx_um": 0.5, "element": "linear"}, "fidelity.rim_dx_um"),
    ({"rim_dx_um": 0.5, "rim_strip_um": 0.0}, "fidelity.rim_strip_um"),
])
def test_bad_rim_refinement_named(spec, field):
    from bearing_envelope.physics.fidelity import fidelity_from

    with pytest.raises(ValueError, match=field.replace(".", r"\.")):
        fidelity_from({"preset": "standard", **spec})


def test_rim_strips_match_a_uniform_fine_window():
    # a 4 um window with 1 um strips around the rims against a uniform 1 um window (same
    # everything else): peak and removed force within 1 %; the 4 um window alone is further off
    from bearing_envelope.physics import solves as hi
    from bearing_envelope.physics.fidelity import fidelity_from

    s = _scene(50.0, load=250.0, revolutions=0.1)
    q, x = 30e3, 0.0
    out = {}
    for name, spec in {"coarse": {"local_dx_um": 4.0}, "strips": {"local_dx_um": 4.0, "rim_dx_um": 1.0},
                       "fine": {"local_dx_um": 1.0}}.items():
        fid = fidelity_from({"preset": "draft", "local_dy_um": 50.0, **spec})
        node = hi.solve_load(s, fid, q, 1.0, hi.SolveStats())
        out[name] = hi.defect_solve(s, fid, node, x, hi.SolveStats())
    f, st, c = out["fine"], out["strips"], out["coarse"]
    assert st.Pd == pytest.approx(f.Pd, rel=0.01)
    assert st.removed_force == pytest.approx(f.removed_force, rel=0.01)
    assert abs(c.Pd / f.Pd - 1) > 2 * abs(st.Pd / f.Pd - 1)
