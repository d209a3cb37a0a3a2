"""Defect window solves on the contact's rows (physics/solves.py, ``contact_rows`` and
``window_solve``): off the inner race a defect window solve is solved on the rows where the
no-defect gap overlaps, and must give the whole window's solution (the truth: the same solve on
every row, as before) to rounding; a solution that would reach beyond the rows is solved again on
the whole window. The CWRU ball pit (0.007 in wide, 0.011 in deep) on the inner contact at 500 N,
``standard`` (rim strips on)."""

import dataclasses

import numpy as np
import pytest

from bearing_envelope.contact import halfspace as hs
from bearing_envelope.physics.fidelity import fidelity_from
from bearing_envelope.physics.geometry import gap_field
from bearing_envelope.physics.scene import Scene
from bearing_envelope.contact import ElasticHalfSpace
from bearing_envelope.physics.solves import (SolveStats, defect_solve, fast_rows, solve_load,
                                             window_solve)

INCH_UM = 25400.0
Q_N = 500.0


def _scene(location):
    m = {"bearing": {"designation": "SKF 6205-2RS"},
         "operation": {"shaft_rate_hz": 29.95, "fs_hz": 48000.0, "revolutions": 1},
         "defect": {"location": location, "shape": "cylinder", "width_um": 0.007 * INCH_UM}}
    return Scene.from_mapping(m, load_kN=1.0, depth_um=0.011 * INCH_UM).for_race("inner")


@pytest.fixture(scope="module")
def ball_node():
    sc = _scene("rolling_element")
    fid = fidelity_from("standard")
    return sc, fid, solve_load(sc, fid, Q_N, 1.05, SolveStats())


def test_rows_hold_every_overlapping_cell_and_only_off_the_inner_race(ball_node):
    sc, fid, node = ball_node
    r0, r1 = node.rows
    n = node.window.shape[0]
    assert 0 < r0 < r1 < n and r1 - r0 < 0.6 * n      # the CWRU pit: about half the rows
    g0 = gap_field(sc, node.window, None) + node.u_ext
    overlap = np.flatnonzero((g0 < node.approach).any(axis=1))
    assert r0 <= overlap[0] and overlap[-1] < r1
    contact = np.flatnonzero((node.p_window0 > 0).any(axis=1))
    assert r0 < contact[0] and contact[-1] < r1 - 1
    inner = solve_load(_scene("inner_race"), fid, Q_N, 1.05, SolveStats())
    assert inner.rows is None and inner.rows_halfspace is None


@pytest.mark.parametrize("x_um", [0.0, 60.0, 140.0])
def test_defect_solve_on_the_rows_is_the_whole_windows(ball_node, x_um):
    sc, fid, node = ball_node
    whole = dataclasses.replace(node, rows=None, rows_halfspace=None, end_ref={})
    st_rows, st_whole = SolveStats(), SolveStats()
    a = defect_solve(sc, fid, node, 1e-6 * x_um, st_rows)
    b = defect_solve(sc, fid, whole, 1e-6 * x_um, st_whole)
    assert st_rows.n_rows_fallback == 0
    assert np.max(np.abs(a.pressure - b.pressure)) <= 1e-9 * b.pressure.max()
    for name in ("P", "Pd", "W"):
        assert getattr(a, name) == pytest.approx(getattr(b, name), rel=1e-9)
    assert a.removed_force == pytest.approx(b.removed_force, rel=1e-7, abs=1e-9 * node.q)
    assert a.area_change == pytest.approx(b.area_change, rel=1e-9)
    if x_um == 0.0:
        assert b.removed_force > 0 and b.P > node.p0     # the pit sheds load, its rims peak


def test_rows_too_narrow_are_solved_on_the_whole_window(ball_node):
    sc, fid, node = ball_node
    win = node.window
    contact = np.flatnonzero((node.p_window0 > 0).any(axis=1))
    mid = int(contact.mean())
    rows = (mid - 10, mid + 10)                          # inside the contact: it reaches beyond
    narrow = dataclasses.replace(node, rows=rows, rows_halfspace=ElasticHalfSpace(
        (rows[1] - rows[0], win.shape[1]), win.dx, win.dy, sc.material.e_star_pa, workers=1))
    g = gap_field(sc, win, 0.0) + node.u_ext
    kw = dict(tol=fid.tol, max_iter=fid.max_iter, approach=node.approach, boundary="ignore",
              element=fid.element, hardness=sc.material.hardness_pa)
    stats = SolveStats()
    p = window_solve(narrow, g, stats, sc.material.e_star_pa, node.p_window0, **kw)
    assert stats.n_rows_fallback == 1
    whole = dataclasses.replace(node, rows=None)
    q = window_solve(whole, g, SolveStats(), sc.material.e_star_pa, node.p_window0, **kw)
    # two solves to the tolerance from different starts
    assert np.abs(p.sum() - q.sum()) <= 1e-4 * q.sum()
    assert np.count_nonzero(p[:rows[0]]) > 0 and np.count_nonzero(p[rows[1]:]) > 0


def _factors_ok(n):
    if n % 4:
        return False
    for f in (2, 3, 5, 7):
        while n % f == 0:
            n //= f
    return n == 1


@pytest.mark.parametrize("rows", [1, 107, 189, 214, 217, 231, 431, 1000])
def test_fast_rows_is_the_next_count_without_large_prime_factors(rows):
    got = fast_rows(rows, 10 ** 6)
    want = next(n for n in range(rows, 2 * rows + 8) if _factors_ok(n))
    assert got == want
    assert fast_rows(rows, rows) == rows                 # never beyond the rows available
    assert fast_rows(189, 10 ** 6) == 192 and fast_rows(231, 10 ** 6) == 240


def test_kernel_spectrum_cache_keeps_the_grids_of_a_ball_case(monkeypatch):
    hs.clear_kernel_cache()
    shapes = [(20 + k, 18) for k in range(hs.KERNEL_CACHE_ENTRIES)]
    specs = [hs.kernel_spectrum(sh, 1e-6, 1e-5, 1e11) for sh in shapes]
    assert hs.kernel_spectrum(shapes[0], 1e-6, 1e-5, 1e11) is specs[0]   # none evicted
    # the byte bound: room for three of these; a new entry evicts the oldest beyond it
    monkeypatch.setattr(hs, "KERNEL_CACHE_BYTES", 3.5 * specs[0].nbytes)
    hs.kernel_spectrum((70, 18), 1e-6, 1e-5, 1e11)
    again = hs.kernel_spectrum(shapes[5], 1e-6, 1e-5, 1e11)
    assert again is not specs[5] and np.array_equal(again, specs[5])
    hs.clear_kernel_cache()
