"""Frictionless normal contact on an elastic half-space: Polonsky-Keer constrained CG.

See :func:`solve_contact` and ``docs/contact.md``.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from . import _kernels
from .halfspace import (DEFAULT_ELEMENT, DEFAULT_FFT_BACKEND, ElasticHalfSpace, get_halfspace,
                        irfft2, rfft2)

__all__ = [
    "ContactSolution",
    "ContactGridError",
    "ContactGridWarning",
    "ContactConvergenceError",
    "solve_contact",
]


class ContactGridError(ValueError):
    """Pressure reaches the edge of the grid: the domain is too small for this load."""

    def __init__(self, message: str, fraction: float):
        super().__init__(message)
        self.fraction = fraction


class ContactGridWarning(UserWarning):
    """Pressure reaches the edge of the grid (``boundary="warn"``)."""


class ContactConvergenceError(RuntimeError):
    """The solver did not reach ``tol`` within ``max_iter`` iterations."""

    def __init__(self, message: str, residual_history: list[float], solution: "ContactSolution | None" = None):
        super().__init__(message)
        self.residual_history = residual_history
        self.solution = solution


@dataclass(frozen=True, eq=False)
class ContactSolution:
    """Result of :func:`solve_contact`.

    Attributes
    ----------
    pressure : ndarray
        Contact pressure (Pa), shape of ``gap``; zero outside the contact and on ``+inf`` cells.
    approach : float
        Rigid-body approach (m): the deformed gap is ``gap + displacement - approach``.
    iterations : int
        Conjugate-gradient iterations done.
    residual : float
        Final value of the convergence measure (see :func:`solve_contact`).
    converged : bool
        ``residual <= tol``.
    contact_area : float
        Area of the cells carrying pressure (m^2).
    force : float
        ``sum(pressure) * dx * dy`` (N).
    residual_history : tuple of float
        Residual at every iteration (index 0: the initial guess).
    displacement : ndarray
        Combined elastic surface displacement ``K * p`` (m) of the returned pressure.
    convolutions : int
        Number of DC-FFT convolutions done (cost measure).
    preconditioner_dropped_at : int or None
        Iteration at which the stall guard switched the Fourier preconditioner off (see
        :func:`solve_contact`, Notes), or None.
    hardness : float or None
        The pressure bound ``H`` (Pa) the solve used, None = elastic.
    plastic : ndarray of bool or None
        Plastic cells, ``p = H`` (None without ``hardness``).
    plastic_depth : ndarray or None
        Permanent (plastic) indentation (m) of every cell: the interpenetration ``-h >= 0`` the
        elastic surfaces would need where ``p = H``, zero elsewhere (None without ``hardness``).
    plastic_area : float
        Area of the plastic cells (m^2); 0 without ``hardness``.
    """

    pressure: np.ndarray
    approach: float
    iterations: int
    residual: float
    converged: bool
    contact_area: float
    force: float
    residual_history: tuple = field(repr=False)
    displacement: np.ndarray = field(repr=False)
    convolutions: int = 0
    preconditioner_dropped_at: int | None = None
    hardness: float | None = None
    plastic: np.ndarray | None = field(default=None, repr=False)
    plastic_depth: np.ndarray | None = field(default=None, repr=False)
    plastic_area: float = 0.0

    @property
    def p_max(self) -> float:
        """Maximum pressure (Pa)."""
        return float(self.pressure.max())

    @property
    def plastic_depth_max(self) -> float:
        """Largest permanent indentation (m); 0 without ``hardness``."""
        return 0.0 if self.plastic_depth is None else float(self.plastic_depth.max())


def _check_scalar(name: str, value, allowed: str = "a finite number > 0") -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {allowed}, got {value!r}") from None
    if not math.isfinite(v) or v <= 0:
        raise ValueError(f"{name} must be {allowed}, got {value!r}")
    return v


def _initial_guess(g: np.ndarray, mat: np.ndarray, force: float, e_star: float, cell: float) -> np.ndarray:
    """Local-Hertz starting pressure.

    For a paraboloid-like gap, Hertz gives ``F = (4/3) E* d sqrt(A_d / (2 pi))`` where ``d`` is
    the approach and ``A_d`` the geometric overlap area ``{g - min g < d}``; find ``d`` from the
    sorted gap, then put ``p ~ sqrt(1 - 2 g'/d)`` on ``{g' < d/2}`` (scaled to the force).
    """
    gv = np.sort(g[mat]) - g[mat].min()
    n = gv.size
    area = np.arange(1, n + 1) * cell
    # force estimate if the approach were gv[k] (include the k+1 cells below it)
    est = (4.0 / 3.0) * e_star * gv * np.sqrt(area / (2.0 * math.pi))
    k = int(np.searchsorted(est, force))
    if k >= n:
        d = gv[-1] if gv[-1] > 0 else 1.0
    elif k == 0:
        d = gv[0]
    else:
        d = gv[k]
    gp = np.where(mat, g - g[mat].min(), np.inf)
    if d <= 0:
        p = (gp <= 0).astype(float)
    else:
        s = 1.0 - 2.0 * gp / d
        p = np.sqrt(np.clip(s, 0.0, None))
        if not p.any():
            p = (gp <= 0).astype(float)
    if not p.any():  # pragma: no cover - degenerate
        p = mat.astype(float)
    return p * (force / (p.sum() * cell))


def solve_contact(
    gap,
    dx: float,
    dy: float,
    force: float | None,
    e_star: float,
    *,
    tol: float = 1e-8,
    max_iter: int = 1000,
    p_init=None,
    approach: float | None = None,
    boundary: str = "raise",
    workers: int | None = None,
    halfspace: ElasticHalfSpace | None = None,
    precondition: bool = True,
    fft_backend: str = DEFAULT_FFT_BACKEND,
    kernels: dict | None = None,
    element: str = DEFAULT_ELEMENT,
    stall_window: int = 40,
    hardness: float | None = None,
) -> ContactSolution:
    """Frictionless normal contact of two elastic half-spaces (Polonsky-Keer CG).

    Parameters
    ----------
    gap : (nx, ny) array_like
        Initial separation ``g`` (m) on the grid (axis 0 = x = rolling, spacing ``dx``; axis 1 =
        y = axial, spacing ``dy``). ``+inf`` marks cells without material (beyond a roller end):
        they never carry pressure. NaN is an error.
    dx, dy : float
        Grid spacing (m), > 0.
    force : float or None
        Normal force (N), > 0 and finite; enforced exactly. Ignored (may be None) when
        ``approach`` is given.
    e_star : float
        Composite modulus (Pa), > 0 (:func:`composite_modulus`).
    tol : float
        Convergence tolerance (see Notes).
    max_iter : int
        Maximum CG iterations; :class:`ContactConvergenceError` (with ``residual_history``) if
        ``tol`` is not reached.
    p_init : (nx, ny) array_like, optional
        Warm start (Pa), e.g. the solution of a neighbouring load or defect position. Negative
        values and values on ``+inf`` cells are dropped, and under displacement control also the
        values on cells with ``gap > approach`` (they can never touch); under force control it
        is rescaled to ``force``.
    approach : float, optional
        Displacement control: the rigid approach (m) is prescribed and the force follows.
    boundary : {"raise", "warn", "ignore"}
        What to do when pressure reaches the outermost finite cells of the grid (the grid is too
        small): raise :class:`ContactGridError` (a ``ValueError``), warn
        (:class:`ContactGridWarning`), or ignore. The message gives the fraction of the force
        carried by the edge cells.
    workers : int, optional
        FFT threads (default ``OMP_NUM_THREADS`` or all cores).
    halfspace : ElasticHalfSpace, optional
        Reuse a prepared operator (must match shape, dx, dy, e_star).
    element : {"uniform", "linear"}
        Pressure discretisation: ``"uniform"`` pressure on each cell (collocation at the cell
        centre; the default, same as tamaas' ``dcfft``) or ``"linear"``: nodal values with
        piecewise-bilinear (pyramidal) interpolation between nodes, as in the source study.
        Both converge to the same continuum solution (see ``docs/contact.md``).
    fft_backend : {"auto", "scipy", "pyfftw"}
        FFT library (:class:`ElasticHalfSpace`); ``"auto"`` uses pyfftw when importable.
    kernels : dict, optional
        Element-wise passes to use (testing): ``contact.NUMPY_KERNELS`` or the default numba ones.
    precondition : bool
        Precondition the CG direction with the approximate inverse of the half-space operator,
        applied in Fourier space on the bounding box of the contact set (see Notes).
    stall_window : int
        Stall guard of the preconditioned iteration: if the residual has not halved within this
        many iterations, continue without the preconditioner (see Notes). >= 1.
    hardness : float, optional
        Indentation hardness ``H`` (Pa), > 0 and finite: elastic-perfectly-plastic surface, the
        pressure is bounded by ``0 <= p <= H`` (see Notes). None (default) = elastic. A bound the
        solution never reaches gives the elastic solution bit for bit.

    Returns
    -------
    ContactSolution

    Notes
    -----
    Discretisation: uniform pressure on each ``dx x dy`` cell, displacement collocated at the
    cell centres, ``u = K * p`` by DC-FFT (:class:`ElasticHalfSpace`). The discrete Signorini
    problem

    .. math::

        h = g + K p - \\alpha,\\quad p \\ge 0,\\quad h \\ge 0,\\quad p\\,h = 0,\\quad
        \\textstyle\\sum p\\,\\Delta x\\Delta y = F

    is solved by the constrained conjugate gradient of Polonsky & Keer (1999): CG on the current
    contact set :math:`I_c = \\{p > 0\\}` with the approach :math:`\\alpha = \\overline{g+Kp}|_{I_c}`,
    negative pressures are cut to zero, cells outside :math:`I_c` with :math:`h < 0` enter
    the contact (and restart CG), and the pressure is rescaled to ``F`` after every step.

    Preconditioner: the operator :math:`K` has the symbol :math:`2/(E^*|q|)`, so its small
    eigenvalues are the short wavelengths that plain CG resolves last (contact edges, defects,
    warm starts). The search direction is :math:`z = P_{I_c} M^{-1} P_{I_c} h` with
    :math:`\\hat M^{-1} = E^*\\sqrt{|q|^2 + q_0^2}/2` applied by a periodic FFT on the bounding
    box of :math:`I_c` (plus a margin), :math:`q_0 = 2\\pi/L_{box}`; under force control
    :math:`z` is projected to zero mean on :math:`I_c`. Its cost is a small fraction of one
    padded convolution.

    Convergence criterion, evaluated on the pressure being returned (its gap ``h`` is computed
    from that pressure):

    .. math::

        r = \\max\\left(\\frac{\\sum|p^{k} - p^{k-1}|}{\\sum p^{k}},\\;
            \\frac{\\max\\left(\\max_{I_c}|h|,\\ \\max_{\\notin I_c}(-h)^+\\right)}{\\max u}
            \\right) \\le \\mathrm{tol},

    i.e. the relative pressure change of the last step AND the worst violation of
    :math:`h = 0` on the contact / :math:`h \\ge 0` outside, relative to the largest elastic
    displacement. :math:`p \\ge 0` and the force hold exactly at every iterate.

    Hardness (elastic-perfectly-plastic surface, ``hardness=H``): the bounded problem

    .. math::

        0 \\le p \\le H,\\quad p = 0 \\Rightarrow h \\ge 0,\\quad 0 < p < H \\Rightarrow h = 0,
        \\quad p = H \\Rightarrow h \\le 0,\\quad \\textstyle\\sum p\\,\\Delta x\\Delta y = F

    is solved by the same iteration on the free set :math:`I_f = \\{0 < p < H\\}`: plastic
    cells (:math:`p = H`) are fixed during a CG step like :math:`p = 0` cells, the approach is the
    mean of :math:`g + Kp` on :math:`I_f`, a step is clipped to :math:`[0, H]`, plastic cells with
    :math:`h > 0` (over-loaded) rejoin :math:`I_f` before a step, which restarts CG and lowers them
    by its line search (cells with :math:`p = 0, h < 0` enter the contact as before), and the force is restored by scaling the free cells only (cells the scaling
    lifts past ``H`` become plastic, iterated until none does), so :math:`0 \\le p \\le H` and
    the force hold exactly at every iterate. The residual adds :math:`\\max_{p = H} h^+`. The
    plastic interpenetration :math:`-h` on the plastic cells is the permanent indentation
    (``plastic_depth``). This is the bounded Polonsky-Keer iteration of ContactMechanics'
    ``hardness`` option (Weber et al. 2018) and of Almqvist et al. (2007).

    References
    ----------
    I. A. Polonsky, L. M. Keer, A numerical method for solving rough contact problems based on
    the multi-level multi-summation and conjugate gradient techniques, Wear 231 (1999) 206-219.
    A. Almqvist, F. Sahlin, R. Larsson, S. Glavatskih, On the dry elasto-plastic contact of
    nominally flat surfaces, Tribol. Int. 40 (2007) 574-579.
    B. Weber, T. Suhina, T. Junge, L. Pastewka, A. M. Brouwer, D. Bonn, Molecular probes reveal
    deviations from Amontons' law in multi-asperity frictional contacts, Nat. Commun. 9 (2018) 888.
    S. Liu, Q. Wang, G. Liu, A versatile method of discrete convolution and FFT (DC-FFT) for
    contact analyses, Wear 243 (2000) 101-111.

    Examples
    --------
    >>> import numpy as np
    >>> from bearing_envelope.contact import solve_contact, hertz
    >>> R, F, E = 0.01, 10.0, 1e11
    >>> a = hertz.sphere(F, R, E).a
    >>> n = 64; d = 6 * a / n
    >>> x = (np.arange(n) - n // 2) * d
    >>> g = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * R)
    >>> s = solve_contact(g, d, d, F, E)
    >>> abs(s.p_max / hertz.sphere(F, R, E).p0 - 1) < 0.01
    True
    """
    problem = _validate(gap, dx, dy, force, e_star, tol=tol, max_iter=max_iter,
                        stall_window=stall_window, boundary=boundary, hardness=hardness,
                        approach=approach)
    hs = _operator(problem, halfspace, workers, fft_backend, element)
    p, empty = _initial_pressure(problem, p_init, hs)
    if empty is not None:
        return empty
    run = _PolonskyKeer(problem, p, hs, _kernels.KERNELS if kernels is None else kernels,
                        precondition, n_conv=1 if (p_init is None and problem.disp_control) else 0)
    run.iterate()
    return _solution(problem, run)


# ---- the stages of solve_contact -----------------------------------------------------------


@dataclass(frozen=True, eq=False)
class _Problem:
    """The validated inputs of one :func:`solve_contact` call (SI units)."""

    g: np.ndarray  # gap (m), +inf = no material
    mat: np.ndarray  # cells with material (finite gap)
    dx: float
    dy: float
    cell: float  # dx * dy (m^2)
    e_star: float
    tol: float
    max_iter: int
    stall_window: int
    boundary: str
    H: float  # pressure bound (Pa), inf = elastic
    hard: bool
    disp_control: bool
    alpha_fixed: float  # prescribed approach (m); nan under force control
    force_v: float  # prescribed force (N); nan under displacement control


def _check_gap(gap) -> np.ndarray:
    g = np.asarray(gap, dtype=float)
    if g.ndim != 2:
        raise ValueError(f"gap must be a 2-D array (nx, ny), got ndim={g.ndim} shape={g.shape}")
    if g.shape[0] < 2 or g.shape[1] < 2:
        raise ValueError(f"gap must be at least 2 x 2, got shape={g.shape}")
    if np.isnan(g).any():
        raise ValueError(f"gap contains NaN ({int(np.isnan(g).sum())} cells); use +inf for 'no material'")
    if np.isneginf(g).any():
        raise ValueError("gap contains -inf; allowed: finite values or +inf (no material)")
    return g


def _check_hardness(hardness) -> float:
    if hardness is None:
        return math.inf
    if isinstance(hardness, bool):
        raise ValueError(f"hardness must be a finite number > 0 (Pa) or None, got {hardness!r}")
    return _check_scalar("hardness", hardness, "a finite number > 0 (Pa) or None")


def _validate(gap, dx, dy, force, e_star, *, tol, max_iter, stall_window, boundary, hardness,
              approach) -> _Problem:
    """Stage 1: check every input (in the documented order) and return the problem."""
    g = _check_gap(gap)
    dx = _check_scalar("dx", dx)
    dy = _check_scalar("dy", dy)
    e_star = _check_scalar("e_star", e_star)
    if not (isinstance(tol, (int, float)) and 0 < tol < 1):
        raise ValueError(f"tol must be in (0, 1), got {tol!r}")
    if int(max_iter) < 1:
        raise ValueError(f"max_iter must be >= 1, got {max_iter!r}")
    if isinstance(stall_window, bool) or not isinstance(stall_window, int) or stall_window < 1:
        raise ValueError(f"stall_window must be an integer >= 1, got {stall_window!r}")
    if boundary not in ("raise", "warn", "ignore"):
        raise ValueError(f"boundary must be 'raise', 'warn' or 'ignore', got {boundary!r}")
    H = _check_hardness(hardness)
    disp_control = approach is not None
    alpha_fixed = force_v = float("nan")
    if disp_control:
        try:
            alpha_fixed = float(approach)
        except (TypeError, ValueError):
            raise ValueError(f"approach must be a finite number (m), got {approach!r}") from None
        if not math.isfinite(alpha_fixed):
            raise ValueError(f"approach must be a finite number (m), got {approach!r}")
    else:
        force_v = _check_scalar("force", force, "a finite number > 0 (N)")
    mat = np.isfinite(g)
    if not mat.any():
        raise ValueError("gap has no finite cell: nothing can carry the load")
    return _Problem(g=g, mat=mat, dx=dx, dy=dy, cell=dx * dy, e_star=e_star, tol=tol,
                    max_iter=max_iter, stall_window=stall_window, boundary=boundary, H=H,
                    hard=hardness is not None, disp_control=disp_control,
                    alpha_fixed=alpha_fixed, force_v=force_v)


def _operator(problem: _Problem, halfspace, workers, fft_backend, element) -> ElasticHalfSpace:
    """Stage 2: the half-space operator, prepared or checked against the problem."""
    g, dx, dy, e_star = problem.g, problem.dx, problem.dy, problem.e_star
    if halfspace is None:
        return get_halfspace(g.shape, dx, dy, e_star, workers=workers, backend=fft_backend, element=element)
    hs = halfspace
    if hs.shape != g.shape or (hs.dx, hs.dy, hs.e_star, hs.element) != (dx, dy, e_star, element):
        raise ValueError(f"halfspace {hs!r} does not match gap shape {g.shape}, dx, dy, e_star, element")
    return hs


def _warm_start(problem: _Problem, p_init) -> np.ndarray | None:
    """The usable part of a warm start (None if nothing is left of it)."""
    g, mat = problem.g, problem.mat
    p = np.array(p_init, dtype=float)
    if p.shape != g.shape:
        raise ValueError(f"p_init.shape must equal gap.shape {g.shape}, got {p.shape}")
    if not np.isfinite(p).all():
        raise ValueError("p_init must be finite")
    p[~mat] = 0.0
    np.maximum(p, 0.0, out=p)
    if problem.hard:
        np.minimum(p, problem.H, out=p)
    if problem.disp_control:
        # h = g + K p - alpha with K p >= 0: a cell with g > alpha can never touch, so warm
        # pressure there (e.g. where a defect has moved in) is dropped before the first step
        p[g > problem.alpha_fixed] = 0.0
    return p if p.any() else None


def _initial_pressure(problem: _Problem, p_init, hs: ElasticHalfSpace):
    """Stage 3: the starting pressure, ``(p, None)``; or ``(None, solution)`` when under
    displacement control nothing overlaps (no contact: the solution is zero)."""
    g, mat, H, hard = problem.g, problem.mat, problem.H, problem.hard
    p = _warm_start(problem, p_init) if p_init is not None else None
    if p is None:
        if problem.disp_control:
            alpha_fixed = problem.alpha_fixed
            over = np.where(mat, np.clip(alpha_fixed - np.where(mat, g, 0.0), 0.0, None), 0.0)
            if not over.any():  # no overlap: no contact
                z = np.zeros_like(g)
                return None, ContactSolution(
                    z, alpha_fixed, 0, 0.0, True, 0.0, 0.0, (0.0,), z.copy(),
                    hardness=H if hard else None, plastic=np.zeros(g.shape, bool) if hard else None,
                    plastic_depth=z.copy() if hard else None)
            ku = hs.displacement(over)
            p = over * (np.sum(over * ku) / np.sum(ku * ku))
            if hard:
                np.minimum(p, H, out=p)
        else:
            p = _initial_guess(g, mat, problem.force_v, problem.e_star, problem.cell)
    if not problem.disp_control:
        p *= problem.force_v / (p.sum() * problem.cell)
        if hard and p.max() > H:
            p = _bounded_initial(p, g, mat, H, problem.force_v / problem.cell)
    return p, None


class _PolonskyKeer:
    """Stage 4: the constrained conjugate-gradient iteration of one solve (its state).

    :meth:`iterate` repeats: exact displacement when due, residual (:meth:`_residual`),
    convergence and stall checks, release of over-loaded plastic cells, CG direction
    (:meth:`_direction`), step length (:meth:`_step_length`) and the clipped, force-restored
    update (:meth:`_update`). See :func:`solve_contact`, Notes.
    """

    def __init__(self, problem: _Problem, p: np.ndarray, hs: ElasticHalfSpace, kernels: dict,
                 precondition: bool, n_conv: int):
        self.problem, self.hs, self.kn = problem, hs, kernels
        self.H = problem.H
        self.H_below = float(np.nextafter(problem.H, 0.0))
        self.pre = (_get_preconditioner(problem.g.shape, problem.dx, problem.dy, problem.e_star,
                                        hs.workers) if precondition else None)
        # finite copy of the gap; non-material cells masked
        self.gzf = np.ascontiguousarray(np.where(problem.mat, problem.g, 0.0)).ravel()
        self.matf = np.ascontiguousarray(problem.mat).ravel()
        self.p = np.ascontiguousarray(p)
        self.u = np.empty_like(self.p)
        self.h = np.empty_like(self.p)
        self.r = np.empty_like(self.p)
        self.t = np.zeros_like(self.p)
        self.pnew = np.empty_like(self.p)
        self.uf, self.hf, self.rf, self.tf = self.u.ravel(), self.h.ravel(), self.r.ravel(), self.t.ravel()
        self.pf = self.p.ravel()
        self.ny = self.p.shape[1]
        self.G_old = 1.0
        self.delta = 0.0
        self.dp = math.inf
        self.history: list[float] = []
        self.converged = False
        self.it = 0
        self.alpha = problem.alpha_fixed if problem.disp_control else 0.0
        self.u_exact = False  # u == K p computed by a convolution (else updated as s (u - tau K t))
        self.n_incr = 0
        self.n_conv = n_conv
        self.anchor, self.it_anchor = math.inf, 0  # stall guard: last residual that halved the one before
        self.dropped_at = None

    def iterate(self) -> None:
        """Iterate until converged (sets ``converged``), out of iterations or stuck."""
        tol = self.problem.tol
        while True:
            self.pf = self.p.ravel()
            if not self.u_exact:
                self.hs.displacement(self.p, out=self.u)
                self.n_conv += 1
                self.u_exact, self.n_incr = True, 0
            n_c, Gh, bbox, err_sat, gap_res, res = self._residual()
            if res <= tol and self.n_incr:
                self.u_exact = False  # confirm with an exact displacement before accepting
                continue
            self.history.append(res)
            if res <= tol:
                self.converged = True
                return
            if self.it >= self.problem.max_iter or (n_c == 0 and not self.problem.hard):
                return
            self._stall_guard(res)
            self.it += 1
            if err_sat > 0.0:
                # plastic cells with h > 0 are over-loaded: they rejoin the free set (at the largest
                # float below H) and this CG step, restarted, lowers them by its line search
                _nrel, n_c, Gh, *bbox = self.kn["release"](self.pf, self.hf, self.H, self.H_below, self.ny)
                self.delta = 0.0
            step = self._step_length(*self._direction(n_c, Gh, bbox), gap_res)
            if step is None:
                return
            self._update(*step)

    def _residual(self):
        """Approach and gap ``h`` of the current pressure, and the convergence measure:
        ``(n_c, Gh, bbox, err_sat, gap_res, res)`` (``n_c`` free cells bounded by ``bbox``,
        ``Gh = sum h^2`` on them, ``err_sat`` the violation on plastic cells)."""
        H, pf = self.H, self.pf
        s_gu, n_c, umax, *bbox = self.kn["gap_stats"](self.gzf, self.uf, pf, self.ny, H)
        if not self.problem.disp_control and n_c:
            self.alpha = s_gu / n_c
        err_in, err_out, Gh, err_sat = self.kn["gap_eval"](self.gzf, self.uf, pf, self.matf,
                                                           self.alpha, self.hf, H)
        scale = umax if umax > 0 else 1.0
        gap_res = max(err_in, err_out, err_sat) / scale
        return n_c, Gh, bbox, err_sat, gap_res, max(self.dp, gap_res)

    def _stall_guard(self, res: float) -> None:
        """Drop the preconditioner when the residual has not halved within ``stall_window``."""
        if res <= _STALL_PROGRESS * self.anchor:
            self.anchor, self.it_anchor = res, self.it
        elif self.pre is not None and self.it - self.it_anchor >= self.problem.stall_window:
            # cycling: plain CG from here, restarted
            self.pre, self.delta, self.dropped_at = None, 0.0, self.it
            self.anchor, self.it_anchor = res, self.it

    def _direction(self, n_c: int, Gh: float, bbox):
        """CG direction on the contact set (preconditioned when `precondition`):
        ``(z, diag, zbar, G)``."""
        if n_c == 0:  # every contact cell plastic: only entering / leaving cells can move
            return self.h, 1.0, 0.0, 0.0
        if self.pre is not None:
            z, diag = self.pre.apply(self.h, self.p, bbox, self.H, self.kn)
            sz, n_c, shz, sh = self.kn["dir_stats"](z.ravel(), self.hf, self.pf, self.H)
            zbar = sz / n_c if not self.problem.disp_control else 0.0
            return z, diag, zbar, shz - zbar * sh
        return self.h, 1.0, 0.0, Gh

    def _converged_on_gap(self, gap_res: float) -> None:
        """End with the gap criterion alone when it holds (the step cannot move ``p``)."""
        if gap_res <= self.problem.tol:
            self.history[-1] = gap_res
            self.converged = True

    def _step_length(self, z, diag, zbar, G, gap_res):
        """New conjugate direction ``t`` and ``(tau, seed)`` of the step along it; None when the
        iteration ends here."""
        if G <= 0.0:
            # h vanishes on the contact set (to rounding): CG has nothing left to do there
            if gap_res <= self.problem.tol:
                self._converged_on_gap(gap_res)
                return None
            # ... but cells outside still interpenetrate (e.g. a one-cell contact): let them enter
            # with the pressure that would lift them alone, p = -h / K(0, 0)
            self.t.fill(0.0)
            return 0.0, 1.0 / self.hs.k0
        beta = self.delta * G / self.G_old
        self.kn["dir_update"](z.ravel(), self.pf, self.tf, zbar, beta, self.H)
        self.G_old = G
        self.hs.displacement(self.t, out=self.r)
        self.n_conv += 1
        sr, st, srt, sht, n_c = self.kn["step_dots"](self.rf, self.tf, self.hf, self.pf, self.H)
        denom = srt - (sr / n_c) * st if not self.problem.disp_control else srt
        if denom <= 0:  # only with t ~ 0 to rounding
            self._converged_on_gap(gap_res)
            return None
        tau = sht / denom
        return tau, tau * diag

    def _update(self, tau: float, seed: float) -> None:
        """Step, clip to ``[0, H]``, let cells enter, restore the force, update ``u``."""
        problem, H = self.problem, self.H
        p, pnew = self.p, self.pnew
        entered, psum, modified = self.kn["update"](self.pf, self.tf, self.hf, tau, seed, pnew.ravel(), H)
        self.delta = 0.0 if entered else 1.0
        if psum <= 0:
            if problem.disp_control:  # everything separated
                self.p = np.zeros_like(p)
                self.dp = 0.0
                self.u_exact = False
                return
            raise ContactConvergenceError(  # pragma: no cover
                "all pressure vanished (no contact)", self.history)
        target = problem.force_v / problem.cell
        sc = problem.force_v / (psum * problem.cell) if not problem.disp_control else 1.0
        if problem.hard and not problem.disp_control and pnew.max() * max(sc, 1.0) >= H:
            # bounded force balance: plastic cells stay at H, the free ones carry the rest
            _project_force(pnew, H, target, self.h)
            self.dp = float(np.abs(pnew - p).sum()) / target
            modified = True
        else:
            self.dp = self.kn["rescale"](pnew.ravel(), self.pf, sc) / (psum * sc)
        self.p, self.pnew = pnew, p
        if not modified and self.n_incr < _MAX_INCREMENTAL:
            # no cell clipped or entered: p_new = sc (p - tau t), so K p_new = sc (u - tau K t)
            self.kn["axpy_scale"](self.uf, self.rf, tau, sc)
            self.n_incr += 1
        else:
            self.u_exact = False


def _solution(problem: _Problem, run: _PolonskyKeer) -> ContactSolution:
    """Stage 5: the result; :class:`ContactConvergenceError` (carrying it) when not converged,
    then the grid-boundary check."""
    p, history, cell, hard, H = run.p, run.history, problem.cell, problem.hard, problem.H
    plastic = plastic_depth = None
    if hard:
        plastic = p >= H
        plastic_depth = np.where(plastic, np.clip(-run.h, 0.0, None), 0.0)
    sol = ContactSolution(
        pressure=p,
        approach=float(run.alpha),
        iterations=run.it,
        residual=float(history[-1]),
        converged=run.converged,
        contact_area=float(np.count_nonzero(p > 0) * cell),
        force=float(p.sum() * cell),
        residual_history=tuple(history),
        displacement=run.u,
        convolutions=run.n_conv,
        preconditioner_dropped_at=run.dropped_at,
        hardness=H if hard else None,
        plastic=plastic,
        plastic_depth=plastic_depth,
        plastic_area=float(np.count_nonzero(plastic) * cell) if hard else 0.0,
    )
    if not run.converged:
        raise ContactConvergenceError(
            f"contact solver did not converge: residual {history[-1]:.3e} > tol {problem.tol:.1e} after "
            f"{run.it} iterations (max_iter={problem.max_iter}); last residuals {history[-5:]}",
            history,
            sol,
        )
    _check_boundary(p, problem.mat, problem.boundary)
    return sol


def _project_force(p: np.ndarray, H: float, target: float, h: np.ndarray) -> None:
    """Restore ``sum p = target`` in place keeping ``0 <= p <= H`` (``p`` already in it).

    Plastic cells (``p >= H``) stay at ``H`` and the free cells ``0 < p < H`` are scaled by one
    factor to carry the rest; cells the factor lifts to ``H`` or past become plastic, repeated
    until none does (the factor only grows, so at most as many rounds as cells, in practice 1-3).
    If the plastic cells alone carry more than ``target``, every cell is scaled down instead. If
    the contact cannot carry ``target`` at ``H`` (all of it plastic), the cells out of contact
    with the smallest gap ``h`` (``+inf`` = no material) join at ``H``, the last one partly: the
    contact grows as the approach would make it.
    """
    sat = p >= H
    free = (p > 0) & ~sat
    rem = target - H * np.count_nonzero(sat)
    fsum = float(p[free].sum())
    if rem < 0:  # scale down: stays within [0, H]
        p *= target / float(p.sum())
        return
    c = 0.0
    while fsum > 0:
        c = rem / fsum
        new = free & (c * p >= H)
        if not new.any():
            break
        sat |= new
        free &= ~new
        rem = target - H * np.count_nonzero(sat)
        fsum = float(p[free].sum())
    if fsum > 0:
        p[free] *= c
        p[sat] = H
        return
    p[sat] = H
    rem = target - H * np.count_nonzero(sat)
    if rem <= 0:
        return
    out = np.where((p <= 0) & np.isfinite(h), h, np.inf).ravel()
    k = int(rem // H)
    cand = np.argpartition(out, min(k + 1, out.size - 1))[: k + 1]
    cand = cand[np.argsort(out[cand], kind="stable")]
    if not np.isfinite(out[cand[-1]]):
        raise ContactConvergenceError(
            f"hardness {H:.4g} Pa: the material area cannot carry the force at p = H", [])
    pf = p.ravel()
    pf[cand[:k]] = H
    pf[cand[k]] = rem - k * H


def _bounded_initial(p: np.ndarray, g: np.ndarray, mat: np.ndarray, H: float, target: float) -> np.ndarray:
    """Initial guess in ``[0, H]`` carrying ``target`` (= force / cell area).

    Clip ``p`` at ``H`` and restore the force on its support (:func:`_project_force`); if the
    support cannot carry it at ``H``, fill cells in order of increasing gap at ``H`` instead
    (the last one partly), which leaves at least one free cell.
    """
    q = np.minimum(p, H)
    if np.count_nonzero(q > 0) * H > target * (1 + 1e-12):
        _project_force(q, H, target, np.where(mat, g, np.inf))
        if np.count_nonzero((q > 0) & (q < H)):
            return q
    order = np.argsort(np.where(mat, g, np.inf), axis=None, kind="stable")
    k = int(target // H)
    if k >= int(mat.sum()):
        raise ValueError(f"hardness {H:.4g} Pa times the material area cannot carry the force")
    q = np.zeros(p.size)
    q[order[:k]] = H
    q[order[k]] = max(target - k * H, 0.5 * H)
    q *= target / q.sum()
    return q.reshape(p.shape)


_MAX_INCREMENTAL = 8  # at most this many incremental displacement updates between exact ones
#: Stall guard: the residual must fall to this fraction of the last anchor (halve) within
#: ``stall_window`` iterations, or the preconditioner is dropped.
_STALL_PROGRESS = 0.5
#: Cells (each side) added to the bounding box of the free set for the preconditioner's FFT.
_PRECONDITIONER_MARGIN = 4
#: Preconditioners kept (per grid and thread; each holds a work array of the grid's size).
_PRE_CACHE_SIZE = 4


class _FourierPreconditioner:
    """Approximate inverse of the half-space operator on the bounding box of the contact set."""

    def __init__(self, shape, dx, dy, e_star, margin: int = _PRECONDITIONER_MARGIN, workers: int = 1):
        self.shape, self.dx, self.dy, self.e_star, self.margin = shape, dx, dy, e_star, margin
        self.workers = workers
        self._symbols: dict = {}
        self._z = np.zeros(shape)
        self._prev = (0, 0, 0, 0)  # the block of _z written last (i0, j0, mx, my)

    def _symbol(self, mx: int, my: int):
        key = (mx, my)
        s = self._symbols.get(key)
        if s is None:
            qx = 2 * np.pi * np.fft.fftfreq(mx, self.dx)
            qy = 2 * np.pi * np.fft.rfftfreq(my, self.dy)
            q0 = 2 * np.pi / max(mx * self.dx, my * self.dy)
            sym = 0.5 * self.e_star * np.sqrt(qx[:, None] ** 2 + qy[None, :] ** 2 + q0 * q0)
            # mean of the full (two-sided) symbol = the diagonal of the periodic operator
            w = np.full(sym.shape[1], 2.0)
            w[0] = 1.0
            if my % 2 == 0:
                w[-1] = 1.0
            diag = float((sym * w).sum()) / (mx * my)
            s = (sym / (mx * my), diag)
            self._symbols[key] = s
        return s

    def apply(self, h: np.ndarray, p: np.ndarray, bbox, H: float = math.inf, kernels=None):
        """Return ``(z, d)``: ``z = P M^-1 P h`` (zero off the free set ``0 < p < H``; a reused
        buffer) and ``d``, the diagonal of ``M^-1``. ``bbox = (i0, i1, j0, j1)`` bounds the free
        set (inclusive). ``kernels``: the element-wise passes (:mod:`._kernels`, default the
        numba ones) that gather the free set's ``h`` and place ``z``."""
        import scipy.fft as sfft

        kn = _kernels.KERNELS if kernels is None else kernels

        nx, ny = self.shape
        m = self.margin
        i0, i1, j0, j1 = bbox
        i0, i1 = max(i0 - m, 0), min(i1 + 1 + m, nx)
        j0, j1 = max(j0 - m, 0), min(j1 + 1 + m, ny)
        mx = min(sfft.next_fast_len(i1 - i0, real=True), nx)
        my = min(sfft.next_fast_len(j1 - j0, real=True), ny)
        i0 = min(i0, nx - mx)
        j0 = min(j0, ny - my)
        hb = np.empty((mx, my))
        kn["free_block"](h, p, H, i0, j0, hb)
        sym, diag = self._symbol(mx, my)
        w = self.workers
        spec = rfft2(hb, workers=w)
        spec *= sym
        zb = irfft2(spec, (mx, my), workers=w)
        kn["place_block"](self._z, zb, p, H, i0, j0, self._prev)
        self._prev = (i0, j0, mx, my)
        return self._z, diag

    def reset(self) -> None:
        """Zero the work array (start of a solve)."""
        i0, j0, mx, my = self._prev
        self._z[i0:i0 + mx, j0:j0 + my] = 0.0
        self._prev = (0, 0, 0, 0)


_PRE_CACHE: dict = {}


def _get_preconditioner(shape, dx, dy, e_star, workers):
    """Preconditioner per grid and thread (it caches symbols and holds a work array)."""
    from threading import get_ident

    key = (tuple(shape), dx, dy, e_star, workers, get_ident())
    pre = _PRE_CACHE.get(key)
    if pre is None:
        if len(_PRE_CACHE) >= _PRE_CACHE_SIZE:
            _PRE_CACHE.pop(next(iter(_PRE_CACHE)))
        pre = _PRE_CACHE[key] = _FourierPreconditioner(shape, dx, dy, e_star, workers=workers)
    pre.reset()
    return pre


def _edge_mask(mat: np.ndarray) -> np.ndarray:
    e = np.zeros_like(mat)
    e[0, :] = e[-1, :] = e[:, 0] = e[:, -1] = True
    return e & mat


def _check_boundary(p: np.ndarray, mat: np.ndarray, boundary: str) -> None:
    if boundary == "ignore":
        return
    edge = _edge_mask(mat)
    loaded = edge & (p > 0)
    if not loaded.any():
        return
    total = float(p.sum())
    frac = float(p[loaded].sum()) / total if total > 0 else 0.0
    frac_cells = float(loaded.sum()) / float(edge.sum())
    msg = (
        f"pressure reaches the grid boundary: {loaded.sum()} of {edge.sum()} edge cells "
        f"({frac_cells:.1%}) carry {frac:.3e} of the force (allowed: 0); enlarge the grid "
        f"or pass boundary='warn'"
    )
    if boundary == "raise":
        raise ContactGridError(msg, frac)
    warnings.warn(msg, ContactGridWarning, stacklevel=3)
