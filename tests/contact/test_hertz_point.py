"""Hertz point contact (issue 23, part C): three independent routes to the ellipse of the SKF 6205
ball contacts and of a sphere on a flat, and the boundary-element solver on a grid sized from the
Hertz ellipse against them (within 0.5 % on a converged grid)."""

import math

import numpy as np
import pytest

from bearing_envelope.contact import hertz, solve_contact

E_STAR = 115.4e9          # steel on steel (Pa)
D_BALL = 7.94e-3          # SKF 6205 ball diameter (m), CWRU
D_PITCH = 39.04e-3        # SKF 6205 pitch diameter (m), CWRU
F_GROOVE = 0.52           # groove conformity (assumed, typical)
Q_BALL = 1000.0           # ball load (N)

_R = 0.5 * D_BALL
_RY = 1.0 / (1.0 / _R - 1.0 / (F_GROOVE * D_BALL))
CASES = {
    # name: (force, R_x, R_y) -- hand curvatures: inner 1/R_x = 2/d + 2/(D - d), outer 2/d - 2/(D + d)
    "6205 inner": (Q_BALL, 1.0 / (1.0 / _R + 2.0 / (D_PITCH - D_BALL)), _RY),
    "6205 outer": (Q_BALL, 1.0 / (1.0 / _R - 2.0 / (D_PITCH + D_BALL)), _RY),
    "sphere on flat": (100.0, 0.01, 0.01),
}


@pytest.mark.parametrize("name", CASES)
def test_curvature_difference_route_equals_the_curvature_ratio_route(name):
    f, rx, ry = CASES[name]
    j, h = hertz.elliptical(f, rx, ry, E_STAR), hertz.harris_point_contact(f, rx, ry, E_STAR)
    for k in ("a", "b", "p0", "approach"):
        assert getattr(h, k) == pytest.approx(getattr(j, k), rel=1e-9), k


@pytest.mark.parametrize("name", CASES)
def test_hamrock_brewe_approximation_within_its_stated_accuracy(name):
    f, rx, ry = CASES[name]
    j, hb = hertz.elliptical(f, rx, ry, E_STAR), hertz.hamrock_brewe(f, rx, ry, E_STAR)
    for k in ("a", "b", "p0"):
        assert getattr(hb, k) == pytest.approx(getattr(j, k), rel=0.03), k
    assert hb.approach == pytest.approx(j.approach, rel=0.06)


def test_sphere_is_the_closed_form():
    """a = (3 F R / 4 E*)^(1/3) = 0.18683 mm, p0 = 3F/(2 pi a^2) = 1.3678 GPa (F = 100 N,
    R = 10 mm, E* = 115 GPa; hand values)."""
    h = hertz.harris_point_contact(100.0, 0.01, 0.01, 1.15e11)
    assert h.a == pytest.approx(0.18683e-3, rel=1e-4) and h.b == h.a
    assert h.p0 == pytest.approx(1.3678e9, rel=1e-4)


def _solve_on_hertz_grid(force, rx, ry, cells_per_semi_axis, extent=1.25):
    """Solve on a grid of ``cells_per_semi_axis`` cells per Hertz semi-axis (each direction)
    covering ``extent`` semi-axes; fit ``p^2 = p0^2 (1 - s^2/c^2)`` along the two central lines.
    Returns (a, b, p0 from the fit, p_max on the grid)."""
    h = hertz.elliptical(force, rx, ry, E_STAR)
    n = cells_per_semi_axis
    dx, dy = h.a / n, h.b / n
    m = 2 * int(math.ceil(extent * n))
    x = (np.arange(m) - 0.5 * (m - 1)) * dx
    y = (np.arange(m) - 0.5 * (m - 1)) * dy
    gap = x[:, None] ** 2 / (2 * rx) + y[None, :] ** 2 / (2 * ry)
    sol = solve_contact(gap, dx, dy, force, E_STAR, tol=1e-10, max_iter=2000, workers=1)
    p = sol.pressure
    c = m // 2 - 1                        # the two central lines sit half a cell off the axes

    def fit(s, line, off, other):
        keep = line > 0.2 * line.max()
        A = np.vstack([np.ones(keep.sum()), s[keep] ** 2]).T
        c0, c1 = np.linalg.lstsq(A, line[keep] ** 2, rcond=None)[0]
        chord = 1.0 - (off / other) ** 2   # the line's chord of the ellipse
        return math.sqrt(c0 / chord), math.sqrt(-c0 / c1) / math.sqrt(chord)

    p0x, a = fit(x, 0.5 * (p[:, c] + p[:, c + 1]), 0.5 * dy, h.b)
    _p0y, b = fit(y, 0.5 * (p[c, :] + p[c + 1, :]), 0.5 * dx, h.a)
    return h, a, b, p0x, float(p.max())


@pytest.mark.parametrize("name", CASES)
def test_solver_reproduces_hertz_on_a_converged_grid(name):
    """20 and 40 cells per semi-axis (grids 50^2 and 100^2, < 0.1 s each): a, b, p0 within 0.5 %
    of Hertz on both, and the two grids agree to 0.2 % (converged)."""
    f, rx, ry = CASES[name]
    res = {n: _solve_on_hertz_grid(f, rx, ry, n) for n in (20, 40)}
    for n, (h, a, b, p0, pmax) in res.items():
        assert a == pytest.approx(h.a, rel=5e-3), (n, "a")
        assert b == pytest.approx(h.b, rel=5e-3), (n, "b")
        assert p0 == pytest.approx(h.p0, rel=5e-3), (n, "p0")
        assert pmax == pytest.approx(h.p0, rel=5e-3), (n, "p_max")
    (_, a1, b1, p1, _), (_, a2, b2, p2, _) = res[20][:5], res[40][:5]
    assert abs(a1 / a2 - 1) < 2e-3 and abs(b1 / b2 - 1) < 2e-3 and abs(p1 / p2 - 1) < 2e-3
