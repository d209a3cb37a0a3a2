"""The pressure table ``P(Q, x)``: built from the solves of :mod:`~bearing_envelope.physics.solves`
at a few roller-load and offset nodes, interpolated per sample, with its interpolation error
measured against direct solves (model: :mod:`bearing_envelope.physics.history`)."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ..contact import ContactConvergenceError
from .fidelity import Fidelity
from .geometry import hertz_estimate
from .kernels import HAVE_NUMBA, ratio_kernel
from .scene import Scene
from .solves import (LoadNode, SolveStats, defect_solve, neighbourhood_max, outside_solve,
                     solve_load, window_spec)
from .table_errors import CHECK_COLUMNS, interpolation_check_errors, relative_error

__all__ = ["PressureTable", "build_table", "offset_count", "direct_pressure", "Q_MIN_FRACTION",
           "unloaded_table", "relative_error", "interpolation_check_errors", "CHECK_COLUMNS",
           "OUTSIDE_LOAD_DENSITY", "CHECK_OFFSETS_PER_LOAD"]

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
        node's roller load ``Q`` (window solves under displacement control). Read between the
        load nodes as the force ``Q_i ratio_force`` itself (:meth:`evaluate_integrals`).
    ratio_area : ndarray (nq, nx)
        Change of the contact area with the defect (window, same approach), divided by the
        node's no-defect area ``A0(Q)`` (``<= 0``); read as the change ``A0(Q_i) ratio_area``.
    approach0, area0 : ndarray (nq,)
        No-defect approach ``delta0(Q)`` (m) and contact area ``A0(Q)`` (m^2) of the global
        solves. Interpolated as ``c(q) q^2`` with ``c`` linear in ``q = Q^(1/3)`` (exact for
        Hertz, where both grow as ``Q^(2/3)``), ``c`` held constant outside the nodes; on the
        dense grid ``q_out`` when the table has ``approach_out``, ``area_out``.
    approach_out, area_out : ndarray (nout,) or None
        The same at ``q_out`` (the ``P_out`` solves' own approach and area, no extra solve):
        ``c`` bends where the contact reaches the end relief, between the load nodes, and the
        approach change ``delta0(Q + dF) - delta0(Q)`` reads its slope (5 load nodes against
        17: its shaft-rate sidebands 11 % off at the 95th percentile read on the nodes, 1.3 %
        on ``q_out``; docs/benchmarks.md, "Load interpolation of the table").
    info : dict
        Diagnostics (interpolation errors, zoom consistency, grids, ...).
    p_cap : float or None
        The hardness bound of the solves (Pa, ``scene.material.hardness_pa``) or None: every
        solved pressure is <= it, but a product of linear readings (``P0 x ratio``) between
        nodes can exceed it (0.37 % measured at 750 kN / 50 um, draft), so ``P`` and ``P_d``
        are clipped to it.

    Raises
    ------
    ValueError
        ``q_out`` too short, not increasing, or of another size than ``p_out`` or the other
        dense arrays.
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
    approach_out: np.ndarray | None = None
    area_out: np.ndarray | None = None

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
        for name in ("approach_out", "area_out"):
            v = getattr(self, name)
            if v is not None and np.shape(v) != self.q_out.shape:
                raise ValueError(f"{name} must match q_out in size")

    @property
    def p_out_nodes(self) -> np.ndarray:
        """``P_out`` at the table's load nodes (Pa)."""
        return np.interp(np.cbrt(self.q_nodes), np.cbrt(self.q_out), self.p_out)

    def p_max_nodes(self) -> np.ndarray:
        """``P(Q_i, x_j) = max(W0 R, P_out)`` at the nodes (Pa), shape (nq, nx).

        Returns
        -------
        ndarray
            Pressure at the table's nodes, Pa, shape ``(nq, nx)``.
        """
        return np.maximum(self.w0[:, None] * self.ratio, self.p_out_nodes[:, None])

    def _q2_rule(self, v, v_out, Q):
        """``c(q) q^2``, ``c`` linear in ``q`` on the dense grid ``q_out`` (``v_out``) when the
        table has it, else on the load nodes (``v``); ``c`` held outside."""
        qs, vs = (self.q_out, v_out) if v_out is not None else (self.q_nodes, v)
        qn = np.cbrt(qs)
        q = np.cbrt(np.clip(Q, 0.0, None))
        return np.interp(q, qn, vs / qn ** 2) * q ** 2

    def approach_no_defect(self, Q) -> np.ndarray:
        """No-defect approach ``delta0(Q)`` (m) at roller loads ``Q`` (N).

        Parameters
        ----------
        Q : float or ndarray
            Roller loads, N.

        Returns
        -------
        ndarray
            Approach, m, shape of ``Q``; a table without ``approach0`` raises ``ValueError``.

        Raises
        ------
        ValueError
            The table stores no no-defect approach per node (an older table).
        """
        if self.approach0 is None:
            raise ValueError("this table has no approach0 (no-defect approach per load node)")
        return self._q2_rule(self.approach0, self.approach_out, Q)

    def area_no_defect(self, Q) -> np.ndarray:
        """No-defect contact area ``A0(Q)`` (m^2) at roller loads ``Q`` (N).

        Parameters
        ----------
        Q : float or ndarray
            Roller loads, N.

        Returns
        -------
        ndarray
            Area, m^2, shape of ``Q``; a table without ``area0`` raises ``ValueError``.

        Raises
        ------
        ValueError
            The table stores no no-defect contact area per node (an older table).
        """
        if self.area0 is None:
            raise ValueError("this table has no area0 (no-defect contact area per load node)")
        return self._q2_rule(self.area0, self.area_out, Q)

    def evaluate_integrals(self, Q, x, *, use_numba: bool = True) -> dict[str, np.ndarray]:
        """Integral signals at roller loads ``Q`` (N) and defect offsets ``x`` (m).

        Parameters
        ----------
        Q : float or ndarray
            Roller loads, N.
        x : float or ndarray
            Defect offsets, m, shape of ``Q``.
        use_numba : bool, default True
            Use the numba kernel for the ratio interpolation.

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

        Notes
        -----
        ``dF`` and ``dA`` themselves (``Q_i ratio_force``, ``A0(Q_i) ratio_area`` per node) are
        blended linearly in ``q`` between the rows, each row read like ``P_d/W0``: both hardly
        change with the load at a given distance from the contact edge, while their ratios to
        ``Q`` and ``A0`` go as ``Q^-1`` and ``Q^-2/3`` (read linearly in ``q`` the removed force
        was 3-22 % off between the 5 nodes of ``standard``, 0.7 % now; docs/benchmarks.md, "Load
        interpolation of the table"). Below the first node the ratios are held (``dF ~ Q``,
        ``dA ~ A0``).
        """
        Q = np.asarray(Q, dtype=float)
        x = np.asarray(x, dtype=float)
        a0 = self.area_no_defect(Q)
        dF = _ratio_eval(self, self.q_nodes[:, None] * self.ratio_force, Q, x, use_numba)
        dA = _ratio_eval(self, self.area0[:, None] * self.ratio_area, Q, x, use_numba)
        below = np.flatnonzero(Q.ravel() < self.q_nodes[0])     # the ratios held there
        if below.size:
            dF.ravel()[below] *= Q.ravel()[below] / self.q_nodes[0]
            dA.ravel()[below] *= a0.ravel()[below] / self.area0[0]
        d0 = self.approach_no_defect(Q)
        Qf = Q + dF
        area = self.area_no_defect(Qf)
        area += dA
        d = self.approach_no_defect(Qf)
        return {"removed_force": dF, "contact_force": Q - dF, "approach": d,
                "approach_change": d - d0, "contact_area": area}

    def scale(self, Q):
        """``s(Q) = kappa a_coef Q^(1/3) + s_const`` (m).

        Parameters
        ----------
        Q : float or ndarray
            Roller loads, N.

        Returns
        -------
        float or ndarray
            ``s(Q)``, m, shape of ``Q``.
        """
        return self.kappa * self.a_coef * np.cbrt(Q) + self.s_const

    def offsets(self) -> np.ndarray:
        """Offsets of the nodes (m).

        Returns
        -------
        ndarray
            ``xi_nodes * s_max``, m, shape ``(nx,)``.
        """
        return self.xi_nodes * self.s_max

    def args(self):
        """Arrays and scalars of the interpolation (for the kernels).

        Returns
        -------
        tuple
            ``(cbrt(q_nodes), offsets(), w0, ratio, ratio_defect, kappa a_coef, s_const,
            cbrt(q_out), p_out)``, arrays C-contiguous.
        """
        return (np.ascontiguousarray(np.cbrt(self.q_nodes)), np.ascontiguousarray(self.offsets()),
                np.ascontiguousarray(self.w0), np.ascontiguousarray(self.ratio),
                np.ascontiguousarray(self.ratio_defect), self.kappa * self.a_coef, self.s_const,
                np.ascontiguousarray(np.cbrt(self.q_out)), np.ascontiguousarray(self.p_out))

    def evaluate(self, Q, x):
        """Interpolated ``(P, P_d)`` (Pa) at roller loads ``Q`` (N) and offsets ``x`` (m).

        Parameters
        ----------
        Q : float or ndarray
            Roller loads, N.
        x : float or ndarray
            Defect offsets, m, shape of ``Q``.

        Returns
        -------
        P, P_d : ndarray
            Maximum pressure of the contact and at the defect, Pa, shape of ``Q``; capped at
            ``p_cap`` when set.
        """
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
        ratio_kernel(np.ascontiguousarray(Q.ravel()), np.ascontiguousarray(x.ravel()), qn, xn,
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


#: Relative width of the load range of a table whose defect meets one load only (an outer-race
#: defect under a steady load): two nodes, ``Q (1 - w)`` and ``Q``.
CONSTANT_LOAD_SPAN = 0.02


def _table_loads(q_max: float, n_loads: int, q_min: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Roller-load nodes, uniform in ``q = Q^(1/3)``, returns ``(q, Q)``.

    ``q_min`` None: from ``Q_MIN_FRACTION q_max`` to ``q_max`` (``n_loads`` nodes; below the
    first node the rows are scaled, not solved). ``q_min`` given (the smallest load the defect
    meets, :func:`~.exposure.exposure`): from ``q_min`` to ``q_max``, as many nodes as keep the
    spacing in ``q`` of the default rule at this ``q_max`` (at least 2, at least ``n_loads`` for
    a range as wide as the default); one load only: the two nodes of
    :data:`CONSTANT_LOAD_SPAN`."""
    top = q_max ** (1 / 3)
    lo_default = (Q_MIN_FRACTION * q_max) ** (1 / 3)
    if q_min is None:
        qn = np.linspace(lo_default, top, n_loads)
        return qn, qn ** 3
    lo = min(q_min, (1.0 - CONSTANT_LOAD_SPAN) * q_max) ** (1 / 3)
    step = (top - lo_default) / max(n_loads - 1, 1)
    n = max(2, int(math.ceil((top - lo) / step - 1e-9)) + 1)
    qn = np.linspace(lo, top, n)
    return qn, qn ** 3


def unloaded_table(scene: Scene) -> PressureTable:
    """The table of a contact that never carries load (:func:`~.exposure.exposure`: the defect
    never meets a loaded element): every reading at ``Q = 0`` is 0 (pressure, force, approach,
    area) without a solve. Its load nodes (1 and 2 N) are placeholders: reading it at ``Q > 0``
    is refused.

    Parameters
    ----------
    scene : Scene
        The scene (its defect extent, Hertz estimate and hardness).

    Returns
    -------
    PressureTable
        The placeholder table, ``info["unloaded"] = True``.
    """
    qn = np.array([1.0, 2.0])
    q_out = np.linspace(1.0, 2.0, OUTSIDE_LOAD_DENSITY + 1)
    z2, zo = np.zeros((2, 2)), np.zeros(q_out.size)
    ex = scene.defect.extent_x_m if scene.defect.active else 0.0
    tab = PressureTable(qn, np.array([0.0, 1.0]), np.zeros(2), np.zeros(2), np.ones((2, 2)), z2,
                        hertz_estimate(scene, 1.0).a, 1.0, 0.5 * ex, 1e-3, q_out, zo,
                        # areas 1 m^2 at the placeholder nodes: read as c(q) q^2, 0 at Q = 0
                        approach0=np.zeros(2), area0=np.ones(2), approach_out=zo,
                        area_out=np.ones(q_out.size),
                        p_cap=scene.material.hardness_pa)
    tab.info = {"unloaded": True, "interp_max_rel_error_p_max": 0.0}
    return tab


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
        step_max = min(d.extent_x_m / fid.offsets_per_width, fid.offset_step_m)
        n = max(n, int(math.ceil(fid.xi_max * s_reach / step_max)) + 1)
        n = min(n, fid.max_offsets)
    step = max(1, int(math.ceil(fid.xi_max * s_reach / (n - 1) / dxw - 1e-9))) * dxw
    n = int(math.ceil(fid.xi_max * s_reach / step - 1e-9)) + 1
    return step * np.arange(n)


def offset_count(scene: Scene, fid: Fidelity, q_max: float) -> int:
    """Defect offsets per load node of a table up to ``q_max`` as :func:`build_table` expects
    them before its first solve (its progress bar's count; the solved contact widths move it
    by a few), for the pre-run cost estimate (:mod:`bearing_envelope.study.limits`).

    Parameters
    ----------
    scene : Scene
        The scene with its modelled contact (``for_race``).
    fid : Fidelity
        The table's fidelity (offset rules and window spacing).
    q_max : float
        The table's largest load, N.

    Returns
    -------
    int
        Offset nodes (:func:`_offset_nodes`).
    """
    d = scene.defect
    s_reach = (REACH_GUESS_FACTOR * hertz_estimate(scene, q_max).a
               + 0.5 * (d.extent_x_m if d.active else 0.0) + fid.neighbourhood_m)
    return int(_offset_nodes(scene, fid, s_reach, window_spec(scene, fid, q_max, 1.0)[2]).size)


def _progress(stats: SolveStats, total: int, progress: bool | None):
    """A tqdm bar over ``total`` solves fed by ``stats`` (None when ``progress`` is None or
    False: a quiet job does not import tqdm, 0.05 CPU s)."""
    if not progress:
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
        node = solve_load(scene, fid, float(q), kappa, stats)
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
                    Rd[i, j] = neighbourhood_max(scene, fid, nd.window, nd.p_window0, xj) / nd.w0
            snap["offsets"] = np.asarray(snap_xi) * s_i
            snap["window_pressure"] = np.repeat(nd.p_window0[None].astype(np.float32),
                                                len(snap_xi), axis=0)
        else:
            p_prev = None
            solved: dict[int, np.ndarray] = {}
            for j in range(nxi - 1, -1, -1):
                if x_nodes[j] > reach or nd.w0 <= 0:
                    tick()
                    continue
                ds = defect_solve(scene, fid, nd, x_nodes[j], stats, p_prev)
                p_prev = solved[j] = ds.pressure
                R[i, j] = ds.W / nd.w0
                Rd[i, j] = ds.Pd / nd.w0
                RF[i, j] = ds.removed_force / nd.q
                RA[i, j] = ds.area_change / nd.area_global
                dF_max = max(dF_max, abs(ds.removed_force) / nd.q)
            # the snapshots are the table's own solves at the offset nodes nearest to
            # xi s(Q) (until issue 33 solved again at xi s(Q) exactly: 30 of the 256 defect
            # solves of a CWRU ball case, for pictures only)
            picked = [_nearest_solved(solved, x_nodes, xi * s_i) for xi in snap_xi]
            fields = [solved[j].astype(np.float32) if j is not None else
                      defect_solve(scene, fid, nd, xi * s_i, stats).pressure.astype(np.float32)
                      for j, xi in zip(picked, snap_xi)]
            snap["offsets"] = np.array([x_nodes[j] if j is not None else xi * s_i
                                        for j, xi in zip(picked, snap_xi)])
            snap["window_pressure"] = np.array(fields) if fields else \
                np.zeros((0,) + nd.window.shape, np.float32)
        snapshots[f"load_{i}"] = snap
    return _DefectRatios(R, Rd, RF, RA, dF_max, snapshots)


def _nearest_solved(solved: dict, x_nodes: np.ndarray, x: float) -> int | None:
    """Index of the solved offset node nearest to ``x`` (m), None when none is solved."""
    return min(solved, key=lambda j: abs(x_nodes[j] - x)) if solved else None


def _outside_maxima(scene: Scene, fid: Fidelity, nodes: list[LoadNode], qn: np.ndarray,
                    kappa: float, stats: SolveStats) -> tuple[np.ndarray, ...]:
    """The no-defect maximum outside the read strip (roller ends) on a load grid
    :data:`OUTSIDE_LOAD_DENSITY` times denser than the nodes (global solves only; the nodes'
    own values are reused), refined by bisection where it bends (:func:`_refine_outside`).
    Returns ``(q_out, p_out, approach_out, area_out)``, ``q_out`` in N: the same global solves'
    approach and contact area come with them."""
    m_out = OUTSIDE_LOAD_DENSITY
    nout = m_out * (qn.size - 1) + 1
    q_base = np.linspace(qn[0], qn[-1], nout)
    v_base = np.empty((nout, 3))
    for k, qo in enumerate(q_base):
        if k % m_out == 0:
            nd = nodes[k // m_out]
            v_base[k] = (nd.outside_max, nd.approach_global, nd.area_global)
        else:
            v_base[k] = outside_solve(scene, fid, float(qo ** 3), kappa, stats)
    q_out, v_out = _refine_outside(scene, fid, kappa, stats, q_base, v_base)
    return q_out ** 3, v_out[:, 0], v_out[:, 1], v_out[:, 2]


def _interpolation_checks(scene: Scene, fid: Fidelity, table: "PressureTable", qn: np.ndarray,
                          dxw: float, stats: SolveStats, seed: int) -> dict[str, Any]:
    """The table's interpolation error against direct solves at ``n_checks`` random loads, at
    :data:`CHECK_OFFSETS_PER_LOAD` offsets each on the window grid (pure table error) and as
    many anywhere (adds the sub-cell discretisation jitter). Returns the ``info`` entries."""
    checks, checks_any, checks_any_failed = [], [], []
    if scene.defect.active and fid.n_checks:
        rng = np.random.default_rng(seed)
        ex = scene.defect.extent_x_m
        for _ in range(fid.n_checks):
            qc = float(rng.uniform(qn[0], qn[-1]) ** 3)
            # offsets where the defect overlaps the contact (beyond, the table is exact)
            reach = table.kappa * table.a_coef * qc ** (1 / 3) + 0.5 * ex
            node = solve_load(scene, fid, qc, table.kappa, stats, with_far=False)
            pairs = []
            for _k in range(CHECK_OFFSETS_PER_LOAD):
                pairs.append((round(float(rng.uniform(0.0, reach)) / dxw) * dxw, checks))
                pairs.append((float(rng.uniform(0.0, reach)), checks_any))
            for xd, out in pairs:
                try:
                    ds = defect_solve(scene, fid, node, xd, stats)
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
    checks_a, err, err_d, err_rms = interpolation_check_errors(checks)
    checks_b, err_any, err_d_any, err_any_rms = interpolation_check_errors(checks_any)
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
                    q_base: np.ndarray, v_base: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bisect the intervals of ``(q_base, v_base)`` (``q = Q^(1/3)``; ``v``: rows of
    :func:`~.solves.outside_solve`) where the solved midpoint's ``P_out`` misses the linear
    reading by more than :data:`OUTSIDE_REFINE_TOL` (relative), at most
    :data:`OUTSIDE_REFINE_DEPTH` times; every midpoint solved is kept. Global solves only."""
    qs, vs = [float(q_base[0])], [np.asarray(v_base[0], float)]

    def bisect(qa, va, qb, vb, depth):
        qm = 0.5 * (qa + qb)
        vm = np.array(outside_solve(scene, fid, qm ** 3, kappa, stats))
        if depth < OUTSIDE_REFINE_DEPTH and \
                abs(vm[0] - 0.5 * (va[0] + vb[0])) > OUTSIDE_REFINE_TOL * vm[0]:
            bisect(qa, va, qm, vm, depth + 1)
            bisect(qm, vm, qb, vb, depth + 1)
        else:
            qs.extend([qm, qb])
            vs.extend([vm, vb])

    for k in range(q_base.size - 1):
        bisect(float(q_base[k]), np.asarray(v_base[k], float), float(q_base[k + 1]),
               np.asarray(v_base[k + 1], float), 1)
    return np.array(qs), np.array(vs)


def build_table(scene: Scene, fidelity: Fidelity, *, q_max: float,
                stats: SolveStats | None = None, progress: bool = False,
                check_seed: int = 20261122, q_min: float | None = None,
                ) -> tuple[PressureTable, list[LoadNode], dict]:
    """Solve the contacts and build the ``P(Q, x)`` table for roller loads up to ``q_max``
    (from ``q_min``, the smallest load the defect meets, when given: :func:`_table_loads`).

    Stages: load nodes uniform in ``Q^(1/3)`` (:func:`_table_loads`); the no-defect global +
    window solve at each (:func:`_solve_load_nodes`, which fixes ``kappa``); offsets on the
    window grid (:func:`_offset_nodes`); the defect window solves (:func:`_defect_ratios`); the
    roller-end maxima on a denser load grid (:func:`_outside_maxima`); the interpolation checks
    against direct solves (:func:`_interpolation_checks`).

    Parameters
    ----------
    scene : Scene
        The scene, its modelled contact (``for_race``) included.
    fidelity : Fidelity
        Grid and node counts.
    q_max : float
        Largest roller load, N.
    stats : SolveStats, optional
        Accumulates the solve counters.
    progress : bool, default False
        Show a progress bar.
    check_seed : int, default 20261122
        Seed of the interpolation checks' random loads and offsets.
    q_min : float, optional
        Smallest roller load the defect meets, N.

    Returns
    -------
    table : PressureTable
        The ``P(Q, x)`` / ``P_d(Q, x)`` table (Pa over N and m) with its integral signals.
    nodes : list of LoadNode
        Per-load solutions (for snapshots).
    snapshots : dict
        Pressure fields at a few offsets per load (for maps like the study's Fig. 4).
    """
    fid = fidelity
    stats = stats or SolveStats()
    d = scene.defect
    nq = fid.n_loads
    qn, q_nodes = _table_loads(q_max, nq, q_min)
    nq = qn.size
    a_coef = hertz_estimate(scene, q_max).a / q_max ** (1 / 3)
    ex = d.extent_x_m if d.active else 0.0
    s_const = 0.5 * ex + fid.neighbourhood_m
    # offsets in absolute x: normalised by the largest load's s(Q) only (the pressure peak
    # oscillates with the offset on the scale of the defect width, fixed in x, not in x/a)
    dxw = window_spec(scene, fid, q_max, 1.0)[2]
    nxi = offset_count(scene, fid, q_max)
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
        q_out, p_out, approach_out, area_out = _outside_maxima(scene, fid, nodes, qn, kappa,
                                                               stats)
        table = PressureTable(q_nodes, x_nodes / s_max, np.array([nd.p0 for nd in nodes]),
                              np.array([nd.w0 for nd in nodes]), dr.ratio, dr.ratio_defect,
                              a_coef, kappa, s_const, s_max, q_out, p_out,
                              out_density=OUTSIDE_LOAD_DENSITY, ratio_force=dr.ratio_force,
                              ratio_area=dr.ratio_area,
                              approach0=np.array([nd.approach_global for nd in nodes]),
                              area0=np.array([nd.area_global for nd in nodes]),
                              p_cap=scene.material.hardness_pa, approach_out=approach_out,
                              area_out=area_out)
        table.info = {
            **_interpolation_checks(scene, fid, table, qn, dxw, stats, check_seed),
            "interp_variables": (
                "W/W0, P_d/W0, removed force dF = Q_i ratio_force and area change dA = A0(Q_i) "
                "ratio_area: each node row read linearly in x at the same distance from its "
                "contact edge kappa a_coef Q_i^(1/3), the rows blended linearly in q = Q^(1/3); "
                "W0, P_out linear in q; P = max(W, P_out); delta0, A0 as c(q) q^2 on q_out; "
                "offset nodes on multiples of the window spacing"),
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


def direct_pressure(scene: Scene, fidelity: Fidelity, q_load: float, x_d: float,
                    *, kappa: float = 1.0, stats: SolveStats | None = None) -> tuple[float, float]:
    """``(P, P_d)`` (Pa) from a direct zoom solve at roller load ``q_load`` and offset ``x_d``.

    Parameters
    ----------
    scene : Scene
        The scene.
    fidelity : Fidelity
        Grid settings.
    q_load : float
        Roller load, N.
    x_d : float
        Defect offset, m.
    kappa : float, default 1
        Solved/Hertz contact half-width ratio of the zoom window.
    stats : SolveStats, optional
        Accumulates the solve counters.

    Returns
    -------
    tuple of float
        ``(P, P_d)``, Pa: maximum pressure and pressure at the defect (the neighbourhood maximum
        without a defect).
    """
    fid = fidelity
    stats = stats or SolveStats()
    node = solve_load(scene, fid, q_load, kappa, stats)
    if not scene.defect.active:
        return node.p0, neighbourhood_max(scene, fid, node.window, node.p_window0, x_d)
    ds = defect_solve(scene, fid, node, x_d, stats)
    return ds.P, ds.Pd


# ---------------------------------------------------------------------------------------------
# kinematics and synthesis
