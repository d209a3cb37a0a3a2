"""Frictionless normal contact on an elastic half-space: Polonsky-Keer constrained CG.

See :func:`solve_contact` and ``docs/contact.md``.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from . import _kernels
from .halfspace import ElasticHalfSpace, get_halfspace

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
    fft_backend: str = "auto",
    kernels: dict | None = None,
    element: str = "uniform",
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
        Element-wise passes to use (testing): ``_kernels.NUMPY`` or the default numba ones.
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
    # ---- validation ----------------------------------------------------------------------
    g = np.asarray(gap, dtype=float)
    if g.ndim != 2:
        raise ValueError(f"gap must be a 2-D array (nx, ny), got ndim={g.ndim} shape={g.shape}")
    if g.shape[0] < 2 or g.shape[1] < 2:
        raise ValueError(f"gap must be at least 2 x 2, got shape={g.shape}")
    if np.isnan(g).any():
        raise ValueError(f"gap contains NaN ({int(np.isnan(g).sum())} cells); use +inf for 'no material'")
    if np.isneginf(g).any():
        raise ValueError("gap contains -inf; allowed: finite values or +inf (no material)")
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
    if hardness is None:
        H = math.inf
    else:
        if isinstance(hardness, bool):
            raise ValueError(f"hardness must be a finite number > 0 (Pa) or None, got {hardness!r}")
        H = _check_scalar("hardness", hardness, "a finite number > 0 (Pa) or None")
    hard = hardness is not None
    disp_control = approach is not None
    if disp_control:
        try:
            alpha_fixed = float(approach)
        except (TypeError, ValueError):
            raise ValueError(f"approach must be a finite number (m), got {approach!r}") from None
        if not math.isfinite(alpha_fixed):
            raise ValueError(f"approach must be a finite number (m), got {approach!r}")
        force_v = float("nan")
    else:
        force_v = _check_scalar("force", force, "a finite number > 0 (N)")
    mat = np.isfinite(g)
    if not mat.any():
        raise ValueError("gap has no finite cell: nothing can carry the load")
    if halfspace is None:
        hs = get_halfspace(g.shape, dx, dy, e_star, workers=workers, backend=fft_backend, element=element)
    else:
        hs = halfspace
        if hs.shape != g.shape or (hs.dx, hs.dy, hs.e_star, hs.element) != (dx, dy, e_star, element):
            raise ValueError(f"halfspace {hs!r} does not match gap shape {g.shape}, dx, dy, e_star, element")
    cell = dx * dy

    # ---- initial pressure ---------------------------------------------------------------
    if p_init is not None:
        p = np.array(p_init, dtype=float)
        if p.shape != g.shape:
            raise ValueError(f"p_init.shape must equal gap.shape {g.shape}, got {p.shape}")
        if not np.isfinite(p).all():
            raise ValueError("p_init must be finite")
        p[~mat] = 0.0
        np.maximum(p, 0.0, out=p)
        if hard:
            np.minimum(p, H, out=p)
        if disp_control:
            # h = g + K p - alpha with K p >= 0: a cell with g > alpha can never touch, so warm
            # pressure there (e.g. where a defect has moved in) is dropped before the first step
            p[g > alpha_fixed] = 0.0
        if not p.any():
            p = None
    else:
        p = None
    if p is None:
        if disp_control:
            over = np.where(mat, np.clip(alpha_fixed - np.where(mat, g, 0.0), 0.0, None), 0.0)
            if not over.any():  # no overlap: no contact
                z = np.zeros_like(g)
                return ContactSolution(z, alpha_fixed, 0, 0.0, True, 0.0, 0.0, (0.0,), z.copy(),
                                       hardness=H if hard else None,
                                       plastic=np.zeros(g.shape, bool) if hard else None,
                                       plastic_depth=z.copy() if hard else None)
            ku = hs.displacement(over)
            p = over * (np.sum(over * ku) / np.sum(ku * ku))
            if hard:
                np.minimum(p, H, out=p)
        else:
            p = _initial_guess(g, mat, force_v, e_star, cell)
    if not disp_control:
        p *= force_v / (p.sum() * cell)
        if hard and p.max() > H:
            p = _bounded_initial(p, g, mat, H, force_v / cell)

    # ---- Polonsky-Keer iterations -------------------------------------------------------
    kn = _kernels.KERNELS if kernels is None else kernels
    gap_stats, gap_eval, dir_stats, dir_update = kn["gap_stats"], kn["gap_eval"], kn["dir_stats"], kn["dir_update"]
    step_dots, update, rescale, axpy_scale = kn["step_dots"], kn["update"], kn["rescale"], kn["axpy_scale"]
    H_below = float(np.nextafter(H, 0.0))
    pre = _get_preconditioner(g.shape, dx, dy, e_star, hs.workers) if precondition else None
    gz = np.ascontiguousarray(np.where(mat, g, 0.0))  # finite copy; non-material cells masked
    matf = np.ascontiguousarray(mat).ravel()
    gzf = gz.ravel()
    p = np.ascontiguousarray(p)
    u = np.empty_like(p)
    h = np.empty_like(p)
    r = np.empty_like(p)
    t = np.zeros_like(p)
    pnew = np.empty_like(p)
    uf, hf, rf, tf = u.ravel(), h.ravel(), r.ravel(), t.ravel()
    ny = p.shape[1]
    G_old = 1.0
    delta = 0.0
    dp = math.inf
    history: list[float] = []
    converged = False
    it = 0
    alpha = alpha_fixed if disp_control else 0.0
    u_exact = False  # u == K p computed by a convolution (else updated as s (u - tau K t))
    n_incr = 0
    n_conv = 1 if (p_init is None and disp_control) else 0
    anchor, it_anchor = math.inf, 0  # stall guard: last residual that halved the one before
    dropped_at = None
    while True:
        pf = p.ravel()
        if not u_exact:
            hs.displacement(p, out=u)
            n_conv += 1
            u_exact, n_incr = True, 0
        s_gu, n_c, umax, *bbox = gap_stats(gzf, uf, pf, ny, H)
        if not disp_control and n_c:
            alpha = s_gu / n_c
        err_in, err_out, Gh, err_sat = gap_eval(gzf, uf, pf, matf, alpha, hf, H)
        scale = umax if umax > 0 else 1.0
        gap_res = max(err_in, err_out, err_sat) / scale
        res = max(dp, gap_res)
        if res <= tol and n_incr:
            u_exact = False  # confirm with an exact displacement before accepting
            continue
        history.append(res)
        if res <= tol:
            converged = True
            break
        if it >= max_iter or (n_c == 0 and not hard):
            break
        if res <= 0.5 * anchor:
            anchor, it_anchor = res, it
        elif pre is not None and it - it_anchor >= stall_window:
            pre, delta, dropped_at = None, 0.0, it  # cycling: plain CG from here, restarted
            anchor, it_anchor = res, it
        it += 1
        if err_sat > 0.0:
            # plastic cells with h > 0 are over-loaded: they rejoin the free set (at the largest
            # float below H) and this CG step, restarted, lowers them by its line search
            _nrel, n_c, Gh, *bbox = kn["release"](pf, hf, H, H_below, ny)
            delta = 0.0
        # CG direction on the contact set (preconditioned when `precondition`)
        if n_c == 0:  # every contact cell plastic: only entering / leaving cells can move
            z, diag, zbar, G = h, 1.0, 0.0, 0.0
        elif pre is not None:
            z, diag = pre.apply(h, p, bbox, H)
            sz, n_c, shz, sh = dir_stats(z.ravel(), hf, pf, H)
            zbar = sz / n_c if not disp_control else 0.0
            G = shz - zbar * sh
        else:
            z, diag, zbar, G = h, 1.0, 0.0, Gh
        if G <= 0.0:
            # h vanishes on the contact set (to rounding): CG has nothing left to do there
            if gap_res <= tol:
                history[-1] = gap_res
                converged = True
                break
            # ... but cells outside still interpenetrate (e.g. a one-cell contact): let them enter
            # with the pressure that would lift them alone, p = -h / K(0, 0)
            tau, seed = 0.0, 1.0 / hs.k0
            t.fill(0.0)
        else:
            beta = delta * G / G_old
            dir_update(z.ravel(), pf, tf, zbar, beta, H)
            G_old = G
            hs.displacement(t, out=r)
            n_conv += 1
            sr, st, srt, sht, n_c = step_dots(rf, tf, hf, pf, H)
            denom = srt - (sr / n_c) * st if not disp_control else srt
            if denom <= 0:  # only with t ~ 0 to rounding
                if gap_res <= tol:
                    history[-1] = gap_res
                    converged = True
                break
            tau = sht / denom
            seed = tau * diag
        entered, psum, modified = update(pf, tf, hf, tau, seed, pnew.ravel(), H)
        delta = 0.0 if entered else 1.0
        if psum <= 0:
            if disp_control:  # everything separated
                p = np.zeros_like(p)
                dp = 0.0
                u_exact = False
                continue
            raise ContactConvergenceError("all pressure vanished (no contact)", history)  # pragma: no cover
        sc = force_v / (psum * cell) if not disp_control else 1.0
        if hard and not disp_control and pnew.max() * max(sc, 1.0) >= H:
            # bounded force balance: plastic cells stay at H, the free ones carry the rest
            _project_force(pnew, H, force_v / cell, h)
            dp = float(np.abs(pnew - p).sum()) / (force_v / cell)
            modified = True
        else:
            dp = rescale(pnew.ravel(), pf, sc) / (psum * sc)
        p, pnew = pnew, p
        if not modified and n_incr < _MAX_INCREMENTAL:
            # no cell clipped or entered: p_new = sc (p - tau t), so K p_new = sc (u - tau K t)
            axpy_scale(uf, rf, tau, sc)
            n_incr += 1
        else:
            u_exact = False

    force_out = float(p.sum() * cell)
    plastic = plastic_depth = None
    if hard:
        plastic = p >= H
        plastic_depth = np.where(plastic, np.clip(-h, 0.0, None), 0.0)
    sol = ContactSolution(
        pressure=p,
        approach=float(alpha),
        iterations=it,
        residual=float(history[-1]),
        converged=converged,
        contact_area=float(np.count_nonzero(p > 0) * cell),
        force=force_out,
        residual_history=tuple(history),
        displacement=u,
        convolutions=n_conv,
        preconditioner_dropped_at=dropped_at,
        hardness=H if hard else None,
        plastic=plastic,
        plastic_depth=plastic_depth,
        plastic_area=float(np.count_nonzero(plastic) * cell) if hard else 0.0,
    )
    if not converged:
        raise ContactConvergenceError(
            f"contact solver did not converge: residual {history[-1]:.3e} > tol {tol:.1e} after "
            f"{it} iterations (max_iter={max_iter}); last residuals {history[-5:]}",
            history,
            sol,
        )
    _check_boundary(p, mat, boundary)
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


class _FourierPreconditioner:
    """Approximate inverse of the half-space operator on the bounding box of the contact set."""

    def __init__(self, shape, dx, dy, e_star, margin: int = 4, workers: int = 1):
        self.shape, self.dx, self.dy, self.e_star, self.margin = shape, dx, dy, e_star, margin
        self.workers = workers
        self._symbols: dict = {}
        self._z = np.zeros(shape)
        self._prev = None

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

    def apply(self, h: np.ndarray, p: np.ndarray, bbox, H: float = math.inf):
        """Return ``(z, d)``: ``z = P M^-1 P h`` (zero off the free set ``0 < p < H``; a reused
        buffer) and ``d``, the diagonal of ``M^-1``. ``bbox = (i0, i1, j0, j1)`` bounds the free
        set (inclusive)."""
        import scipy.fft as sfft

        nx, ny = self.shape
        m = self.margin
        i0, i1, j0, j1 = bbox
        i0, i1 = max(i0 - m, 0), min(i1 + 1 + m, nx)
        j0, j1 = max(j0 - m, 0), min(j1 + 1 + m, ny)
        mx = min(sfft.next_fast_len(i1 - i0, real=True), nx)
        my = min(sfft.next_fast_len(j1 - j0, real=True), ny)
        i0 = min(i0, nx - mx)
        j0 = min(j0, ny - my)
        sl = (slice(i0, i0 + mx), slice(j0, j0 + my))
        pb = p[sl]
        icb = (pb > 0) & (pb < H)
        hb = np.where(icb, h[sl], 0.0)
        sym, diag = self._symbol(mx, my)
        w = self.workers
        zb = sfft.irfft2(sfft.rfft2(hb, workers=w) * sym, s=(mx, my), norm="forward", workers=w)
        z = self._z
        if self._prev is not None:
            z[self._prev] = 0.0
        z[sl] = np.where(icb, zb, 0.0)
        self._prev = sl
        return z, diag

    def reset(self) -> None:
        """Zero the work array (start of a solve)."""
        if self._prev is not None:
            self._z[self._prev] = 0.0
            self._prev = None


_PRE_CACHE: dict = {}


def _get_preconditioner(shape, dx, dy, e_star, workers):
    """Preconditioner per grid and thread (it caches symbols and holds a work array)."""
    from threading import get_ident

    key = (tuple(shape), dx, dy, e_star, workers, get_ident())
    pre = _PRE_CACHE.get(key)
    if pre is None:
        if len(_PRE_CACHE) >= 4:
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
