import math
import warnings

import numpy as np
import pytest

from bearing_envelope.contact import (
    ContactConvergenceError,
    ContactGridError,
    ContactGridWarning,
    ElasticHalfSpace,
    composite_modulus,
    hertz,
    influence_coefficients,
    solve_contact,
)



def centred_axis(n: int, d: float) -> np.ndarray:
    """Node coordinates with node ``n // 2`` exactly at 0."""
    return (np.arange(n) - n // 2) * d


def paraboloid(nx, ny, dx, dy, rx, ry):
    x = centred_axis(nx, dx)
    y = centred_axis(ny, dy)
    return x[:, None] ** 2 / (2 * rx) + y[None, :] ** 2 / (2 * ry)


# ---------------------------------------------------------------- half-space operator
def test_dcfft_equals_direct_sum():
    nx, ny, dx, dy, E = 9, 14, 1e-5, 3e-5, 1e11
    p = np.random.default_rng(1).random((nx, ny))
    u = ElasticHalfSpace((nx, ny), dx, dy, E, backend="scipy").displacement(p)
    X = np.arange(nx)[:, None] * dx
    Y = np.arange(ny)[None, :] * dy
    ref = sum(p[i, j] * influence_coefficients(X - i * dx, Y - j * dy, dx, dy, E) for i in range(nx) for j in range(ny))
    assert np.abs(u - ref).max() <= 1e-13 * np.abs(ref).max()


def test_influence_far_field_is_point_load():
    k = influence_coefficients(200e-3, -70e-3, 1e-3, 2e-3, 1.0)
    assert k * math.pi * math.hypot(200e-3, 70e-3) / 2e-6 == pytest.approx(1.0, rel=1e-4)


def test_composite_modulus():
    assert composite_modulus(210e9, 0.3, 210e9, 0.3) == pytest.approx(210e9 / (2 * 0.91))
    assert composite_modulus(1e9, 0.5, math.inf, 0.3) == pytest.approx(1e9 / 0.75)
    with pytest.raises(ValueError, match="nu2"):
        composite_modulus(1e9, 0.3, 1e9, 0.7)
    with pytest.raises(ValueError, match="E1"):
        composite_modulus(-1.0, 0.3, 1e9, 0.3)


# ---------------------------------------------------------------- Hertz validation
def test_sphere_against_hertz(sphere_case):
    c = sphere_case
    ref, n = c["ref"], c["n"]
    s = solve_contact(c["gap"], c["d"], c["d"], c["F"], c["E"])
    assert s.converged
    p0 = s.pressure[n // 2, n // 2]
    assert p0 == s.p_max
    assert p0 / ref.p0 - 1 == pytest.approx(0.0, abs=5e-4)  # measured: 8.5e-5
    assert math.sqrt(s.contact_area / math.pi) / ref.a == pytest.approx(1.0, rel=0.01)
    assert s.approach / ref.approach == pytest.approx(1.0, rel=1e-3)
    assert s.force == pytest.approx(c["F"], rel=1e-9)
    # the pressure field itself, away from the edge singularity of the derivative
    x = centred_axis(n, c["d"])
    pr = ref.pressure(x[:, None], x[None, :])
    assert np.abs(s.pressure - pr).max() < 0.03 * ref.p0


def test_elongated_ellipse_against_hertz():
    rx, ry, F, E = 0.01, 1.5, 100.0, 1e11  # Ry/Rx = 150
    ref = hertz.elliptical(F, rx, ry, E)
    nx, ny = 64, 64
    dx, dy = 3 * ref.a / (nx // 2), 3 * ref.b / (ny // 2)
    s = solve_contact(paraboloid(nx, ny, dx, dy, rx, ry), dx, dy, F, E)
    assert s.p_max / ref.p0 == pytest.approx(1.0, rel=0.02)
    ic = s.pressure > 0
    ia = np.nonzero(ic.any(axis=1))[0]
    ib = np.nonzero(ic.any(axis=0))[0]
    # half-width of the loaded strip (+ half a cell for the cell extent)
    a_num = (ia.max() - ia.min() + 1) * dx / 2
    b_num = (ib.max() - ib.min() + 1) * dy / 2
    assert a_num / ref.a == pytest.approx(1.0, rel=0.04)
    assert b_num / ref.b == pytest.approx(1.0, rel=0.04)
    # area-equivalent semi-axes, sharper than the cell count
    assert s.contact_area / ref.area == pytest.approx(1.0, rel=0.02)
    assert s.approach / ref.approach == pytest.approx(1.0, rel=0.02)


# ---------------------------------------------------------------- conditions
def test_force_balance_and_complementarity(sphere_case):
    c = sphere_case
    tol = 1e-8
    s = solve_contact(c["gap"], c["d"], c["d"], c["F"], c["E"], tol=tol)
    assert abs(s.pressure.sum() * c["d"] ** 2 / c["F"] - 1) < 1e-9
    assert (s.pressure >= 0).all()
    h = c["gap"] + s.displacement - s.approach
    scale = s.displacement.max()
    on = s.pressure > 0
    assert np.abs(h[on]).max() <= tol * scale
    assert h[~on].min() >= -tol * scale
    assert np.abs(s.pressure * h).max() <= tol * scale * s.p_max


def test_symmetry():
    n, d, R, F, E = 64, 1e-5, 0.01, 5.0, 1e11
    x = centred_axis(n, d)[1:]  # odd grid, symmetric about the centre node
    g = (x[:, None] ** 2 / (2 * R)) + (x[None, :] ** 2 / (4 * R))
    s = solve_contact(g, d, d, F, E)
    p = s.pressure
    assert np.abs(p - p[::-1, :]).max() <= 1e-7 * p.max()
    assert np.abs(p - p[:, ::-1]).max() <= 1e-7 * p.max()


def test_tightening_tol_no_longer_changes_solution(sphere_case):
    c = sphere_case
    args = (c["gap"], c["d"], c["d"], c["F"], c["E"])
    s8 = solve_contact(*args, tol=1e-8)
    s10 = solve_contact(*args, tol=1e-10)
    s6 = solve_contact(*args, tol=1e-6)
    assert s10.iterations > s8.iterations
    d8 = np.abs(s8.pressure - s10.pressure).max() / s10.p_max
    d6 = np.abs(s6.pressure - s10.pressure).max() / s10.p_max
    assert d8 < 1e-6  # the solution at the default tol is converged in the pressure
    assert d8 < d6


def test_flat_punch_edge_peak_grows_with_refinement():
    # rigid flat-ended circular punch (gap 0 inside radius c, +inf outside: no material)
    c, F, E = 1e-3, 100.0, 1e11
    pm = F / (math.pi * c * c)
    peaks = []
    for n in (16, 32, 64):
        d = 2.2 * c / n
        x = centred_axis(n, d) + d / 2
        r = np.hypot(x[:, None], x[None, :])
        g = np.where(r <= c, 0.0, np.inf)
        s = solve_contact(g, d, d, F, E)
        assert np.abs(s.pressure[r > c]).max() == 0.0
        peaks.append(s.p_max / pm)
    assert peaks[0] < peaks[1] < peaks[2]
    assert peaks[2] > 1.3 * peaks[0]  # ~ sqrt(refinement): singular edge


# ---------------------------------------------------------------- options
def test_warm_start_reduces_iterations(sphere_case):
    # a smooth bump in the contact moves by 0.2 cell (a rolling feature between two time steps)
    c = sphere_case
    n, d, ref = c["n"], c["d"], c["ref"]
    x = (np.arange(n) - n // 2) * d

    def gap(offset):
        bump = np.exp(-((x[:, None] - offset * d) ** 2 + x[None, :] ** 2) / (2 * (0.3 * ref.a) ** 2))
        return c["gap"] + 0.2 * ref.approach * bump

    s0 = solve_contact(gap(0.0), d, d, c["F"], c["E"])
    cold = solve_contact(gap(0.2), d, d, c["F"], c["E"])
    warm = solve_contact(gap(0.2), d, d, c["F"], c["E"], p_init=s0.pressure)
    assert warm.iterations < cold.iterations  # measured 10 vs 13
    assert np.abs(warm.pressure - cold.pressure).max() < 1e-6 * cold.p_max
    same = solve_contact(gap(0.0), d, d, c["F"], c["E"], p_init=s0.pressure)
    assert same.iterations <= 1


def test_inf_cells_carry_no_pressure(sphere_case):
    c = sphere_case
    g = c["gap"].copy()
    n = c["n"]
    g[:, n // 2 + 5 :] = np.inf  # cut the sphere: no material beyond
    s = solve_contact(g, c["d"], c["d"], c["F"], c["E"])
    assert (s.pressure[np.isinf(g)] == 0).all()
    assert s.pressure.sum() * c["d"] ** 2 == pytest.approx(c["F"], rel=1e-12)
    # the truncated body carries an edge peak at the cut
    assert s.p_max > 1.2 * c["ref"].p0


def test_displacement_control_reproduces_force_control(sphere_case):
    c = sphere_case
    sf = solve_contact(c["gap"], c["d"], c["d"], c["F"], c["E"])
    sd = solve_contact(c["gap"], c["d"], c["d"], None, c["E"], approach=sf.approach)
    assert sd.force == pytest.approx(c["F"], rel=1e-6)
    assert np.abs(sd.pressure - sf.pressure).max() < 1e-6 * sf.p_max
    assert sd.approach == sf.approach


def test_displacement_control_without_overlap_is_zero(sphere_case):
    c = sphere_case
    s = solve_contact(c["gap"], c["d"], c["d"], None, c["E"], approach=-1e-6)
    assert s.force == 0 and not s.pressure.any()


# ---------------------------------------------------------------- errors
@pytest.mark.parametrize("force", [0.0, -1.0, math.nan, math.inf])
def test_bad_force(sphere_case, force):
    c = sphere_case
    with pytest.raises(ValueError, match=r"force must be a finite number > 0"):
        solve_contact(c["gap"], c["d"], c["d"], force, c["E"])


@pytest.mark.parametrize("name", ["dx", "dy", "e_star"])
def test_bad_scalars(sphere_case, name):
    c = sphere_case
    kw = dict(dx=c["d"], dy=c["d"], e_star=c["E"])
    kw[name] = 0.0
    with pytest.raises(ValueError, match=name):
        solve_contact(c["gap"], kw["dx"], kw["dy"], c["F"], kw["e_star"])


def test_bad_gap(sphere_case):
    c = sphere_case
    g = c["gap"].copy()
    g[3, 4] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        solve_contact(g, c["d"], c["d"], c["F"], c["E"])
    with pytest.raises(ValueError, match="2-D"):
        solve_contact(c["gap"][0], c["d"], c["d"], c["F"], c["E"])
    with pytest.raises(ValueError, match="boundary must be"):
        solve_contact(c["gap"], c["d"], c["d"], c["F"], c["E"], boundary="maybe")


def test_grid_too_small_raises_or_warns(sphere_case):
    c = sphere_case
    small = c["gap"][48:80, 48:80]  # box of side 1.5a: contact spills over the edge
    with pytest.raises(ContactGridError, match="grid boundary") as ei:
        solve_contact(small, c["d"], c["d"], c["F"], c["E"])
    assert isinstance(ei.value, ValueError) and 0 < ei.value.fraction < 1
    with pytest.warns(ContactGridWarning, match="of the force"):
        solve_contact(small, c["d"], c["d"], c["F"], c["E"], boundary="warn")


def test_non_convergence_reports_history(sphere_case):
    c = sphere_case
    with pytest.raises(ContactConvergenceError, match="did not converge") as ei:
        solve_contact(c["gap"], c["d"], c["d"], c["F"], c["E"], max_iter=3)
    assert len(ei.value.residual_history) == 4
    assert ei.value.solution.iterations == 3


# ---------------------------------------------------------------- implementation variants
def test_numba_and_numpy_passes_agree(sphere_case):
    from bearing_envelope.contact import NUMPY_KERNELS

    c = sphere_case
    g = c["gap"].copy()
    g[:, -20:] = np.inf  # exercise the no-material cells too
    args = (g, c["d"], c["d"], c["F"], c["E"])
    a = solve_contact(*args, kernels=NUMPY_KERNELS, boundary="ignore")
    b = solve_contact(*args, boundary="ignore")
    assert a.iterations == b.iterations
    assert np.abs(a.pressure - b.pressure).max() <= 1e-10 * a.p_max


def test_preconditioner_block_passes_numba_equal_numpy_and_masking():
    """The preconditioner's gather (h on the free set 0 < p < H of a block) and place (zero the
    last block, write z on the free set of the new one): numba equals the numpy reference bit
    for bit, and both equal the masks written out here."""
    from bearing_envelope.contact import DEFAULT_KERNELS, NUMPY_KERNELS

    rng = np.random.default_rng(5)
    p = np.where(rng.random((12, 9)) < 0.4, 0.0, rng.uniform(0, 2, (12, 9)))
    p[3, 4] = 1.5
    h = rng.normal(size=p.shape)
    H = 1.5
    for kn in (NUMPY_KERNELS, DEFAULT_KERNELS):
        hb = np.full((5, 4), np.nan)
        kn["free_block"](h, p, H, 2, 3, hb)
        free = (p > 0) & (p < H)
        np.testing.assert_array_equal(hb, np.where(free, h, 0.0)[2:7, 3:7])
        z = np.full(p.shape, 7.0)
        zb = rng.normal(size=(5, 4))
        kn["place_block"](z, zb, p, H, 6, 5, (0, 0, 3, 2))
        want = np.full(p.shape, 7.0)
        want[0:3, 0:2] = 0.0
        want[6:11, 5:9] = np.where(free[6:11, 5:9], zb, 0.0)
        np.testing.assert_array_equal(z, want)


def test_preconditioner_cuts_iterations_same_answer(sphere_case):
    c = sphere_case
    args = (c["gap"], c["d"], c["d"], c["F"], c["E"])
    plain = solve_contact(*args, precondition=False)
    pre = solve_contact(*args)
    assert pre.iterations * 2 <= plain.iterations  # measured 8 vs 21
    # incremental displacement updates while the contact set is unchanged save convolutions
    assert pre.convolutions < 2 * pre.iterations + 1
    assert np.abs(plain.pressure - pre.pressure).max() < 1e-6 * pre.p_max


def test_pyfftw_backend_matches_scipy_if_available():
    pytest.importorskip("pyfftw")
    p = np.random.default_rng(2).random((24, 40))
    a = ElasticHalfSpace(p.shape, 1e-5, 2e-5, 1e11, backend="scipy").displacement(p)
    b = ElasticHalfSpace(p.shape, 1e-5, 2e-5, 1e11, backend="pyfftw").displacement(p)
    assert np.abs(a - b).max() <= 1e-12 * np.abs(a).max()


# ---------------------------------------------------------------- pyramidal (bilinear) elements
def test_linear_element_kernel_against_brute_force():
    from bearing_envelope.contact.halfspace import influence_coefficients_linear

    dx, dy = 1.0, 2.0
    m = 400  # midpoint rule on the tent x tent weight, away from the singular point
    s = (np.arange(m) + 0.5) / m * 2 - 1
    S, T = np.meshgrid(s * dx, s * dy, indexing="ij")
    w = (1 - np.abs(S) / dx) * (1 - np.abs(T) / dy) * (2 * dx / m) * (2 * dy / m)
    for x, y in [(1.0, 0.0), (3.0, -2.0), (15.9, 0.0), (16.1, 0.0), (30.0, 40.0)]:
        ref = np.sum(w / np.hypot(x - S, y - T)) / math.pi
        assert influence_coefficients_linear(x, y, dx, dy, 1.0) == pytest.approx(ref, rel=1e-6)
    # total load dx*dy: far field equals the point load
    assert influence_coefficients_linear(3000.0, 0.0, dx, dy, 1.0) * math.pi * 3000.0 / (dx * dy) == pytest.approx(1.0, rel=1e-6)


def test_linear_and_uniform_elements_converge_to_hertz():
    R, F, E = 0.01, 10.0, 1e11
    ref = hertz.sphere(F, R, E)
    err = {"uniform": [], "linear": []}
    for n in (32, 64, 128):
        d = 6 * ref.a / n
        x = centred_axis(n, d)
        g = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * R)
        for el in err:
            s = solve_contact(g, d, d, F, E, element=el)
            assert s.force == pytest.approx(F, rel=1e-12)
            err[el].append(abs(s.pressure[n // 2, n // 2] / ref.p0 - 1))
    for el, e in err.items():
        assert e[0] > e[1] > e[2], (el, e)  # both converge (measured ~2nd order)
    assert err["linear"][-1] < 5e-4 and err["uniform"][-1] < 5e-4  # 1.8e-4 and 8.5e-5 at 128^2


def test_element_name_checked(sphere_case):
    c = sphere_case
    with pytest.raises(ValueError, match="element must be one of"):
        solve_contact(c["gap"], c["d"], c["d"], c["F"], c["E"], element="quadratic")


def test_halfspace_displacement_of_hertz_pressure():
    # Johnson eq. 3.41: under p0 sqrt(1 - r^2/a^2), u = pi p0 (2 a^2 - r^2) / (4 a E*) for r <= a
    E, a, p0 = 1e11, 1e-4, 1e9
    n = 128
    d = 4 * a / n
    x = centred_axis(n, d)
    r2 = x[:, None] ** 2 + x[None, :] ** 2
    p = p0 * np.sqrt(np.clip(1 - r2 / a**2, 0, None))
    u = ElasticHalfSpace((n, n), d, d, E).displacement(p)
    inside = r2 <= (0.8 * a) ** 2
    ref = math.pi * p0 * (2 * a * a - r2) / (4 * a * E)
    assert np.abs(u - ref)[inside].max() < 2e-3 * ref.max()


def test_concurrent_solves_in_threads(sphere_case):
    from concurrent.futures import ThreadPoolExecutor

    c = sphere_case
    forces = [c["F"] * k for k in (0.8, 1.0, 1.2, 1.4)]
    ref = [solve_contact(c["gap"], c["d"], c["d"], f, c["E"]).pressure for f in forces]
    with ThreadPoolExecutor(4) as ex:
        got = list(ex.map(lambda f: solve_contact(c["gap"], c["d"], c["d"], f, c["E"]).pressure, forces))
    for a, b in zip(ref, got):
        assert np.array_equal(a, b)


# ---------------------------------------------------------------- property tests (hypothesis)
from hypothesis import given, settings, strategies as st  # noqa: E402


def _sphere_fixed_grid(n=64):
    R, E, Fmax = 0.01, 1e11, 40.0
    d = 3 * hertz.sphere(Fmax, R, E).a / n  # box 3a at the largest force
    x = centred_axis(n, d)
    return (x[:, None] ** 2 + x[None, :] ** 2) / (2 * R), d, E


@settings(max_examples=12, deadline=None)
@given(f1=st.floats(1.0, 20.0), k=st.floats(1.01, 2.0))
def test_property_approach_increases_with_force(f1, k):
    g, d, E = _sphere_fixed_grid()
    s1 = solve_contact(g, d, d, f1, E)
    s2 = solve_contact(g, d, d, k * f1, E)
    assert s2.approach > s1.approach
    assert s2.contact_area >= s1.contact_area


@settings(max_examples=12, deadline=None)
@given(f1=st.floats(5.0, 10.0), k=st.floats(1.5, 4.0))
def test_property_p0_scales_as_cube_root_of_force(f1, k):
    # fixed grid (contact radius >= 10 cells): discretisation error < 1 %
    g, d, E = _sphere_fixed_grid()
    s1 = solve_contact(g, d, d, f1, E)
    s2 = solve_contact(g, d, d, k * f1, E)
    assert s2.p_max / s1.p_max == pytest.approx(k ** (1 / 3), rel=0.01)


@settings(max_examples=8, deadline=None)
@given(k=st.floats(0.3, 3.0))
def test_property_self_similar_grid_scales_exactly(k):
    # grid scaled with the Hertz radius (box 6a(F)): the discrete problems are exactly similar
    R, E, F = 0.01, 1e11, 10.0
    n = 48
    out = []
    for f in (F, k * F):
        d = 6 * hertz.sphere(f, R, E).a / n
        x = centred_axis(n, d)
        s = solve_contact((x[:, None] ** 2 + x[None, :] ** 2) / (2 * R), d, d, f, E)
        out.append(s)
    assert out[1].p_max / out[0].p_max == pytest.approx(k ** (1 / 3), rel=1e-6)
    assert out[1].approach / out[0].approach == pytest.approx(k ** (2 / 3), rel=1e-6)


def test_tiny_contacts_converge():
    # a contact of one or a few cells: CG runs out of directions before neighbours enter
    R, E = 0.01, 1e11
    n = 16
    d = 8 * hertz.sphere(40.0, R, E).a / n
    x = centred_axis(n, d)
    g = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * R)
    for f in (0.05, 0.59, 0.75, 3.44, 4.29):
        s = solve_contact(g, d, d, f, E)
        assert s.converged and s.force == pytest.approx(f, rel=1e-12)
        h = g + s.displacement - s.approach
        assert h.min() >= -1e-8 * s.displacement.max()


# ---------------------------------------------------------------- warm starts and the stall guard
def _stall_case():
    """A real defect-window solve (default scene, 750 kN, 100 um pit, 2 um x 40 um window) that
    cycled in the preconditioned iteration: the warm start (the neighbouring offset's pressure)
    carried pressure over the pit, whose gap is 100 um, far above the approach."""
    from pathlib import Path

    d = np.load(Path(__file__).parents[1] / "data" / "window_warm_start_stall.npz")
    return {k: d[k] if d[k].ndim else float(d[k]) for k in d.files}


def test_warm_start_over_an_opened_pit_converges_like_a_cold_start():
    c = _stall_case()
    kw = dict(tol=c["tol"], approach=c["approach"], boundary="ignore", max_iter=300)
    cold = solve_contact(c["gap"], c["dx"], c["dy"], None, c["e_star"], **kw)
    warm = solve_contact(c["gap"], c["dx"], c["dy"], None, c["e_star"], p_init=c["p_init"], **kw)
    # before the fix this solve ran 3,000 iterations at a residual of order 1
    assert warm.iterations <= 60
    pit = c["gap"] > c["approach"]
    assert np.all(warm.pressure[pit] == 0) and pit.sum() > 1000
    assert np.abs(warm.pressure - cold.pressure).max() <= 1e-3 * cold.p_max
    assert warm.force == pytest.approx(cold.force, rel=1e-4)
    # complementarity of the warm solution: h >= 0 off contact, h ~ 0 on it
    h = c["gap"] + warm.displacement - warm.approach
    on = warm.pressure > 0
    assert np.abs(h[on]).max() <= 10 * c["tol"] * warm.displacement.max()
    assert h[~on].min() >= -10 * c["tol"] * warm.displacement.max()


def test_stall_guard_switches_to_plain_cg_and_keeps_the_answer(sphere_case):
    c = sphere_case
    # a rough sphere: the residual does not halve at every iteration
    gap = c["gap"] + 2e-8 * np.random.default_rng(0).standard_normal(c["gap"].shape)
    ref = solve_contact(gap, c["d"], c["d"], c["F"], c["E"])
    assert ref.preconditioner_dropped_at is None
    # a window of one iteration trips the guard early: the plain-CG continuation must reach
    # the same solution
    s = solve_contact(gap, c["d"], c["d"], c["F"], c["E"], stall_window=1)
    assert s.preconditioner_dropped_at is not None and s.converged
    assert np.abs(s.pressure - ref.pressure).max() <= 1e-5 * ref.p_max
    assert s.force == pytest.approx(c["F"], rel=1e-12)


@pytest.mark.parametrize("bad", [0, -3, 2.5, True])
def test_stall_window_validated(sphere_case, bad):
    c = sphere_case
    with pytest.raises(ValueError, match="stall_window"):
        solve_contact(c["gap"], c["d"], c["d"], c["F"], c["E"], stall_window=bad)
