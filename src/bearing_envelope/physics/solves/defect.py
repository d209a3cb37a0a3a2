"""The window solve with the defect at one offset (:func:`defect_solve`, warm-started, with
rim strips when the fidelity asks), the no-defect reference with end strips and the far
field's take-up of the removed force (:func:`far_uptake`)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ...contact import ContactConvergenceError
from ..fidelity import Fidelity
from ..geometry import gap_field
from ..scene import Scene
from .load_node import LoadNode
from .rims import _strip_schwarz, neighbourhood_max
from .stats import SolveStats
from .windows import window_solve

__all__ = ["DefectSolve", "defect_solve", "far_uptake"]


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
