"""numba kernels of the lumped-parameter bearing: contact laws, the right-hand side and the
fixed-step RK4 integrator (equations: ``docs/dynamics.md``; layouts: :mod:`.layout`).

Every kernel is a pure function of its arguments (the output arrays aside): the right-hand side
of one state at one time is :func:`rhs_kernel`, which :func:`~.model.rhs` wraps for
``scipy.integrate.solve_ivp``.
"""

from __future__ import annotations

import math

import numpy as np

from .layout import P_NAMES, REC_SIZE_FIXED

__all__ = ["HAVE_NUMBA", "hertz_force", "table_force", "cage_angle_at", "contact_forces",
           "rhs_kernel", "rk4_run"]

try:  # pragma: no cover - numba optional at import time
    import numba

    HAVE_NUMBA = True
    _jit = numba.njit(cache=True, fastmath=False)
except ImportError:  # pragma: no cover
    HAVE_NUMBA = False

    def _jit(f):
        return f

(MS, KS, CS, MH, KH, CH, MR, KR, CR, SENS_C, SENS_S, ME, KI, KO, NEXP, CC, GAP, CA, FX, FY, FC,
 RI, RO, DRACE, DANG, WS, CT0, CDT, N15) = range(len(P_NAMES))
_E0 = 5  # first element DOF (layout.StateLayout.ELEM0)


@_jit
def hertz_force(delta, ddelta, k, n, n15, c):
    """Contact force ``max(0, K delta^n + c d(delta)/dt)`` for ``delta > 0``, else 0 (N).

    Parameters
    ----------
    delta, ddelta : float
        Approach (m) and its rate (m/s).
    k, n : float
        ``K`` (N m^-n) and ``n`` of ``Q = K delta^n``.
    n15 : float
        1 when ``n == 3/2`` (``delta sqrt(delta)``).
    c : float
        Contact damping, N s/m.

    Returns
    -------
    float
        Force, N, >= 0.
    """
    if delta <= 0.0:
        return 0.0
    el = k * delta * math.sqrt(delta) if n15 == 1.0 else k * delta ** n
    f = el + c * ddelta
    return f if f > 0.0 else 0.0


@_jit
def _bracket(a, v):
    """Index ``i`` with ``a[i] <= v < a[i + 1]`` clamped to ``[0, len - 2]`` (bisection)."""
    lo = 0
    hi = a.size - 1
    if v <= a[0]:
        return 0
    if v >= a[hi]:
        return hi - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if a[mid] <= v:
            lo = mid
        else:
            hi = mid
    return lo


@_jit
def table_force(x, delta, tx, td, tf):
    """Bilinear reading of the defect law ``tf[i, j] = F(tx[i], td[j])`` (N): 0 for
    ``delta <= 0``, extrapolated linearly in ``delta`` beyond the nodes and clipped at 0 (the
    reading of ``physics/defect_contact.py``'s table); ``x`` must lie in ``[tx[0], tx[-1]]``.

    Parameters
    ----------
    x : float
        Element position relative to the pit centre along its motion, m.
    delta : float
        Approach of the contact, m.
    tx, td : ndarray
        Ascending nodes of ``x`` and ``delta``, m.
    tf : ndarray
        Forces, N, shape ``(tx.size, td.size)``.

    Returns
    -------
    float
        Force, N, >= 0.
    """
    if delta <= 0.0:
        return 0.0
    i = _bracket(tx, x)
    j = _bracket(td, delta)
    u = (x - tx[i]) / (tx[i + 1] - tx[i])
    w = (delta - td[j]) / (td[j + 1] - td[j])
    f0 = tf[i, j] + w * (tf[i, j + 1] - tf[i, j])
    f1 = tf[i + 1, j] + w * (tf[i + 1, j + 1] - tf[i + 1, j])
    f = f0 + u * (f1 - f0)
    return f if f > 0.0 else 0.0


@_jit
def cage_angle_at(t, cage, t0, dt):
    """Cage angle (rad) and rate (rad/s) at ``t`` from uniform nodes ``cage[k]`` at
    ``t0 + k dt`` (linear between nodes, the end slopes beyond them).

    Parameters
    ----------
    t : float
        Time, s.
    cage : ndarray
        Angles at the nodes, rad (>= 2 nodes).
    t0, dt : float
        First node time and spacing, s.

    Returns
    -------
    tuple of float
        ``(angle, rate)``.
    """
    s = (t - t0) / dt
    k = int(math.floor(s))
    if k < 0:
        k = 0
    elif k > cage.size - 2:
        k = cage.size - 2
    rate = (cage[k + 1] - cage[k]) / dt
    return cage[k] + rate * (t - t0 - k * dt), rate


@_jit
def _wrap(a):
    """Angle wrapped to ``[-pi, pi)``."""
    return a - 2.0 * math.pi * math.floor((a + math.pi) / (2.0 * math.pi))


@_jit
def _defect_x(P, th, t):
    """Position (m) of an element at angle ``th`` relative to the pit, along its motion relative
    to the defective race (entry edge at negative ``x``)."""
    if P[DRACE] == 1.0:
        return P[RO] * _wrap(th - P[DANG])
    return P[RI] * _wrap(P[DANG] + P[WS] * t - th)


@_jit
def contact_forces(t, y, P, cage, cph, sph, tx, td, tf, qi, qo, xd):
    """Contact forces of every element at ``(t, y)``: inner ``qi`` and outer ``qo`` (N, along the
    normal, >= 0), the defect positions ``xd`` (m; 1e9 when no defect); returns the defect
    contact's force (N, summed over the elements on the defect).

    Parameters
    ----------
    t : float
        Time, s.
    y : ndarray
        State (:class:`~.layout.StateLayout`).
    P : ndarray
        Scalar parameters (:data:`~.layout.P_NAMES`).
    cage : ndarray
        Cage-angle nodes (:func:`cage_angle_at`).
    cph, sph : ndarray
        cos and sin of each element's pitch angle ``2 pi j / Z``.
    tx, td, tf : ndarray
        Defect law (:func:`table_force`).
    qi, qo, xd : ndarray
        Outputs, length ``Z``.

    Returns
    -------
    float
        Force of the defect contact, N.
    """
    z = cph.size
    nd = _E0 + z
    thc, thd = cage_angle_at(t, cage, P[CT0], P[CDT])
    c0 = math.cos(thc)
    s0 = math.sin(thc)
    xi, yi, xo, yo = y[0], y[1], y[2], y[3]
    vxi, vyi, vxo, vyo = y[nd], y[nd + 1], y[nd + 2], y[nd + 3]
    ca, g = P[CA], P[GAP]
    fdef = 0.0
    for j in range(z):
        c = c0 * cph[j] - s0 * sph[j]
        s = s0 * cph[j] + c0 * sph[j]
        ri = xi * c + yi * s
        ro = xo * c + yo * s
        rid = vxi * c + vyi * s + thd * (yi * c - xi * s)
        rod = vxo * c + vyo * s + thd * (yo * c - xo * s)
        u = y[_E0 + j]
        ud = y[nd + _E0 + j]
        di = (ri - g) * ca - u
        dout = u - (ro + g) * ca
        ddi = rid * ca - ud
        ddo = ud - rod * ca
        xd[j] = 1e9
        if P[DRACE] != 0.0:
            xd[j] = _defect_x(P, thc + 2.0 * math.pi * j / z, t)
        on = xd[j] >= tx[0] and xd[j] <= tx[tx.size - 1]
        qi[j] = hertz_force(di, ddi, P[KI], P[NEXP], P[N15], P[CC])
        qo[j] = hertz_force(dout, ddo, P[KO], P[NEXP], P[N15], P[CC])
        if on:
            el = table_force(xd[j], dout if P[DRACE] == 1.0 else di, tx, td, tf)
            if el > 0.0:
                el = el + P[CC] * (ddo if P[DRACE] == 1.0 else ddi)
                el = el if el > 0.0 else 0.0
            if P[DRACE] == 1.0:
                qo[j] = el
            else:
                qi[j] = el
            fdef += el
    return fdef


@_jit
def rhs_kernel(t, y, P, cage, cph, sph, tx, td, tf, qi, qo, xd, dydt):
    """``dy/dt`` at ``(t, y)`` into ``dydt`` (equations of motion, ``docs/dynamics.md``);
    returns the defect contact force (N). Arguments as :func:`contact_forces`.

    Parameters
    ----------
    t, y, P, cage, cph, sph, tx, td, tf, qi, qo, xd
        As :func:`contact_forces`.
    dydt : ndarray
        Output, shape of ``y``.

    Returns
    -------
    float
        Force of the defect contact, N.
    """
    z = cph.size
    nd = _E0 + z
    fdef = contact_forces(t, y, P, cage, cph, sph, tx, td, tf, qi, qo, xd)
    thc, thd = cage_angle_at(t, cage, P[CT0], P[CDT])
    c0 = math.cos(thc)
    s0 = math.sin(thc)
    ca = P[CA]
    fxi = 0.0
    fyi = 0.0
    fxo = 0.0
    fyo = 0.0
    for j in range(z):
        c = c0 * cph[j] - s0 * sph[j]
        s = s0 * cph[j] + c0 * sph[j]
        fxi -= qi[j] * ca * c
        fyi -= qi[j] * ca * s
        fxo += qo[j] * ca * c
        fyo += qo[j] * ca * s
        dydt[_E0 + j] = y[nd + _E0 + j]
        dydt[nd + _E0 + j] = (qi[j] - qo[j] + P[FC]) / P[ME]
    for i in range(_E0):
        dydt[i] = y[nd + i]
    rel = y[4] - (P[SENS_C] * y[2] + P[SENS_S] * y[3])
    reld = y[nd + 4] - (P[SENS_C] * y[nd + 2] + P[SENS_S] * y[nd + 3])
    fr = P[KR] * rel + P[CR] * reld
    dydt[nd] = (P[FX] + fxi - P[KS] * y[0] - P[CS] * y[nd]) / P[MS]
    dydt[nd + 1] = (P[FY] + fyi - P[KS] * y[1] - P[CS] * y[nd + 1]) / P[MS]
    dydt[nd + 2] = (fxo - P[KH] * y[2] - P[CH] * y[nd + 2] + fr * P[SENS_C]) / P[MH]
    dydt[nd + 3] = (fyo - P[KH] * y[3] - P[CH] * y[nd + 3] + fr * P[SENS_S]) / P[MH]
    dydt[nd + 4] = -fr / P[MR]
    return fdef


@_jit
def _record(t, y, k1, fdef, P, cage, cph, sph, qo, row):
    """One row of the internal record (:data:`~.layout.REC_FIXED`, the ``Z`` outer loads, the
    ``Z`` element velocities)."""
    z = cph.size
    nd = _E0 + z
    thc, _ = cage_angle_at(t, cage, P[CT0], P[CDT])
    c0 = math.cos(thc)
    s0 = math.sin(thc)
    fx = 0.0
    fy = 0.0
    for j in range(z):
        fx += qo[j] * P[CA] * (c0 * cph[j] - s0 * sph[j])
        fy += qo[j] * P[CA] * (s0 * cph[j] + c0 * sph[j])
        row[REC_SIZE_FIXED + j] = qo[j]
        row[REC_SIZE_FIXED + z + j] = y[nd + _E0 + j]
    row[0], row[1] = fx, fy
    row[2], row[3] = y[2], y[3]
    row[4], row[5] = k1[nd + 2], k1[nd + 3]
    row[6], row[7] = y[4], k1[nd + 4]
    row[8] = fdef
    row[9], row[10] = y[0], y[1]


@_jit
def rk4_run(y, t0, dt, n_rec, every, P, cage, cph, sph, tx, td, tf, rec):
    """Integrate ``n_rec * every`` classical RK4 steps of ``dt`` from ``(t0, y)`` (``y`` updated
    in place), recording a row of ``rec`` at the start of every ``every``-th step.

    Parameters
    ----------
    y : ndarray
        State at ``t0``; holds the state at the end on return.
    t0, dt : float
        Start time and step, s.
    n_rec, every : int
        Rows to record and steps per row.
    P, cage, cph, sph, tx, td, tf
        As :func:`contact_forces`.
    rec : ndarray
        Output, shape ``(n_rec, REC_SIZE_FIXED + 2 Z)``.

    Returns
    -------
    float
        The time at the end, s.
    """
    z = cph.size
    n = y.size
    k1 = np.empty(n)
    k2 = np.empty(n)
    k3 = np.empty(n)
    k4 = np.empty(n)
    tmp = np.empty(n)
    qi = np.empty(z)
    qo = np.empty(z)
    xd = np.empty(z)
    h2 = 0.5 * dt
    for r in range(n_rec):
        for m in range(every):
            t = t0 + (r * every + m) * dt
            fdef = rhs_kernel(t, y, P, cage, cph, sph, tx, td, tf, qi, qo, xd, k1)
            if m == 0:
                _record(t, y, k1, fdef, P, cage, cph, sph, qo, rec[r])
            for i in range(n):
                tmp[i] = y[i] + h2 * k1[i]
            rhs_kernel(t + h2, tmp, P, cage, cph, sph, tx, td, tf, qi, qo, xd, k2)
            for i in range(n):
                tmp[i] = y[i] + h2 * k2[i]
            rhs_kernel(t + h2, tmp, P, cage, cph, sph, tx, td, tf, qi, qo, xd, k3)
            for i in range(n):
                tmp[i] = y[i] + dt * k3[i]
            rhs_kernel(t + dt, tmp, P, cage, cph, sph, tx, td, tf, qi, qo, xd, k4)
            for i in range(n):
                y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
    return t0 + n_rec * every * dt
