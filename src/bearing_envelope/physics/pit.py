"""Does the pit bottom carry load? The depth threshold of a defect (issue 12 part 4).

A flat defect of depth ``h`` and width ``w`` (rims rounded with radius ``r``) changes the contact
only through the cells the deformed roller touches. If the roller never reaches the pit's
deepest cells, a deeper pit of the same width gives exactly the same contact (the gap grows
only where the surfaces are apart), and "depth" is not a variable of the history: only the
width and the rim shape are. This module measures, for one roller load and defect offset, the
depth below which the deepest cells of the pit carry load:

- :func:`bottom_loaded` solves the zoom window with the defect (the same route as the history
  table, :func:`bearing_envelope.physics.history.defect_solve`) and says whether any of the pit's
  deepest cells (rigid cell-averaged depth within ``1e-3`` of the pit's largest) has pressure;
- :func:`depth_threshold` bisects on the depth (geometrically, between ``h_lo`` and ``h_hi``)
  for a fixed width or for the default rule ``w = 2 h``.

With ``w = 2 h`` and ``h < r`` the pit has no flat bottom: it is a circular trough of radius
``r`` whose deepest point is ``r - sqrt(r^2 - h^2)`` deep (6.8 um for h = 15 um, r = 20 um); its
"bottom" is then that deepest line.

Independent estimate (plane strain, the pit long along the axis): a traction-free slot of
half-width ``c`` in a contact at pressure ``p`` lets the roller sink ``2 p c / E*`` into it at its
centre (the face displacement of a Griffith crack). Fixed width: ``h* ~ p w / E*`` (the rounded
rims narrow the free slot, so the measured value lies a little below). ``w = 2 h``: the trough's
depth ``r - sqrt(r^2 - h^2)`` equals ``2 p h / E*`` at ``h* = 2 r s / (1 + s^2)``, ``s = 2 p / E*``
(:func:`slot_estimate`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .fidelity import Fidelity, fidelity_from
from .geometry import gap_field
from .solves import SolveStats, defect_solve, solve_load
from .loads import scene_load_distribution
from .scene import Scene

__all__ = ["BottomContact", "bottom_loaded", "depth_threshold", "pit_scene", "slot_estimate"]

#: Relative pressure (of the no-defect maximum) above which a cell counts as loaded.
LOADED = 1e-9
#: A cell belongs to the pit's bottom when its rigid depth is within this fraction of the largest.
BOTTOM_TOLERANCE = 1e-3


@dataclass
class BottomContact:
    """One solve: does the pit's bottom carry load?"""

    depth_um: float
    width_um: float
    q_load: float
    x_d: float
    loaded: bool
    bottom_force_fraction: float  # force on the bottom cells / window force
    max_cell_depth_um: float      # rigid depth of the deepest cells (cell average)
    p0: float                     # no-defect maximum pressure at this roller load (Pa)
    p_centre: float               # no-defect maximum at the defect's axial position (Pa)
    a_hertz: float                # Hertz half-width across rolling at this roller load (m)


def slot_estimate(p: float, e_star: float, width_um: float | None,
                  edge_radius_um: float = 20.0) -> float:
    """Plane-strain estimate of the threshold depth (um) at contact pressure ``p`` (Pa): fixed
    ``width_um``: ``p w / E*``; ``None`` (w = 2 h): ``2 r s / (1 + s^2)`` with ``s = 2 p / E*``.

    Parameters
    ----------
    p : float
        Contact pressure at the defect (Pa).
    e_star : float
        Composite modulus ``E*`` (Pa).
    width_um : float or None
        The pit's width (um), or None for ``w = 2 h``.
    edge_radius_um : float
        The rim radius (um), for ``w = 2 h``.

    Returns
    -------
    float
        The threshold depth (um).
    """
    s = 2.0 * p / e_star
    if width_um is None:
        return 2.0 * edge_radius_um * s / (1.0 + s * s)
    return 0.5 * s * width_um


def pit_scene(mapping: dict | None, load_kN: float, depth_um: float,
              width_um: float | None) -> Scene:
    """The scene with ``defect.width_um = width_um`` (``None``: the default ``w = 2 h``).

    Parameters
    ----------
    mapping : dict or None
        Scene overrides (``Scene.from_mapping``).
    load_kN : float
        Bearing load (kN).
    depth_um : float
        Pit depth (um).
    width_um : float or None
        Pit width (um), or None for ``w = 2 h``.

    Returns
    -------
    Scene
        The scene.
    """
    m = {k: dict(v) if isinstance(v, dict) else v for k, v in (mapping or {}).items()}
    if width_um is not None:
        m["defect"] = {**(m.get("defect") or {}), "width_um": float(width_um)}
    return Scene.from_mapping(m, load_kN=load_kN, depth_um=depth_um)


def bottom_loaded(scene: Scene, fidelity: Fidelity | str | dict | None, q_load: float,
                  x_d: float = 0.0, *, node=None, stats: SolveStats | None = None
                  ) -> BottomContact:
    """Solve the window at roller load ``q_load`` (N) with the defect at offset ``x_d`` (m).

    Parameters
    ----------
    scene : Scene
        The scene with the pit.
    fidelity : Fidelity, preset name, mapping or None
        The fidelity of the solve.
    q_load : float
        Roller load (N).
    x_d : float
        Defect offset from the contact centre (m).
    node : LoadNode, optional
        The load's no-defect solves, if made already.
    stats : SolveStats, optional
        Counters to add the solve to.

    Returns
    -------
    BottomContact
        Whether the pit's bottom carries load, the bottom's share of the window force, the
        deepest cells' depth and the no-defect pressures at this load.
    """
    fid = fidelity_from(fidelity)
    stats = stats or SolveStats()
    if node is None:
        node = solve_load(scene, fid, q_load, 1.0, stats)
    ds = defect_solve(scene, fid, node, x_d, stats)
    win = node.window
    depth = gap_field(scene, win, x_d) - gap_field(scene, win, None)
    depth = np.where(np.isfinite(depth), depth, 0.0)
    dmax = float(depth.max())
    bottom = depth >= (1.0 - BOTTOM_TOLERANCE) * dmax
    p = ds.pressure
    on = p[bottom] > LOADED * node.p0
    total = float(p.sum())
    frac = float(p[bottom].sum()) / total if total > 0 else 0.0
    d = scene.defect
    return BottomContact(d.depth_um, 1e6 * d.extent_x_m, q_load, x_d, bool(on.any()), frac,
                         1e6 * dmax, node.p0, node.w0, node.a_hertz)


def depth_threshold(load_kN: float, width_um: float | None, fidelity="standard", *,
                    mapping: dict | None = None, x_d: float = 0.0, q_load: float | None = None,
                    h_lo: float = 0.01, h_hi: float = 200.0, rel_tol: float = 0.01
                    ) -> tuple[float, list[BottomContact]]:
    """Depth (um) below which the pit bottom carries load, by bisection in ``log h``.

    ``width_um``: fixed width, or ``None`` for the default ``w = 2 h``. The roller load is
    ``q_load`` (N) or the most loaded roller's ``Q_max`` of ``load_kN``. Returns the geometric
    mean of the last bracket (``h_loaded < h* <= h_free``, ratio ``<= 1 + rel_tol``) and every
    solve made. ``h* = h_lo`` if the bottom is free already at ``h_lo``; ``inf`` if it is still
    loaded at ``h_hi``.

    Parameters
    ----------
    load_kN : float
        Bearing load (kN).
    width_um : float or None
        Pit width (um), or None for ``w = 2 h``.
    fidelity : Fidelity, preset name or mapping
        The fidelity of the solves.
    mapping : dict, optional
        Scene overrides.
    x_d : float
        Defect offset from the contact centre (m).
    q_load : float, optional
        Roller load (N) instead of ``Q_max``.
    h_lo, h_hi : float
        The depth bracket searched (um).
    rel_tol : float
        Relative width of the final bracket.

    Returns
    -------
    tuple of (float, list of BottomContact)
        ``h*`` (um) and every solve made.
    """
    fid = fidelity_from(fidelity)
    stats = SolveStats()
    if q_load is None:
        q_load = scene_load_distribution(pit_scene(mapping, load_kN, h_hi, width_um)).q_max
    nodes = {}

    def probe(h):
        sc = pit_scene(mapping, load_kN, h, width_um)
        key = width_um if width_um is not None else 2.0 * h
        if key not in nodes:   # the window depends on the width, not on the depth
            nodes.clear()
            nodes[key] = solve_load(sc, fid, q_load, 1.0, stats)
        return bottom_loaded(sc, fid, q_load, x_d, node=nodes[key], stats=stats)

    log = []
    lo, hi = h_lo, h_hi
    r_lo, r_hi = probe(lo), probe(hi)
    log += [r_lo, r_hi]
    if not r_lo.loaded:
        return h_lo, log
    if r_hi.loaded:
        return math.inf, log
    while hi / lo > 1.0 + rel_tol:
        mid = math.sqrt(lo * hi)
        r = probe(mid)
        log.append(r)
        if r.loaded:
            lo = mid
        else:
            hi = mid
    return math.sqrt(lo * hi), log
