"""The no-defect state at one roller load: :class:`LoadNode` (global and window solutions,
far field, rows) and :func:`solve_load`, which makes it."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..fidelity import Fidelity
from ..geometry import Grid, gap_field, make_grid
from ..scene import Scene
from .global_solve import (_bilinear, _far_field, _halfspace, global_extent, global_solve,
                           window_spec)
from .stats import SolveStats
from .windows import FarResponse, WindowState, contact_rows, far_response

__all__ = ["LoadNode", "solve_load"]


@dataclass
class LoadNode:
    """Global and window no-defect solutions at one roller load (internal, kept for snapshots)."""

    q: float
    a_hertz: float
    grid: Grid
    pressure: np.ndarray
    approach: float
    window: Grid
    u_ext: np.ndarray
    p_window0: np.ndarray
    strip: np.ndarray          # window columns read (bool over window y)
    outside_max: float         # max global pressure outside the read strip
    p0: float                  # max no-defect pressure of the whole contact
    w0: float                  # max no-defect pressure in the window's read strip
    half_width: float          # solved contact half-width at y = y_d (m)
    zoom_consistency: float    # |max p_window0 - max p_global| / p0 in the read strip
    halfspace: Any = field(repr=False, default=None)
    approach_global: float = 0.0   # approach of the global no-defect solve at q (m)
    area_global: float = 0.0       # contact area of the global no-defect solve (m^2)
    area_window0: float = 0.0      # contact area of the window's no-defect solve (m^2)
    #: The far field's linear response (:class:`FarResponse`); None = frozen far field
    far: "FarResponse | None" = field(repr=False, default=None)
    #: The no-defect window with axial end strips (:func:`_end_reference`), once solved
    end_ref: dict = field(repr=False, default_factory=dict)
    #: Window rows ``[r0, r1)`` the defect solves are solved on (:func:`contact_rows`) and their
    #: half-space operator; None = every row (the inner race)
    rows: tuple[int, int] | None = None
    rows_halfspace: Any = field(repr=False, default=None)


def solve_load(scene: Scene, fid: Fidelity, q_load: float, kappa: float, stats: SolveStats,
                p_init_global=None, *, with_far: bool = True) -> LoadNode:
    """Global no-defect solve and zoom window at roller load ``q_load`` (:class:`LoadNode`);
    ``with_far=False`` skips the far field's response (:func:`far_response`: only the removed force
    needs it; the table's pressure checks do not).

    Parameters
    ----------
    scene : Scene
        The case's scene.
    fid : Fidelity
        The fidelity (grids, tolerance, strips).
    q_load : float
        Roller load (N).
    kappa : float
        Solved/Hertz contact half-width ratio (the read strip is ``s = kappa a + w_x/2 + r_n``).
    stats : SolveStats
        Counters.
    p_init_global : numpy.ndarray, optional
        Warm start of the global solve (Pa, the global grid's shape).
    with_far : bool
        Compute the far field's response.

    Returns
    -------
    LoadNode
        The global and window no-defect solutions at this load.

    Raises
    ------
    RuntimeError
        The defect window reaches outside the global grid (a grid-sizing defect, not an input
        error).
    """
    e_star = scene.material.e_star_pa
    a, s, dxw, dyw, xh, yd, hy_read, hy = window_spec(scene, fid, q_load, kappa)
    dxg, dyg = fid.global_dx_m, fid.global_dy_m
    xw = make_grid(-xh, xh, 0.0, 1.0, dxw, 1.0).x
    grid, sol = global_solve(scene, fid, q_load, global_extent(fid, kappa, a), stats,
                             p_init_global)
    pg = sol.pressure
    # solved half-width at the defect's axial position
    jy = int(np.argmin(np.abs(grid.y - yd)))
    col = pg[:, jy]
    half_width = float(np.max(np.abs(grid.x[col > 0])) + 0.5 * dxg) if np.any(col > 0) else 0.0
    # window: its axial edges coincide with global cell edges and dy_global = m dy_window, so the
    # global cells outside the window are exactly the far field (no overlap, no gap)
    j_lo = int(np.clip(np.floor((yd - hy - grid.y[0]) / dyg + 0.5), 0, grid.y.size - 1))
    j_hi = int(np.clip(np.floor((yd + hy - grid.y[0]) / dyg + 0.5), 0, grid.y.size - 1))
    m = max(1, int(math.ceil(dyg / dyw - 1e-9)))
    ny_w = (j_hi - j_lo + 1) * m
    y0 = grid.y[j_lo] - 0.5 * dyg
    win = Grid(xw, y0 + (np.arange(ny_w) + 0.5) * (dyg / m), dxw, dyg / m)
    hs = _halfspace(win, e_star, "auto", fid.element)
    u_ext = _far_field(grid, pg, win, j_lo, j_hi, m, e_star, fid.element)
    gwin = gap_field(scene, win, None)
    void = ~np.isfinite(gwin)
    u_ext[void] = 0.0
    if np.isnan(u_ext).any():
        raise RuntimeError("zoom window not inside the global grid")  # pragma: no cover
    p_in = _bilinear(grid.x, grid.y, pg, win.x, win.y)
    p_in[void] = 0.0
    g0 = gwin + u_ext
    # the window's no-defect solve carries the force the global solve put on the same cells;
    # its approach (not the coarse global one, which differs by the coarse grid's discretisation
    # error) then drives the defect solves under displacement control
    f_win = float(pg[:, j_lo:j_hi + 1].sum()) * dxg * dyg
    if f_win > 0:
        sol0 = stats.solve(g0, win.dx, win.dy, f_win, e_star, tol=fid.tol, max_iter=fid.max_iter,
                           p_init=p_in, boundary="ignore", halfspace=hs, element=fid.element,
                           hardness=scene.material.hardness_pa)
        approach0, pw0 = sol0.approach, sol0.pressure
    else:
        # the contact does not reach the defect's axial position at this load (e.g. a defect
        # near a roller end at a small load): nothing to zoom into
        approach0, pw0 = sol.approach, np.zeros(win.shape)
    rows = contact_rows(scene, g0, approach0) if f_win > 0 else None
    hs_rows = None if rows is None else \
        _halfspace(Grid(win.x[rows[0]:rows[1]], win.y, win.dx, win.dy), e_star, "auto", fid.element)
    far = None
    if with_far and fid.far_field == "responds" and f_win > 0:
        far = far_response(scene, fid, grid, pg, win, j_lo, j_hi, m, stats,
                           WindowState(g0, approach0, pw0, hs, win, rows, hs_rows))
    strip = np.abs(win.y - yd) <= hy_read + 1e-12
    gstrip = np.abs(grid.y - yd) <= hy_read + 1e-12
    outside = float(pg[:, ~gstrip].max()) if np.any(~gstrip) else 0.0
    w0 = float(pw0[:, strip].max())
    p0 = max(w0, outside)
    cons = abs(w0 - float(p_in[:, strip].max())) / p0
    return LoadNode(q_load, a, grid, pg.astype(np.float32), approach0, win, u_ext,
                    pw0, strip, outside, p0, w0, half_width, cons, hs,
                    approach_global=float(sol.approach), area_global=float(sol.contact_area),
                    area_window0=float(np.count_nonzero(pw0 > 0)) * win.dx * win.dy,
                    far=far, rows=rows, rows_halfspace=hs_rows)
