"""The global no-defect solve over the whole roller (its grid grown until the contact fits, looked
up in the no-defect cache), the far field it leaves on the defect window, the window's size
(:func:`window_spec`) and the solves that need no window (:func:`outside_solve`,
:func:`outside_max`)."""

from __future__ import annotations

import math

import numpy as np

from ...contact import ContactGridError, ElasticHalfSpace
from ..fidelity import Fidelity
from ..geometry import Grid, gap_field, hertz_estimate, make_grid
from ..nodefect_cache import GlobalSolution, global_key
from ..scene import Scene
from .stats import SolveStats

__all__ = ["GlobalGridError", "global_solve", "outside_max", "outside_solve", "window_spec"]


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
