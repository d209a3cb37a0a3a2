"""The defect contact law of the dynamic model: the total force ``F(x, delta)`` of one
element's contact with a pitted race, from the project's own boundary-element solutions
(issue 42 part 1), and the defect's characteristic scales (issue 42 part 3).

Model
-----
An element whose centre sits at ``x`` (m, along rolling, from the pit centre) is pressed onto
the race by the rigid approach ``delta`` (m, measured from the healthy surface's first point of
contact). The initial gap is the scene's (:func:`~bearing_envelope.physics.geometry.gap_field`:
the contact's curvature, the groove or roller profile with its ends, and the pit's depth
averaged over each cell) with the pit centred at ``-x`` from the contact centre. Every node
of the table is one frictionless contact solve (:func:`~bearing_envelope.contact.solve_contact`,
Polonsky-Keer) **under displacement control**: the approach is prescribed and the force is the
solution's, so the table is tabulated directly in ``delta`` and no ``Q(delta)`` inversion is
needed. Two exact reductions keep it cheap:

- **the rigid overlap bounds the contact**: a cell whose no-defect gap is ``>= delta`` can carry
  no pressure (``h = g + K p - delta >= g - delta >= 0`` since ``K p >= 0``; a pit only widens
  the gap), so each approach is solved on the grid's cells inside the bounding box of
  ``{g0 < delta}`` plus :data:`OVERLAP_MARGIN_CELLS` (the whole table's grid is that box at the
  largest approach);
- **a pit outside the healthy contact changes nothing**: where the pit's added depth is zero on
  every cell of the no-defect contact set at ``delta``, the no-defect pressure still satisfies
  complementarity with the new gap (which only grew where the pressure is 0), so it is the
  solution: the force is the healthy one exactly, no solve. The entry and exit edges are thus
  where the pit's footprint meets the healthy contact, ``|x| = w_x/2 + a_x(delta)``.

The frictionless quasi-static normal contact is even in ``x`` for the symmetric pit shapes
(``flat``, ``dent``, ``cylinder``): ``x >= 0`` is solved and mirrored (entry = exit).

Reading the table (what the dynamic model does): bilinear in ``(x, delta)`` inside the ``x``
range, Hertz ``K delta^1.5`` outside it (``K`` of :func:`hertz_constant`); above the largest
approach the last two approach nodes are extrapolated linearly; ``F = 0`` for ``delta <= 0``.
:meth:`DefectContactTable.force` is that reading.

The defect's characteristic scales (:func:`defect_scales`, :func:`hertz_constant`,
:func:`rigid_drop`, :func:`element_mass`, :func:`tabulated_race`) live in
:mod:`.defect_scales` and are re-exported here.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..contact import ContactConvergenceError, ElasticHalfSpace, hertz
from .defect_scales import (DefectScales, defect_scales, element_mass, hertz_constant,
                            rigid_drop, tabulated_race)
from .fidelity import DEFAULT_PRESET, Fidelity, fidelity_from
from .geometry import Grid, gap_field, good_size, make_grid
from .loads import scene_load_distribution
from .scene import Scene
from .solves import SolveStats

__all__ = ["DefectContactTable", "tabulated_race", "build_defect_table", "defect_table", "defect_force",
           "hertz_constant", "rigid_drop", "table_grid", "DefectScales", "defect_scales",
           "element_mass", "LOAD_FACTOR", "LOCAL_ERROR_FLOOR", "DELTA_NODES_PER_LOAD",
           "OVERLAP_MARGIN_CELLS", "EDGE_MARGIN_NODES", "RIM_CELLS", "TABLE_CACHE_SIZE"]


#: The table reaches the approach of ``LOAD_FACTOR x`` the scene's largest element load on
#: the healthy race, added to the rigid drop into the pit (:func:`rigid_drop`): an element that
#: strikes the exit edge meets loads above the static ones.
LOAD_FACTOR = 4.0
#: Approach nodes per load node of the fidelity (``fid.n_loads``): ``3 n_loads + 1`` nodes
#: (draft 10, standard 16, paper 28), quadratic in the node index (dense near 0, where the force
#: grows as ``delta^1.5``).
DELTA_NODES_PER_LOAD = 3
#: Cells kept on every side of the rigid overlap box of an approach.
OVERLAP_MARGIN_CELLS = 3
#: Offset nodes beyond the largest entry/exit edge (``w_x/2 + a_x(delta_max)``), where the
#: contact is Hertzian again.
EDGE_MARGIN_NODES = 2
#: Iteration budget of a warm-started solve before it is retried cold with ``fid.max_iter``.
WARM_MAX_ITER = 300
#: Pit shapes the mirrored (even in x) table is built for.
SYMMETRIC_SHAPES = ("flat", "dent", "cylinder")


@dataclass(frozen=True, eq=False)
class DefectContactTable:
    """Total contact force of an element over a pit, ``force_n[i, j] = F(x_m[i], delta_m[j])``.

    Attributes
    ----------
    x_m : numpy.ndarray (nx,)
        Element-centre position relative to the pit centre along rolling (m), ascending,
        symmetric about 0; beyond ``|x| = edge_m[-1]`` (the last entry/exit edge) the columns are
        the healthy contact's.
    delta_m : numpy.ndarray (nd,)
        Rigid approach (m), ascending from 0.
    force_n : numpy.ndarray (nx, nd)
        Total contact force (N), ``>= 0``, non-decreasing in ``delta`` at every ``x``.
    healthy_force_n : numpy.ndarray (nd,)
        The no-defect solve's force at each approach (N), on the same grid.
    edge_m : numpy.ndarray (nd,)
        Entry/exit edge per approach, ``w_x/2 + a_x`` with ``a_x`` the healthy solve's contact
        half-width along rolling (m; the extent of its loaded cells).
    hertz_k : float
        Closed-form Hertz constant ``K`` of ``F = K delta^1.5`` for this contact (N m^-1.5).
    element, race : str
        ``ball`` | ``roller``; the race whose contact is tabulated (``inner`` | ``outer``).
    pit : dict
        The pit: ``location``, ``shape``, ``width_um`` (along rolling), ``length_um`` (axial),
        ``depth_um``, ``edge_radius_um`` (not where it sits on its race: the law does not
        depend on it).
    fidelity : str
        Preset name the solves used.
    tol : float
        Solver tolerance (relative, :func:`~bearing_envelope.contact.solve_contact`).
    grid_dx_m, grid_dy_m : float
        Cell sizes of the solves (m).
    hardness_pa : float or None
        Pressure bound of the solves (Pa), None = elastic.
    rigid_drop_m : float
        Approach at which a rigid element centred over the pit first touches (m).
    discretisation_error : float
        Largest ``|F_healthy / (K delta^1.5) - 1|`` over the approach nodes whose healthy
        contact's half-widths span at least 10 cells along both axes (NaN if none; rollers
        whose contact reaches the roller ends are not Hertzian and report it too).
    interpolation_error : float
        Largest ``|F_bilinear - F_direct|`` at the check points (cell midpoints), relative to
        the healthy force at the point's approach, over the points where that force is at
        least :data:`LOCAL_ERROR_FLOOR` of the table's largest (NaN if none).
    interpolation_error_of_max : float
        The same error relative to the table's largest force.
    checks : tuple
        ``(x, delta, F_direct, F_bilinear)`` per check point (m, m, N, N).
    cpu_s : float
        Process CPU time of the build (s), checks included.
    n_solves : int
        Contact solves made (skipped nodes not counted).
    """

    x_m: np.ndarray
    delta_m: np.ndarray
    force_n: np.ndarray
    healthy_force_n: np.ndarray
    edge_m: np.ndarray
    hertz_k: float
    element: str
    race: str
    pit: dict
    fidelity: str
    tol: float
    grid_dx_m: float
    grid_dy_m: float
    hardness_pa: float | None
    rigid_drop_m: float
    discretisation_error: float = math.nan
    interpolation_error: float = math.nan
    interpolation_error_of_max: float = math.nan
    checks: tuple = ()
    cpu_s: float = 0.0
    n_solves: int = 0
    info: dict = field(default_factory=dict)

    def force(self, x, delta, *, outside: str | None = None) -> np.ndarray:
        """The dynamic model's reading: bilinear inside the ``x`` range, Hertz outside.

        Parameters
        ----------
        x : array_like
            Element-centre position from the pit centre (m).
        delta : array_like
            Rigid approach (m), broadcast with ``x``.
        outside : {"hertz", "healthy"}, optional
            The law beyond the ``x`` range: ``K delta^1.5`` (closed form), or the healthy solve
            ``healthy_force_n`` read linearly in ``delta`` (continuous with the table's edge
            columns). Default: ``hertz`` for a ball, ``healthy`` for a roller (whose contact
            leaves Hertz once it reaches the roller ends: 22 % below ``K delta^1.5`` at 172 kN
            in the default scene).

        Returns
        -------
        numpy.ndarray
            Force (N): 0 for ``delta <= 0``; the ``outside`` law for ``|x| > x_m[-1]``;
            bilinear in the table, the last two approach nodes extrapolated linearly above
            ``delta_m[-1]``.

        Raises
        ------
        ValueError
            ``outside`` is neither ``hertz`` nor ``healthy``.
        """
        if outside is None:
            outside = "hertz" if self.element == "ball" else "healthy"
        if outside not in ("hertz", "healthy"):
            raise ValueError(f"outside: got {outside!r}; allowed: hertz | healthy")
        x, d = np.broadcast_arrays(np.asarray(x, float), np.asarray(delta, float))
        dp = np.clip(d, 0.0, None)
        xs, ds = self.x_m, self.delta_m
        i = np.clip(np.searchsorted(xs, x) - 1, 0, xs.size - 2)
        j = np.clip(np.searchsorted(ds, dp) - 1, 0, ds.size - 2)
        tx = np.clip((x - xs[i]) / (xs[i + 1] - xs[i]), 0.0, 1.0)
        td = (dp - ds[j]) / (ds[j + 1] - ds[j])          # > 1 above the last node: extrapolated
        f = self.force_n
        lo = f[i, j] + td * (f[i, j + 1] - f[i, j])
        hi = f[i + 1, j] + td * (f[i + 1, j + 1] - f[i + 1, j])
        inside = (1.0 - tx) * lo + tx * hi
        h0 = self.healthy_force_n
        far = self.hertz_k * dp ** 1.5 if outside == "hertz" else \
            h0[j] + td * (h0[j + 1] - h0[j])
        out = np.where(np.abs(x) > xs[-1], far, np.clip(inside, 0.0, None))
        return np.where(d > 0.0, out, 0.0)

    def approach(self, x: float, force: float) -> float:
        """The approach (m) at which the element at ``x`` carries ``force`` (N): the inverse of
        :meth:`force` along ``delta`` (monotone), e.g. how far an element under a constant load
        moves in over the pit, ``approach(0, Q) - approach(x_far, Q)``.

        Parameters
        ----------
        x : float
            Element-centre position from the pit centre (m).
        force : float
            Force (N), >= 0.

        Returns
        -------
        float
            The approach (m); above the last node the last two nodes extrapolated linearly
            (as :meth:`force`); for ``force = 0`` the last approach without force.

        Raises
        ------
        ValueError
            ``force`` not a finite number >= 0.
        """
        x, force = float(x), float(force)
        if not (math.isfinite(force) and force >= 0.0):
            raise ValueError(f"force: got {force!r}; allowed: a finite number >= 0")
        if abs(x) > self.x_m[-1] and self.element == "ball":
            return (force / self.hertz_k) ** (2.0 / 3.0)
        row = self.force(x, self.delta_m)
        if force == 0.0:
            return float(self.delta_m[int(np.flatnonzero(row <= 0.0)[-1])])
        i = int(np.clip(np.searchsorted(row, force, side="left"), 1, row.size - 1))
        f1, f2 = row[i - 1], row[i]
        d1, d2 = self.delta_m[i - 1], self.delta_m[i]
        return float(d1 + (force - f1) * (d2 - d1) / (f2 - f1)) if f2 > f1 else float(d2)

    def metadata(self) -> dict:
        """What made the table and its measured errors, JSON-able (for a case file's
        attributes: the model that made a dynamic record).

        Returns
        -------
        dict
            Element, race, pit, fidelity, tolerance, cell sizes (um), hardness (Pa or None),
            node counts, largest approach (um), rigid drop (um), Hertz ``K``, the
            discretisation and interpolation errors, CPU seconds and solves.
        """
        return {"model": "defect_contact_table", "element": self.element, "race": self.race,
                "pit": dict(self.pit), "fidelity": self.fidelity, "tol": self.tol,
                "dx_um": 1e6 * self.grid_dx_m, "dy_um": 1e6 * self.grid_dy_m,
                "hardness_pa": self.hardness_pa, "n_x": int(self.x_m.size),
                "n_delta": int(self.delta_m.size), "delta_max_um": 1e6 * float(self.delta_m[-1]),
                "x_max_um": 1e6 * float(self.x_m[-1]), "rigid_drop_um": 1e6 * self.rigid_drop_m,
                "hertz_k": self.hertz_k, "discretisation_error": self.discretisation_error,
                "interpolation_error": self.interpolation_error,
                "interpolation_error_of_max": self.interpolation_error_of_max,
                "cpu_s": self.cpu_s, "n_solves": self.n_solves}

    def resume_approach(self, x: float = 0.0) -> float:
        """Approach (m) at which the element at ``x`` regains contact: the zero of
        ``F^(2/3)``, linear between the first two approach nodes with force at the nearest
        tabulated ``x`` (each edge contact grows about as ``(delta - delta_0)^1.5``); the last
        force-free node when only one node carries force; NaN when none does.

        Parameters
        ----------
        x : float
            Element-centre position (m).

        Returns
        -------
        float
            The approach (m).
        """
        row = self.force_n[int(np.argmin(np.abs(self.x_m - x)))]
        on = np.flatnonzero(row > 0.0)
        if not on.size:
            return math.nan
        k = int(on[0])
        if k + 1 >= row.size or k == 0:
            return float(self.delta_m[max(k - 1, 0)])
        d1, d2 = self.delta_m[k], self.delta_m[k + 1]
        s1, s2 = row[k] ** (2.0 / 3.0), row[k + 1] ** (2.0 / 3.0)
        d0 = d1 - s1 * (d2 - d1) / (s2 - s1) if s2 > s1 else d1
        return float(min(max(d0, self.delta_m[k - 1]), d1))


# ---------------------------------------------------------------------------------------------
# geometry of the table


#: Cells across a rounded rim's radius (``edge_radius_um``): the spacing is capped at
#: ``r / RIM_CELLS`` across rolling, and along the axis for a ball (whose round pit holds it on
#: the pit's axial sides). Measured on the 6205's 0.021 in round pit (20 um rims, draft): the
#: force at the pit centre moved 16 % when the axial cells went from 25 to 12.5 um and 0.5 %
#: from 12.5 to 6.25 um; halving the cells across rolling moved it < 0.1 %.
RIM_CELLS = 2


def table_grid(scene: Scene, fid: Fidelity, delta_max: float) -> Grid:
    """The solves' grid: the rigid overlap box ``{g0 < delta_max}`` and
    :data:`OVERLAP_MARGIN_CELLS` cells, at ``dx = min(local_dx, w_x/4)``,
    ``dy = min(local_dy, w_y/6)`` (the zoom window's spacing rule), both capped at
    ``edge_radius / RIM_CELLS`` (``dy`` for balls only: :data:`RIM_CELLS`), axially at most the
    roller/groove length and one cell.

    Parameters
    ----------
    scene : Scene
        The scene (curvatures, profile, pit footprint).
    fid : Fidelity
        Spacings.
    delta_max : float
        Largest approach (m).

    Returns
    -------
    Grid
        Cell-centred grid, symmetric about the contact centre.
    """
    b, d = scene.bearing, scene.defect
    dx, dy = fid.local_dx_m, fid.local_dy_m
    if d.active:
        dx, dy = min(dx, d.extent_x_m / 4.0), min(dy, d.extent_y_m / 6.0)
        if d.shape in ("flat", "cylinder") and d.edge_radius_um > 0:
            rim = 1e-6 * d.edge_radius_um / RIM_CELLS
            dx = min(dx, rim)
            dy = min(dy, rim) if b.kind == "ball" else dy
    hx = math.sqrt(2.0 * b.rx_m * delta_max) + OVERLAP_MARGIN_CELLS * dx
    hy = b.half_length_m + dy
    if math.isfinite(b.ry_m) and not b.profile_file:   # s(y) >= y^2/(2 R_y): crown and relief
        hy = min(hy, math.sqrt(2.0 * b.ry_m * delta_max) + OVERLAP_MARGIN_CELLS * dy)
    return make_grid(-hx, hx, -hy, hy, dx, dy, y_center=0.0)


def _crop(g0: np.ndarray, delta: float) -> tuple[slice, slice]:
    """Rows and columns of the bounding box of ``{g0 < delta}`` and the margin, symmetric about
    the grid's centre, each half a 5-smooth count of cells (fast FFT lengths)."""
    over = g0 < delta
    if over[[0, -1], :].any() or over[:, [0, -1]].any():
        raise RuntimeError(f"defect contact grid too small: the healthy gap overlaps its edge at "
                           f"approach {delta:.4g} m")       # pragma: no cover (table_grid bounds it)
    rows = np.flatnonzero(over.any(axis=1))
    cols = np.flatnonzero(over.any(axis=0))
    out = []
    for idx, n in ((rows, g0.shape[0]), (cols, g0.shape[1])):
        half = n // 2
        reach = max(half - int(idx[0]), int(idx[-1]) + 1 - half) if idx.size else 1
        k = min(half, good_size(reach + OVERLAP_MARGIN_CELLS))
        out.append(slice(half - k, half + k))
    return out[0], out[1]


def _delta_nodes(scene: Scene, fid: Fidelity, delta_max: float | None, load_factor: float
                 ) -> tuple[np.ndarray, float]:
    """Approach nodes ``delta_max (k/n)^2``, ``k = 0..n``, and the rigid drop; the default
    ``delta_max`` rounded up to two significant digits."""
    drop = rigid_drop(scene)
    if delta_max is None:
        q = max(float(np.max(scene_load_distribution(scene).load_at(0.0, r)))
                for r in ("inner", "outer"))
        b = scene.bearing
        delta_max = _round_up(drop + hertz.elliptical(load_factor * q, b.rx_m, b.ry_m,
                                                      scene.material.e_star_pa).approach)
    n = DELTA_NODES_PER_LOAD * fid.n_loads
    return delta_max * (np.arange(n + 1) / n) ** 2, drop


def _round_up(v: float) -> float:
    """``v > 0`` rounded up to two significant digits: scenes that differ only slightly (the
    motor load's speed changes the centrifugal force) get the same nodes, and one table
    (:func:`defect_table`)."""
    unit = 10.0 ** (math.floor(math.log10(v)) - 1)
    return unit * math.ceil(v / unit - 1e-9)


def _x_nodes(scene: Scene, fid: Fidelity, grid: Grid, a_max: float) -> np.ndarray:
    """Offsets ``x >= 0``: multiples of the grid's ``dx`` (the pit sits the same way on every
    cell), spaced ``<= min(offset_step, w_x / offsets_per_width)``, to
    ``w_x/2 + a_max`` and :data:`EDGE_MARGIN_NODES` more."""
    ex = scene.defect.extent_x_m
    step = grid.dx * max(1, round(min(fid.offset_step_um * 1e-6, ex / fid.offsets_per_width)
                                  / grid.dx))
    n = int(math.ceil((0.5 * ex + a_max) / step)) + EDGE_MARGIN_NODES
    return step * np.arange(n + 1)


# ---------------------------------------------------------------------------------------------
# the solves


@dataclass
class _Level:
    """One approach of the table (internal): its crop of the grid, half-space operator and
    the healthy solve's pressure, force and contact half-width along rolling."""

    delta: float
    rows: slice
    cols: slice
    halfspace: ElasticHalfSpace | None
    p0: np.ndarray
    f0: float
    a_x: float
    a_y: float = 0.0


def _solve(stats: SolveStats, scene: Scene, fid: Fidelity, grid: Grid, g: np.ndarray,
           hs: ElasticHalfSpace, delta: float, p_init: np.ndarray | None):
    """One displacement-controlled solve on a crop; a warm start that stalls within
    :data:`WARM_MAX_ITER` is retried cold with ``fid.max_iter`` (non-convergence then raises
    :class:`~bearing_envelope.contact.ContactConvergenceError` with its diagnostics)."""
    kw = dict(tol=fid.tol, approach=delta, boundary="ignore", halfspace=hs, element=fid.element,
              hardness=scene.material.hardness_pa)
    e_star = scene.material.e_star_pa
    if p_init is not None:
        try:
            return stats.solve(g, grid.dx, grid.dy, None, e_star, p_init=p_init,
                               max_iter=min(fid.max_iter, WARM_MAX_ITER), **kw)
        except ContactConvergenceError:
            pass
    return stats.solve(g, grid.dx, grid.dy, None, e_star, max_iter=fid.max_iter, **kw)


def _level(stats: SolveStats, scene: Scene, fid: Fidelity, grid: Grid, g0: np.ndarray,
           delta: float) -> _Level:
    """The healthy solve of one approach on its crop (no solve at ``delta <= 0``)."""
    if delta <= 0.0:
        return _Level(float(delta), slice(0, 0), slice(0, 0), None, np.zeros((0, 0)), 0.0, 0.0)
    rows, cols = _crop(g0, delta)
    sub = Grid(grid.x[rows], grid.y[cols], grid.dx, grid.dy)
    hs = ElasticHalfSpace(sub.shape, grid.dx, grid.dy, scene.material.e_star_pa, workers=1,
                          backend="auto", element=fid.element)
    sol = _solve(stats, scene, fid, sub, g0[rows, cols], hs, delta, None)
    loaded = np.flatnonzero((sol.pressure > 0).any(axis=1))
    a_x = float(np.max(np.abs(sub.x[loaded]))) + 0.5 * grid.dx if loaded.size else 0.0
    cols_on = np.flatnonzero((sol.pressure > 0).any(axis=0))
    a_y = 0.5 * (float(sub.y[cols_on[-1]] - sub.y[cols_on[0]]) + grid.dy) if cols_on.size \
        else 0.0
    return _Level(float(delta), rows, cols, hs, sol.pressure, float(sol.force), a_x, a_y)


def defect_force(scene: Scene, fid: Fidelity, grid: Grid, x: float, delta: float, *,
                 stats: SolveStats | None = None, p_init: np.ndarray | None = None,
                 level: _Level | None = None) -> tuple[float, np.ndarray]:
    """Force (N) of the element at ``x`` (m, from the pit centre) at approach ``delta`` (m):
    one solve on the approach's crop of ``grid``, or the healthy solve's force where the pit
    does not reach its contact set (exact; module docstring).

    Parameters
    ----------
    scene : Scene
        The scene, its contact race set (:meth:`Scene.for_race`).
    fid : Fidelity
        Tolerance, iteration cap, element.
    grid : Grid
        The table's grid (:func:`table_grid`).
    x : float
        Element-centre position from the pit centre (m).
    delta : float
        Rigid approach (m).
    stats : SolveStats, optional
        Counters.
    p_init : numpy.ndarray, optional
        Warm start on the crop.
    level : _Level, optional
        The approach's healthy solve and crop, when made already.

    Returns
    -------
    tuple of (float, numpy.ndarray)
        The force (N) and the pressure on the crop (Pa).
    """
    stats = stats if stats is not None else SolveStats()
    g0 = gap_field(scene, grid, None)
    if level is None:
        level = _level(stats, scene, fid, grid, g0, delta)
    return _node(stats, scene, fid, grid, g0, gap_field(scene, grid, -float(x)), level, p_init)


def _node(stats: SolveStats, scene: Scene, fid: Fidelity, grid: Grid, g0: np.ndarray,
          g: np.ndarray, level: _Level, p_init: np.ndarray | None) -> tuple[float, np.ndarray]:
    """:func:`defect_force` with the healthy gap ``g0`` and the pitted gap ``g`` on the whole
    grid given."""
    if level.halfspace is None:
        return 0.0, level.p0
    g = g[level.rows, level.cols]
    if not np.any((g != g0[level.rows, level.cols]) & (level.p0 > 0)):
        return level.f0, level.p0
    sub = Grid(grid.x[level.rows], grid.y[level.cols], grid.dx, grid.dy)
    sol = _solve(stats, scene, fid, sub, g, level.halfspace, level.delta,
                 level.p0 if p_init is None else p_init)
    return float(sol.force), sol.pressure


# ---------------------------------------------------------------------------------------------
# the table


def _check_build(scene: Scene, race: str | None, delta_m, x_m, load_factor: float) -> None:
    """Bad input: one line naming the field, before any solve."""
    d = scene.defect
    if not d.active:
        raise ValueError(f"scene.defect.depth_um: got {d.depth_um!r}; allowed: > 0 (a defect "
                         f"contact table needs a pit)")
    if d.shape not in SYMMETRIC_SHAPES:
        raise ValueError(f"scene.defect.shape: got {d.shape!r}; allowed: "
                         f"{' | '.join(SYMMETRIC_SHAPES)} (the table is mirrored in x)")
    if race not in (None, "inner", "outer"):
        raise ValueError(f"race: got {race!r}; allowed: inner | outer | None")
    if not (math.isfinite(load_factor) and load_factor > 0):
        raise ValueError(f"load_factor: got {load_factor!r}; allowed: a finite number > 0")
    for name, v in (("delta_m", delta_m), ("x_m", x_m)):
        if v is None:
            continue
        a = np.asarray(v, dtype=float)
        if a.ndim != 1 or a.size < 2 or not np.all(np.isfinite(a)) or a[0] != 0.0 \
                or np.any(np.diff(a) <= 0):
            raise ValueError(f"{name}: got {v!r}; allowed: at least 2 finite values, strictly "
                             f"ascending, starting at 0")


def _default_race(scene: Scene, race: str | None) -> str:
    """The tabulated contact: given, else the pit's race (a rolling-element pit: the outer)."""
    if race is not None:
        return race
    return tabulated_race(scene)


def _sweep(stats: SolveStats, scene: Scene, fid: Fidelity, grid: Grid, g0: np.ndarray,
           xs: np.ndarray, levels: list[_Level]) -> np.ndarray:
    """``F[i, j]`` at ``xs[i] >= 0`` and ``levels[j]``: per approach, the offsets in order,
    each warm started from its neighbour's pressure."""
    gaps = [gap_field(scene, grid, -float(x)) for x in xs]   # the pit at -x from the contact
    force = np.zeros((xs.size, len(levels)))
    for j, lev in enumerate(levels):
        p = None
        for i in range(xs.size):
            force[i, j], p = _node(stats, scene, fid, grid, g0, gaps[i], lev, p)
    return force


def build_defect_table(scene: Scene, fidelity: "str | Fidelity | dict" = DEFAULT_PRESET, *,
                       race: str | None = None, delta_max_m: float | None = None,
                       delta_m=None, x_m=None, load_factor: float = LOAD_FACTOR,
                       n_checks: int | None = None, seed: int = 0) -> DefectContactTable:
    """Build the defect contact table of ``scene`` (module docstring: the model).

    Parameters
    ----------
    scene : Scene
        The scene with its pit (``flat``, ``dent`` or ``cylinder``; depth > 0).
    fidelity : str, mapping or Fidelity
        Preset or settings (:func:`~bearing_envelope.physics.fidelity.fidelity_from`): the cell
        sizes ``local_dx_um``/``local_dy_um`` (capped at ``w_x/4``, ``w_y/6``), ``tol``,
        ``max_iter``, ``element``, the offset spacing (``offset_step_um``,
        ``offsets_per_width``) and ``n_loads`` (``3 n_loads + 1`` approach nodes).
    race : {"inner", "outer"}, optional
        The contact tabulated; default the pit's race (outer for a rolling-element pit).
    delta_max_m : float, optional
        Largest approach (m); default the rigid drop plus the Hertz approach of
        ``load_factor`` x the scene's largest element load.
    delta_m : array_like, optional
        The approach nodes themselves (m; ascending from 0); overrides ``delta_max_m``.
    x_m : array_like, optional
        Offsets ``x >= 0`` (m; ascending from 0), mirrored; default to the last entry/exit edge
        and :data:`EDGE_MARGIN_NODES` more.
    load_factor : float
        See ``delta_max_m``.
    n_checks : int, optional
        Direct solves at cell midpoints measuring the interpolation error (default
        ``max(fid.n_checks, 4)``; 0 = none).
    seed : int
        Seed of the check cells' choice.

    Returns
    -------
    DefectContactTable
        The table, what made it, its measured errors and its cost.
    """
    t0 = time.process_time()
    fid = fidelity_from(fidelity)
    _check_build(scene, race, delta_m, x_m, load_factor)
    sc = scene.for_race(_default_race(scene, race))
    if delta_m is not None:
        deltas, drop = np.asarray(delta_m, dtype=float), rigid_drop(sc)
    else:
        deltas, drop = _delta_nodes(sc, fid, delta_max_m, load_factor)
    grid = table_grid(sc, fid, float(deltas[-1]))
    g0 = gap_field(sc, grid, None)
    stats = SolveStats()
    levels = [_level(stats, sc, fid, grid, g0, float(d)) for d in deltas]
    a_x = np.array([lev.a_x for lev in levels])
    xs = _x_nodes(sc, fid, grid, float(a_x.max())) if x_m is None else np.asarray(x_m, float)
    half = _sweep(stats, sc, fid, grid, g0, xs, levels)
    f0 = np.array([lev.f0 for lev in levels])
    table = DefectContactTable(
        x_m=np.concatenate([-xs[:0:-1], xs]), delta_m=deltas,
        force_n=np.concatenate([half[:0:-1], half]), healthy_force_n=f0,
        edge_m=0.5 * sc.defect.extent_x_m + a_x, hertz_k=hertz_constant(sc),
        element=sc.bearing.kind, race=sc.bearing.contact_race, pit=_pit(sc),
        fidelity=fid.name, tol=fid.tol, grid_dx_m=grid.dx, grid_dy_m=grid.dy,
        hardness_pa=sc.material.hardness_pa, rigid_drop_m=drop,
        discretisation_error=_hertz_error(f0, deltas, levels, grid, hertz_constant(sc)),
        info={"grid_shape": grid.shape, "iterations": stats.n_iterations,
              "stall_guard": stats.n_stall_guard, "failed_solves": stats.n_failed})
    nc = max(fid.n_checks, 4) if n_checks is None else int(n_checks)
    checks = _checks(stats, sc, fid, grid, g0, table, levels, nc, seed)
    return _finish(table, checks, stats, time.process_time() - t0)


def _pit(scene: Scene) -> dict:
    """The pit's geometry as the table records it."""
    d = scene.defect
    return {"location": d.location, "shape": d.shape, "width_um": 1e6 * d.extent_x_m,
            "length_um": 1e6 * d.extent_y_m, "depth_um": d.depth_um,
            "edge_radius_um": d.edge_radius_um}


#: Least healthy contact half-width across rolling, in cells, at which the healthy force is
#: compared with Hertz (:attr:`DefectContactTable.discretisation_error`).
HERTZ_CHECK_CELLS = 10


def _hertz_error(f0: np.ndarray, deltas: np.ndarray, levels: list, grid: Grid,
                 k: float) -> float:
    """Largest ``|F0 / (K delta^1.5) - 1|`` where the contact's half-widths span >=
    HERTZ_CHECK_CELLS cells along both axes."""
    a_x = np.array([lev.a_x for lev in levels])
    a_y = np.array([lev.a_y for lev in levels])
    ok = (a_x >= HERTZ_CHECK_CELLS * grid.dx) & (a_y >= HERTZ_CHECK_CELLS * grid.dy) & \
        (deltas > 0)
    if not ok.any():
        return math.nan
    return float(np.max(np.abs(f0[ok] / (k * deltas[ok] ** 1.5) - 1.0)))


def _checks(stats: SolveStats, scene: Scene, fid: Fidelity, grid: Grid, g0: np.ndarray,
            table: DefectContactTable, levels: list[_Level], n: int, seed: int) -> list:
    """Direct solves at the midpoints of ``n`` cells of the table that the pit reaches (chosen
    with ``seed``): ``(x, delta, F_direct, F_bilinear, F_healthy)`` each."""
    nh = (table.x_m.size + 1) // 2
    xs, f = table.x_m[nh - 1:], table.force_n[nh - 1:]
    f0 = table.healthy_force_n
    cand = [(i, j) for i in range(xs.size - 1) for j in range(1, f0.size - 1)
            if np.any(f[i:i + 2, j:j + 2] < f0[None, j:j + 2] * (1.0 - 1e-9))]
    if n <= 0 or not cand:
        return []
    rng = np.random.default_rng(seed)
    pick = rng.choice(len(cand), size=min(n, len(cand)), replace=False)
    out = []
    for k in sorted(pick):
        i, j = cand[k]
        x, d = 0.5 * (xs[i] + xs[i + 1]), 0.5 * (levels[j].delta + levels[j + 1].delta)
        lev = _level(stats, scene, fid, grid, g0, d)
        fd, _ = _node(stats, scene, fid, grid, g0, gap_field(scene, grid, -x), lev, None)
        out.append((float(x), float(d), fd, float(table.force(x, d)), lev.f0))
    return out


#: The local interpolation error (:attr:`DefectContactTable.interpolation_error`) is taken at
#: check points whose healthy force is at least this fraction of the table's largest: below it
#: the bilinear reading of a force growing as ``delta^1.5`` from 0 is off by up to ~12 % of
#: a force that is < 1 % of the largest (measured, standard, 6205 0.021 in pit).
LOCAL_ERROR_FLOOR = 0.05


def _finish(table: DefectContactTable, checks: list, stats: SolveStats,
            cpu_s: float) -> DefectContactTable:
    """The table with its measured interpolation error and cost."""
    fmax = float(table.force_n.max())
    err = max((abs(c[3] - c[2]) / c[4] for c in checks if c[4] >= LOCAL_ERROR_FLOOR * fmax),
              default=math.nan)
    err_max = max((abs(c[3] - c[2]) / fmax for c in checks), default=math.nan) \
        if fmax > 0 else math.nan
    return dataclasses.replace(table, checks=tuple(c[:4] for c in checks),
                               interpolation_error=float(err),
                               interpolation_error_of_max=float(err_max), cpu_s=float(cpu_s),
                               n_solves=int(stats.n_solves))


# ---------------------------------------------------------------------------------------------
# one table per pit and contact in a process


#: Tables :func:`defect_table` keeps (least recently used dropped).
TABLE_CACHE_SIZE = 16
_TABLES: "dict[tuple, DefectContactTable]" = {}


def defect_table(scene: Scene, fidelity: "str | Fidelity | dict" = DEFAULT_PRESET, *,
                 race: str | None = None) -> DefectContactTable:
    """:func:`build_defect_table` with its defaults, kept per process: the key is everything
    the table reads (the bearing, the materials, the pit, the fidelity, the race and the
    approach nodes, which the load distribution sets), so the records of one pit that differ
    only in speed or motor load share a table.

    Parameters
    ----------
    scene : Scene
        The scene with its pit.
    fidelity : str, mapping or Fidelity
        As :func:`build_defect_table`.
    race : {"inner", "outer"}, optional
        As :func:`build_defect_table`.

    Returns
    -------
    DefectContactTable
        The (shared, read-only) table.
    """
    fid = fidelity_from(fidelity)
    _check_build(scene, race, None, None, LOAD_FACTOR)
    sc = scene.for_race(_default_race(scene, race))
    deltas, _ = _delta_nodes(sc, fid, None, LOAD_FACTOR)
    # the law does not depend on where the pit sits on its race (only the loads it meets do)
    pit = dataclasses.replace(sc.defect, position_deg=0.0, spin_axis="fixed", spin_seed=0)
    key = (sc.bearing, sc.material, pit, fid, tuple(deltas.tolist()))
    if key in _TABLES:
        _TABLES[key] = _TABLES.pop(key)
        return _TABLES[key]
    table = build_defect_table(sc, fid, race=sc.bearing.contact_race, delta_m=deltas)
    for a in (table.x_m, table.delta_m, table.force_n, table.healthy_force_n, table.edge_m):
        a.setflags(write=False)
    _TABLES[key] = table
    while len(_TABLES) > TABLE_CACHE_SIZE:
        _TABLES.pop(next(iter(_TABLES)))
    return table
