"""The lumped-parameter bearing in time: its right-hand side for ``solve_ivp``, the initial state
from the quasi-static solution, and :func:`simulate_dynamics` (fixed-step RK4 in numba, recorded
through :func:`bearing_envelope.physics.acquisition.acquire`). Equations: ``docs/dynamics.md``.
"""

from __future__ import annotations

import math
import numbers
import time
import warnings
from dataclasses import dataclass

import numpy as np

from ..acquisition import acquire, antialias_filter
from ..scene import Acquisition
from .kernels import CDT, CT0, cage_angle_at, contact_forces, rhs_kernel, rk4_loop, rk4_run
from .layout import REC_CONTACT, REC_FIXED, REC_SIZE_FIXED, StateLayout
from .params import (MODEL_NAME, PEAK_LOAD_FACTOR, DynamicParams, highest_frequency_hz, quasi_static,
                     step_size)

#: Time at which a run starts when none is given, s.
START_S = 0.0

__all__ = ["Arrays", "arrays", "rhs", "element_loads", "initial_state", "simulate_dynamics",
           "DynamicResult", "jacobian", "linearised_frequencies_hz", "modal_oversample",
           "SETTLE_PERIODS", "record_names", "KERNELS"]

#: Settling before ``t = 0`` (discarded), in periods of the slowest structural mode, at least
#: 20 ms: the start from the quasi-static state rings the rings' modes down.
SETTLE_PERIODS = 30.0
#: Spacing of the cage-angle nodes with slip, s (the slip process is piecewise linear per
#: inner-race pass, longer than this).
_CAGE_NODE_S = 2e-5
#: The integrators :func:`simulate_dynamics` can run, by name: ``fast`` the fused loop
#: (:func:`~.kernels.rk4_loop`), ``reference`` the step-by-step one it is tested against
#: (:func:`~.kernels.rk4_run`); the same arithmetic, the same bits.
KERNELS = {"fast": rk4_loop, "reference": rk4_run}


@dataclass(frozen=True)
class Arrays:
    """The kernels' inputs of one parameter set over one time span."""

    P: np.ndarray
    cage: np.ndarray
    cph: np.ndarray
    sph: np.ndarray
    tx: np.ndarray
    td: np.ndarray
    tf: np.ndarray

    def kernel_args(self) -> tuple:
        """The kernels' arguments after ``(t, y)`` and before the outputs, in their order.

        Returns
        -------
        tuple of ndarray
            ``P, cage, cph, sph, tx, td, tf``.
        """
        return self.P, self.cage, self.cph, self.sph, self.tx, self.td, self.tf


def arrays(params: DynamicParams, t_lo: float = 0.0, t_hi: float = 1.0) -> Arrays:
    """The kernels' arrays for times in ``[t_lo, t_hi]`` (the cage nodes cover them; outside,
    the end rates continue).

    Parameters
    ----------
    params : DynamicParams
        The model (:func:`~.params.params_from_scene`): masses (kg), stiffnesses (N/m), radii (m),
        rates (Hz), load (N), the defect law.
    t_lo, t_hi : float
        Time span, s.

    Returns
    -------
    Arrays
        The race profiles, cage angle nodes and defect-law tables the kernels read over the
        span.
    """
    if params.cage_angle is None:
        t0, dt = 0.0, 1.0
        cage = np.array([0.0, 2 * math.pi * params.cage_rate_hz])
    else:
        n = max(2, int(math.ceil((t_hi - t_lo) / _CAGE_NODE_S)) + 1)
        t0, dt = t_lo, (t_hi - t_lo) / (n - 1) if t_hi > t_lo else 1.0
        cage = np.asarray(params.cage_angle(t0 + dt * np.arange(n)), dtype=float)
    cage = np.ascontiguousarray(cage, dtype=float)
    ph = 2 * math.pi * np.arange(params.z) / params.z
    none = (np.array([1e18, 2e18]), np.array([0.0, 1.0]), np.zeros((2, 2)))
    law = params.defect
    tx, td, tf = none if law is None else (law.x_m, law.delta_m, law.force_n)
    element = law is not None and params.defect_race == "element"
    inner = (params.pit.inner or law) if element else None
    tx2, td2, tf2 = none if inner is None else (inner.x_m, inner.delta_m, inner.force_n)
    turns = np.floor((cage_angle_at(t_lo, cage, t0, dt)[0] + math.pi) / (2 * math.pi)), \
        np.floor((cage_angle_at(t_hi, cage, t0, dt)[0] + math.pi) / (2 * math.pi))
    lo, hi = int(min(turns)), int(max(turns)) + 1
    orient = params.pit.table(lo, hi) if element else np.zeros((1, 2))
    P = np.concatenate([params.vector(t0, dt, lo, (tx2.size, td2.size, orient.shape[0])),
                        tx2, td2, np.ravel(tf2), orient.ravel()])
    return Arrays(P, cage, np.cos(ph), np.sin(ph), tx, td, np.ascontiguousarray(tf))


def rhs(t: float, y: np.ndarray, params: DynamicParams, a: Arrays | None = None) -> np.ndarray:
    """``dy/dt`` of the model at ``(t, y)`` (the ``solve_ivp`` contract).

    Parameters
    ----------
    t : float
        Time, s.
    y : ndarray
        State (:class:`~.layout.StateLayout`).
    params : DynamicParams
        The model (:func:`~.params.params_from_scene`): masses (kg), stiffnesses (N/m), radii (m),
        rates (Hz), load (N), the defect law.
    a : Arrays, optional
        Precomputed :func:`arrays` (for speed; must cover ``t`` when the cage slips).

    Returns
    -------
    numpy.ndarray
        ``dy/dt``.
    """
    a = arrays(params, t, t + 1e-3) if a is None else a
    z = params.z
    out = np.empty(len(y))
    rhs_kernel(float(t), np.ascontiguousarray(y, dtype=float), *a.kernel_args(), np.empty(z),
               np.empty(z), np.empty(z + 1), out)
    return out


def element_loads(t: float, y: np.ndarray, params: DynamicParams,
                  a: Arrays | None = None) -> tuple[np.ndarray, np.ndarray, float]:
    """Inner and outer contact loads of every element at ``(t, y)`` and the defect force.

    Parameters
    ----------
    t : float
        Time, s.
    y : ndarray
        State.
    params : DynamicParams
        The model (:func:`~.params.params_from_scene`): masses (kg), stiffnesses (N/m), radii (m),
        rates (Hz), load (N), the defect law.
    a : Arrays, optional
        Precomputed :func:`arrays`.

    Returns
    -------
    q_inner, q_outer : ndarray
        Contact loads, N, shape ``(Z,)``.
    defect_force : float
        Force of the defect contact, N.
    """
    a = arrays(params, t, t + 1e-3) if a is None else a
    qi, qo, xd = np.empty(params.z), np.empty(params.z), np.empty(params.z + 1)
    f = contact_forces(float(t), np.ascontiguousarray(y, dtype=float), *a.kernel_args(), qi, qo, xd)
    return qi, qo, float(f)


def initial_state(params: DynamicParams, t: float = START_S) -> np.ndarray:
    """The quasi-static state at ``t`` (zero velocities): the housing on its support, the inner
    ring displaced by the Harris/Stribeck ``(delta_r, delta_y)`` (:func:`~.params.quasi_static`), each
    element where its inner contact carries its quasi-static load (or, unloaded, resting on the
    outer race with its centrifugal force).

    Parameters
    ----------
    params : DynamicParams
        The model (:func:`~.params.params_from_scene`): masses (kg), stiffnesses (N/m), radii (m),
        rates (Hz), load (N), the defect law.
    t : float
        Time, s (the cage angle).

    Returns
    -------
    numpy.ndarray
        State vector.
    """
    lay = StateLayout(params.z)
    a = arrays(params, t - 1e-3, t + 1e-3)
    thc = cage_angle_at(float(t), a.cage, a.P[CT0], a.P[CDT])[0]
    la, f, ca, n = params.load_angle_rad, params.force_n, math.cos(params.contact_angle_rad), params.exponent
    y = np.zeros(lay.size)
    ho = f / params.housing_stiffness_n_m if params.housing_stiffness_n_m > 0 else 0.0
    ld = quasi_static(params, thc - la) if f > 0 else None
    dr, dy = (ld.delta_r, ld.delta_y) if ld is not None else (0.0, 0.0)
    y[[lay.XO, lay.YO]] = ho * math.cos(la), ho * math.sin(la)
    y[[lay.XI, lay.YI]] = ((ho + dr) * math.cos(la) - dy * math.sin(la),
                           (ho + dr) * math.sin(la) + dy * math.cos(la))
    y[lay.RES] = math.cos(params.sensor_angle_rad) * y[lay.XO] + math.sin(params.sensor_angle_rad) * y[lay.YO]
    g = 0.25 * params.clearance_m
    for j in range(params.z):
        th = thc + 2 * math.pi * j / params.z
        ri = y[lay.XI] * math.cos(th) + y[lay.YI] * math.sin(th)
        ro = y[lay.XO] * math.cos(th) + y[lay.YO] * math.sin(th)
        q = 0.0 if ld is None else float(ld.q[j])
        if q > 0:
            y[lay.element(j)] = (ri - g) * ca - (q / params.k_inner) ** (1 / n)
        else:
            y[lay.element(j)] = (ro + g) * ca + (params.centrifugal_n * ca / params.k_outer) ** (1 / n)
    return y


def jacobian(params: DynamicParams, y: np.ndarray, t: float = START_S, rel: float = 1e-7) -> np.ndarray:
    """Central-difference Jacobian ``d(dy/dt)/dy`` of :func:`rhs` at ``(t, y)``.

    Parameters
    ----------
    params : DynamicParams
        The model (:func:`~.params.params_from_scene`): masses (kg), stiffnesses (N/m), radii (m),
        rates (Hz), load (N), the defect law.
    y : ndarray
        State.
    t : float
        Time, s.
    rel : float
        Step relative to the state's largest position (or 1e-12 m).

    Returns
    -------
    numpy.ndarray
        ``(2N, 2N)``.
    """
    a = arrays(params, t - 1e-3, t + 1e-3)
    h = rel * max(float(np.max(np.abs(y))), 1e-5)
    J = np.empty((y.size, y.size))
    for i in range(y.size):
        e = np.zeros(y.size)
        e[i] = h
        J[:, i] = (rhs(t, y + e, params, a) - rhs(t, y - e, params, a)) / (2 * h)
    return J


def linearised_frequencies_hz(params: DynamicParams, y: np.ndarray, t: float = START_S) -> np.ndarray:
    """Natural frequencies (Hz, ascending, > 0) of the model linearised at ``(t, y)``: the
    eigenvalues of :func:`jacobian` (undamped: ``+- i omega``).

    Parameters
    ----------
    params : DynamicParams
        The model (:func:`~.params.params_from_scene`): masses (kg), stiffnesses (N/m), radii (m),
        rates (Hz), load (N), the defect law.
    y : ndarray
        State (an equilibrium).
    t : float
        Time, s.

    Returns
    -------
    numpy.ndarray
        Frequencies ``|Im lambda| / 2 pi`` of the eigenvalues with ``Im > 0``, ascending.
    """
    lam = np.linalg.eigvals(jacobian(params, y, t))
    return np.sort(lam.imag[lam.imag > 1e-6 * np.max(np.abs(lam))]) / (2 * math.pi)


def modal_oversample(params: DynamicParams, fs_hz: float, peak_factor: float = PEAK_LOAD_FACTOR) -> int:
    """The internal record rate as a multiple of ``fs``: the smallest ``N >= 2`` with
    ``N fs >= 2 f_max`` (:func:`~.params.highest_frequency_hz`), so that the record's point
    samples do not alias the resolved contact modes before the anti-alias filter.

    Parameters
    ----------
    params : DynamicParams
        The model (:func:`~.params.params_from_scene`): masses (kg), stiffnesses (N/m), radii (m),
        rates (Hz), load (N), the defect law.
    fs_hz : float
        Output rate, Hz.
    peak_factor : float
        As :func:`~.params.highest_frequency_hz`.

    Returns
    -------
    int
        ``N``.
    """
    return max(2, int(math.ceil(2.0 * highest_frequency_hz(params, peak_factor) / fs_hz)))


@dataclass(frozen=True)
class DynamicResult:
    """A run of the model, every signal sampled at ``fs_hz`` from ``t = 0``.

    Attributes
    ----------
    t_s : ndarray
        Sample times, s.
    fs_hz : float
    housing_force_n : ndarray
        ``(n, 2)``: the force the elements pass to the outer ring (x, y), N.
    housing_displacement_m, housing_acceleration_m_s2 : ndarray
        ``(n, 2)``: outer ring with housing, x, y.
    resonator_displacement_m, resonator_acceleration_m_s2 : ndarray
        ``(n,)``: the sensor structure's degree of freedom along the sensor axis.
    inner_displacement_m : ndarray
        ``(n, 2)``: inner ring with the shaft.
    element_load_n : ndarray
        ``(n, Z)``: each element's outer contact load, N.
    defect_force_n : ndarray
        ``(n,)``: force of the contact on the defect (0 when none is on it), N.
    element_velocity_m_s : ndarray
        ``(n, Z)``: each element's velocity along its normal, outwards (point samples), m/s.
    defect_contact : ndarray
        ``(n,)``: the contact that reads the defect law, +1 outer, -1 inner, 0 none (point
        samples; a pitted element meets both).
    state_end : ndarray
        The state where the integration stopped (at ``t_end_s``, past the record by the
        anti-alias filter's half length).
    t_end_s : float
    defect_force_peak_n : float
        Largest defect contact force of the internal record (before the anti-alias filter), N.
    model : str
        The model that made them.
    step_s : float
        Integration step, s.
    steps : int
        Steps integrated (settling included).
    oversample : int
        Internal record rate / ``fs_hz``.
    cpu_s : float
        Process CPU time of the run, s.
    params : DynamicParams
    """

    t_s: np.ndarray
    fs_hz: float
    housing_force_n: np.ndarray
    housing_displacement_m: np.ndarray
    housing_acceleration_m_s2: np.ndarray
    resonator_displacement_m: np.ndarray
    resonator_acceleration_m_s2: np.ndarray
    inner_displacement_m: np.ndarray
    element_load_n: np.ndarray
    defect_force_n: np.ndarray
    element_velocity_m_s: np.ndarray
    state_end: np.ndarray
    t_end_s: float
    defect_force_peak_n: float
    model: str
    step_s: float
    steps: int
    oversample: int
    cpu_s: float
    params: DynamicParams
    defect_contact: np.ndarray | None = None


def record_names(z: int) -> tuple[str, ...]:
    """Names of the internal record's columns (:data:`~.layout.REC_FIXED`, ``element_k`` the
    outer loads, ``velocity_k`` the element velocities, :data:`~.layout.REC_CONTACT`).

    Parameters
    ----------
    z : int
        Elements.

    Returns
    -------
    tuple of str
        The fixed columns, then ``element_0 .. element_{z-1}``, ``velocity_0 ..
        velocity_{z-1}`` and ``defect_contact``.
    """
    return (REC_FIXED + tuple(f"element_{k}" for k in range(z))
            + tuple(f"velocity_{k}" for k in range(z)) + (REC_CONTACT,))


class _Stream:
    """Integrates forward on demand and serves rows of the internal record by index
    ``j`` (time ``j rec_dt``), keeping only what a later request may still ask for."""

    def __init__(self, params, a, y0, j_first, rec_dt, every, run=rk4_loop):
        self.a, self.y, self.rec_dt, self.every, self.run = a, y0.copy(), rec_dt, every, run
        self.z = params.z
        self.next_j = j_first
        self.buf = np.empty((0, REC_SIZE_FIXED + 2 * params.z + 1))
        self.buf_j = j_first
        self.steps = 0

    def rows(self, j_lo: int, j_hi: int) -> np.ndarray:
        if j_lo < self.buf_j:
            raise RuntimeError(f"dynamics stream: row {j_lo} already dropped (first kept {self.buf_j})")
        if j_hi >= self.next_j:
            n = j_hi + 1 - self.next_j
            new = np.empty((n, self.buf.shape[1]))
            a = self.a
            self.run(self.y, self.next_j * self.rec_dt, self.rec_dt / self.every, n, self.every,
                    *a.kernel_args(), new)
            if not np.all(np.isfinite(self.y)):
                bad = ~np.all(np.isfinite(new), axis=1)
                k = int(np.argmax(bad)) if bad.any() else n
                raise FloatingPointError(
                    f"dynamics: state not finite at t = {(self.next_j + k) * self.rec_dt:.6g} s "
                    f"(step {self.rec_dt / self.every:.3g} s; the step rule gives a stable step)")
            self.steps += n * self.every
            self.next_j += n
            self.buf = np.concatenate([self.buf, new])[j_lo - self.buf_j:]
            self.buf_j = j_lo
        return self.buf[j_lo - self.buf_j: j_hi + 1 - self.buf_j]

    def evaluate(self, t: np.ndarray) -> dict:
        j = np.rint(np.asarray(t) / self.rec_dt).astype(np.int64)
        r = self.rows(int(j[0]), int(j[-1]))
        return {name: r[:, i] for i, name in enumerate(record_names(self.z))}


def _check_table_range(params: DynamicParams, peak: float) -> None:
    """Warn when the defect contact went above the law's largest tabulated force (read by
    linear extrapolation in ``delta``)."""
    if params.defect is None:
        return
    laws = [params.defect] + ([params.pit.inner] if params.defect_race == "element"
                              and params.pit.inner is not None else [])
    top = min(float(law.force_n[:, -1].max()) for law in laws)
    if peak > top:
        warnings.warn(f"simulate_dynamics: the defect contact reached {peak:.4g} N, above the defect "
                      f"law's largest tabulated force {top:.4g} N: read "
                      "by linear extrapolation in delta (extend delta_m)", RuntimeWarning, stacklevel=3)


def _settle_s(params: DynamicParams) -> float:
    """Settling time before ``t = 0`` (:data:`SETTLE_PERIODS` of the housing's mode, >= 20 ms)."""
    f = math.sqrt(params.housing_stiffness_n_m / params.housing_mass_kg) / (2 * math.pi) \
        if params.housing_stiffness_n_m > 0 else 50.0
    return max(0.02, SETTLE_PERIODS / f)


def simulate_dynamics(params: DynamicParams, duration_s: float, fs_hz: float, *,
                      dt_s: float | None = None, steps_per_period: float | None = None,
                      oversample: int | None = None, acquisition_mode: str = Acquisition.mode,
                      settle_s: float | None = None, y0: np.ndarray | None = None,
                      kernel: str = "fast") -> DynamicResult:
    """Run the model for ``duration_s`` and record it at ``fs_hz``.

    The state starts at :func:`initial_state` (or ``y0``) at ``-settle_s`` and is integrated by
    classical RK4 with a fixed step (:func:`~.params.step_size` unless ``dt_s``), rounded down
    so that a whole number of steps spans each internal record interval ``1/(N fs)``; the
    internal record (rate ``N fs``, ``N`` = ``oversample`` or :func:`modal_oversample`) goes
    through :func:`~bearing_envelope.physics.acquisition.acquire` (anti-alias FIR, decimation to
    ``fs``; ``point``: ``N = 1``, samples at ``k / fs``).

    Parameters
    ----------
    params : DynamicParams
        The model (:func:`~.params.params_from_scene`): masses (kg), stiffnesses (N/m), radii (m),
        rates (Hz), load (N), the defect law.
    duration_s : float
        Record length, s (> 0).
    fs_hz : float
        Output rate, Hz (> 0).
    dt_s : float, optional
        Largest step, s (default: the step rule).
    steps_per_period : float, optional
        The step rule's steps per period of the highest frequency (default: the scene's,
        :func:`~.params.rule_steps`).
    oversample : int, optional
        ``N`` (default :func:`modal_oversample`).
    acquisition_mode : {"antialiased", "point"}
        ``antialiased``: the internal record (rate ``N fs``) through the anti-alias FIR and
        decimated to ``fs``; ``point``: ``N = 1``, samples at ``k / fs``.
    settle_s : float, optional
        Settling before ``t = 0``, s (default: :data:`SETTLE_PERIODS` housing periods).
    y0 : ndarray, optional
        State at ``-settle_s`` (default :func:`initial_state`).
    kernel : {"fast", "reference"}
        The integrator (:data:`KERNELS`): ``fast`` the fused loop, ``reference`` the
        step-by-step one; the same result to the bit.

    Returns
    -------
    DynamicResult
        Every signal at ``fs_hz`` from ``t = 0``: housing force (N), displacements (m) and
        accelerations (m/s^2), element loads (N), defect force (N), the final state.

    Raises
    ------
    ValueError
        ``duration_s`` or ``fs_hz`` not finite and > 0, an ``acquisition`` other than
        ``antialiased`` or ``point``, a ``kernel`` not in :data:`KERNELS`, or a ``y0`` of
        another shape than the state.
    """
    for name, v in (("duration_s", duration_s), ("fs_hz", fs_hz)):
        if not (isinstance(v, numbers.Real) and math.isfinite(v) and v > 0):
            raise ValueError(f"simulate_dynamics: {name} got {v!r}; allowed: finite > 0")
    if acquisition_mode not in ("antialiased", "point"):
        raise ValueError(f"simulate_dynamics: acquisition_mode got {acquisition_mode!r}; allowed: antialiased | point")
    if kernel not in KERNELS:
        raise ValueError(f"simulate_dynamics: kernel got {kernel!r}; allowed: {' | '.join(KERNELS)}")
    cpu0 = time.process_time()
    n_out = int(round(duration_s * fs_hz))
    ov = 1 if acquisition_mode == "point" else (modal_oversample(params, fs_hz) if oversample is None
                                           else int(oversample))
    rec_dt = 1.0 / (ov * fs_hz)
    dt = step_size(params, steps_per_period) if dt_s is None else float(dt_s)
    every = max(1, int(math.ceil(rec_dt / dt - 1e-9)))
    settle = _settle_s(params) if settle_s is None else float(settle_s)
    lead = 0 if acquisition_mode == "point" else (antialias_filter(ov).size - 1) // 2
    j_first = -int(math.ceil(settle / rec_dt - 1e-9)) - lead
    t_first = j_first * rec_dt
    a = arrays(params, t_first, duration_s + 0.1)
    y = initial_state(params, t_first) if y0 is None else np.asarray(y0, dtype=float).copy()
    if y.shape != (StateLayout(params.z).size,):
        raise ValueError(f"simulate_dynamics: y0 has shape {y.shape}; allowed: "
                         f"({StateLayout(params.z).size},)")
    st = _Stream(params, a, y, j_first, rec_dt, every, KERNELS[kernel])
    names = record_names(params.z)
    ranges: dict = {}
    sig = acquire(st.evaluate, n_out, fs_hz, mode=acquisition_mode, oversample=ov,
                  filtered=names[:REC_SIZE_FIXED + params.z], ranges=ranges)
    peak = ranges.get("defect_force", [0.0, float(np.max(sig["defect_force"], initial=0.0))])[1]
    _check_table_range(params, peak)
    z = params.z

    def pair(name):
        return np.stack([sig[f"{name}_x"], sig[f"{name}_y"]], axis=1)

    return DynamicResult(np.arange(n_out) / fs_hz, float(fs_hz), pair("housing_force"),
                         pair("housing_disp"), pair("housing_acc"), sig["resonator_disp"],
                         sig["resonator_acc"], pair("inner_disp"),
                         np.stack([sig[f"element_{k}"] for k in range(z)], axis=1),
                         sig["defect_force"],
                         np.stack([sig[f"velocity_{k}"] for k in range(z)], axis=1),
                         st.y.copy(), st.next_j * rec_dt, peak, MODEL_NAME, rec_dt / every, st.steps, ov,
                         time.process_time() - cpu0, params, sig[REC_CONTACT])
