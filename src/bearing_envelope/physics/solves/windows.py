"""Window solves: the rows a defect window solve is solved on (:func:`contact_rows`,
:func:`fast_rows`), one window solve on them (:func:`window_solve`), and the window's linear
response to the far field's take-up (:func:`far_response`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..fidelity import Fidelity
from ..geometry import Grid, gap_field
from ..scene import Scene
from .global_solve import _far_field, _halfspace
from .stats import SolveStats

__all__ = ["CONTACT_ROWS_MARGIN", "contact_rows", "fast_rows", "window_solve", "WindowState"]


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
