"""Refined strips of the defect window: rim strips across rolling and axial end strips
(:class:`RimStrip`), solved alternately with the window (block Gauss-Seidel), where they lie
(:func:`end_intervals`), and the maximum pressure near the defect (:func:`neighbourhood_max`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...contact import ContactConvergenceError
from ...contact.halfspace import subcell_displacement
from ..fidelity import Fidelity
from ..geometry import Grid, gap_field
from ..scene import Scene
from .global_solve import _halfspace
from .load_node import LoadNode
from .stats import SolveStats
from .windows import fast_rows, window_solve

__all__ = ["RimStrip", "neighbourhood_max", "end_intervals"]


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
