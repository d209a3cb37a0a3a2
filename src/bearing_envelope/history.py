"""Time history of the maximum contact pressure of one load x depth case.

Model only what the scene requires (issue 3, design.md section 2):

1. **Kinematics.** The inner ring (and the defect on it) turns at the shaft rate ``f_r``; the
   defect's angle from the load direction is ``theta_d = 2 pi f_r t``. The cage turns at ``f_c``;
   roller ``j`` sits at ``theta_c + 2 pi j / Z``. The defect meets a roller whenever the relative
   angle ``theta_d - theta_c`` crosses a multiple of ``2 pi / Z``, i.e. at ``Z (f_r - f_c) = BPFI``.
   The **BPFI override** (the study's 231.9 Hz against the geometric 194.2 Hz) is realised through
   the implied cage rate ``f_c = f_r - BPFI / Z`` (5.259 Hz instead of FTF = 6.973 Hz): event
   spacing is exactly ``1/BPFI`` and the load-zone modulation of the defect stays at ``f_r``.
   Both BPFI values are recorded. Arc-length offset of the defect from the nearest roller's
   contact centre: ``x = R_i wrap(theta_d - theta_c)`` with ``wrap`` into ``[-pi/Z, pi/Z)`` and
   ``R_i`` the raceway radius at the contact. With cage slip the cage rate is reduced by a seeded
   random fraction, piecewise constant over each BPFI period, uniform in ``[0, 2 s]`` (mean ``s``):
   roller passage times jitter.
2. **Roller load** at the defect: the load-zone law ``Q(psi)`` of :mod:`bearing_envelope.loads`
   evaluated at the defect's angle ``psi = theta_d``. (The roller centred on the defect has this
   load at the event; using the law at the defect angle, not at the nearest roller's, keeps the
   no-defect signal free of a spurious BPFI-rate step.)
3. **Table P(Q, x)** instead of a solve per sample (zoom route, design.md section 4): for each
   roller-load node a global no-defect solve over the whole roller length (coarse grid), then a
   fine local window around the defect spanning the whole contact width and a short axial
   stretch. The window's axial edges coincide with global cell edges; the displacement of the
   global pressure outside the window is computed exactly at the window's axial spacing (each
   coarse cell split into sub-cells of the same pressure) and interpolated linearly across
   rolling only. The window's no-defect solve carries the force the global solve put on the same
   cells; its approach then drives the defect solves under displacement control (the force the
   defect removes, ~0.1-1 % of Q, is recorded). Results are read only ``window_margin_um`` inside
   the window's axial edges. Symmetry ``P(Q, -x) = P(Q, x)``; each offset is warm-started from
   its neighbour (a stalled warm start is retried from the no-defect window solution, then cold).
   Offset nodes are multiples of the window spacing (every node sees the defect at the same
   sub-cell position). Interpolation (:class:`PressureTable`): ratios ``P/P0(Q)``, rows read at
   the offset scaled to each row's contact size ``s(Q) = kappa a_H(Q) + w_x/2 + r_n``, blended
   linearly in ``q = Q^(1/3)``; ``P0`` linear in ``q``. Beyond the last node the defect cannot
   touch the contact: ``P = P0(Q)`` and the neighbourhood carries no pressure. The interpolation
   error is measured against direct solves at random ``(Q, x)`` (x on the window grid: pure table
   error; x anywhere: plus the sub-cell discretisation jitter of an under-resolved rim) and stored.
4. **Signals** per sample: ``p_max`` (maximum over the whole contact) and ``p_max_defect``
   (maximum in the defect's neighbourhood: footprint grown by ``neighbourhood_um``), roller load
   and offset. Synthesis over all samples by a numba kernel (:func:`synthesize`) or numpy
   (:func:`synthesize_numpy`).
"""

from __future__ import annotations

import math
import time as _time
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from .fidelity import Fidelity, fidelity_from
from .geometry import Grid, gap_field, hertz_estimate, make_grid
from .loads import LoadDistribution, scene_load_distribution
from .scene import Scene

__all__ = ["SolveStats", "LoadNode", "PressureTable", "History", "build_table", "simulate",
           "synthesize", "synthesize_numpy", "kinematics", "direct_pressure", "Q_MIN_FRACTION",
           "OUTSIDE_LOAD_DENSITY", "GlobalGridError", "evaluate_signals", "acquire",
           "antialias_filter", "antialias_undershoot", "auto_oversample", "acquisition_settings",
           "synthesize_case",
           "CONTACT_SIGNALS", "STATE_SIGNALS", "SIGNAL_UNITS"]

#: Random offsets checked per random roller load (each kind: on the grid / anywhere).
CHECK_OFFSETS_PER_LOAD = 3

#: Smallest tabulated roller load, as a fraction of the largest; below it ``P0 ~ Q^(1/3)``.
Q_MIN_FRACTION = 0.05

#: Roller loads of the no-defect maximum outside the read strip (the roller-end peaks) per
#: interval of the table's load nodes: ``P_out`` grows faster than ``Q^(1/3)`` once the contact
#: reaches the end relief, so it gets global-only solves on a denser load grid. The nodes of
#: the table are every ``OUTSIDE_LOAD_DENSITY``-th point of that grid.
OUTSIDE_LOAD_DENSITY = 3

#: Refinement of the ``P_out(Q)`` grid (see :class:`PressureTable`): an interval is bisected
#: while its solved midpoint differs from the linear reading by more than this (relative) ...
OUTSIDE_REFINE_TOL = 0.002
#: ... at most this many times (the finest interval is 2^-depth of a base interval).
OUTSIDE_REFINE_DEPTH = 5


@dataclass
class SolveStats:
    """Counters of contact solves (for the benchmark and the case file)."""

    n_solves: int = 0
    n_iterations: int = 0
    solver_seconds: float = 0.0
    n_failed: int = 0
    failed_seconds: float = 0.0
    n_stall_guard: int = 0     # solves whose preconditioner the solver's stall guard dropped
    callback: Callable[[], None] | None = field(default=None, repr=False)

    def solve(self, *args, **kwargs):
        """:func:`solve_contact` with its cost counted, also when it raises (stalled solves
        that a caller retries are part of the cost: ``n_failed``, ``failed_seconds``)."""
        from .contact import ContactConvergenceError, solve_contact

        t0 = _time.perf_counter()
        try:
            sol = solve_contact(*args, **kwargs)
        except ContactConvergenceError as exc:
            dt = _time.perf_counter() - t0
            self.solver_seconds += dt
            self.failed_seconds += dt
            self.n_solves += 1
            self.n_failed += 1
            self.n_iterations += len(exc.residual_history)
            raise
        self.solver_seconds += _time.perf_counter() - t0
        self.n_solves += 1
        self.n_iterations += sol.iterations
        self.n_stall_guard += sol.preconditioner_dropped_at is not None
        if self.callback is not None:
            self.callback()
        return sol


# ---------------------------------------------------------------------------------------------
# one roller load: global no-defect solve and the zoom window


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


def _bilinear(xg: np.ndarray, yg: np.ndarray, f: np.ndarray, x: np.ndarray, y: np.ndarray,
              fill: float = 0.0) -> np.ndarray:
    from scipy.interpolate import RegularGridInterpolator

    it = RegularGridInterpolator((xg, yg), f, bounds_error=False, fill_value=fill)
    X, Y = np.meshgrid(x, y, indexing="ij")
    return it((X, Y))


def _halfspace(grid: Grid, e_star: float, backend: str, element: str = "uniform"):
    """Single-threaded half-space operator: the sweep runs one case per core, and threaded FFTs
    on a shared 2-core machine were measured 10-100x slower. ``auto`` (pyfftw if present) pays a
    planning cost once per grid and is worth it for the many window solves; the single global
    solve per load uses pocketfft (no planning)."""
    from .contact import ElasticHalfSpace

    return ElasticHalfSpace(grid.shape, grid.dx, grid.dy, e_star, workers=1, backend=backend,
                            element=element)


def _window_spec(scene: Scene, fid: Fidelity, q_load: float, kappa: float):
    d = scene.defect
    a = hertz_estimate(scene, q_load).a
    ex = d.extent_x_m if d.active else 0.0
    ey = d.extent_y_m if d.active else 0.0
    nb = 1e-6 * fid.neighbourhood_um
    s = kappa * a + 0.5 * ex + nb
    dx = 1e-6 * fid.local_dx_um
    if d.active:
        dx = min(dx, ex / 4.0)
    dy = 1e-6 * fid.local_dy_um
    if d.active:
        dy = min(dy, ey / 6.0)
    xh = max(fid.global_extent * kappa * a, fid.xi_max * s + 0.5 * ex + nb + 2 * dx)
    yd = 1e-3 * d.axial_position_mm
    hy_read = 0.5 * ey + nb
    hy = hy_read + 1e-6 * fid.window_margin_um
    return a, s, dx, dy, xh, yd, hy_read, hy


#: Growth factor of the global grid's half-extent across rolling when the contact reaches its
#: edge, and the number of sizes tried before :func:`_global_solve` gives up.
GLOBAL_GRID_GROWTH = 1.3
GLOBAL_GRID_ATTEMPTS = 4
#: Axial reach of the global grid beyond each roller end, in axial cells: just over one, so that
#: exactly one cell centre lies past each end (no material there: gap ``+inf``).
GLOBAL_END_CELLS = 1.01


class GlobalGridError(RuntimeError):
    """The global no-defect contact kept reaching the edge of its grid after every enlargement."""


def _global_solve(scene: Scene, fid: Fidelity, q_load: float, extent: float, stats: SolveStats,
                  p_init=None):
    """Global no-defect solve over the whole roller length (plus one ``+inf`` cell each side).

    The half-extent across rolling starts at ``extent`` (m) and grows by
    :data:`GLOBAL_GRID_GROWTH` whenever the pressure reaches the grid's edge
    (:class:`~bearing_envelope.contact.ContactGridError`), at most :data:`GLOBAL_GRID_ATTEMPTS`
    sizes. Returns ``(grid, solution)``; raises :class:`GlobalGridError` naming the load and the
    last extent.
    """
    from .contact import ContactGridError

    e_star = scene.material.e_star_pa
    dxg, dyg = 1e-6 * fid.global_dx_um, 1e-6 * fid.global_dy_um
    half = scene.bearing.half_length_m
    for _attempt in range(GLOBAL_GRID_ATTEMPTS):
        grid = make_grid(-extent, extent, -half - GLOBAL_END_CELLS * dyg, half + GLOBAL_END_CELLS * dyg,
                         dxg, dyg)
        try:
            sol = stats.solve(gap_field(scene, grid, None), dxg, dyg, q_load, e_star, tol=fid.tol,
                              max_iter=fid.max_iter, p_init=p_init, boundary="raise",
                              halfspace=_halfspace(grid, e_star, "scipy", fid.element),
                              element=fid.element, hardness=scene.material.hardness_pa)
            return grid, sol
        except ContactGridError:
            extent *= GLOBAL_GRID_GROWTH
    raise GlobalGridError(f"global grid could not be sized at roller load {q_load:.6g} N: the "
                          f"contact reached the edge of every grid up to a half-extent of "
                          f"{extent / GLOBAL_GRID_GROWTH:.4g} m across rolling")


def _solve_load(scene: Scene, fid: Fidelity, q_load: float, kappa: float, stats: SolveStats,
                p_init_global=None) -> LoadNode:
    e_star = scene.material.e_star_pa
    a, s, dxw, dyw, xh, yd, hy_read, hy = _window_spec(scene, fid, q_load, kappa)
    dxg, dyg = 1e-6 * fid.global_dx_um, 1e-6 * fid.global_dy_um
    xw = make_grid(-xh, xh, 0.0, 1.0, dxw, 1.0).x
    extent = max(fid.global_extent * kappa * a, float(np.max(np.abs(xw))) + dxg)
    grid, sol = _global_solve(scene, fid, q_load, extent, stats, p_init_global)
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
    # far field: the global pressure outside the window, each coarse cell split into m axial
    # sub-cells (the same load), convolved on the global x grid at the window's axial spacing,
    # so u_ext is exact in y at the window's columns and only interpolated (linearly) in x
    p_out = pg.astype(float).copy()
    p_out[:, j_lo:j_hi + 1] = 0.0
    if m > 1:
        p_out = np.repeat(p_out, m, axis=1)
    hs_f = _halfspace(Grid(grid.x, np.zeros(p_out.shape[1]), dxg, dyg / m), e_star, "scipy",
                      fid.element)
    u_cols = hs_f.displacement(p_out)[:, j_lo * m:(j_hi + 1) * m]
    u_ext = np.empty(win.shape)
    for k in range(win.shape[1]):
        u_ext[:, k] = np.interp(win.x, grid.x, u_cols[:, k], left=np.nan, right=np.nan)
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
    strip = np.abs(win.y - yd) <= hy_read + 1e-12
    gstrip = np.abs(grid.y - yd) <= hy_read + 1e-12
    outside = float(pg[:, ~gstrip].max()) if np.any(~gstrip) else 0.0
    w0 = float(pw0[:, strip].max())
    p0 = max(w0, outside)
    cons = abs(w0 - float(p_in[:, strip].max())) / p0
    return LoadNode(q_load, a, grid, pg.astype(np.float32), approach0, win, u_ext,
                    pw0, strip, outside, p0, w0, half_width, cons, hs,
                    approach_global=float(sol.approach), area_global=float(sol.contact_area),
                    area_window0=float(np.count_nonzero(pw0 > 0)) * win.dx * win.dy)


def _outside_max(scene: Scene, fid: Fidelity, q_load: float, kappa: float,
                 stats: SolveStats) -> float:
    """Maximum no-defect pressure outside the read strip from a global solve only (Pa)."""
    a, s, dxw, dyw, xh, yd, hy_read, hy = _window_spec(scene, fid, q_load, kappa)
    extent = max(fid.global_extent * kappa * a, xh + 1e-6 * fid.global_dx_um)
    grid, sol = _global_solve(scene, fid, q_load, extent, stats)
    gstrip = np.abs(grid.y - yd) <= hy_read + 1e-12
    return float(sol.pressure[:, ~gstrip].max()) if np.any(~gstrip) else 0.0


#: Iteration budget of a warm-started window solve before it is retried from the no-defect
#: window solution (then cold) with the full ``fidelity.max_iter``.
WARM_START_MAX_ITER = 300


@dataclass
class DefectSolve:
    """One window solve with the defect, at the no-defect window approach (internal).

    ``P`` / ``Pd``: maximum pressure of the whole contact / in the defect neighbourhood (Pa);
    ``pressure``: the window field (Pa); ``removed_force``: window force without the defect
    minus with it, at the same approach (N, > 0 when the defect unloads the contact);
    ``area_change``: window contact area with minus without the defect (m^2, <= 0); ``W``:
    maximum in the window's read strip (Pa; with rim strips, read from them where they are).
    """

    P: float
    Pd: float
    pressure: np.ndarray
    removed_force: float
    area_change: float
    W: float = 0.0


def _defect_solve(scene: Scene, fid: Fidelity, node: LoadNode, x_d: float, stats: SolveStats,
                  p_init=None) -> DefectSolve:
    """Window solve with the defect at offset ``x_d`` under the no-defect window approach."""
    from .contact import ContactConvergenceError

    win = node.window
    g = gap_field(scene, win, x_d) + node.u_ext
    kw = dict(tol=fid.tol, max_iter=fid.max_iter, approach=node.approach, boundary="ignore",
              halfspace=node.halfspace, element=fid.element, hardness=scene.material.hardness_pa)
    e_star = scene.material.e_star_pa
    try:
        # A warm start that converges does so in tens of iterations; one that stalls would use
        # all of max_iter (measured: 4 stalled solves took 73 % of a fine case's solver time),
        # so the warm attempt gets a short budget before the retries below.
        warm = dict(kw, max_iter=min(fid.max_iter, WARM_START_MAX_ITER))
        sol = stats.solve(g, win.dx, win.dy, None, e_star,
                          p_init=node.p_window0 if p_init is None else p_init, **warm)
    except ContactConvergenceError:
        # a warm start from a neighbour with another contact set can stall Polonsky-Keer:
        # retry from the no-defect window solution, then cold
        try:
            sol = stats.solve(g, win.dx, win.dy, None, e_star, p_init=node.p_window0, **kw)
        except ContactConvergenceError:
            sol = stats.solve(g, win.dx, win.dy, None, e_star, p_init=None, **kw)
    p = sol.pressure
    cell = win.dx * win.dy
    strips = []
    if fid.rim_dx_um:
        strips, p = _rim_schwarz(scene, fid, node, x_d, g, p, stats)
    if not strips:
        W = float(p[:, node.strip].max())
        Pd = _neighbourhood_max(scene, fid, win, p, x_d)
        dF = float(node.p_window0.sum() - p.sum()) * cell
        dA = float(np.count_nonzero(p > 0)) * cell - node.area_window0
        return DefectSolve(max(W, node.outside_max), Pd, p, dF, dA, W)
    # parent cells replaced by a strip count through the strip's force and area; the parent is
    # read for peaks except in the strips' read zones, where the strips are read
    replaced = np.zeros(win.shape[0], bool)
    unread = np.zeros(win.shape[0], bool)
    force, area = 0.0, 0.0
    W, Pd = 0.0, 0.0
    for st in strips:
        replaced[st.i0:st.i1] = True
        unread |= st.parent_read_mask
        cc = st.grid.dx * st.grid.dy
        force += float(st.pressure.sum()) * cc
        area += float(np.count_nonzero(st.pressure > 0)) * cc
        pr = st.pressure[st.read]
        W = max(W, float(pr[:, node.strip].max()) if pr.size else 0.0)
        Pd = max(Pd, _neighbourhood_max(scene, fid, Grid(st.grid.x[st.read], st.grid.y, st.grid.dx,
                                                          st.grid.dy), pr, x_d))
    pp = np.where(unread[:, None], 0.0, p)
    W = max(W, float(pp[:, node.strip].max()))
    Pd = max(Pd, _neighbourhood_max(scene, fid, win, pp, x_d))
    force += float(p[~replaced].sum()) * cell
    area += float(np.count_nonzero(p[~replaced] > 0)) * cell
    dF = float(node.p_window0.sum()) * cell - force
    dA = area - node.area_window0
    return DefectSolve(max(W, node.outside_max), Pd, p, dF, dA, W)


@dataclass
class RimStrip:
    """One refined strip around a defect rim (internal): parent window rows ``i0:i1`` solved
    again on ``grid`` (``m`` sub-cells per parent cell across rolling, same axial cells).
    ``read``: the strip's rows read for results (bool over ``grid.x``); ``parent_read_mask``:
    the parent rows those cover (bool over the window's x)."""

    i0: int
    i1: int
    grid: Grid
    pressure: np.ndarray
    read: np.ndarray
    parent_read_mask: np.ndarray


#: Rim strips and window are solved alternately (block Gauss-Seidel on the two sets of cells,
#: each under the other's displacement) until the window force changes by less than this
#: (relative) between passes ...
RIM_SCHWARZ_TOL = 1e-4
#: ... or this many passes.
RIM_SCHWARZ_MAX = 8


def _rim_schwarz(scene: Scene, fid: Fidelity, node: LoadNode, x_d: float, g: np.ndarray,
                 p: np.ndarray, stats: SolveStats) -> tuple[list[RimStrip], np.ndarray]:
    """Alternate the rim strips (:func:`_refine_rims`) and the window without the strips' rows
    (their pressure, averaged over each parent cell, imposed as a displacement) until the
    window's force settles (:data:`RIM_SCHWARZ_TOL`). A single pass over-estimates the force:
    the strips' resolved rim pressure would not unload the cells around them (measured: the
    removed force 1 % low after one pass at 500 kN / 50 um). Returns the strips and the window
    pressure (the strips' rows hold their parent-cell means)."""
    from .contact import ContactConvergenceError

    win = node.window
    cell = win.dx * win.dy
    m = int(round(fid.local_dx_um / fid.rim_dx_um))
    e_star = scene.material.e_star_pa
    f_old = float(p.sum()) * cell
    strips: list[RimStrip] = []
    for _pass in range(RIM_SCHWARZ_MAX):
        strips = _refine_rims(scene, fid, node, x_d, p, stats)
        if not strips:
            return strips, p
        p_s = np.zeros_like(p)
        rows = np.zeros(win.shape[0], bool)
        for st in strips:
            p_s[st.i0:st.i1] = st.pressure.reshape(st.i1 - st.i0, m, -1).mean(axis=1)
            rows[st.i0:st.i1] = True
        g2 = g + node.halfspace.displacement(p_s)
        g2[rows] = np.inf
        kw = dict(tol=fid.tol, max_iter=fid.max_iter, approach=node.approach, boundary="ignore",
                  halfspace=node.halfspace, element=fid.element,
                  hardness=scene.material.hardness_pa)
        p_w = np.where(rows[:, None], 0.0, p)
        try:
            sol = stats.solve(g2, win.dx, win.dy, None, e_star, p_init=p_w, **kw)
        except ContactConvergenceError:
            sol = stats.solve(g2, win.dx, win.dy, None, e_star, p_init=None, **kw)
        p = np.where(rows[:, None], p_s, sol.pressure)
        f_new = float(p.sum()) * cell
        if abs(f_new - f_old) <= RIM_SCHWARZ_TOL * max(f_new, 1e-300):
            break
        f_old = f_new
    return strips, p


def _rim_intervals(scene: Scene, fid: Fidelity, win: Grid, x_d: float) -> list[tuple[int, int]]:
    """Parent-row ranges ``[i0, i1)`` of the strips: each rim zone across rolling (the edge
    radius inside the footprint boundary, ``x_d +- w_x/2``) grown by ``rim_strip_um`` on each
    side, widened to whole parent cells; overlapping strips merge."""
    d = scene.defect
    hx = 0.5 * d.extent_x_m
    r = min(1e-6 * d.edge_radius_um, hx) if d.shape == "flat" else hx
    b = 1e-6 * fid.rim_strip_um
    x_lo_edge = win.x[0] - 0.5 * win.dx
    out = []
    for lo, hi in ((x_d - hx - b, x_d - hx + r + b), (x_d + hx - r - b, x_d + hx + b)):
        i0 = int(np.clip(math.floor((lo - x_lo_edge) / win.dx + 1e-9), 0, win.shape[0]))
        i1 = int(np.clip(math.ceil((hi - x_lo_edge) / win.dx - 1e-9), 0, win.shape[0]))
        if i1 > i0:
            if out and i0 <= out[-1][1]:
                out[-1] = (out[-1][0], max(out[-1][1], i1))
            else:
                out.append((i0, i1))
    return out


def _refine_rims(scene: Scene, fid: Fidelity, node: LoadNode, x_d: float, p: np.ndarray,
                 stats: SolveStats) -> list[RimStrip]:
    """Solve the strips around the defect's rims at ``fid.rim_dx_um`` under the window's
    displacement.

    Each strip covers whole parent rows ``i0:i1``, split into ``m = local_dx / rim_dx`` rows,
    with the window's axial cells. The displacement of everything outside the strip is exact
    at the strip's cells: the window pressure outside the strip, each parent cell split into
    ``m`` sub-cells carrying the same pressure (a uniform patch is the sum of its parts),
    convolved at the strip's spacing, plus the window's far field ``u_ext`` (interpolated
    linearly across rolling, as the window does with the global solve). The strip is solved
    under displacement control at the window's approach (one pass: the other strip, if any,
    stays at the parent's pressure). Strips without contact are skipped.
    """
    from .contact import ContactConvergenceError

    win = node.window
    m = int(round(fid.local_dx_um / fid.rim_dx_um))
    dxc = win.dx / m
    e_star = scene.material.e_star_pa
    b = 1e-6 * fid.rim_strip_um
    fine_hs = _halfspace(Grid(np.zeros(win.shape[0] * m), win.y, dxc, win.dy), e_star, "scipy")
    out = []
    for i0, i1 in _rim_intervals(scene, fid, win, x_d):
        if not np.any(p[i0:i1] > 0):
            continue
        p_out = p.copy()
        p_out[i0:i1] = 0.0
        u_near = fine_hs.displacement(np.repeat(p_out, m, axis=0))[i0 * m:i1 * m]
        xc = win.x[i0] - 0.5 * win.dx + (np.arange((i1 - i0) * m) + 0.5) * dxc
        grid = Grid(xc, win.y, dxc, win.dy)
        u_far = np.empty(grid.shape)
        for k in range(win.shape[1]):
            u_far[:, k] = np.interp(xc, win.x, node.u_ext[:, k])
        g = gap_field(scene, grid, x_d)
        void = ~np.isfinite(g)
        u = u_near + u_far
        u[void] = 0.0
        hs = _halfspace(grid, e_star, "auto")
        kw = dict(tol=fid.tol, max_iter=fid.max_iter, approach=node.approach, boundary="ignore",
                  halfspace=hs, hardness=scene.material.hardness_pa)
        try:
            sol = stats.solve(g + u, dxc, win.dy, None, e_star,
                              p_init=np.repeat(p[i0:i1], m, axis=0), **kw)
        except ContactConvergenceError:
            sol = stats.solve(g + u, dxc, win.dy, None, e_star, p_init=None, **kw)
        # read only half the margin away from the strip's ends (where the nested boundary is)
        lo, hi = xc[0] - 0.5 * dxc + 0.5 * b, xc[-1] + 0.5 * dxc - 0.5 * b
        read = (xc >= lo) & (xc <= hi)
        pread = (win.x - 0.5 * win.dx >= lo - 1e-12) & (win.x + 0.5 * win.dx <= hi + 1e-12)
        # parent rows not fully inside the read zone stay read from the parent
        read_c = np.repeat(pread[i0:i1], m) & read
        out.append(RimStrip(i0, i1, grid, sol.pressure, read_c, pread))
    return out


def _neighbourhood_max(scene: Scene, fid: Fidelity, win: Grid, p: np.ndarray, x_d: float) -> float:
    d = scene.defect
    nb = 1e-6 * fid.neighbourhood_um
    ex = d.extent_x_m if d.active else 0.0
    ey = d.extent_y_m if d.active else 0.0
    yd = 1e-3 * d.axial_position_mm
    mx = np.abs(win.x - x_d) <= 0.5 * ex + nb + 1e-12
    my = np.abs(win.y - yd) <= 0.5 * ey + nb + 1e-12
    if not mx.any() or not my.any():
        return 0.0
    return float(p[np.ix_(mx, my)].max())


# ---------------------------------------------------------------------------------------------
# the table


@dataclass
class PressureTable:
    """Tabulated ``P(Q, x)`` and ``P_d(Q, x)`` with their interpolation rule.

    Nodes: roller loads ``q_nodes`` uniform in ``Q^(1/3)``; offsets ``x_nodes = xi_nodes * s_max``
    (absolute, multiples of the window spacing, shared by all loads). Interpolation of the
    ratios ``P/P0`` and ``P_d/P0``: at a load ``Q`` between rows ``i`` and ``i+1``, each row is read
    (linearly in ``x``) at the offset with the same distance to that row's contact edge,
    ``x_i = max(|x| + kappa (a_H(Q_i) - a_H(Q)), 0)``, and the two values are blended linearly in
    ``q = Q^(1/3)``: the defect's rims cross each row's contact edge at the same reading, which
    is where the ratios change fastest (the earlier reading ``x_i = x s(Q_i)/s(Q)``, with
    ``s(Q) = kappa a_H(Q) + w_x/2 + r_n``, put the edge at different fractions of ``s`` per row:
    8.7 % max error against direct solves over a revolution at 500 kN / 50 um, 4.6 % with this
    reading; docs/benchmarks.md). Below the first node the row is read at ``x s(Q_0)/s(Q)``.
    ``P0`` is linear in ``q`` (exact for Hertz) and goes to 0 with ``q`` below the first node.
    Beyond the last node ``P = P0`` and ``P_d = 0`` exactly.

    Attributes
    ----------
    q_nodes : ndarray (nq,)
        Roller loads of the nodes (N).
    xi_nodes : ndarray (nx,)
        Offsets of the nodes divided by ``s_max``.
    p0 : ndarray (nq,)
        No-defect maximum pressure ``P0(Q)`` of the whole contact at the nodes (Pa).
    w0 : ndarray (nq,)
        No-defect maximum pressure in the window's read strip ``W0(Q)`` (Pa).
    ratio, ratio_defect : ndarray (nq, nx)
        ``W / W0`` (maximum in the read strip, around the defect) and ``P_d / W0`` (defect
        neighbourhood).
    q_out, p_out : ndarray (nout,)
        Dense roller loads (N, increasing; global solves only) and the maximum no-defect
        pressure outside the read strip there (Pa): the roller-end peaks, which grow faster
        than ``Q^(1/3)`` once the contact reaches the end relief. ``P = max(W, P_out)``, linear
        in ``q`` between the points. A base grid uniform in ``Q^(1/3)`` (``out_density`` points
        per node interval) refined by bisection where the linear reading misses a solve by more
        than :data:`OUTSIDE_REFINE_TOL` (the onset of the end peak, and its steps as the contact
        crosses a global cell).
    a_coef : float
        Hertz semi-axis per ``Q^(1/3)`` (m N^-1/3).
    kappa : float
        Solved/Hertz half-width ratio used in ``s(Q)``.
    s_const : float
        ``w_x/2 + r_n`` (m).
    s_max : float
        ``s`` at the largest load (m).
    out_density : int
        Points of the base grid of ``q_out`` per interval of ``q_nodes`` (the nodes are among
        ``q_out``).
    ratio_force : ndarray (nq, nx)
        Force the defect removes from the contact at the no-defect approach, divided by the
        node's roller load ``Q`` (window solves under displacement control).
    ratio_area : ndarray (nq, nx)
        Change of the contact area with the defect (window, same approach), divided by the
        node's no-defect area ``A0(Q)`` (``<= 0``).
    approach0, area0 : ndarray (nq,)
        No-defect approach ``delta0(Q)`` (m) and contact area ``A0(Q)`` (m^2) of the global
        solves. Interpolated as ``c(q) q^2`` with ``c`` linear in ``q = Q^(1/3)`` (exact for
        Hertz, where both grow as ``Q^(2/3)``), ``c`` held constant outside the nodes.
    info : dict
        Diagnostics (interpolation errors, zoom consistency, grids, ...).
    p_cap : float or None
        The hardness bound of the solves (Pa, ``scene.material.hardness_pa``) or None: every
        solved pressure is <= it, but a product of linear readings (``P0 x ratio``) between
        nodes can exceed it (0.37 % measured at 750 kN / 50 um, draft), so ``P`` and ``P_d``
        are clipped to it.
    """

    q_nodes: np.ndarray
    xi_nodes: np.ndarray
    p0: np.ndarray
    w0: np.ndarray
    ratio: np.ndarray
    ratio_defect: np.ndarray
    a_coef: float
    kappa: float
    s_const: float
    s_max: float
    q_out: np.ndarray
    p_out: np.ndarray
    out_density: int = OUTSIDE_LOAD_DENSITY
    ratio_force: np.ndarray | None = None
    ratio_area: np.ndarray | None = None
    approach0: np.ndarray | None = None
    area0: np.ndarray | None = None
    info: dict = field(default_factory=dict)
    p_cap: float | None = None

    def __post_init__(self):
        shape = (self.q_nodes.size, self.xi_nodes.size)
        if self.ratio_force is None:
            self.ratio_force = np.zeros(shape)
        if self.ratio_area is None:
            self.ratio_area = np.zeros(shape)
        if self.q_out.size < self.out_density * (self.q_nodes.size - 1) + 1:
            raise ValueError(f"q_out has {self.q_out.size} loads; expected at least out_density x "
                             f"(n_loads - 1) + 1 = {self.out_density * (self.q_nodes.size - 1) + 1}")
        if self.q_out.size != self.p_out.size or np.any(np.diff(self.q_out) <= 0):
            raise ValueError("q_out must be increasing and match p_out in size")

    @property
    def p_out_nodes(self) -> np.ndarray:
        """``P_out`` at the table's load nodes (Pa)."""
        return np.interp(np.cbrt(self.q_nodes), np.cbrt(self.q_out), self.p_out)

    def p_max_nodes(self) -> np.ndarray:
        """``P(Q_i, x_j) = max(W0 R, P_out)`` at the nodes (Pa), shape (nq, nx)."""
        return np.maximum(self.w0[:, None] * self.ratio, self.p_out_nodes[:, None])

    def _q2_rule(self, v, Q):
        qn = np.cbrt(self.q_nodes)
        q = np.cbrt(np.clip(Q, 0.0, None))
        return np.interp(q, qn, v / qn ** 2) * q ** 2

    def approach_no_defect(self, Q) -> np.ndarray:
        """No-defect approach ``delta0(Q)`` (m) at roller loads ``Q`` (N)."""
        if self.approach0 is None:
            raise ValueError("this table has no approach0 (no-defect approach per load node)")
        return self._q2_rule(self.approach0, Q)

    def area_no_defect(self, Q) -> np.ndarray:
        """No-defect contact area ``A0(Q)`` (m^2) at roller loads ``Q`` (N)."""
        if self.area0 is None:
            raise ValueError("this table has no area0 (no-defect contact area per load node)")
        return self._q2_rule(self.area0, Q)

    def evaluate_integrals(self, Q, x, *, use_numba: bool = True) -> dict[str, np.ndarray]:
        """Integral signals at roller loads ``Q`` (N) and defect offsets ``x`` (m).

        Returns
        -------
        dict
            ``removed_force`` ``dF`` (N): the force the defect removes from the contact at the
            no-defect approach; ``contact_force`` ``Q - dF`` (N): the force through the contact
            at fixed approach (blocked-force excitation); ``approach`` ``delta`` (m): the
            approach at the fixed roller load ``Q``, ``delta0(Q + dF)`` (the defect's lost
            stiffness taken up by the no-defect load-approach curve, first order in
            ``dF / Q``); ``approach_change`` ``delta - delta0(Q)`` (m, >= 0); ``contact_area``
            (m^2): ``A0(Q + dF) + dA`` with ``dA`` the window's area change at fixed approach.
        """
        Q = np.asarray(Q, dtype=float)
        x = np.asarray(x, dtype=float)
        rf = _ratio_eval(self, self.ratio_force, Q, x, use_numba)
        ra = _ratio_eval(self, self.ratio_area, Q, x, use_numba)
        dF = Q * rf
        d0 = self.approach_no_defect(Q)
        d = self.approach_no_defect(Q + dF)
        area = self.area_no_defect(Q + dF) + ra * self.area_no_defect(Q)
        return {"removed_force": dF, "contact_force": Q - dF, "approach": d,
                "approach_change": d - d0, "contact_area": area}

    def scale(self, Q):
        """``s(Q) = kappa a_coef Q^(1/3) + s_const`` (m)."""
        return self.kappa * self.a_coef * np.cbrt(Q) + self.s_const

    def offsets(self) -> np.ndarray:
        """Offsets of the nodes (m)."""
        return self.xi_nodes * self.s_max

    def args(self):
        """Arrays and scalars of the interpolation (for the kernels)."""
        return (np.ascontiguousarray(np.cbrt(self.q_nodes)), np.ascontiguousarray(self.offsets()),
                np.ascontiguousarray(self.w0), np.ascontiguousarray(self.ratio),
                np.ascontiguousarray(self.ratio_defect), self.kappa * self.a_coef, self.s_const,
                np.ascontiguousarray(np.cbrt(self.q_out)), np.ascontiguousarray(self.p_out))

    def evaluate(self, Q, x):
        """Interpolated ``(P, P_d)`` (Pa) at roller loads ``Q`` (N) and offsets ``x`` (m)."""
        Q = np.asarray(Q, dtype=float)
        x = np.asarray(x, dtype=float)
        P, Pd = _table_eval_numpy(Q, x, *self.args())
        if self.p_cap is not None:
            P, Pd = np.minimum(P, self.p_cap), np.minimum(Pd, self.p_cap)
        return P, Pd


def _ratio_eval(table: "PressureTable", T: np.ndarray, Q, x, use_numba: bool = True) -> np.ndarray:
    """A ratio table (fill 0 beyond the last offset) read like ``P_d/W0`` (no ``P0`` factor)."""
    qn, xn, _, _, _, ka, s0, _, _ = table.args()
    T = np.ascontiguousarray(T, dtype=float)
    if use_numba and HAVE_NUMBA:
        out = np.empty(Q.size)
        _ratio_kernel(np.ascontiguousarray(Q.ravel()), np.ascontiguousarray(x.ravel()), qn, xn,
                      ka, s0, T, out)
        return out.reshape(Q.shape)
    q = np.cbrt(np.clip(Q, 0.0, None))
    nq, nx = T.shape
    qc = np.clip(q, qn[0], qn[-1])
    i = np.clip(np.searchsorted(qn, qc, side="right") - 1, 0, nq - 2)
    tq = (qc - qn[i]) / (qn[i + 1] - qn[i])

    def row(ii):
        xr = _row_offset(x, q, qn, ii, ka, s0)
        j = np.clip(np.searchsorted(xn, xr, side="right") - 1, 0, nx - 2)
        tx = np.clip((xr - xn[j]) / (xn[j + 1] - xn[j]), 0.0, 1.0)
        v = (1 - tx) * T[ii, j] + tx * T[ii, j + 1]
        return np.where(xr >= xn[-1], 0.0, v)

    return (1 - tq) * row(i) + tq * row(i + 1)


def _row_offset(x, q, qn, ii, ka, s0):
    """Offset at which row ``ii`` is read for offset ``x`` at ``q = Q^(1/3)``: the same distance
    to the row's contact edge ``ka q_i`` (``ka = kappa a_coef``); below the first node, scaled
    by ``s(Q_0)/s(Q)``."""
    ax = np.abs(x)
    qi = qn[ii]
    return np.where(q >= qn[0], np.maximum(ax + ka * (qi - q), 0.0), ax * (ka * qi + s0) / (ka * q + s0))


def _table_eval_numpy(Q, x, qn, xn, p0, R, Rd, ka, s0, qo, po):
    q = np.cbrt(np.clip(Q, 0.0, None))
    nq, nx = R.shape
    qc = np.clip(q, qn[0], qn[-1])
    i = np.clip(np.searchsorted(qn, qc, side="right") - 1, 0, nq - 2)
    tq = (qc - qn[i]) / (qn[i + 1] - qn[i])
    p0q = np.where(q < qn[0], p0[0] * q / qn[0], p0[i] * (1 - tq) + p0[i + 1] * tq)
    pout = np.where(q < qo[0], po[0] * q / qo[0], np.interp(q, qo, po))

    def row(T, ii, fill):
        xr = _row_offset(x, q, qn, ii, ka, s0)
        j = np.clip(np.searchsorted(xn, xr, side="right") - 1, 0, nx - 2)
        tx = np.clip((xr - xn[j]) / (xn[j + 1] - xn[j]), 0.0, 1.0)
        v = (1 - tx) * T[ii, j] + tx * T[ii, j + 1]
        return np.where(xr >= xn[-1], fill, v)

    r = (1 - tq) * row(R, i, 1.0) + tq * row(R, i + 1, 1.0)
    rd = (1 - tq) * row(Rd, i, 0.0) + tq * row(Rd, i + 1, 0.0)
    return np.maximum(p0q * r, pout), p0q * rd


#: Reach of the contact across rolling guessed before any solve, as a multiple of the Hertz
#: semi-axis at the largest load: sizes the offset grid only for the progress bar's count (the
#: solved half-width, with roller-end truncation, fixes the real grid through ``kappa``).
REACH_GUESS_FACTOR = 1.1
#: Margin on the solved-to-Hertz half-width ratio ``kappa``: the offset reach ``s(Q)`` and the
#: window cover the solved contact with 2 % to spare.
KAPPA_MARGIN = 1.02
#: Largest normalised offset ``x / s(Q)`` of the pressure-field snapshots (0 = centred defect).
SNAPSHOT_XI_MAX = 0.8


def _table_loads(q_max: float, n_loads: int) -> tuple[np.ndarray, np.ndarray]:
    """Roller-load nodes, uniform in ``q = Q^(1/3)`` from ``Q_MIN_FRACTION q_max`` to ``q_max``:
    returns ``(q, Q)``."""
    qn = np.linspace((Q_MIN_FRACTION * q_max) ** (1 / 3), q_max ** (1 / 3), n_loads)
    return qn, qn ** 3


def _offset_nodes(scene: Scene, fid: Fidelity, s_reach: float, dxw: float) -> np.ndarray:
    """Defect offsets of the table (m): multiples of the window spacing ``dxw`` from 0 to
    ``xi_max s_reach``, at least ``n_offsets`` of them and, with a defect, at most
    ``min(width / offsets_per_width, offset_step_um)`` apart (capped at ``max_offsets``).

    Every node sees the defect at the same sub-cell position: the peak over cells jitters by up
    to ~10 % with the sub-cell position of an under-resolved rim; that part is measured
    separately by the off-grid interpolation checks.
    """
    d = scene.defect
    n = fid.n_offsets
    if d.active:
        step_max = min(d.extent_x_m / fid.offsets_per_width, 1e-6 * fid.offset_step_um)
        n = max(n, int(math.ceil(fid.xi_max * s_reach / step_max)) + 1)
        n = min(n, fid.max_offsets)
    step = max(1, int(math.ceil(fid.xi_max * s_reach / (n - 1) / dxw - 1e-9))) * dxw
    n = int(math.ceil(fid.xi_max * s_reach / step - 1e-9)) + 1
    return step * np.arange(n)


def _progress(stats: SolveStats, total: int, progress: bool | None):
    """A tqdm bar over ``total`` solves fed by ``stats`` (None when ``progress`` is None)."""
    if progress is None:
        return None
    try:
        import sys

        from tqdm.auto import tqdm
    except ImportError:  # pragma: no cover
        return None
    bar = tqdm(total=total, desc="contact solves", unit="solve",
               disable=not (progress and sys.stderr.isatty()))
    stats.callback = bar.update
    return bar


def _solve_load_nodes(scene: Scene, fid: Fidelity, q_nodes: np.ndarray,
                      stats: SolveStats) -> tuple[list[LoadNode], float]:
    """No-defect solves at every load node, largest first (each widens ``kappa`` for the next):
    returns the nodes in ascending load and ``kappa`` over all of them."""
    kappa = 1.0
    nodes = []
    for q in q_nodes[::-1]:
        node = _solve_load(scene, fid, float(q), kappa, stats)
        nodes.append(node)
        kappa = max(kappa, KAPPA_MARGIN * node.half_width / node.a_hertz)
    nodes = nodes[::-1]
    kappa = max([1.0] + [KAPPA_MARGIN * nd.half_width / nd.a_hertz for nd in nodes])
    return nodes, kappa


@dataclass
class _DefectRatios:
    """Stage result of :func:`_defect_ratios` (arrays (n_loads, n_offsets), see PressureTable)."""

    ratio: np.ndarray
    ratio_defect: np.ndarray
    ratio_force: np.ndarray
    ratio_area: np.ndarray
    removed_force_max: float
    snapshots: dict


def _defect_ratios(scene: Scene, fid: Fidelity, nodes: list[LoadNode], q_nodes: np.ndarray,
                   x_nodes: np.ndarray, s_of_q: Callable[[float], float], stats: SolveStats,
                   tick: Callable[[], Any]) -> _DefectRatios:
    """The window solves with the defect at every (load node, offset) and the snapshots.

    Offsets beyond ``xi_max s(Q)`` (the defect cannot touch the contact) keep the no-defect
    ratios (1, 0, 0, 0); each load's offsets run from the farthest inwards, each solve warm
    started from the previous one.
    """
    d = scene.defect
    nq, nxi = len(nodes), x_nodes.size
    R = np.ones((nq, nxi))
    Rd = np.zeros((nq, nxi))
    RF = np.zeros((nq, nxi))     # removed force / Q at fixed approach
    RA = np.zeros((nq, nxi))     # window contact-area change / global area A0(Q)
    dF_max = 0.0
    snapshots: dict[str, Any] = {}
    snap_xi = np.linspace(0.0, SNAPSHOT_XI_MAX, fid.n_snapshot_offsets) \
        if fid.n_snapshot_offsets else []
    for i, nd in enumerate(nodes):
        s_i = s_of_q(q_nodes[i])
        reach = fid.xi_max * s_i          # beyond: the defect cannot touch the contact
        snap: dict[str, Any] = {
            "roller_load": q_nodes[i], "global_x": nd.grid.x, "global_y": nd.grid.y,
            "global_pressure": nd.pressure, "window_x": nd.window.x, "window_y": nd.window.y,
        }
        if not d.active:
            for j, xj in enumerate(x_nodes):
                if nd.w0 > 0:
                    Rd[i, j] = _neighbourhood_max(scene, fid, nd.window, nd.p_window0, xj) / nd.w0
            snap["offsets"] = np.asarray(snap_xi) * s_i
            snap["window_pressure"] = np.repeat(nd.p_window0[None].astype(np.float32),
                                                len(snap_xi), axis=0)
        else:
            p_prev = None
            for j in range(nxi - 1, -1, -1):
                if x_nodes[j] > reach or nd.w0 <= 0:
                    tick()
                    continue
                ds = _defect_solve(scene, fid, nd, x_nodes[j], stats, p_prev)
                p_prev = ds.pressure
                R[i, j] = ds.W / nd.w0
                Rd[i, j] = ds.Pd / nd.w0
                RF[i, j] = ds.removed_force / nd.q
                RA[i, j] = ds.area_change / nd.area_global
                dF_max = max(dF_max, abs(ds.removed_force) / nd.q)
            fields = [_defect_solve(scene, fid, nd, xi * s_i, stats).pressure.astype(np.float32)
                      for xi in snap_xi]
            snap["offsets"] = np.asarray(snap_xi) * s_i
            snap["window_pressure"] = np.array(fields) if fields else \
                np.zeros((0,) + nd.window.shape, np.float32)
        snapshots[f"load_{i}"] = snap
    return _DefectRatios(R, Rd, RF, RA, dF_max, snapshots)


def _outside_maxima(scene: Scene, fid: Fidelity, nodes: list[LoadNode], qn: np.ndarray,
                    kappa: float, stats: SolveStats) -> tuple[np.ndarray, np.ndarray]:
    """The no-defect maximum outside the read strip (roller ends) on a load grid
    :data:`OUTSIDE_LOAD_DENSITY` times denser than the nodes (global solves only; the nodes'
    own values are reused), refined by bisection where it bends (:func:`_refine_outside`).
    Returns ``(q_out, p_out)``, ``q_out`` in N."""
    m_out = OUTSIDE_LOAD_DENSITY
    nout = m_out * (qn.size - 1) + 1
    q_base = np.linspace(qn[0], qn[-1], nout)
    p_base = np.empty(nout)
    for k, qo in enumerate(q_base):
        if k % m_out == 0:
            p_base[k] = nodes[k // m_out].outside_max
        else:
            p_base[k] = _outside_max(scene, fid, float(qo ** 3), kappa, stats)
    q_out, p_out = _refine_outside(scene, fid, kappa, stats, q_base, p_base)
    return q_out ** 3, p_out


def _check_errors(rows) -> tuple[np.ndarray, float, float, float]:
    """``(rows as (n, 7) array, max rel. error of P, max error of P_d / P0, rms rel. error of P)``
    of interpolation checks ``(Q, x, P, P_d, P_interp, P_d_interp, P0)``."""
    a = np.array(rows, dtype=float).reshape(-1, 7)
    if not len(a):
        return a, 0.0, 0.0, 0.0
    e = np.abs(a[:, 4] - a[:, 2]) / a[:, 2]
    return (a, float(e.max()), float(np.max(np.abs(a[:, 5] - a[:, 3]) / a[:, 6])),
            float(np.sqrt(np.mean(e ** 2))))


def _interpolation_checks(scene: Scene, fid: Fidelity, table: "PressureTable", qn: np.ndarray,
                          dxw: float, stats: SolveStats, seed: int) -> dict[str, Any]:
    """The table's interpolation error against direct solves at ``n_checks`` random loads, at
    :data:`CHECK_OFFSETS_PER_LOAD` offsets each on the window grid (pure table error) and as
    many anywhere (adds the sub-cell discretisation jitter). Returns the ``info`` entries."""
    from .contact import ContactConvergenceError

    checks, checks_any, checks_any_failed = [], [], []
    if scene.defect.active and fid.n_checks:
        rng = np.random.default_rng(seed)
        ex = scene.defect.extent_x_m
        for _ in range(fid.n_checks):
            qc = float(rng.uniform(qn[0], qn[-1]) ** 3)
            # offsets where the defect overlaps the contact (beyond, the table is exact)
            reach = table.kappa * table.a_coef * qc ** (1 / 3) + 0.5 * ex
            node = _solve_load(scene, fid, qc, table.kappa, stats)
            pairs = []
            for _k in range(CHECK_OFFSETS_PER_LOAD):
                pairs.append((round(float(rng.uniform(0.0, reach)) / dxw) * dxw, checks))
                pairs.append((float(rng.uniform(0.0, reach)), checks_any))
            for xd, out in pairs:
                try:
                    ds = _defect_solve(scene, fid, node, xd, stats)
                except ContactConvergenceError as exc:
                    if out is checks:
                        raise  # on-grid offsets are the table's own kind of solve
                    # Off-grid offsets put the defect rim a fraction of a cell off the grid; at
                    # fine windows Polonsky-Keer can cycle there (residual ~0.6 after max_iter).
                    # Such a check measures sub-cell jitter only, so it is counted and reported
                    # instead of failing the case.
                    checks_any_failed.append((qc, xd, float(exc.residual_history[-1])))
                    warnings.warn(f"off-grid interpolation check at Q = {qc:.4g} N, "
                                  f"x = {xd:.4g} m did not converge: {exc}", RuntimeWarning,
                                  stacklevel=3)
                    continue
                Pi, Pdi = table.evaluate(qc, xd)
                out.append((qc, xd, ds.P, ds.Pd, float(Pi), float(Pdi), node.p0))
    checks_a, err, err_d, err_rms = _check_errors(checks)
    checks_b, err_any, err_d_any, err_any_rms = _check_errors(checks_any)
    return {
        "interp_max_rel_error_p_max": err,
        "interp_max_rel_error_p_max_defect": err_d,
        "interp_checks": checks_a,
        "interp_rms_rel_error_p_max": err_rms,
        "any_offset_max_rel_error_p_max": err_any,
        "any_offset_rms_rel_error_p_max": err_any_rms,
        "any_offset_max_rel_error_p_max_defect": err_d_any,
        "any_offset_checks": checks_b,
        "any_offset_checks_failed": len(checks_any_failed),
    }


def _refine_outside(scene: Scene, fid: Fidelity, kappa: float, stats: SolveStats,
                    q_base: np.ndarray, p_base: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bisect the intervals of ``(q_base, p_base)`` (``q = Q^(1/3)``) where the solved midpoint
    misses the linear reading by more than :data:`OUTSIDE_REFINE_TOL` (relative), at most
    :data:`OUTSIDE_REFINE_DEPTH` times; every midpoint solved is kept. Global solves only."""
    qs, ps = [float(q_base[0])], [float(p_base[0])]

    def bisect(qa, pa, qb, pb, depth):
        qm = 0.5 * (qa + qb)
        pm = _outside_max(scene, fid, qm ** 3, kappa, stats)
        if depth < OUTSIDE_REFINE_DEPTH and abs(pm - 0.5 * (pa + pb)) > OUTSIDE_REFINE_TOL * pm:
            bisect(qa, pa, qm, pm, depth + 1)
            bisect(qm, pm, qb, pb, depth + 1)
        else:
            qs.extend([qm, qb])
            ps.extend([pm, pb])

    for k in range(q_base.size - 1):
        bisect(float(q_base[k]), float(p_base[k]), float(q_base[k + 1]), float(p_base[k + 1]), 1)
    return np.array(qs), np.array(ps)


def build_table(scene: Scene, fidelity: Fidelity | str | None = None, *, q_max: float,
                stats: SolveStats | None = None, progress: bool = False,
                check_seed: int = 20261122) -> tuple[PressureTable, list[LoadNode], dict]:
    """Solve the contacts and build the ``P(Q, x)`` table for roller loads up to ``q_max``.

    Stages: load nodes uniform in ``Q^(1/3)`` (:func:`_table_loads`); the no-defect global +
    window solve at each (:func:`_solve_load_nodes`, which fixes ``kappa``); offsets on the
    window grid (:func:`_offset_nodes`); the defect window solves (:func:`_defect_ratios`); the
    roller-end maxima on a denser load grid (:func:`_outside_maxima`); the interpolation checks
    against direct solves (:func:`_interpolation_checks`).

    Returns
    -------
    table : PressureTable
    nodes : list of LoadNode
        Per-load solutions (for snapshots).
    snapshots : dict
        Pressure fields at a few offsets per load (for maps like the study's Fig. 4).
    """
    fid = fidelity_from(fidelity)
    stats = stats or SolveStats()
    d = scene.defect
    nq = fid.n_loads
    qn, q_nodes = _table_loads(q_max, nq)
    a_coef = hertz_estimate(scene, q_max).a / q_max ** (1 / 3)
    ex = d.extent_x_m if d.active else 0.0
    s_const = 0.5 * ex + 1e-6 * fid.neighbourhood_um
    # offsets in absolute x: normalised by the largest load's s(Q) only (the pressure peak
    # oscillates with the offset on the scale of the defect width, fixed in x, not in x/a)
    dxw = _window_spec(scene, fid, q_max, 1.0)[2]
    nxi = _offset_nodes(scene, fid, REACH_GUESS_FACTOR * a_coef * q_max ** (1 / 3) + s_const,
                        dxw).size
    n_total = nq * 2 + 2 * (nq - 1) + (nq * (nxi + fid.n_snapshot_offsets) + fid.n_checks * (
        2 + 2 * CHECK_OFFSETS_PER_LOAD) if d.active else 0)
    bar = _progress(stats, n_total, progress)
    try:
        nodes, kappa = _solve_load_nodes(scene, fid, q_nodes, stats)
        s_max = kappa * a_coef * q_max ** (1 / 3) + s_const
        x_nodes = _offset_nodes(scene, fid, s_max, dxw)
        dr = _defect_ratios(scene, fid, nodes, q_nodes, x_nodes,
                            lambda q: kappa * a_coef * q ** (1 / 3) + s_const, stats,
                            bar.update if bar is not None else (lambda: None))
        q_out, p_out = _outside_maxima(scene, fid, nodes, qn, kappa, stats)
        table = PressureTable(q_nodes, x_nodes / s_max, np.array([nd.p0 for nd in nodes]),
                              np.array([nd.w0 for nd in nodes]), dr.ratio, dr.ratio_defect,
                              a_coef, kappa, s_const, s_max, q_out, p_out,
                              out_density=OUTSIDE_LOAD_DENSITY, ratio_force=dr.ratio_force,
                              ratio_area=dr.ratio_area,
                              approach0=np.array([nd.approach_global for nd in nodes]),
                              area0=np.array([nd.area_global for nd in nodes]),
                              p_cap=scene.material.hardness_pa)
        table.info = {
            **_interpolation_checks(scene, fid, table, qn, dxw, stats, check_seed),
            "interp_variables": "W/W0 bilinear in q = Q^(1/3) and x scaled by s(Q); W0, P_out linear in q; P = max(W, P_out); "
                                "offset nodes on multiples of the window spacing",
            "zoom_consistency_max": float(max(nd.zoom_consistency for nd in nodes)),
            "approach_force_change_max": float(dr.removed_force_max),
            "global_dx": nodes[0].grid.dx, "global_dy": nodes[0].grid.dy,
            "window_dx": nodes[0].window.dx, "window_dy": nodes[0].window.dy,
            "approach": np.array([nd.approach for nd in nodes]),
            "half_width": np.array([nd.half_width for nd in nodes]),
            "a_hertz": np.array([nd.a_hertz for nd in nodes]),
        }
    finally:
        if bar is not None:
            bar.close()
            stats.callback = None
    return table, nodes, dr.snapshots


def direct_pressure(scene: Scene, fidelity: Fidelity | str | None, q_load: float, x_d: float,
                    *, kappa: float = 1.0, stats: SolveStats | None = None) -> tuple[float, float]:
    """``(P, P_d)`` (Pa) from a direct zoom solve at roller load ``q_load`` and offset ``x_d``."""
    fid = fidelity_from(fidelity)
    stats = stats or SolveStats()
    node = _solve_load(scene, fid, q_load, kappa, stats)
    if not scene.defect.active:
        return node.p0, _neighbourhood_max(scene, fid, node.window, node.p_window0, x_d)
    ds = _defect_solve(scene, fid, node, x_d, stats)
    return ds.P, ds.Pd


# ---------------------------------------------------------------------------------------------
# kinematics and synthesis


def kinematics(scene: Scene, t: np.ndarray, *, t_end: float | None = None) -> dict[str, np.ndarray]:
    """Shaft and cage angles, defect offset and roller index at times ``t`` (s).

    Returns a dict with ``theta_shaft`` (rad, the defect's angle from the load direction),
    ``theta_cage`` (rad), ``offset`` (m), ``roller`` (index of the nearest roller) and
    ``theta_roller`` (rad, that roller's angle from the load direction). ``t_end`` (s): end of
    the whole record when ``t`` is one block of it (keeps the seeded slip process the same).
    """
    b = scene.bearing
    z = b.rollers_per_row
    theta_d = 2.0 * np.pi * scene.operation.shaft_rate_hz * t
    theta_c = cage_angle(scene, t, t_end=t_end)
    pitch = 2.0 * np.pi / z
    rel = theta_d - theta_c
    k = np.floor((rel + 0.5 * pitch) / pitch)
    wrapped = rel - k * pitch
    return {"theta_shaft": theta_d, "theta_cage": theta_c,
            "offset": b.inner_race_radius_m * wrapped, "roller": np.mod(k, z).astype(np.int64),
            "theta_roller": theta_d - wrapped}


def cage_angle(scene: Scene, t: np.ndarray, *, t_end: float | None = None) -> np.ndarray:
    """Cage angle (rad) at times ``t``; with slip a seeded, piecewise-constant random slip.

    ``t_end`` (s): the record's end when ``t`` is a block of it (the slip draws depend only on
    the seed and ``t_end``, so blocks of one record agree). Times slightly before 0 (the
    anti-alias filter's lead-in) continue the first period's rate.
    """
    op = scene.operation
    fc = scene.cage_rate_hz
    if op.cage_slip_percent <= 0:
        return 2.0 * np.pi * fc * t
    rng = np.random.default_rng(op.slip_seed)
    period = 1.0 / scene.bpfi_hz
    last = max(float(t[-1]) if t.size else 0.0, 0.0 if t_end is None else float(t_end))
    n = int(np.ceil(last / period)) + 2
    s = rng.uniform(0.0, 2e-2 * op.cage_slip_percent, n)
    rate = 2.0 * np.pi * fc * (1.0 - s)
    edges = np.concatenate([[0.0], np.cumsum(rate * period)])   # angle at k * period
    k = np.clip((t / period).astype(np.int64), 0, n - 1)
    return edges[k] + rate[k] * (t - k * period)


def _law_params(ld: LoadDistribution):
    return (ld.stiffness, ld.delta_r, ld.clearance, math.cos(ld.contact_angle_rad), ld.exponent)


def synthesize_numpy(scene: Scene, table: PressureTable, ld: LoadDistribution, t: np.ndarray,
                     *, t_end: float | None = None):
    """Per-sample synthesis, numpy version: ``(p_max, p_max_defect, roller_load, offset)``.

    The roller load is the load-zone law at the defect's angle (``load.roller_load: smooth``)
    or at the angle of the roller over the defect (``discrete``).
    """
    kin = kinematics(scene, t, t_end=t_end)
    psi = kin["theta_roller"] if scene.load.roller_load == "discrete" else kin["theta_shaft"]
    Q = ld.load_at(psi)
    P, Pd = table.evaluate(Q, kin["offset"])
    return P, Pd, Q, kin["offset"]


try:  # pragma: no cover - numba optional at import time
    import numba

    @numba.njit(cache=True, fastmath=False)
    def _row(T, i, xn, xr, fill):
        nx = xn.size
        if xr >= xn[nx - 1]:
            return fill
        # uniform offset nodes: direct index
        step = xn[1] - xn[0]
        j = int(xr / step)
        if j > nx - 2:
            j = nx - 2
        tx = (xr - xn[j]) / step
        if tx < 0.0:
            tx = 0.0
        elif tx > 1.0:
            tx = 1.0
        return (1.0 - tx) * T[i, j] + tx * T[i, j + 1]

    @numba.njit(cache=True, fastmath=False)
    def _row_x(x, q, qn, i, ka, s0):
        ax = abs(x)
        if q >= qn[0]:
            v = ax + ka * (qn[i] - q)
            return v if v > 0.0 else 0.0
        return ax * (ka * qn[i] + s0) / (ka * q + s0)

    @numba.njit(cache=True, fastmath=False)
    def _synth_kernel(t, theta_c, fr, z, ri, K, dr, c, ca, n, discrete, qn, xn, p0, R, Rd, ka,
                      s0, qo, po, P, Pd, Qo, Xo):
        pitch = 2.0 * np.pi / z
        nq = qn.size
        for k in range(t.size):
            th = 2.0 * np.pi * fr * t[k]
            rel = th - theta_c[k]
            m = np.floor((rel + 0.5 * pitch) / pitch)
            x = ri * (rel - m * pitch)
            psi = th - (rel - m * pitch) if discrete else th
            d = (dr * np.cos(psi) - 0.5 * c) * ca
            Q = K * d ** n if d > 0.0 else 0.0
            Qo[k] = Q
            Xo[k] = x
            q = np.cbrt(Q)
            qc = min(max(q, qn[0]), qn[nq - 1])
            i = 0
            while i < nq - 2 and qn[i + 1] <= qc:
                i += 1
            tq = (qc - qn[i]) / (qn[i + 1] - qn[i])
            if q < qn[0]:
                p0q = p0[0] * q / qn[0]
            else:
                p0q = p0[i] * (1 - tq) + p0[i + 1] * tq
            x0 = _row_x(x, q, qn, i, ka, s0)
            x1 = _row_x(x, q, qn, i + 1, ka, s0)
            if q < qo[0]:
                pout = po[0] * q / qo[0]
            elif q >= qo[qo.size - 1]:
                pout = po[qo.size - 1]
            else:
                m2 = min(max(np.searchsorted(qo, q, side="right") - 1, 0), qo.size - 2)
                f = (q - qo[m2]) / (qo[m2 + 1] - qo[m2])
                pout = (1.0 - f) * po[m2] + f * po[m2 + 1]
            w = p0q * ((1 - tq) * _row(R, i, xn, x0, 1.0) + tq * _row(R, i + 1, xn, x1, 1.0))
            P[k] = w if w > pout else pout
            Pd[k] = p0q * ((1 - tq) * _row(Rd, i, xn, x0, 0.0) + tq * _row(Rd, i + 1, xn, x1, 0.0))

    @numba.njit(cache=True, fastmath=False)
    def _ratio_kernel(Qa, Xa, qn, xn, ka, s0, T, out):
        nq = qn.size
        for k in range(Qa.size):
            Q = Qa[k]
            q = np.cbrt(Q) if Q > 0.0 else 0.0
            qc = min(max(q, qn[0]), qn[nq - 1])
            i = 0
            while i < nq - 2 and qn[i + 1] <= qc:
                i += 1
            tq = (qc - qn[i]) / (qn[i + 1] - qn[i])
            out[k] = ((1 - tq) * _row(T, i, xn, _row_x(Xa[k], q, qn, i, ka, s0), 0.0)
                      + tq * _row(T, i + 1, xn, _row_x(Xa[k], q, qn, i + 1, ka, s0), 0.0))

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover
    HAVE_NUMBA = False


def synthesize(scene: Scene, table: PressureTable, ld: LoadDistribution, t: np.ndarray,
               *, t_end: float | None = None):
    """Per-sample synthesis with the numba kernel (falls back to numpy without numba).

    Same outputs as :func:`synthesize_numpy`: ``(p_max, p_max_defect, roller_load, offset)``.
    """
    if not HAVE_NUMBA:  # pragma: no cover
        return synthesize_numpy(scene, table, ld, t, t_end=t_end)
    t = np.ascontiguousarray(t, dtype=float)
    theta_c = np.ascontiguousarray(cage_angle(scene, t, t_end=t_end))
    n = t.size
    P, Pd, Q, X = (np.empty(n) for _ in range(4))
    K, dr, c, ca, ex = _law_params(ld)
    _synth_kernel(t, theta_c, scene.operation.shaft_rate_hz, scene.bearing.rollers_per_row,
                  scene.bearing.inner_race_radius_m, K, dr, c, ca, ex,
                  scene.load.roller_load == "discrete", *table.args(), P, Pd, Q, X)
    if table.p_cap is not None:
        np.minimum(P, table.p_cap, out=P)
        np.minimum(Pd, table.p_cap, out=Pd)
    return P, Pd, Q, X


#: Signals of a case that describe the contact (filtered by the anti-alias acquisition), and the
#: kinematic bookkeeping that is point-sampled in every mode (a sawtooth offset is not filtered).
CONTACT_SIGNALS = ("p_max", "p_max_defect", "removed_force", "contact_force", "approach",
                   "approach_change", "contact_area")
STATE_SIGNALS = ("roller_load", "defect_offset")

#: Units of every signal a case can hold.
SIGNAL_UNITS = {"p_max": "Pa", "p_max_defect": "Pa", "removed_force": "N", "contact_force": "N",
                "approach": "m", "approach_change": "m", "contact_area": "m^2",
                "roller_load": "N", "defect_offset": "m"}


def evaluate_signals(scene: Scene, table: PressureTable, ld: LoadDistribution, t: np.ndarray,
                     *, t_end: float | None = None, use_numba: bool = True) -> dict[str, np.ndarray]:
    """Every signal of :data:`CONTACT_SIGNALS` and :data:`STATE_SIGNALS` at the instants ``t``
    (s): pressures from :meth:`PressureTable.evaluate`, integrals from
    :meth:`PressureTable.evaluate_integrals`."""
    fn = synthesize if use_numba else synthesize_numpy
    P, Pd, Q, X = fn(scene, table, ld, t, t_end=t_end)
    out = {"p_max": P, "p_max_defect": Pd, "roller_load": Q, "defect_offset": X}
    out.update(table.evaluate_integrals(Q, X, use_numba=use_numba))
    return out


# ---------------------------------------------------------------------------------------------
# acquisition: point samples or anti-aliased


#: Anti-alias filter of the ``antialiased`` acquisition, as fractions of the output rate fs:
#: pass band up to ``ANTIALIAS_PASS`` (the fs/4-3fs/8 band and every BPFI band lie inside),
#: stop band from ``ANTIALIAS_STOP`` = Nyquist with at least ``ANTIALIAS_ATTEN_DB``.
ANTIALIAS_PASS = 0.40
ANTIALIAS_STOP = 0.50
ANTIALIAS_ATTEN_DB = 80.0

#: Output samples per block of the anti-aliased synthesis (bounds memory: the internal rate is
#: ``oversample x fs``; a block holds ``oversample x (ACQUISITION_BLOCK + filter length)`` samples).
ACQUISITION_BLOCK = 8192


def antialias_filter(oversample: int) -> np.ndarray:
    """Linear-phase FIR low-pass for decimating ``oversample x fs`` to ``fs``.

    Kaiser-window design (:func:`scipy.signal.firwin`) at the internal rate, cut-off half-way
    between :data:`ANTIALIAS_PASS` and :data:`ANTIALIAS_STOP` (0.45 fs), designed for
    ``ANTIALIAS_ATTEN_DB + 5`` dB so that the stop band from fs/2 up is at least
    :data:`ANTIALIAS_ATTEN_DB` down (checked in the tests); pass-band ripple < 1e-4. The length
    is ``2 K oversample + 1`` (odd, symmetric: the centre tap is the zero-delay sample), unit DC
    gain.
    """
    from scipy.signal import firwin, kaiser_beta, kaiserord

    n = int(oversample)
    fs_int = float(n)                      # in units of the output rate
    width = ANTIALIAS_STOP - ANTIALIAS_PASS
    numtaps, _ = kaiserord(ANTIALIAS_ATTEN_DB + 5.0, width / (0.5 * fs_int))
    k = int(math.ceil((numtaps - 1) / (2.0 * n)))
    h = firwin(2 * k * n + 1, 0.5 * (ANTIALIAS_PASS + ANTIALIAS_STOP), fs=fs_int,
               window=("kaiser", kaiser_beta(ANTIALIAS_ATTEN_DB + 5.0)))
    return h / h.sum()


def auto_oversample(scene: Scene, fidelity: Fidelity | str | None = None) -> int:
    """``oversample: auto``: the smallest ``N`` with the defect moving no more than the table's
    offset-node spacing per internal sample, ``N = ceil(v / (fs dx))`` with
    ``v = 2 pi (f_r - f_c) R_i`` the defect's speed relative to the cage (4.24 m/s in the default
    scene) and ``dx = min(w_x / offsets_per_width, offset_step_um)`` the largest node spacing of
    ``fidelity``'s table (:func:`_offset_nodes`; ``offset_step_um`` for a healthy race), but not
    below the window spacing. The interpolated history has no feature finer than the node
    spacing, so a denser internal rate changes nothing: measured, N = 8, 16 and 33 at
    ``standard`` agree to < 0.01 % in every amplitude (``docs/benchmarks.md``, "Accuracy per CPU
    second"). N = 9 (15 um defect) and 6 (100 um) at ``standard``."""
    fid = fidelity_from(fidelity)
    v = 2.0 * math.pi * (scene.operation.shaft_rate_hz - scene.cage_rate_hz) * \
        scene.bearing.inner_race_radius_m
    step = 1e-6 * fid.offset_step_um
    if scene.defect.active:
        step = min(step, scene.defect.extent_x_m / fid.offsets_per_width)
        step = max(step, _window_spec(scene, fid, 1.0, 1.0)[2])
    return max(1, int(math.ceil(v / (scene.operation.fs_hz * step) - 1e-9)))


def acquire(evaluate: Callable[[np.ndarray], dict], n_samples: int, fs: float, *,
            mode: str = "antialiased", oversample: int = 1, filtered: tuple[str, ...] | None = None,
            block: int = ACQUISITION_BLOCK,
            ranges: dict[str, list[float]] | None = None) -> dict[str, np.ndarray]:
    """Sample signals given as functions of time at ``fs``: point samples or anti-aliased.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(t) -> {name: array like t}``: the signals at times ``t`` (s); called on
        blocks, also at times slightly before 0 and after the record (filter lead-in/out).
    n_samples : int
        Output samples, at ``t_k = k / fs``.
    fs : float
        Output rate (Hz).
    mode : {"antialiased", "point"}
        ``point``: ``evaluate(t_k)``. ``antialiased``: evaluated at ``oversample x fs``, filtered
        by :func:`antialias_filter` and decimated with :func:`scipy.signal.upfirdn`, the filter
        centred on each output instant (zero phase, no delay).
    oversample : int
        Internal rate factor (``>= 1``).
    filtered : tuple of str, optional
        Names that are filtered; the others are point-sampled at ``t_k`` (default: all).
    block : int
        Output samples per block (memory bound).
    ranges : dict, optional
        Filled with ``name -> [min, max]`` of each filtered signal's internal samples (before the
        filter). The filter is linear with some negative taps, so an anti-aliased output of a
        signal that is ``>= 0`` internally can undershoot 0 near sharp features, by at most
        ``max x sum(-h[h < 0])`` (:func:`antialias_undershoot`); these ranges let a caller check
        the physics (``p >= 0``) on the internal samples and the filter bound on the output.

    Returns
    -------
    dict
        ``name -> array (n_samples,)``.
    """
    from scipy.signal import upfirdn

    if mode not in ("antialiased", "point"):
        raise ValueError(f"acquisition mode: got {mode!r}; allowed: antialiased | point")
    if isinstance(oversample, bool) or not isinstance(oversample, (int, np.integer)) or oversample < 1:
        raise ValueError(f"acquisition oversample: got {oversample!r}; allowed: an integer >= 1")
    n_samples = int(n_samples)
    if mode == "point":
        return {k: np.asarray(v, dtype=float) for k, v in evaluate(np.arange(n_samples) / fs).items()}
    n = int(oversample)
    h = antialias_filter(n)
    k_half = (h.size - 1) // (2 * n)             # filter half-length in output samples
    c = k_half * n
    out: dict[str, np.ndarray] = {}
    for m0 in range(0, n_samples, block):
        m1 = min(n_samples, m0 + block)
        j = np.arange(m0 * n - c, (m1 - 1) * n + c + 1)
        sig = evaluate(j / (n * fs))
        if not out:
            out = {k: np.empty(n_samples) for k in sig}
        for name, x in sig.items():
            x = np.asarray(x, dtype=float)
            if filtered is not None and name not in filtered:
                out[name][m0:m1] = x[c::n][: m1 - m0]
            else:
                y = upfirdn(h, x, 1, n)
                out[name][m0:m1] = y[2 * k_half: 2 * k_half + (m1 - m0)]
                if ranges is not None and x.size:
                    lo, hi = ranges.get(name, [math.inf, -math.inf])
                    ranges[name] = [min(lo, float(x.min())), max(hi, float(x.max()))]
    return out


def antialias_undershoot(oversample: int) -> float:
    """``sum(-h[h < 0])`` of :func:`antialias_filter`: an anti-aliased output of a signal with
    internal samples in ``[0, M]`` lies in ``[-u M, (1 + u) M]`` with ``u`` this value."""
    h = antialias_filter(oversample)
    return float(-h[h < 0].sum())


# ---------------------------------------------------------------------------------------------
# the case


@dataclass
class History:
    """Result of :func:`simulate` (what :func:`bearing_envelope.io.write_case` stores)."""

    scene: Scene
    fidelity: Fidelity
    time: np.ndarray
    p_max: np.ndarray
    p_max_defect: np.ndarray
    roller_load: np.ndarray
    defect_offset: np.ndarray
    table: PressureTable
    snapshots: dict
    load_distribution: LoadDistribution
    signals: dict
    stats: dict
    acquisition: dict = field(default_factory=dict)


def add_noise(x: np.ndarray, snr_db: float, seed: int) -> np.ndarray:
    """``x`` plus white Gaussian noise at ``snr_db`` (signal power = variance of ``x``), seeded."""
    rng = np.random.default_rng(seed)
    power = float(np.var(x))
    sigma = math.sqrt(power / 10.0 ** (snr_db / 10.0)) if power > 0 else 0.0
    return x + sigma * rng.standard_normal(x.size)


def acquisition_settings(scene: Scene, fidelity: Fidelity | str | None = None) -> dict[str, Any]:
    """The acquisition a case uses: ``mode``, resolved ``oversample`` (1 for ``point``), the
    filter's pass/stop edges (fractions of fs), its stop-band attenuation target (dB) and length."""
    acq = scene.operation.acquisition
    if acq.mode == "point":
        return {"mode": "point", "oversample": 1}
    n = auto_oversample(scene, fidelity) if acq.oversample == "auto" else int(acq.oversample)
    return {"mode": acq.mode, "oversample": n, "oversample_setting": str(acq.oversample),
            "filter": "Kaiser-window FIR, linear phase, centred (zero delay), scipy.signal.upfirdn",
            "pass_band_fs": ANTIALIAS_PASS, "stop_band_fs": ANTIALIAS_STOP,
            "stop_band_attenuation_db": ANTIALIAS_ATTEN_DB,
            "filter_taps": int(antialias_filter(n).size)}


def synthesize_case(scene: Scene, table: PressureTable, ld: LoadDistribution,
                    fidelity: Fidelity | str | None = None, *, use_numba: bool = True,
                    acquisition: dict | None = None) -> tuple[np.ndarray, dict, dict]:
    """All signals of a case at ``fs`` with the scene's acquisition (or ``acquisition``, a dict
    like :func:`acquisition_settings`). Returns ``(time, signals, acquisition)``."""
    op = scene.operation
    acq = acquisition or acquisition_settings(scene, fidelity)
    n = scene.n_samples
    t_end = (n + 1) / op.fs_hz + 1.0 / scene.bpfi_hz

    def ev(t):
        return evaluate_signals(scene, table, ld, t, t_end=t_end, use_numba=use_numba)

    ranges: dict[str, list[float]] = {}
    sig = acquire(ev, n, op.fs_hz, mode=acq["mode"], oversample=acq["oversample"],
                  filtered=CONTACT_SIGNALS, ranges=ranges)
    if acq["mode"] == "antialiased":
        acq = {**acq, "internal_range": ranges,
               "undershoot_bound": antialias_undershoot(acq["oversample"])}
    return np.arange(n) / op.fs_hz, sig, acq


def simulate(scene: Scene, fidelity: Fidelity | str | None = None, *, progress: bool = False,
             use_numba: bool = True) -> History:
    """Simulate one case: load distribution, contact table, acquisition of every signal, noise.

    Parameters
    ----------
    scene : Scene
    fidelity : Fidelity, preset name or None (``standard``)
    progress : bool
        Show a tqdm bar over the contact solves (only on a terminal).
    use_numba : bool
        Use the numba synthesis kernels (else numpy).
    """
    fid = fidelity_from(fidelity)
    t_start = _time.perf_counter()
    ld = scene_load_distribution(scene)
    stats = SolveStats()
    table, nodes, snaps = build_table(scene, fid, q_max=ld.q_max, stats=stats, progress=progress)
    t_table = _time.perf_counter() - t_start
    op = scene.operation
    t1 = _time.perf_counter()
    t, sig, acq = synthesize_case(scene, table, ld, fid, use_numba=use_numba)
    t_synth = _time.perf_counter() - t1
    P, Pd, Q, X = sig["p_max"], sig["p_max_defect"], sig["roller_load"], sig["defect_offset"]
    signals = {k: sig[k] for k in CONTACT_SIGNALS}
    if op.noise_snr_db is not None:
        signals.update({
            "p_max": add_noise(P, op.noise_snr_db, op.noise_seed),
            "p_max_defect": add_noise(Pd, op.noise_snr_db, op.noise_seed + 1),
            "p_max_clean": P, "p_max_defect_clean": Pd,
        })
    stats_d = {
        "n_solves": stats.n_solves, "n_iterations": stats.n_iterations,
        "n_failed_solves": stats.n_failed, "failed_solver_seconds": stats.failed_seconds,
        "n_stall_guard": stats.n_stall_guard,
        "solver_seconds": stats.solver_seconds, "table_seconds": t_table,
        "synthesis_seconds": t_synth, "wall_seconds": _time.perf_counter() - t_start,
    }
    return History(scene, fid, t, signals["p_max"], signals["p_max_defect"], Q, X, table, snaps,
                   ld, signals, stats_d, acq)
