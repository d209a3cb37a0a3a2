"""Elastic-perfectly-plastic surface: ``solve_contact(..., hardness=H)`` keeps 0 <= p <= H."""

import math

import numpy as np
import pytest
from scipy.linalg import cho_factor, solve_triangular
from scipy.optimize import brentq, lsq_linear

from bearing_envelope.contact import NUMPY_KERNELS, hertz, influence_coefficients, solve_contact


def _sphere(n, box_in_a, F=10.0, R=0.01, E=1.0e11):
    ref = hertz.sphere(F, R, E)
    d = box_in_a * ref.a / n
    x = (np.arange(n) - n // 2) * d
    gap = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * R)
    return gap, d, F, E, ref


def _check_bounded_kkt(s, gap, H, tol):
    """Both-bound complementarity, relative to the largest elastic displacement."""
    p = s.pressure
    h = gap + s.displacement - s.approach
    scale = s.displacement.max()
    zero, sat = p <= 0, p >= H
    free = ~zero & ~sat
    assert p.min() >= 0 and p.max() <= H
    assert h[zero].min() >= -tol * scale  # p = 0  -> h >= 0
    assert np.abs(h[free]).max() <= tol * scale  # 0 < p < H -> h = 0
    assert h[sat].max() <= tol * scale  # p = H  -> h <= 0
    return h


@pytest.mark.parametrize("frac", [0.7, 0.3])
def test_sphere_past_hardness(frac):
    gap, d, F, E, ref = _sphere(96, 8.0)
    H = frac * ref.p0
    tol = 1e-8
    s = solve_contact(gap, d, d, F, E, hardness=H, tol=tol)
    assert s.converged and s.hardness == H
    assert abs(s.pressure.sum() * d * d / F - 1) < 1e-9  # force balance
    h = _check_bounded_kkt(s, gap, H, tol)
    # a plastic zone at the centre, where p = H, carrying a permanent indentation
    c = gap.shape[0] // 2
    assert s.plastic[c, c] and s.pressure[c, c] == H
    assert np.array_equal(s.plastic, s.pressure >= H)
    assert s.plastic.sum() > 20 and s.plastic_area == pytest.approx(s.plastic.sum() * d * d)
    assert s.plastic_depth_max > 0
    assert np.array_equal(s.plastic_depth > 0, s.plastic & (h < 0))
    np.testing.assert_allclose(s.plastic_depth[s.plastic], np.clip(-h[s.plastic], 0, None))
    assert (s.plastic_depth[~s.plastic] == 0).all()
    # the bounded contact is wider than Hertz: F = area * mean p <= area * H
    assert s.contact_area >= F / H
    assert s.contact_area > math.pi * ref.a ** 2


def test_large_hardness_is_elastic_bit_for_bit(sphere_case):
    c = sphere_case
    args = (c["gap"], c["d"], c["d"], c["F"], c["E"])
    e = solve_contact(*args)
    b = solve_contact(*args, hardness=1e3 * e.p_max)  # never reached: same iterates
    assert np.array_equal(e.pressure, b.pressure) and e.approach == b.approach
    assert e.iterations == b.iterations and e.residual_history == b.residual_history
    assert not b.plastic.any() and b.plastic_depth_max == 0.0
    assert e.hardness is None and e.plastic is None and e.plastic_depth_max == 0.0
    # and a pitted, warm-started, displacement-controlled solve too
    g2 = c["gap"].copy()
    g2[50:60, 60:66] += 2e-7
    for kw in (dict(p_init=e.pressure), dict(precondition=False)):
        a1 = solve_contact(g2, *args[1:], **kw)
        a2 = solve_contact(g2, *args[1:], hardness=1e3 * e.p_max, **kw)
        assert np.array_equal(a1.pressure, a2.pressure)
    d1 = solve_contact(g2, c["d"], c["d"], None, c["E"], approach=e.approach)
    d2 = solve_contact(g2, c["d"], c["d"], None, c["E"], approach=e.approach, hardness=1e3 * e.p_max)
    assert np.array_equal(d1.pressure, d2.pressure)


def _dense_bounded_reference(gap, d, F, E, H):
    """Independent answer: min 1/2 p'Kp + (g - a)'p on 0 <= p <= H by bounded-variable least
    squares (scipy's BVLS, an exact active-set method: K = L L', so the objective is
    1/2 |L'p + L^-1 (g - a)|^2 + const), the approach ``a`` found by bracketing
    ``sum p(a) dx dy = F`` (monotone in ``a``). K is the dense matrix of the same Love patch
    coefficients, built cell by cell without FFT."""
    n = gap.shape[0]
    X, Y = np.meshgrid(np.arange(n) * d, np.arange(n) * d, indexing="ij")
    xs, ys = X.ravel(), Y.ravel()
    K = influence_coefficients(xs[:, None] - xs[None, :], ys[:, None] - ys[None, :], d, d, E)
    L = cho_factor(K, lower=True)[0]
    L = np.tril(L)
    A = L.T
    gv = gap.ravel()

    def p_of(a):
        b = -solve_triangular(L, gv - a, lower=True)
        r = lsq_linear(A, b, bounds=(0.0, H), method="bvls", tol=1e-14, lsmr_tol=None)
        return r.x

    a = brentq(lambda a: p_of(a).sum() * d * d - F, 0.0, gv.max(), xtol=1e-22, rtol=1e-15, maxiter=200)
    return p_of(a).reshape(gap.shape), a


def test_agrees_with_dense_bounded_lcp_reference():
    gap, d, F, E, ref = _sphere(20, 8.0)
    H = 0.5 * ref.p0
    s = solve_contact(gap, d, d, F, E, hardness=H, tol=1e-12, max_iter=5000)
    assert s.plastic.sum() >= 5  # the reference must see a plastic zone too
    p_ref, a_ref = _dense_bounded_reference(gap, d, F, E, H)
    assert np.abs(s.pressure - p_ref).max() <= 1e-4 * H
    assert s.approach == pytest.approx(a_ref, rel=1e-6)


def test_numba_and_numpy_passes_agree_with_hardness(sphere_case):
    c = sphere_case
    g = c["gap"].copy()
    g[:, -20:] = np.inf
    H = 0.6 * c["ref"].p0
    args = (g, c["d"], c["d"], c["F"], c["E"])
    a = solve_contact(*args, kernels=NUMPY_KERNELS, boundary="ignore", hardness=H)
    b = solve_contact(*args, boundary="ignore", hardness=H)
    assert a.plastic.any() and a.iterations == b.iterations
    assert np.abs(a.pressure - b.pressure).max() <= 1e-10 * H


def test_displacement_control_with_hardness_reproduces_force_control():
    gap, d, F, E, ref = _sphere(64, 8.0)
    H = 0.6 * ref.p0
    f = solve_contact(gap, d, d, F, E, hardness=H, tol=1e-10)
    u = solve_contact(gap, d, d, None, E, approach=f.approach, hardness=H, tol=1e-10)
    assert u.force == pytest.approx(F, rel=1e-6)
    assert np.abs(u.pressure - f.pressure).max() <= 1e-5 * H
    assert u.pressure.max() <= H and np.array_equal(u.plastic, f.plastic)


def test_warm_start_above_hardness_is_clipped():
    gap, d, F, E, ref = _sphere(64, 8.0)
    H = 0.6 * ref.p0
    e = solve_contact(gap, d, d, F, E)
    s = solve_contact(gap, d, d, F, E, hardness=H, p_init=e.pressure)
    c = solve_contact(gap, d, d, F, E, hardness=H)
    assert np.abs(s.pressure - c.pressure).max() <= 1e-5 * H


@pytest.mark.parametrize("bad", [0.0, -1e9, math.inf, math.nan, "hard", True])
def test_bad_hardness_named(sphere_case, bad):
    c = sphere_case
    with pytest.raises(ValueError, match="hardness"):
        solve_contact(c["gap"], c["d"], c["d"], c["F"], c["E"], hardness=bad)


def test_no_overlap_with_hardness_reports_an_empty_plastic_set(sphere_case):
    c = sphere_case
    s = solve_contact(c["gap"], c["d"], c["d"], None, c["E"], approach=-1e-9, hardness=1e9)
    assert s.force == 0 and s.hardness == 1e9 and not s.plastic.any() and s.plastic_depth_max == 0
