"""Initial gap field of the roller / inner-race contact, with the defect, on a contact grid.

Grid convention (``docs/interfaces.md``): arrays ``[i, j]``, axis 0 = ``x`` = rolling direction,
axis 1 = ``y`` = roller axis; cell-centred, SI units (m).

The undeformed gap between roller and inner raceway is

.. math::

    g(x, y) = \\frac{x^2}{2R_x} + s(y) + D(x - x_d, y - y_d),

* rolling direction: ``1/R_x = 2/d + 1/R_i`` with ``R_i = (D_pitch - d cos(alpha))/2`` the
  raceway radius at the contact (7.68 mm for the default scene);
* axial: ``s(y) = y^2 / (2 R_y)``, ``1/R_y = 1/c_r - 1/c_i`` (roller crown ``c_r`` convex,
  raceway ``c_i`` concave; 4233 mm), plus the roller end relief
  (:class:`bearing_envelope.physics.scene.EndRelief`); ``+inf`` beyond the roller ends ``|y| > L/2``.
  With a measured ``profile_file`` the roller part is the file's deviation (linearly
  interpolated) instead: ``s(y) = dev(y) - y^2/(2 c_i)``;
* the defect ``D >= 0`` (a pit in the raceway), centred at ``(x_d, y_d)``
  (:func:`defect_depth`).
"""

from __future__ import annotations

import math
import os
from collections import OrderedDict
import warnings
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..checks import check_input_file
from ..contact import hertz

__all__ = ["Grid", "make_grid", "read_profile", "read_defect_profile", "axial_separation", "defect_depth", "gap_field",
           "hertz_estimate", "good_size"]


@dataclass(frozen=True)
class Grid:
    """Cell-centred rectangular grid.

    Attributes
    ----------
    x, y : ndarray
        Cell-centre coordinates (m) along rolling (axis 0) and axial (axis 1) directions.
    dx, dy : float
        Spacings (m).
    """

    x: np.ndarray
    y: np.ndarray
    dx: float
    dy: float

    @property
    def shape(self) -> tuple[int, int]:
        """``(nx, ny)``: cells along x (rolling, axis 0) and y (axial, axis 1)."""
        return (self.x.size, self.y.size)

    def mesh(self):
        """``X, Y`` arrays of shape ``(nx, ny)``.

        Returns
        -------
        tuple of numpy.ndarray
            ``(X, Y)``, the cell centres (m).
        """
        return np.meshgrid(self.x, self.y, indexing="ij")


def good_size(n: int) -> int:
    """Smallest integer >= n whose only prime factors are 2, 3 and 5 (FFT-friendly).

    Parameters
    ----------
    n : int
        A grid size.

    Returns
    -------
    int
        The 5-smooth size.
    """
    n = max(int(n), 1)
    while True:
        m = n
        for p in (2, 3, 5):
            while m % p == 0:
                m //= p
        if m == 1:
            return n
        n += 1


def make_grid(x_lo: float, x_hi: float, y_lo: float, y_hi: float, dx: float, dy: float,
              *, x_center: float = 0.0, y_center: float | None = None) -> Grid:
    """Grid covering ``[x_lo, x_hi] x [y_lo, y_hi]`` with spacings ``dx, dy`` (m).

    The sizes are even and rounded up to FFT-friendly numbers; the grid is symmetric about ``x_center``
    (default 0, so that ``x = 0`` is a symmetry line of the cells) and about ``y_center``
    (default the middle of ``[y_lo, y_hi]``).

    Parameters
    ----------
    x_lo, x_hi, y_lo, y_hi : float
        The region to cover (m).
    dx, dy : float
        Cell sizes (m).
    x_center : float
        Symmetry line across rolling (m).
    y_center : float, optional
        Symmetry line along the axis (m; default the middle of ``[y_lo, y_hi]``).

    Returns
    -------
    Grid
        Cell centres and spacings.
    """
    if y_center is None:
        y_center = 0.5 * (y_lo + y_hi)
    hx = max(x_hi - x_center, x_center - x_lo)
    hy = max(y_hi - y_center, y_center - y_lo)
    # even sizes: cell centres at +-d/2, +-3d/2, ... about the centre for every grid, so a
    # defect at an offset that is a multiple of d sits the same way on every grid
    nx = 2 * good_size(math.ceil(hx / dx))
    ny = 2 * good_size(max(math.ceil(hy / dy), 1))
    x = x_center + (np.arange(nx) - 0.5 * (nx - 1)) * dx
    y = y_center + (np.arange(ny) - 0.5 * (ny - 1)) * dy
    return Grid(x, y, float(dx), float(dy))


#: Largest measured-profile file read (bytes): a profile of 10^5 rows is about 3 MB.
MAX_PROFILE_BYTES = 16 << 20


def _two_columns(path: str, names: str) -> tuple[np.ndarray, np.ndarray]:
    """The two columns of a text or CSV file (``#`` comments), at least 3 rows, finite, the
    first strictly increasing; ``names`` (e.g. ``"y_mm, deviation_um"``) names them in errors."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")   # "input contained no data": the shape says it
            data = np.loadtxt(path, delimiter=None if not path.endswith(".csv") else ",",
                              comments="#", ndmin=2)
    except (ValueError, UnicodeDecodeError) as exc:
        raise ValueError(f"not a two-column numeric file ({names}): "
                         f"{' '.join(str(exc).split())[:160]}") from None
    if data.shape[1] != 2 or data.shape[0] < 3:
        raise ValueError(f"expected two columns ({names}) and >= 3 rows, got shape {data.shape}")
    if not np.all(np.isfinite(data)):
        raise ValueError("non-finite values")
    if not np.all(np.diff(data[:, 0]) > 0):
        raise ValueError("positions must increase strictly")
    return data[:, 0], data[:, 1]


@lru_cache(maxsize=8)
def _read_profile_cached(path: str, mtime: float):
    y, dev = _two_columns(path, "y_mm, deviation_um")
    return y * 1e-3, dev * 1e-6


def read_profile(path: str) -> tuple[np.ndarray, np.ndarray]:
    """Read a measured roller profile: two columns ``y_mm, deviation_um`` (text or CSV).

    Returns ``(y, deviation)`` in m. ``deviation`` is the drop of the roller surface from its
    generatrix at the centre (positive = material removed). ``#`` starts a comment.

    Parameters
    ----------
    path : str
        The profile file.

    Returns
    -------
    tuple of numpy.ndarray
        ``(y, deviation)`` in m.
    """
    path = check_input_file(path, "profile file", max_bytes=MAX_PROFILE_BYTES)
    return _read_profile_cached(path, os.path.getmtime(path))


@lru_cache(maxsize=8)
def _read_defect_profile_cached(path: str, mtime: float):
    x, dep = _two_columns(path, "x_um, depth_um")
    if np.any(dep < 0) or not np.any(dep > 0):
        raise ValueError("depths must be >= 0 with at least one > 0")
    return x * 1e-6, dep * 1e-6


def read_defect_profile(path: str) -> tuple[np.ndarray, np.ndarray]:
    """Read a measured defect profile: two columns ``x_um, depth_um`` (text or CSV).

    ``x`` runs across the defect along rolling (from its centre), ``depth >= 0`` below the
    raceway; zero outside the file's range. In the gap the profile is scaled so that its deepest
    point equals the case's depth and extruded over the defect's axial length
    (:func:`defect_depth`, ``shape: profile``). Returns ``(x, depth)`` in m.

    Parameters
    ----------
    path : str
        The profile file.

    Returns
    -------
    tuple of numpy.ndarray
        ``(x, depth)`` in m.
    """
    path = check_input_file(path, "defect profile file", max_bytes=MAX_PROFILE_BYTES)
    return _read_defect_profile_cached(path, os.path.getmtime(path))


def axial_separation(bearing, y) -> np.ndarray:
    """Axial part ``s(y)`` of the gap (m) at axial positions ``y`` (m); ``+inf`` for ``|y| > L/2``.

    Parameters
    ----------
    bearing : bearing_envelope.physics.scene.Bearing
        The roller's profile: its length ``L`` and end relief (crown radius or drop).
    y : array_like
        Axial positions from the roller centre (m).

    Returns
    -------
    numpy.ndarray
        ``s(y)`` (m), the shape of ``y``.
    """
    y = np.asarray(y, dtype=float)
    half = bearing.half_length_m
    ay = np.abs(y)
    if getattr(bearing, "kind", "roller") == "ball":
        # a ball in its groove: the quadratic of the groove conformity, no end relief; no
        # material beyond the groove (width roller_length_mm)
        s = y * y / (2.0 * bearing.ry_m)
    elif bearing.profile_file:
        yp, dev = read_profile(bearing.profile_file)
        s = np.interp(y, yp, dev) - y * y / (2e-3 * bearing.raceway_profile_radius_mm)
        s = s - np.min(s[ay <= half]) if np.any(ay <= half) else s
    else:
        s = y * y / (2.0 * bearing.ry_m)
        rel = bearing.end_relief
        if rel.kind == "radius":
            r = 1e-3 * rel.radius_mm
            u = np.clip(ay - (half - r), 0.0, r)
            s = s + r - np.sqrt(np.clip(r * r - u * u, 0.0, None))
        else:
            ln = 1e-3 * rel.length_mm
            t = np.clip((ay - (half - ln)) / ln, 0.0, 1.0)
            s = s - 1e-6 * rel.drop_um * np.log1p(-(1.0 - math.exp(-1.0)) * t * t)
    return np.where(ay <= half, s, np.inf)


def defect_depth(defect, u, v) -> np.ndarray:
    """Depth (m, >= 0) of the defect at local coordinates ``u = x - x_d``, ``v = y - y_d`` (m).

    ``flat``: flat bottom at depth ``h``; within ``edge_radius`` of the footprint boundary the
    surface follows a rim arc of that radius, ``r - sqrt(r^2 - d^2)`` (``d`` = distance inside
    the rectangular footprint), capped at ``h``. ``dent``:
    ``h cos^2(pi u / (2 h_x)) cos^2(pi v / (2 h_y))`` inside the footprint (smooth).

    Parameters
    ----------
    defect : bearing_envelope.physics.scene.Defect
        The defect (shape, depth, footprint, rim radius).
    u, v : array_like
        Local coordinates across rolling and along the axis (m), broadcast together.

    Returns
    -------
    numpy.ndarray
        Depth (m), the broadcast shape of ``u`` and ``v``.
    """
    u = np.asarray(u, dtype=float)
    v = np.asarray(v, dtype=float)
    h = 1e-6 * defect.depth_um
    if h <= 0:
        return np.zeros(np.broadcast(u, v).shape)
    hx, hy = 0.5 * defect.extent_x_m, 0.5 * defect.extent_y_m
    dist = np.minimum(hx - np.abs(u), hy - np.abs(v))
    inside = dist > 0
    if defect.shape == "dent":
        d = h * np.cos(0.5 * np.pi * np.clip(u / hx, -1, 1)) ** 2 \
            * np.cos(0.5 * np.pi * np.clip(v / hy, -1, 1)) ** 2
        return np.where(inside, d, 0.0)
    if defect.shape == "profile":
        xp, dp = read_defect_profile(defect.profile_file)
        prof = np.interp(u, xp, dp, left=0.0, right=0.0)
        return np.where(np.abs(v) < hy, h / max(float(np.max(dp)), 1e-300) * prof, 0.0)
    if defect.shape == "cylinder":
        # circular footprint of diameter w: distance inside the circle
        dist = hx - np.hypot(u, v)
        inside = dist > 0
    r = 1e-6 * defect.edge_radius_um
    if r <= 0:
        return np.where(inside, h, 0.0)
    dd = np.clip(dist, 0.0, None)
    arc = np.where(dd < r, r - np.sqrt(np.clip(r * r - dd * dd, 0.0, None)), np.inf)
    return np.where(inside, np.minimum(h, arc), 0.0)


#: Largest spacing (m) of the sub-points over which :func:`gap_field` averages the defect's depth
#: in a cell, along each axis (at least ``supersample`` of them). A flat defect deeper than its
#: edge radius has a vertical wall where the rim arc ends (the depth steps from ``r`` to ``h``):
#: point sampling places that step to within half the sub-point spacing. Two points per 40 um
#: window column made the 500 um-long, 50 um-deep defect's volume 1.5 % small or 1.0 % large
#: (which, depended on rounding in the last bit of the column centres), and the removed force
#: did not converge monotonically with the window's (or, below it, the global grid's) axial
#: spacing (``docs/benchmarks.md``, "Global axial grid and the integral signals").
DEFECT_SUBPOINT_M = 0.5e-6


def gap_field(scene, grid: Grid, x_d: float | None = None, *,
              supersample: tuple[int, int] = (4, 2)) -> np.ndarray:
    """Initial gap ``g(x, y)`` (m) on ``grid`` with the defect centred at ``x = x_d``.

    Parameters
    ----------
    scene : bearing_envelope.physics.scene.Scene
        The case's scene: the contact's curvatures, the roller's profile and the defect's
        shape (depth, width, rims, axial position).
    grid : Grid
        Contact grid (m), ``x`` along rolling and ``y`` axial, centred on the contact.
    x_d : float or None
        Defect offset from the contact centre along rolling (m); ``None`` = no defect (also when
        the scene's defect depth is 0).
    supersample : (int, int)
        Least number of sub-points per cell along ``x`` and ``y`` over which the defect depth is
        averaged (more where a cell is wider than that many :data:`DEFECT_SUBPOINT_M`).

    Returns
    -------
    ndarray, shape ``grid.shape``
        ``+inf`` beyond the roller ends.
    """
    b = scene.bearing
    gx = grid.x ** 2 / (2.0 * b.rx_m)
    gy = axial_separation(b, grid.y)
    g = gx[:, None] + gy[None, :]
    if x_d is not None and scene.defect.active:
        g = g + _defect_cell_average(scene.defect, grid, x_d, supersample)
    return g


def _footprint_cells(c: np.ndarray, d: float, centre: float, half: float) -> slice:
    """The cells (centres ``c``, spacing ``d``) that overlap ``[centre - half, centre + half]``."""
    hit = np.flatnonzero((c + 0.5 * d > centre - half) & (c - 0.5 * d < centre + half))
    return slice(int(hit[0]), int(hit[-1]) + 1) if hit.size else slice(0, 0)


def _defect_cell_average(defect, grid: Grid, x_d: float, supersample) -> np.ndarray:
    """The defect's depth averaged over each cell (m), evaluated only on the cells the footprint
    overlaps (0 elsewhere; a measured profile's rows are all kept): over ``sx`` sub-points along
    ``x`` (at least ``supersample[0]``, at most :data:`DEFECT_SUBPOINT_M` apart) and along ``y``
    ``supersample[1]`` of them, or in the columns within the edge radius of an axial end (where
    a flat or measured-profile defect's depth changes along ``y``: the rim and the wall)
    sub-points at most :data:`DEFECT_SUBPOINT_M` apart (a dent is smooth; a cylinder's
    columns keep ``supersample[1]`` as before but for its two end bands). The average changes
    continuously with ``x_d`` (point sampling makes the rim peak jitter by +-15 % with the
    defect's sub-cell position)."""
    yd = 1e-3 * defect.axial_position_mm
    hy, r = 0.5 * defect.extent_y_m, 1e-6 * defect.edge_radius_um
    sx = max(supersample[0], math.ceil(grid.dx / DEFECT_SUBPOINT_M - 1e-9))
    rows = slice(None) if defect.shape == "profile" else \
        _footprint_cells(grid.x, grid.dx, x_d, 0.5 * defect.extent_x_m)
    cols = _footprint_cells(grid.y, grid.dy, yd, hy)
    ends = np.zeros(grid.shape[1], bool)
    for c in (yd - hy + 0.5 * r, yd + hy - 0.5 * r):
        ends[_footprint_cells(grid.y, grid.dy, c, 0.5 * r + 1e-12)] = True
    out = np.zeros(grid.shape)
    x = grid.x[rows]
    for sel, sy in ((np.flatnonzero(~ends[cols]) + (cols.start or 0), supersample[1]),
                    (np.flatnonzero(ends), max(supersample[1],
                                               math.ceil(grid.dy / DEFECT_SUBPOINT_M - 1e-9)))):
        if sel.size:
            out[rows, sel] = _sub_point_mean(defect, x, grid.y[sel], grid.dx, grid.dy, x_d, yd,
                                             sx, sy)
    return out


#: Cell-averaged depth blocks kept by :func:`_sub_point_mean` (least recently used dropped).
SUBPOINT_CACHE_SIZE = 256
_SUBPOINT_CACHE: "OrderedDict[tuple, np.ndarray]" = OrderedDict()


def _sub_point_mean(defect, x, y, dx, dy, x_d, yd, sx, sy) -> np.ndarray:
    """Mean depth (m) over ``sx x sy`` sub-points of the cells centred at ``x`` x ``y``.

    Cached: the table's offsets are multiples of the window spacing, so the defect sits at the
    same sub-cell position on every one of them and the block (the cells its footprint
    overlaps) repeats; the key is everything the block depends on, the defect's position
    relative to the first cell to 1e-9 of a cell (issue 33: 7 % of a CWRU ball case's CPU)."""
    key = (defect, round((float(x[0]) - x_d) / dx, 9), x.size, y.tobytes(), dx, dy, yd, sx, sy) \
        if x.size and np.all(np.abs(np.diff(x) - dx) <= 1e-9 * dx) else None
    if key is not None and key in _SUBPOINT_CACHE:
        _SUBPOINT_CACHE.move_to_end(key)
        return _SUBPOINT_CACHE[key]
    out = _sub_point_mean_solve(defect, x, y, dx, dy, x_d, yd, sx, sy)
    if key is not None:
        out.setflags(write=False)
        _SUBPOINT_CACHE[key] = out
        while len(_SUBPOINT_CACHE) > SUBPOINT_CACHE_SIZE:
            _SUBPOINT_CACHE.popitem(last=False)
    return out


def _sub_point_mean_solve(defect, x, y, dx, dy, x_d, yd, sx, sy) -> np.ndarray:
    """:func:`_sub_point_mean` computed: ``sx x sy`` sub-points per cell."""
    ox = ((np.arange(sx) + 0.5) / sx - 0.5) * dx
    oy = ((np.arange(sy) + 0.5) / sy - 0.5) * dy
    v = (y[:, None] + oy[None, :]).ravel() - yd           # every column's sub-points at once
    acc = np.zeros((x.size, y.size))
    for u in ox:
        acc += defect_depth(defect, x[:, None] + u - x_d, v[None, :]).reshape(
            x.size, y.size, sy).sum(axis=2)
    return acc / (sx * sy)


def hertz_estimate(scene, force: float):
    """Hertz ellipse of the no-defect contact at roller load ``force`` (N) (unbounded crown).

    Uses :func:`bearing_envelope.contact.hertz.elliptical` with ``R_x``, ``R_y`` of the scene and
    ``E*`` of its materials. Used to size grids; the roller length is not taken into account.

    Parameters
    ----------
    scene : Scene
        The scene (roller and race curvatures, materials).
    force : float
        Roller load (N).

    Returns
    -------
    HertzContact
        The Hertz ellipse (semi-axes, peak pressure, approach).
    """
    b = scene.bearing
    return hertz.elliptical(force, b.rx_m, b.ry_m, scene.material.e_star_pa)
