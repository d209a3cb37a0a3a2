"""Contact solves of the zoom route: the global no-defect solve over the whole roller, the
local window solves with the defect, and the rim strips (see :mod:`bearing_envelope.physics.history`
for the model). Public entry points are used by :mod:`~bearing_envelope.physics.table` and
:mod:`~bearing_envelope.physics.pit`."""

from __future__ import annotations

import dataclasses
import math
import time as _time
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ..contact import (ContactConvergenceError, ContactGridError, ElasticHalfSpace,
                       solve_contact)
from ..contact.halfspace import subcell_displacement
from .fidelity import Fidelity
from .geometry import Grid, gap_field, hertz_estimate, make_grid
from .nodefect_cache import GlobalSolution, NoDefectCache, global_key
from .scene import Scene

__all__ = ["SolveStats", "LoadNode", "DefectSolve", "RimStrip", "GlobalGridError", "global_solve",
           "solve_load", "outside_max", "outside_solve", "defect_solve", "neighbourhood_max",
           "window_spec", "far_uptake", "end_intervals"]

@dataclass
class SolveStats:
    """Counters of contact solves (for the benchmark and the case file)."""

    n_solves: int = 0
    n_iterations: int = 0
    solver_seconds: float = 0.0
    n_failed: int = 0
    failed_seconds: float = 0.0
    n_stall_guard: int = 0     # solves whose preconditioner the solver's stall guard dropped
    #: defect window solves on the contact's rows (:func:`window_solve`) whose contact reached
    #: beyond them and were solved again on the whole window
    n_rows_fallback: int = 0
    callback: Callable[[], None] | None = field(default=None, repr=False)
    #: Where the global no-defect solves are looked up and stored (None: always solved).
    cache: NoDefectCache | None = field(default=None, repr=False)

    def solve(self, *args, **kwargs):
        """:func:`solve_contact` with its cost counted, also when it raises (stalled solves
        that a caller retries are part of the cost: ``n_failed``, ``failed_seconds``).

        Parameters
        ----------
        *args, **kwargs
            Passed to :func:`~bearing_envelope.contact.solve_contact`.

        Returns
        -------
        ContactSolution
            The solve's result.
        """
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
    #: The far field's linear response (:class:`FarResponse`); None = frozen far field
    far: "FarResponse | None" = field(repr=False, default=None)
    #: The no-defect window with axial end strips (:func:`_end_reference`), once solved
    end_ref: dict = field(repr=False, default_factory=dict)
    #: Window rows ``[r0, r1)`` the defect solves are solved on (:func:`contact_rows`) and their
    #: half-space operator; None = every row (the inner race)
    rows: tuple[int, int] | None = None
    rows_halfspace: Any = field(repr=False, default=None)


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
    return ElasticHalfSpace(grid.shape, grid.dx, grid.dy, e_star, workers=1, backend=backend,
                            element=element)


def window_spec(scene: Scene, fid: Fidelity, q_load: float, kappa: float):
    """The defect window's size and spacing at roller load ``q_load`` (N).

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

    Returns
    -------
    tuple
        ``(a, s, dx, dy, xh, yd, hy_read, hy)``: Hertz semi-axis, read strip's half-width, window
        spacings, window half-extent across rolling, defect's axial position, read and window
        half-extents along the axis (m).
    """
    d = scene.defect
    a = hertz_estimate(scene, q_load).a
    ex = d.extent_x_m if d.active else 0.0
    ey = d.extent_y_m if d.active else 0.0
    nb = fid.neighbourhood_m
    s = kappa * a + 0.5 * ex + nb
    dx = fid.local_dx_m
    if d.active:
        dx = min(dx, ex / 4.0)
    dy = fid.local_dy_m
    if d.active:
        dy = min(dy, ey / 6.0)
    xh = max(fid.global_extent * kappa * a, fid.xi_max * s + 0.5 * ex + nb + 2 * dx)
    yd = 1e-3 * d.axial_position_mm
    hy_read = 0.5 * ey + nb
    hy = hy_read + fid.window_margin_m
    return a, s, dx, dy, xh, yd, hy_read, hy


#: Growth factor of the global grid's half-extent across rolling when the contact reaches its
#: edge, and the number of sizes tried before :func:`global_solve` gives up.
#: 8 sizes reach 1.3^7 = 6.3x the Hertz-sized start: a measured roller profile can widen the
#: contact beyond the crown radius' Hertz estimate (a 10 um end drop over 34 mm needed 5-8
#: sizes once the start no longer followed the defect window, issue 25); a contact that fits
#: the first size (every default case) is solved exactly as before.
GLOBAL_GRID_GROWTH = 1.3
GLOBAL_GRID_ATTEMPTS = 8
#: Axial reach of the global grid beyond each roller end, in axial cells: just over one, so that
#: exactly one cell centre lies past each end (no material there: gap ``+inf``).
GLOBAL_END_CELLS = 1.01


class GlobalGridError(RuntimeError):
    """The global no-defect contact kept reaching the edge of its grid after every enlargement."""


def global_solve(scene: Scene, fid: Fidelity, q_load: float, extent: float, stats: SolveStats,
                  p_init=None) -> tuple[Grid, GlobalSolution]:
    """Global no-defect solve over the whole roller length (plus one ``+inf`` cell each side).

    The half-extent across rolling starts at ``extent`` (m) and grows by
    :data:`GLOBAL_GRID_GROWTH` whenever the pressure reaches the grid's edge
    (:class:`~bearing_envelope.contact.ContactGridError`), at most :data:`GLOBAL_GRID_ATTEMPTS`
    sizes. With ``stats.cache`` (and no ``p_init``) the result is read from / stored in the
    content-addressed no-defect store (:mod:`~bearing_envelope.physics.nodefect_cache`), keyed by
    the initial grid's gap field and everything else the solve reads. Returns ``(grid,
    solution)``; raises :class:`GlobalGridError` naming the load and the last extent.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    fid : Fidelity
        The fidelity (global grid, tolerance).
    q_load : float
        Roller load (N).
    extent : float
        Initial half-extent across rolling (m).
    stats : SolveStats
        Counters (and the no-defect store, ``stats.cache``).
    p_init : numpy.ndarray, optional
        Warm start: a pressure field (Pa) of the grid's shape.

    Returns
    -------
    tuple of (Grid, GlobalSolution)
        The grid and the solution.
    """
    dxg, dyg = fid.global_dx_m, fid.global_dy_m
    half = scene.bearing.half_length_m
    grid = make_grid(-extent, extent, -half - GLOBAL_END_CELLS * dyg, half + GLOBAL_END_CELLS * dyg,
                     dxg, dyg)
    gap = gap_field(scene, grid, None)
    cache = stats.cache if p_init is None else None
    if cache is not None:
        sha, key = global_key(gap, grid.x, grid.y, _global_key_fields(scene, fid, q_load))
        hit = cache.load(sha, key)
        if hit is not None:
            gx, gy, dx, dy, sol = hit
            return Grid(gx, gy, dx, dy), sol
    grid, sol = _global_solve_grown(scene, fid, q_load, extent, grid, gap, stats, p_init)
    if cache is not None:
        cache.store(sha, key, grid.x, grid.y, grid.dx, grid.dy, sol)
    return grid, sol


def _global_key_fields(scene: Scene, fid: Fidelity, q_load: float) -> dict:
    """The scalars a global solve depends on besides its initial grid and gap field."""
    return {"q_load_n": float(q_load), "e_star_pa": float(scene.material.e_star_pa),
            "hardness_pa": scene.material.hardness_pa, "tol": float(fid.tol),
            "max_iter": int(fid.max_iter), "element": fid.element,
            "growth": float(GLOBAL_GRID_GROWTH), "attempts": int(GLOBAL_GRID_ATTEMPTS),
            "half_length_m": float(scene.bearing.half_length_m)}


def _global_solve_grown(scene: Scene, fid: Fidelity, q_load: float, extent: float, grid: Grid,
                        gap: np.ndarray, stats: SolveStats, p_init) -> tuple[Grid, GlobalSolution]:
    """The solve of :func:`global_solve` on ``grid`` (gap ``gap``), enlarged while the contact
    reaches its edge."""
    e_star = scene.material.e_star_pa
    dxg, dyg = grid.dx, grid.dy
    half = scene.bearing.half_length_m
    for _attempt in range(GLOBAL_GRID_ATTEMPTS):
        try:
            sol = stats.solve(gap, dxg, dyg, q_load, e_star, tol=fid.tol,
                              max_iter=fid.max_iter, p_init=p_init, boundary="raise",
                              halfspace=_halfspace(grid, e_star, "scipy", fid.element),
                              element=fid.element, hardness=scene.material.hardness_pa)
            return grid, GlobalSolution(np.asarray(sol.pressure, dtype=np.float64),
                                        float(sol.approach), float(sol.contact_area),
                                        int(sol.iterations), float(sol.residual))
        except ContactGridError:
            extent *= GLOBAL_GRID_GROWTH
            grid = make_grid(-extent, extent, -half - GLOBAL_END_CELLS * dyg,
                             half + GLOBAL_END_CELLS * dyg, dxg, dyg)
            gap = gap_field(scene, grid, None)
    raise GlobalGridError(f"global grid could not be sized at roller load {q_load:.6g} N: the "
                          f"contact reached the edge of every grid up to a half-extent of "
                          f"{extent / GLOBAL_GRID_GROWTH:.4g} m across rolling")


def global_extent(fid: Fidelity, kappa: float, a_hertz: float) -> float:
    """Half-extent (m) across rolling of the global grid at the start of :func:`global_solve`:
    ``global_extent x kappa x a_H``, the contact and a margin. It does not depend on the defect
    (the zoom window may reach further: :func:`_far_field` extends the global pressure with
    unloaded cells), so every depth case of a load solves the same global contacts (issue 25:
    shared through :mod:`~bearing_envelope.physics.nodefect_cache`).

    Parameters
    ----------
    fid : Fidelity
        Numerical settings; its ``global_extent`` is the multiple of the contact half-width.
    kappa : float
        Solved/Hertz half-width ratio (dimensionless, about 1).
    a_hertz : float
        Hertz semi-axis across rolling at this load (m).

    Returns
    -------
    float
        Half-extent of the global grid across rolling (m).
    """
    return fid.global_extent * kappa * a_hertz


def _far_field(grid: Grid, pg: np.ndarray, win: Grid, j_lo: int, j_hi: int, m: int,
               e_star: float, element: str) -> np.ndarray:
    """Displacement at the window's cells of the global pressure outside the window's axial
    columns ``j_lo..j_hi`` (m).

    Each coarse cell is split into ``m`` axial sub-cells (the same load) and convolved on the
    global x grid at the window's axial spacing, so the result is exact in y at the window's
    columns and only interpolated (linearly) in x. Where the window reaches beyond the global
    grid across rolling, the grid is extended by unloaded cells at the same spacing (outside the
    contact the pressure is 0, so this is what a larger global grid would give).
    """
    dxg, dyg = grid.dx, grid.dy
    p_out = pg.astype(float).copy()
    p_out[:, j_lo:j_hi + 1] = 0.0
    reach = float(max(abs(win.x[0]), abs(win.x[-1])))
    n_pad = max(0, int(math.ceil((reach - float(grid.x[-1])) / dxg - 1e-9)))
    xg = grid.x
    if n_pad:
        p_out = np.pad(p_out, ((n_pad, n_pad), (0, 0)))
        xg = np.concatenate([grid.x[0] - dxg * np.arange(n_pad, 0, -1), grid.x,
                             grid.x[-1] + dxg * np.arange(1, n_pad + 1)])
    if m > 1:
        p_out = np.repeat(p_out, m, axis=1)
    hs_f = _halfspace(Grid(xg, np.zeros(p_out.shape[1]), dxg, dyg / m), e_star, "scipy",
                      element)
    u_cols = hs_f.displacement(p_out)[:, j_lo * m:(j_hi + 1) * m]
    u_ext = np.empty(win.shape)
    for k in range(win.shape[1]):
        u_ext[:, k] = np.interp(win.x, xg, u_cols[:, k], left=np.nan, right=np.nan)
    return u_ext


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


#: Rows (each side) a defect window solve keeps beyond the rows where the no-defect gap
#: overlaps (:func:`contact_rows`).
CONTACT_ROWS_MARGIN = 4


def contact_rows(scene: Scene, g0: np.ndarray, approach: float) -> tuple[int, int] | None:
    """The window rows ``[r0, r1)`` a defect window solve is solved on: the rows where the
    no-defect gap (with the far field's displacement) ``g0`` overlaps at the window's approach
    (``g0 < approach``; the Hertz contact's rows and about 40 % more) and
    :data:`CONTACT_ROWS_MARGIN` each side. A cell whose gap does not overlap can carry no
    pressure (there ``h = g + K p - approach >= g - approach >= 0``, the displacement ``K p``
    being >= 0): a pit only widens the gap, so the solution on these rows is the whole
    window's. The window spans the defect's reach across rolling (``xi_max s(Q)``): for the
    CWRU ball pit (0.18 mm against a 0.23 mm wide contact) about twice these rows.
    :func:`window_solve` checks every solve and solves the whole window where a row outside
    would overlap. None (every row): a location that solves every row
    (:attr:`~bearing_envelope.physics.locations.FaultLocation.solves_every_row`: the inner
    race, whose default sweep and
    discretisation-error model were computed on the whole window (the same solution, but not
    bit for bit: the convolutions' rounding differs), a defect-free scene, or rows that cover
    most of the window anyway.

    Parameters
    ----------
    scene : Scene
        The case's scene (its defect's location).
    g0 : numpy.ndarray
        The no-defect window gap with the far field's displacement (m), window shape.
    approach : float
        The window's no-defect approach (m).

    Returns
    -------
    tuple of (int, int) or None
        The rows, or None for every row.
    """
    if scene.defect.fault_location.solves_every_row or not scene.defect.active:
        return None
    nz = np.flatnonzero((g0 < approach).any(axis=1))
    n = g0.shape[0]
    if not nz.size:
        return None
    r0 = max(0, int(nz[0]) - CONTACT_ROWS_MARGIN)
    rows = fast_rows(int(nz[-1]) + 1 + CONTACT_ROWS_MARGIN - r0, n)
    if rows > 0.8 * n:
        return None
    r0 = min(r0, n - rows)
    return r0, r0 + rows


def fast_rows(rows: int, limit: int) -> int:
    """The smallest row count ``>= rows`` that is a multiple of 4 with only the factors 2, 3, 5
    and 7 (the padded convolution, ``2 rows`` long, then has at least 2^3 and no radix-11 pass),
    at most ``limit``: a row count with a large prime factor (214 = 2 x 107) made a window
    convolution 2.6x slower than 216 rows, and over 60-470 rows this rule's convolutions cost
    3.7 % less than the next 11-smooth count's (5.5 % on a CWRU ball case's row counts: 192
    instead of 189, 240 instead of 231; measured per count, 2026-11-28).

    Parameters
    ----------
    rows : int
        Rows needed.
    limit : int
        Rows available.

    Returns
    -------
    int
        The row count.
    """
    m = max(4, 4 * math.ceil(int(rows) / 4))
    while not _smooth7(m):
        m += 4
    return min(limit, m)


def _smooth7(n: int) -> bool:
    """``n`` has no prime factor above 7."""
    for f in (2, 3, 5, 7):
        while n % f == 0:
            n //= f
    return n == 1


def window_solve(node: "LoadNode | WindowState", g: np.ndarray, stats: SolveStats,
                 e_star: float, p_init: np.ndarray | None, **kw) -> np.ndarray:
    """A defect window solve under displacement control (``kw["approach"]``) on the node's
    contact rows (:attr:`LoadNode.rows`; every row when None): returns the window pressure (Pa,
    window shape, zero outside the rows). The solution is checked on the whole window: where a
    row outside would interpenetrate (``g + K p - approach < 0``) the contact reaches beyond the
    rows and the whole window is solved, warm started from it (``stats.n_rows_fallback``);
    where no row outside overlaps (``g >= approach``) the check needs no convolution.

    Parameters
    ----------
    node : LoadNode or WindowState
        The load node (window, its operators, the rows).
    g : numpy.ndarray
        The window's gap with the far field's displacement (m), window shape.
    stats : SolveStats
        Counters.
    e_star : float
        Composite modulus (Pa).
    p_init : numpy.ndarray or None
        Warm start (Pa), window shape.
    **kw
        Passed to :func:`~bearing_envelope.contact.solve_contact` (``approach`` required).

    Returns
    -------
    numpy.ndarray
        The pressure (Pa), window shape.
    """
    win = node.window
    if node.rows is None:
        return stats.solve(g, win.dx, win.dy, None, e_star, p_init=p_init,
                           halfspace=node.halfspace, **kw).pressure
    r0, r1 = node.rows
    sol = stats.solve(g[r0:r1], win.dx, win.dy, None, e_star,
                      p_init=None if p_init is None else p_init[r0:r1],
                      halfspace=node.rows_halfspace, **kw)
    p = np.zeros(win.shape)
    p[r0:r1] = sol.pressure
    outside = np.ones(win.shape[0], bool)
    outside[r0:r1] = False
    # outside the rows h >= g - approach (K p >= 0): only an overlapping gap needs K p
    if np.any(g[outside] < kw["approach"]) and np.any(
            g[outside] + node.halfspace.displacement(p)[outside] < kw["approach"]):
        stats.n_rows_fallback += 1
        p = stats.solve(g, win.dx, win.dy, None, e_star, p_init=p, halfspace=node.halfspace,
                        **kw).pressure
    return p


#: Approach (m) of the far-field flat-punch solve (:func:`far_response`); the response is
#: linear, so only the scale of the solved pressures depends on it.
FAR_RESPONSE_APPROACH = 1e-6
#: Displacement (m) imposed on the no-defect window to measure its pressure response to the far
#: field's take-up (:func:`far_response`): small against the approach (~50 um), large against the
#: solver's tolerance times the pressure.
WINDOW_RESPONSE_STEP = 1e-8


@dataclass
class WindowState:
    """The no-defect window of a load node (internal): gap with the far field's displacement,
    approach, pressure and half-space operator; the window and the rows its solves with a
    defect use (:func:`window_solve`, as :class:`LoadNode`)."""

    gap: np.ndarray
    approach: float
    pressure: np.ndarray
    halfspace: Any
    window: Grid | None = None
    rows: tuple[int, int] | None = None
    rows_halfspace: Any = None


@dataclass
class FarResponse:
    """The far field's linear response at one load node (:func:`far_response`).

    ``z``: displacement at the window's cells of the far field's flat-punch pressure per unit
    approach (dimensionless); ``stiffness``: the force (N) of the take-up's shape ``psi_c``
    (:func:`far_response`); ``window_z``, ``window_force``: ``sum(z R) dA_w`` and
    ``sum(R) dA_w`` (N) of the no-defect window's pressure response ``R`` (Pa) to the
    displacement of ``psi_c``.
    """

    z: np.ndarray
    stiffness: float
    window_z: float
    window_force: float

    def uptake(self, dp: np.ndarray, cell: float) -> float:
        """Force (N) the far field and the window together regain when the window's pressure
        changes by ``dp`` (Pa) at fixed approach: the far field's pressure change is taken as
        ``alpha psi_c`` (the take-up's shape); it unloads the window further by ``alpha R``;
        reciprocity fixes ``alpha``: ``alpha stiffness = -sum(z (dp + alpha R)) dA``; the gain
        is ``alpha (stiffness + window_force)``.

        Parameters
        ----------
        dp : ndarray
            Change of the window's pressure (Pa), window shape.
        cell : float
            Area of one window cell ``dx dy`` (m^2).

        Returns
        -------
        float
            The force regained (N); positive when the window sheds load (``dp`` < 0 where
            ``z`` > 0).
        """
        alpha = -float(np.sum(self.z * dp)) * cell / (self.stiffness + self.window_z)
        return alpha * (self.stiffness + self.window_force)


def far_response(scene: Scene, fid: Fidelity, grid: Grid, pg: np.ndarray, win: Grid, j_lo: int,
                 j_hi: int, m: int, stats: SolveStats, w0: WindowState) -> FarResponse | None:
    """How the far field takes up the load the window sheds (issue 25 part C).

    The far field (the no-defect global contact outside the window's columns) is linear: its
    contact set is fixed (the defect changes the contact's force by ~1e-3). Three solves:

    1. ``psi``, the far-field pressure that raises the far contact uniformly by one unit of
       displacement while the window carries nothing (``K_ff psi = 1``: a flat punch on the
       global grid); ``z = K_wf psi`` at the window's cells. By reciprocity a window pressure
       change ``dp`` changes the far field's force at fixed approach by ``-sum(z dp) dA``,
       exactly for any ``dp``.
    2. The shape of that take-up: the far field's pressure response ``psi_c`` to the pressure
       the centred defect removes from the frozen window (one window solve with the defect at
       x = 0, its pressure change summed onto the global cells, convolved, and the far field
       solved under the opposite displacement).
    3. The no-defect window's pressure response ``R`` to the displacement of ``psi_c``: the
       far field's take-up unloads the window further (:meth:`FarResponse.uptake` closes the
       loop).

    Parameters
    ----------
    scene : Scene
        The case's scene (elastic modulus, hardness, the defect).
    fid : Fidelity
        Numerical settings (solver tolerance and iterations, element shape).
    grid : Grid
        The global grid (m).
    pg : ndarray
        The global no-defect pressure (Pa), ``grid`` shape.
    win : Grid
        The defect window (m).
    j_lo, j_hi : int
        The global grid's axial columns the window covers (inclusive): the far field is the
        loaded cells outside them.
    m : int
        Window axial cells per global axial cell.
    stats : SolveStats
        Counts the solves done.
    w0 : WindowState
        The no-defect window: its gap with the far field's displacement (m), approach (m),
        pressure (Pa) and half-space operator.

    Returns
    -------
    FarResponse or None
        The far field's response ``z`` (dimensionless), the take-up's force per unit
        amplitude and the window's response sums (N); None for a healthy race or when the far
        field carries no load.
    """
    far = pg > 0
    far[:, j_lo:j_hi + 1] = False
    if not far.any() or not scene.defect.active:
        return None
    e_star = scene.material.e_star_pa
    kw = dict(tol=fid.tol, max_iter=fid.max_iter, boundary="ignore", element=fid.element)
    hs_g = _halfspace(grid, e_star, "scipy", fid.element)
    punch = stats.solve(np.where(far, 0.0, np.inf), grid.dx, grid.dy, None, e_star,
                        approach=FAR_RESPONSE_APPROACH, halfspace=hs_g, **kw)
    z = np.nan_to_num(_far_field(grid, punch.pressure, win, j_lo, j_hi, m, e_star, fid.element)
                      / FAR_RESPONSE_APPROACH, nan=0.0)
    g_none = gap_field(scene, win, None)
    # the far field's displacement (0 beyond the roller ends, where both gaps are +inf)
    u_ext = np.zeros(win.shape)
    fin = np.isfinite(g_none)
    u_ext[fin] = w0.gap[fin] - g_none[fin]
    cen = window_solve(w0, gap_field(scene, win, 0.0) + u_ext, stats, e_star, w0.pressure,
                       approach=w0.approach, hardness=scene.material.hardness_pa, **kw)
    lost = _on_global_cells(grid, win, j_lo, m, w0.pressure - cen)
    u_lost = hs_g.displacement(lost)
    shape = stats.solve(np.where(far, -u_lost, np.inf), grid.dx, grid.dy, None, e_star,
                        approach=0.0, halfspace=hs_g, **kw)
    if not np.any(shape.pressure > 0):
        return None
    z_c = np.nan_to_num(_far_field(grid, shape.pressure, win, j_lo, j_hi, m, e_star,
                                   fid.element), nan=0.0)
    step = WINDOW_RESPONSE_STEP / max(float(np.abs(z_c).max()), 1e-300)
    resp = window_solve(w0, w0.gap + step * z_c, stats, e_star, w0.pressure,
                        approach=w0.approach, hardness=scene.material.hardness_pa, **kw)
    R = (resp - w0.pressure) / step
    cell = win.dx * win.dy
    return FarResponse(z, float(shape.pressure.sum()) * grid.dx * grid.dy,
                       float(np.sum(z * R)) * cell, float(np.sum(R)) * cell)


def _on_global_cells(grid: Grid, win: Grid, j_lo: int, m: int, p_w: np.ndarray) -> np.ndarray:
    """A window pressure field as pressures on the global grid's cells (the same force per
    cell; window cells beyond the global grid across rolling are dropped: the far field sees
    them from at least a window margin away, where that is a shift of < one global cell)."""
    out = np.zeros(grid.shape)
    i = np.floor((win.x - (grid.x[0] - 0.5 * grid.dx)) / grid.dx).astype(int)
    ok = (i >= 0) & (i < grid.shape[0])
    cols = p_w.reshape(p_w.shape[0], -1, m).sum(axis=2)           # m sub-columns per column
    np.add.at(out, (i[ok], slice(j_lo, j_lo + cols.shape[1])), cols[ok])
    return out * (win.dx * win.dy) / (grid.dx * grid.dy)


def outside_solve(scene: Scene, fid: Fidelity, q_load: float, kappa: float,
                  stats: SolveStats) -> tuple[float, float, float]:
    """From a global no-defect solve only: the maximum pressure outside the read strip (Pa),
    the approach (m) and the contact area (m^2).

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

    Returns
    -------
    tuple of (float, float, float)
        ``(p_out, approach, area)`` in Pa, m, m^2.
    """
    a, s, dxw, dyw, xh, yd, hy_read, hy = window_spec(scene, fid, q_load, kappa)
    grid, sol = global_solve(scene, fid, q_load, global_extent(fid, kappa, a), stats)
    gstrip = np.abs(grid.y - yd) <= hy_read + 1e-12
    p_out = float(sol.pressure[:, ~gstrip].max()) if np.any(~gstrip) else 0.0
    return p_out, float(sol.approach), float(sol.contact_area)


def outside_max(scene: Scene, fid: Fidelity, q_load: float, kappa: float,
                stats: SolveStats) -> float:
    """Maximum no-defect pressure outside the read strip from a global solve only (Pa).

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

    Returns
    -------
    float
        The pressure (Pa).
    """
    return outside_solve(scene, fid, q_load, kappa, stats)[0]


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


def defect_solve(scene: Scene, fid: Fidelity, node: LoadNode, x_d: float, stats: SolveStats,
                  p_init=None) -> DefectSolve:
    """Window solve with the defect at offset ``x_d`` under the no-defect window approach.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    fid : Fidelity
        The fidelity.
    node : LoadNode
        The load's no-defect solves (:func:`solve_load`).
    x_d : float
        Defect offset from the contact centre (m).
    stats : SolveStats
        Counters.
    p_init : numpy.ndarray, optional
        Warm start: a pressure field (Pa) of the grid's shape.

    Returns
    -------
    DefectSolve
        Pressure, peaks, removed force and area change, with the strips' results.
    """
    win = node.window
    g = gap_field(scene, win, x_d) + node.u_ext
    kw = dict(tol=fid.tol, max_iter=fid.max_iter, approach=node.approach, boundary="ignore",
              element=fid.element, hardness=scene.material.hardness_pa)
    e_star = scene.material.e_star_pa
    try:
        # A warm start that converges does so in tens of iterations; one that stalls would use
        # all of max_iter (measured: 4 stalled solves took 73 % of a fine case's solver time),
        # so the warm attempt gets a short budget before the retries below.
        warm = dict(kw, max_iter=min(fid.max_iter, WARM_START_MAX_ITER))
        p = window_solve(node, g, stats, e_star,
                         node.p_window0 if p_init is None else p_init, **warm)
    except ContactConvergenceError:
        # a warm start from a neighbour with another contact set can stall Polonsky-Keer:
        # retry from the no-defect window solution, then cold
        try:
            p = window_solve(node, g, stats, e_star, node.p_window0, **kw)
        except ContactConvergenceError:
            p = window_solve(node, g, stats, e_star, None, **kw)
    cell = win.dx * win.dy
    strips = []
    if fid.rim_dx_um or fid.end_dy_um:
        strips, p = _strip_schwarz(scene, fid, node, x_d, g, p, stats)
    if not strips:
        W = float(p[:, node.strip].max())
        Pd = neighbourhood_max(scene, fid, win, p, x_d)
        dF = float(node.p_window0.sum() - p.sum()) * cell - far_uptake(node, p)
        dA = float(np.count_nonzero(p > 0)) * cell - node.area_window0
        return DefectSolve(max(W, node.outside_max), Pd, p, dF, dA, W)
    # parent cells a strip owns count through the strip's force and area; the parent is read
    # for peaks except in the strips' read zones, where the strips are read
    owned = np.zeros(win.shape, bool)
    unread = np.zeros(win.shape, bool)
    force, area = 0.0, 0.0
    W, Pd = 0.0, 0.0
    for st in strips:
        owned |= st.own
        unread |= st.parent_read
        cc = st.grid.dx * st.grid.dy
        ps = st.pressure[st.fine_count]
        force += float(ps.sum()) * cc
        area += float(np.count_nonzero(ps > 0)) * cc
        pr = np.where(st.read, st.pressure, 0.0)
        W = max(W, float(pr[:, st.columns(node.strip)].max(initial=0.0)))
        Pd = max(Pd, neighbourhood_max(scene, fid, st.grid, pr, x_d))
    pp = np.where(unread, 0.0, p)
    W = max(W, float(pp[:, node.strip].max()))
    Pd = max(Pd, neighbourhood_max(scene, fid, win, pp, x_d))
    force += float(p[~owned].sum()) * cell
    area += float(np.count_nonzero(p[~owned] > 0)) * cell
    f0, a0, p0 = float(node.p_window0.sum()) * cell, node.area_window0, node.p_window0
    if any(st.axis == 1 for st in strips):
        f0, a0, p0 = _end_reference(scene, fid, node, stats)
    dF = f0 - force - far_uptake(node, p, p0)
    dA = area - a0
    return DefectSolve(max(W, node.outside_max), Pd, p, dF, dA, W)


def _end_reference(scene: Scene, fid: Fidelity, node: LoadNode,
                   stats: SolveStats) -> tuple[float, float, np.ndarray]:
    """Force (N), contact area (m^2) and window field (Pa) of the no-defect window with its
    axial end strips, solved once per load node (cached in ``node.end_ref``) with the same
    alternation (:func:`_strip_schwarz`, no rim strips): the removed force is counted from it,
    so that the difference of the two axial spacings is not (measured without it: 0.036 N, 10 %
    of the removed force, at 750 kN / 20 um, Q = 120 kN)."""
    if "ref" not in node.end_ref:
        win = node.window
        cell = win.dx * win.dy
        g0 = gap_field(scene, win, None) + node.u_ext
        strips, p = _strip_schwarz(scene, dataclasses.replace(fid, rim_dx_um=None), node, None,
                                   g0, node.p_window0, stats)
        owned = np.zeros(win.shape, bool)
        force = float(node.p_window0.sum()) * cell if not strips else 0.0
        area = node.area_window0 if not strips else 0.0
        for st in strips:
            owned |= st.own
            cc = st.grid.dx * st.grid.dy
            force += float(st.pressure[st.fine_own].sum()) * cc
            area += float(np.count_nonzero(st.pressure[st.fine_own] > 0)) * cc
        if strips:
            force += float(p[~owned].sum()) * cell
            area += float(np.count_nonzero(p[~owned] > 0)) * cell
        node.end_ref["ref"] = (force, area, p)
    return node.end_ref["ref"]


def far_uptake(node: LoadNode, p: np.ndarray, p0: np.ndarray | None = None) -> float:
    """Force (N) the far field takes up at fixed approach when the window's pressure goes from
    the no-defect ``p0`` (default ``p_window0``) to ``p`` (:class:`FarResponse`); 0 with a
    frozen far field.

    Parameters
    ----------
    node : LoadNode
        The load node whose window and far-field response are used.
    p : numpy.ndarray
        The window's pressure (Pa), window shape.
    p0 : numpy.ndarray, optional
        The no-defect pressure (Pa) it is compared with (default ``node.p_window0``).

    Returns
    -------
    float
        The force (N).
    """
    if node.far is None:
        return 0.0
    return node.far.uptake(p - (node.p_window0 if p0 is None else p0),
                           node.window.dx * node.window.dy)


@dataclass
class RimStrip:
    """One refined strip of the defect window (internal): the window's parent cells ``i0:i1``
    along ``axis`` (0: rows, a rim strip across rolling; 1: columns, an axial end strip) solved
    again on ``grid``, ``m`` sub-cells per parent cell along ``axis`` (the same cells along the
    other). ``own``: the parent cells it replaces (bool, window shape; an end strip leaves the
    rim strips' rows to them); ``read``: its cells read for results (bool, ``grid`` shape);
    ``parent_read``: the parent cells those cover (bool, window shape)."""

    i0: int
    i1: int
    grid: Grid
    pressure: np.ndarray
    read: np.ndarray
    parent_read: np.ndarray
    axis: int = 0
    m: int = 1
    own: np.ndarray | None = None
    #: window columns ``j0:j1`` a rim strip (axis 0) spans: the read strip and a margin
    #: (:func:`_rim_columns`); ``j1`` None = every column
    j0: int = 0
    j1: int | None = None
    #: the parent cells whose force and area it counts and whose mean the window holds
    #: (``own`` but where an end strip crosses a rim strip: the end strip's); None = ``own``
    count: np.ndarray | None = None

    @property
    def counted(self) -> np.ndarray:
        """The parent cells (bool, window shape) whose force and area this strip counts."""
        return self.own if self.count is None else self.count

    @property
    def fine_count(self) -> np.ndarray:
        """``counted`` on the strip's cells."""
        return np.repeat(self.counted[self.slab], self.m, axis=self.axis)

    @property
    def slab(self) -> tuple[slice, slice]:
        """The parent cells of the strip (index into the window)."""
        s = slice(self.i0, self.i1)
        return (s, slice(self.j0, self.j1)) if self.axis == 0 else (slice(None), s)

    @property
    def fine_own(self) -> np.ndarray:
        """``own`` on the strip's cells."""
        return np.repeat(self.own[self.slab], self.m, axis=self.axis)

    def columns(self, parent_cols: np.ndarray) -> np.ndarray:
        """A bool over the window's columns as one over the strip's columns.

        Parameters
        ----------
        parent_cols : numpy.ndarray
            Bool over the window's columns.

        Returns
        -------
        numpy.ndarray
            Bool over the strip's columns.
        """
        return np.repeat(parent_cols[self.slab[1]], self.m if self.axis == 1 else 1)

    def coarse(self) -> np.ndarray:
        """The strip's pressure averaged over each parent cell (shape of ``own[slab]``).

        Returns
        -------
        numpy.ndarray
            Mean pressure (Pa) per parent cell.
        """
        p = self.pressure
        if self.axis == 0:
            return p.reshape(-1, self.m, p.shape[1]).mean(axis=1)
        return p.reshape(p.shape[0], -1, self.m).mean(axis=2)


#: Strips and window are solved alternately (block Gauss-Seidel on the sets of cells, each
#: under the others' displacement) until the window force changes by less than this
#: (relative) between passes ...
RIM_SCHWARZ_TOL = 1e-4
#: ... or this many passes.
RIM_SCHWARZ_MAX = 8


def _strip_schwarz(scene: Scene, fid: Fidelity, node: LoadNode, x_d: float, g: np.ndarray,
                   p: np.ndarray, stats: SolveStats) -> tuple[list[RimStrip], np.ndarray]:
    """Alternate the strips (:func:`_refine_strips`: rim strips across rolling, axial end
    strips) and the window without the strips' cells (their pressure, averaged over each parent
    cell, imposed as a displacement) until the window's force settles (:data:`RIM_SCHWARZ_TOL`).
    A single pass over-estimates the force: the strips' resolved rim pressure would not unload
    the cells around them (measured: the removed force 1 % low after one pass at 500 kN /
    50 um). Returns the strips and the window pressure (the strips' cells hold their
    parent-cell means)."""
    win = node.window
    cell = win.dx * win.dy
    e_star = scene.material.e_star_pa
    f_old = float(p.sum()) * cell
    strips: list[RimStrip] = []
    kw = dict(tol=fid.tol, max_iter=fid.max_iter, approach=node.approach, boundary="ignore",
              element=fid.element, hardness=scene.material.hardness_pa)
    for _pass in range(RIM_SCHWARZ_MAX):
        strips = _refine_strips(scene, fid, node, x_d, p, stats)
        if not strips:
            return strips, p
        p_s = np.zeros_like(p)
        owned = np.zeros(win.shape, bool)
        for st in strips:
            p_s[st.slab] = np.where(st.counted[st.slab], st.coarse(), p_s[st.slab])
            owned |= st.own
        g2 = g + node.halfspace.displacement(p_s)
        g2[owned] = np.inf
        p_w = np.where(owned, 0.0, p)
        try:
            p_new = window_solve(node, g2, stats, e_star, p_w, **kw)
        except ContactConvergenceError:
            p_new = window_solve(node, g2, stats, e_star, None, **kw)
        p = np.where(owned, p_s, p_new)
        f_new = float(p.sum()) * cell
        if abs(f_new - f_old) <= RIM_SCHWARZ_TOL * max(f_new, 1e-300):
            break
        f_old = f_new
    return strips, p


def _intervals(centre: float, half: float, r: float, b: float, edge0: float, d: float, n: int,
               keep=lambda edge: True) -> list[tuple[int, int]]:
    """Parent-cell ranges ``[i0, i1)`` along one axis of the strips around the two edges
    ``centre +- half`` of a footprint: each rim zone (``r`` inside the edge) grown by ``b`` on
    each side, widened to whole cells of size ``d`` (the first cell's lower edge at ``edge0``,
    ``n`` cells); overlapping strips merge; an edge ``keep`` rejects has no strip."""
    out = []
    for edge, lo, hi in ((centre - half, centre - half - b, centre - half + r + b),
                         (centre + half, centre + half - r - b, centre + half + b)):
        if not keep(edge):
            continue
        i0 = int(np.clip(math.floor((lo - edge0) / d + 1e-9), 0, n))
        i1 = int(np.clip(math.ceil((hi - edge0) / d - 1e-9), 0, n))
        if i1 > i0:
            if out and i0 <= out[-1][1]:
                out[-1] = (out[-1][0], max(out[-1][1], i1))
            else:
                out.append((i0, i1))
    return out


def _rim_radius(scene: Scene, half: float) -> float:
    """The rim zone inside a footprint edge: the edge radius of a flat defect, else the whole
    half-extent (a dent or a round pit changes depth everywhere)."""
    d = scene.defect
    return min(1e-6 * d.edge_radius_um, half) if d.shape == "flat" else half


def _rim_intervals(scene: Scene, fid: Fidelity, win: Grid, x_d: float) -> list[tuple[int, int]]:
    """Window-row ranges of the rim strips across rolling (around ``x_d +- w_x/2``)."""
    hx = 0.5 * scene.defect.extent_x_m
    return _intervals(x_d, hx, _rim_radius(scene, hx), fid.rim_strip_m,
                      win.x[0] - 0.5 * win.dx, win.dx, win.shape[0])


#: Window cells (axially) a rim strip reaches beyond the read strip on each side: the strip's
#: own boundary there (0.5 um cells against the window's 2 um) stays clear of every cell read.
RIM_BOX_MARGIN_CELLS = 2


def _rim_columns(node: "LoadNode") -> tuple[int, int]:
    """Window columns ``[j0, j1)`` of the rim strips: the read strip (the defect's axial extent
    and the neighbourhood, ``node.strip``) and :data:`RIM_BOX_MARGIN_CELLS` each side. Until
    issue 33 the strips spanned every window column: 3x the cells for the CWRU ball pit, the
    refined rows far from the defect read nowhere."""
    cols = np.flatnonzero(node.strip)
    if not cols.size:
        return 0, node.window.shape[1]
    return (max(0, int(cols[0]) - RIM_BOX_MARGIN_CELLS),
            min(node.window.shape[1], int(cols[-1]) + 1 + RIM_BOX_MARGIN_CELLS))


def end_intervals(scene: Scene, fid: Fidelity, win: Grid) -> list[tuple[int, int]]:
    """Window-column ranges of the axial end strips (around ``y_d +- w_y/2``). An end on or
    beyond a roller end (a defect spanning the roller) or outside the window has none.

    Parameters
    ----------
    scene : Scene
        The scene (defect extent and axial position, roller length).
    fid : Fidelity
        The fidelity (``end_strip_um``).
    win : Grid
        The defect window.

    Returns
    -------
    list of tuple of (int, int)
        ``(first, end)`` column ranges of the window, one per axial end that gets a strip.
    """
    d = scene.defect
    hy = 0.5 * d.extent_y_m
    y0, y1 = win.y[0] - 0.5 * win.dy, win.y[-1] + 0.5 * win.dy
    half = scene.bearing.half_length_m

    def inside(edge):
        return abs(edge) < half and y0 < edge < y1

    return _intervals(1e-3 * d.axial_position_mm, hy, _rim_radius(scene, hy), fid.end_strip_m,
                      y0, win.dy, win.shape[1], inside)


def _refine_strips(scene: Scene, fid: Fidelity, node: LoadNode, x_d: float, p: np.ndarray,
                   stats: SolveStats) -> list[RimStrip]:
    """Solve the rim strips (``fid.rim_dx_um``) and the axial end strips (``fid.end_dy_um``)
    under the window's displacement (:func:`_solve_strip`). Where they cross, both solve the
    cells (each under the other's mean pressure elsewhere): the end strip counts their force and
    area (the axial end resolved; a narrow defect's rim strips cover its whole footprint across
    rolling, and on four small scenes the removed force was 0.06-1.3 % from a uniform window at
    the end strips' spacing this way, 0.6-3.2 % with the crossings left to the rim strips); the
    peaks there are read from the rim strip (the rim peak needs its spacing across rolling)."""
    win = node.window
    out: list[RimStrip] = []
    if not scene.defect.active:
        return out
    m_end = int(math.ceil(win.dy / fid.end_dy_m - 1e-9)) if fid.end_dy_um else 1
    ends = end_intervals(scene, fid, win) if m_end >= 2 else []
    rims = _rim_intervals(scene, fid, win, x_d) if fid.rim_dx_um else []
    rows = np.zeros(win.shape[0], bool)
    for i0, i1 in rims:
        rows[i0:i1] = True
    cols = np.zeros(win.shape[1], bool)
    for j0, j1 in ends:
        cols[j0:j1] = True
    j0, j1 = _rim_columns(node)
    for i0, i1 in rims:
        own = np.zeros(win.shape, bool)
        own[i0:i1, j0:j1] = True
        st = _solve_strip(scene, fid, node, x_d, p, 0, i0, i1,
                          int(round(fid.local_dx_um / fid.rim_dx_um)), own, fid.rim_strip_m, stats,
                          (j0, j1))
        if st is not None and cols.any():
            st.count = own.copy()
            st.count[:, cols] = False
        out.append(st)
    for j0, j1 in ends:
        own = np.zeros(win.shape, bool)
        own[:, j0:j1] = True
        st = _solve_strip(scene, fid, node, x_d, p, 1, j0, j1, m_end, own, fid.end_strip_m, stats)
        if st is not None and rows.any():
            # the rim peak is read from the rim strips only (the end strip's 2 um rows put it
            # 2.8 % above a uniform 5 um window at 750 kN / 20 um, defect at the contact edge)
            st.read &= ~rows[:, None]
            st.parent_read &= ~rows[:, None]
        out.append(st)
    return [st for st in out if st is not None]


def _solve_strip(scene: Scene, fid: Fidelity, node: LoadNode, x_d: float, p: np.ndarray,
                 axis: int, i0: int, i1: int, m: int, own: np.ndarray, b: float,
                 stats: SolveStats, cols: tuple[int, int] | None = None) -> RimStrip | None:
    """Solve one strip: the window's parent cells ``i0:i1`` along ``axis``, each split into
    ``m`` along it, under the window's displacement, at the window's approach.

    The displacement of everything outside the strip's own cells is exact at the strip's
    cells: the window pressure there (the other strips' cells hold their parent-cell means),
    each parent cell split into ``m`` sub-cells carrying the same pressure (a uniform patch is
    the sum of its parts), convolved at the strip's spacing, plus the window's far field
    ``u_ext`` (interpolated linearly along ``axis``, as the window does with the global
    solve). Cells of the strip it does not own are not solved (another strip's). Returns None
    when the strip has no contact. Results are read only half the margin ``b`` away from the
    strip's ends along ``axis`` (where the nested boundary is)."""
    win = node.window
    e_star = scene.material.e_star_pa
    j0, j1 = cols if cols is not None and axis == 0 else (0, None)
    st = RimStrip(i0, i1, win, np.empty(0), np.empty(0), np.empty(0), axis, m, own, j0=j0, j1=j1)
    if not np.any(p[own] > 0):
        return None
    d = (win.dx, win.dy)[axis] / m
    c_par = (win.x, win.y)[axis]
    c = c_par[i0] - 0.5 * m * d + (np.arange((i1 - i0) * m) + 0.5) * d
    fine_shape = list(win.shape)
    fine_shape[axis] *= m
    ks = range(win.shape[1])[j0:j1]
    if axis == 0:
        fine = Grid(np.zeros(fine_shape[0]), win.y, d, win.dy)
        grid = Grid(c, win.y[j0:j1], d, win.dy)
        u_far = np.stack([np.interp(c, win.x, node.u_ext[:, k]) for k in ks], 1)
    else:
        fine = Grid(win.x, np.zeros(fine_shape[1]), win.dx, d)
        grid = Grid(win.x, c, win.dx, d)
        u_far = np.stack([np.interp(c, win.y, node.u_ext[k]) for k in range(win.shape[0])], 0)
    sl_f = [slice(None), slice(j0, j1)]
    sl_f[axis] = slice(i0 * m, i1 * m)
    p_rest = np.where(own, 0.0, p)
    if axis == 0 and node.rows is not None:
        # the same displacement at the strip's cells from the loaded rows and the strip's only,
        # by m convolutions on the window's grid (subcell_displacement)
        lo, hi = _near_rows(node, p_rest, i0, i1)
        u_near = subcell_displacement(p_rest[lo:hi], win.dx, win.dy, e_star, m,
                                      rows=(i0 - lo, i1 - lo))[:, j0:j1]
    else:
        u_near = _halfspace(fine, e_star, "scipy").displacement(
            np.repeat(p_rest, m, axis=axis))[tuple(sl_f)]
    fo = st.fine_own
    g = np.where(fo, gap_field(scene, grid, x_d), np.inf)
    u = u_near + u_far
    u[~np.isfinite(g)] = 0.0
    kw = dict(tol=fid.tol, max_iter=fid.max_iter, approach=node.approach, boundary="ignore",
              halfspace=_halfspace(grid, e_star, "auto"), hardness=scene.material.hardness_pa)
    try:
        sol = stats.solve(g + u, grid.dx, grid.dy, None, e_star,
                          p_init=np.where(fo, np.repeat(p[st.slab], m, axis=axis), 0.0), **kw)
    except ContactConvergenceError:
        sol = stats.solve(g + u, grid.dx, grid.dy, None, e_star, p_init=None, **kw)
    lo, hi = c[0] - 0.5 * d + 0.5 * b, c[-1] + 0.5 * d - 0.5 * b
    read1 = (c >= lo) & (c <= hi)
    dp = (win.dx, win.dy)[axis]
    pread1 = (c_par - 0.5 * dp >= lo - 1e-12) & (c_par + 0.5 * dp <= hi + 1e-12)
    # parent cells not fully inside the read zone stay read from the parent
    shape1 = (-1, 1) if axis == 0 else (1, -1)
    read = fo & (np.repeat(pread1[i0:i1], m) & read1).reshape(shape1)
    parent_read = own & pread1.reshape(shape1)
    st.grid, st.pressure, st.read, st.parent_read = grid, sol.pressure, read, parent_read
    return st


def _near_rows(node: LoadNode, p_rest: np.ndarray, i0: int, i1: int) -> tuple[int, int]:
    """Window rows ``[lo, hi)`` holding every loaded row of ``p_rest`` and the strip's rows
    ``i0:i1``, grown to the node's contact rows plus the strip's length where the window allows
    (one grid size per node and strip length: its kernel spectrum is computed once), to a
    fast row count (:func:`fast_rows`)."""
    n = p_rest.shape[0]
    nz = np.flatnonzero((p_rest != 0).any(axis=1))
    lo = min(i0, int(nz[0])) if nz.size else i0
    hi = max(i1, int(nz[-1]) + 1) if nz.size else i1
    r0, r1 = node.rows
    length = fast_rows(max(hi - lo, (r1 - r0) + (i1 - i0)), n)
    length = max(length, hi - lo)
    hi = min(n, lo + length)
    return hi - length, hi


def neighbourhood_max(scene: Scene, fid: Fidelity, win: Grid, p: np.ndarray, x_d: float) -> float:
    """The largest pressure (Pa) in the defect's neighbourhood (its footprint plus
    ``fid.neighbourhood_um`` on every side) of the window field ``p``; 0 when none of it is in
    the window.

    Parameters
    ----------
    scene : Scene
        The case's scene (the defect's footprint).
    fid : Fidelity
        The fidelity (``neighbourhood_um``).
    win : Grid
        The window.
    p : numpy.ndarray
        The window's pressure (Pa).
    x_d : float
        Defect offset (m).

    Returns
    -------
    float
        The pressure (Pa).
    """
    d = scene.defect
    nb = fid.neighbourhood_m
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
