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

__all__ = ["HAVE_NUMBA", "hertz_force", "table_force", "cage_angle_at", "element_pit_offsets",
           "pit_arrays",
           "contact_forces", "rhs_kernel", "rk4_run", "rk4_loop"]

try:  # pragma: no cover - numba optional at import time
    import numba

    HAVE_NUMBA = True
    _jit = numba.njit(cache=True, fastmath=False)
    # inlined in numba's IR: a call with array arguments costs their reference counting
    _jit_inline = numba.njit(cache=True, fastmath=False, inline="always")
except ImportError:  # pragma: no cover
    HAVE_NUMBA = False

    def _jit(f):
        return f

    _jit_inline = _jit

(MS, KS, CS, MH, KH, CH, MR, KR, CR, SENS_C, SENS_S, ME, KI, KO, NEXP, CC, GAP, CA, FX, FY, FC,
 RI, RO, DRACE, DANG, WS, CT0, CDT, N15, RE, SPR, BI2, BO2, TURN0, NX2, ND2, NOR) = range(len(P_NAMES))
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
def _pit_element(P, thc, t, x_lo, x_hi, z):
    """Index of the element nearest a race pit at cage angle ``thc``, time ``t``: with its two
    neighbours the only elements whose defect position (:func:`_defect_x`) can fall in the
    law's ``[x_lo, x_hi]`` (every other is >= 1.5 pitches from the pit, the law reaches < 1);
    -1 when the law reaches a pitch or more (then every element reads it)."""
    pitch = 2.0 * math.pi / z
    if P[DRACE] == 1.0:
        r = P[RO]
        phi = P[DANG] - thc
    else:
        r = P[RI]
        phi = P[DANG] + P[WS] * t - thc
    if max(-x_lo, x_hi) >= r * pitch:
        return -1
    return int(math.floor(phi / pitch + 0.5)) % z


@_jit
def _near(j, jn, z):
    """Whether element ``j`` is element ``jn`` or its neighbour (always, for ``jn < 0``)."""
    d = j - jn
    if d < 0:
        d += z
    return jn < 0 or d <= 1 or d >= z - 1


@_jit
def _approaches(r, c, s, thd, u, ud, ca, g):
    """Approaches (m) of an element's inner and outer contact and their rates (m/s):
    ``(di, dout, ddi, ddo)``; ``r`` the rings' ``(x_i, y_i, x_o, y_o)`` and their velocities,
    ``(c, s)`` the element's normal, ``thd`` the cage rate (the normal's turning), ``u, ud``
    the element's displacement and velocity, ``ca`` cos(contact angle), ``g`` the quarter
    clearance."""
    ri = r[0] * c + r[1] * s
    ro = r[2] * c + r[3] * s
    rid = r[4] * c + r[5] * s + thd * (r[1] * c - r[0] * s)
    rod = r[6] * c + r[7] * s + thd * (r[3] * c - r[2] * s)
    return (ri - g) * ca - u, u - (ro + g) * ca, rid * ca - ud, ud - rod * ca


@_jit
def _law_force(x, delta, ddelta, tx, td, tf, c):
    """The defect law at ``(x, delta)`` with the contact damping while it carries force (N)."""
    el = table_force(x, delta, tx, td, tf)
    if el > 0.0:
        el = el + c * ddelta
        el = el if el > 0.0 else 0.0
    return el


@_jit
def element_pit_offsets(P, thc):
    """Where a pit on element 0 is, at cage angle ``thc``: its position in the outer and in the
    inner contact (m, arc length on the element's surface from the pit centre to the contact
    point along the surface's motion relative to the contact: the entry edge at negative ``x``)
    and its squared distance from the element's rolling track (m^2).

    The element turns relative to the cage by ``beta = spr thc + lon_k`` (rolling without slip on
    the fixed outer race: ``spr = BSF / FTF``); the pit is at the outer contact at ``beta = 0``,
    at the inner at ``beta = pi``: ``x_o = r wrap(beta)``, ``x_i = r wrap(beta - pi)``.
    ``(track offset m, lon rad)`` of cage turn ``k + turn0``: the ``k``-th pair of the
    orientation rows at the end of ``P`` (a turn runs from ``thc = (2k - 1) pi`` to ``(2k + 1) pi``: the
    orientation changes where the element is least loaded; clamped to the rows).

    Parameters
    ----------
    P : ndarray
        Parameters (:data:`~.layout.P_NAMES`: ``re``, ``spr``, ``turn0``, ``nor``; then the
        element pit's arrays, :func:`pit_arrays`).
    thc : float
        Cage angle (element 0's angle from the load direction), rad.

    Returns
    -------
    tuple of float
        ``(x_outer, x_inner, offset^2)``.
    """
    k = int(math.floor((thc + math.pi) / (2.0 * math.pi)) - P[TURN0])
    n = int(P[NOR])
    if k < 0:
        k = 0
    elif k > n - 1:
        k = n - 1
    o = P.size - 2 * n + 2 * k
    w = _wrap(P[SPR] * thc + P[o + 1])
    return P[RE] * w, P[RE] * (w - math.pi if w >= 0.0 else w + math.pi), P[o] * P[o]


@_jit
def pit_arrays(P):
    """The element pit's inner contact law ``(tx2, td2, tf2)``: views of ``P`` past its scalars
    (:data:`~.layout.P_NAMES`), which hold ``tx2`` (``P[NX2]`` nodes), ``td2`` (``P[ND2]``),
    ``tf2`` row by row, then the ``P[NOR]`` orientation rows (track offset, longitude) of
    :func:`element_pit_offsets`. Packed into ``P`` rather than passed as arrays of their own:
    each array argument of the kernels costs the healthy bearing ~4 % of its run time.

    Parameters
    ----------
    P : ndarray
        Parameters and the packed arrays (:func:`~.model.arrays`).

    Returns
    -------
    tuple of ndarray
        ``tx2``, ``td2``, ``tf2`` (``(nx2, nd2)``).
    """
    o = len(P_NAMES)
    nx = int(P[NX2])
    nd = int(P[ND2])
    return P[o:o + nx], P[o + nx:o + nx + nd], P[o + nx + nd:o + nx + nd + nx * nd].reshape((nx, nd))


@_jit_inline
def _element_pit(P, thc, di, dout, ddi, ddo, tx, td, tf, qi, qo, xd):
    """Element 0's contacts with the pit on its surface (its outer law ``tx, td, tf``, its inner
    law in ``P``, :func:`pit_arrays`) where the pit is inside a law's ``x`` range and within that contact's Hertz
    axial semi-axis ``b`` (``off^2 <= b^2 = P[BO2 | BI2] delta``): overwrites ``qo[0]`` or
    ``qi[0]``, ``xd[0]`` (the pit's position in the nearer contact) and ``xd[Z]`` (the side:
    +1 outer, -1 inner, 0 none); returns the force (N)."""
    z = qi.size
    xo, xi, off2 = element_pit_offsets(P, thc)
    xd[0] = xo if abs(xo) <= abs(xi) else xi
    if xo >= tx[0] and xo <= tx[tx.size - 1] and off2 <= P[BO2] * max(dout, 0.0):
        qo[0] = _law_force(xo, dout, ddo, tx, td, tf, P[CC])
        xd[z] = 1.0
        return qo[0]
    o = len(P_NAMES)                # the inner law's x nodes: P[o : o + nx2]
    if xi >= P[o] and xi <= P[o + int(P[NX2]) - 1] and off2 <= P[BI2] * max(di, 0.0):
        tx2, td2, tf2 = pit_arrays(P)
        qi[0] = _law_force(xi, di, ddi, tx2, td2, tf2, P[CC])
        xd[z] = -1.0
        return qi[0]
    return 0.0


@_jit
def contact_forces(t, y, P, cage, cph, sph, tx, td, tf, qi, qo, xd):
    """Contact forces of every element at ``(t, y)``: inner ``qi`` and outer ``qo`` (N, along the
    normal, >= 0), the defect positions ``xd[:Z]`` (m; 1e9 when no defect) and ``xd[Z]`` which
    contact reads the defect law (+1 outer, -1 inner, 0 none); returns the defect contact's
    force (N, summed over the elements on the defect).

    Parameters
    ----------
    t : float
        Time, s.
    y : ndarray
        State (:class:`~.layout.StateLayout`).
    P : ndarray
        Scalar parameters (:data:`~.layout.P_NAMES`), then a pitted element's packed arrays
        (:func:`pit_arrays`).
    cage : ndarray
        Cage-angle nodes (:func:`cage_angle_at`).
    cph, sph : ndarray
        cos and sin of each element's pitch angle ``2 pi j / Z``.
    tx, td, tf : ndarray
        Defect law (:func:`table_force`): of the pitted race, or of a pitted element's outer
        contact.
    qi, qo : ndarray
        Outputs, length ``Z``.
    xd : ndarray
        Output, length ``Z + 1``.

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
    rings = (y[0], y[1], y[2], y[3], y[nd], y[nd + 1], y[nd + 2], y[nd + 3])
    ca, g = P[CA], P[GAP]
    fdef = 0.0
    xd[z] = 0.0
    drace = P[DRACE]
    race = drace == 1.0 or drace == 2.0
    jn = _pit_element(P, thc, t, tx[0], tx[tx.size - 1], z) if race else -1
    for j in range(z):
        c = c0 * cph[j] - s0 * sph[j]
        s = s0 * cph[j] + c0 * sph[j]
        di, dout, ddi, ddo = _approaches(rings, c, s, thd, y[_E0 + j], y[nd + _E0 + j], ca, g)
        xd[j] = 1e9
        qi[j] = hertz_force(di, ddi, P[KI], P[NEXP], P[N15], P[CC])
        qo[j] = hertz_force(dout, ddo, P[KO], P[NEXP], P[N15], P[CC])
        if race and _near(j, jn, z):
            xd[j] = _defect_x(P, thc + 2.0 * math.pi * j / z, t)
            if xd[j] >= tx[0] and xd[j] <= tx[tx.size - 1]:
                if drace == 1.0:
                    qo[j] = _law_force(xd[j], dout, ddo, tx, td, tf, P[CC])
                    fdef += qo[j]
                    xd[z] = 1.0
                else:
                    qi[j] = _law_force(xd[j], di, ddi, tx, td, tf, P[CC])
                    fdef += qi[j]
                    xd[z] = -1.0
    if drace == 3.0:
        di, dout, ddi, ddo = _approaches(rings, c0 * cph[0] - s0 * sph[0],
                                         s0 * cph[0] + c0 * sph[0], thd, y[_E0], y[nd + _E0], ca, g)
        fdef = _element_pit(P, thc, di, dout, ddi, ddo, tx, td, tf, qi, qo, xd)
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
def _record(t, y, k1, fdef, side, P, cage, cph, sph, qo, row):
    """One row of the internal record (:data:`~.layout.REC_FIXED`, the ``Z`` outer loads, the
    ``Z`` element velocities, the defect's side :data:`~.layout.REC_CONTACT`)."""
    z = cph.size
    thc, _ = cage_angle_at(t, cage, P[CT0], P[CDT])
    c0 = math.cos(thc)
    s0 = math.sin(thc)
    fx = 0.0
    fy = 0.0
    for j in range(z):
        fx += qo[j] * P[CA] * (c0 * cph[j] - s0 * sph[j])
        fy += qo[j] * P[CA] * (s0 * cph[j] + c0 * sph[j])
    _write_row(y, k1, fx, fy, fdef, side, qo, z, row)


@_jit_inline
def _write_row(y, k1, fx, fy, fdef, side, qo, z, row):
    """The record row's layout, once for :func:`_record` and :func:`rk4_loop`: ``fx, fy`` the
    elements' force on the outer ring (N), ``fdef`` the defect force (N), ``side`` its contact."""
    nd = _E0 + z
    for j in range(z):
        row[REC_SIZE_FIXED + j] = qo[j]
        row[REC_SIZE_FIXED + z + j] = y[nd + _E0 + j]
    row[0], row[1] = fx, fy
    row[2], row[3] = y[2], y[3]
    row[4], row[5] = k1[nd + 2], k1[nd + 3]
    row[6], row[7] = y[4], k1[nd + 4]
    row[8] = fdef
    row[9], row[10] = y[0], y[1]
    row[REC_SIZE_FIXED + 2 * z] = side


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
        Output, shape ``(n_rec, REC_SIZE_FIXED + 2 Z + 1)``.

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
    xd = np.empty(z + 1)
    h2 = 0.5 * dt
    for r in range(n_rec):
        for m in range(every):
            t = t0 + (r * every + m) * dt
            fdef = rhs_kernel(t, y, P, cage, cph, sph, tx, td, tf, qi, qo, xd, k1)
            if m == 0:
                _record(t, y, k1, fdef, xd[z], P, cage, cph, sph, qo, rec[r])
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


@_jit_inline
def _stage(t, thc, thd, c0, s0, y, P, cph, sph, pitch, tx, td, tf, qi, qo, xd, dydt):
    """:func:`rhs_kernel` in one pass over the elements, given the cage angle ``thc``, its rate
    ``thd``, ``c0, s0 = cos, sin(thc)`` (once per stage time) and ``pitch[j] = 2 pi j / Z``; the
    parameters read once into locals: the same operations in the same order, so the same bits.
    Returns the defect force and the force the elements pass to the outer ring (x, y), N."""
    z = cph.size
    nd = _E0 + z
    rings = (y[0], y[1], y[2], y[3], y[nd], y[nd + 1], y[nd + 2], y[nd + 3])
    ca, g = P[CA], P[GAP]
    ki, ko, nexp, n15, cc, fc, me = P[KI], P[KO], P[NEXP], P[N15], P[CC], P[FC], P[ME]
    x_lo, x_hi = tx[0], tx[tx.size - 1]
    fdef = 0.0
    xd[z] = 0.0
    drace = P[DRACE]
    race = drace == 1.0 or drace == 2.0
    fxi = 0.0
    fyi = 0.0
    fxo = 0.0
    fyo = 0.0
    jn = _pit_element(P, thc, t, x_lo, x_hi, z) if race else -1
    for j in range(z):
        c = c0 * cph[j] - s0 * sph[j]
        s = s0 * cph[j] + c0 * sph[j]
        ud = y[nd + _E0 + j]
        di, dout, ddi, ddo = _approaches(rings, c, s, thd, y[_E0 + j], ud, ca, g)
        qij = hertz_force(di, ddi, ki, nexp, n15, cc)
        qoj = hertz_force(dout, ddo, ko, nexp, n15, cc)
        if race and _near(j, jn, z):
            xdj = _defect_x(P, thc + pitch[j], t)
            if xdj >= x_lo and xdj <= x_hi:
                if drace == 1.0:
                    qoj = _law_force(xdj, dout, ddo, tx, td, tf, cc)
                    fdef += qoj
                    xd[z] = 1.0
                else:
                    qij = _law_force(xdj, di, ddi, tx, td, tf, cc)
                    fdef += qij
                    xd[z] = -1.0
        qi[j] = qij
        qo[j] = qoj
        if drace == 3.0 and j == 0:
            fdef = _element_pit(P, thc, di, dout, ddi, ddo, tx, td, tf, qi, qo, xd)
            qij = qi[0]
            qoj = qo[0]
        fxi -= qij * ca * c
        fyi -= qij * ca * s
        fxo += qoj * ca * c
        fyo += qoj * ca * s
        dydt[_E0 + j] = ud
        dydt[nd + _E0 + j] = (qij - qoj + fc) / me
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
    return fdef, fxo, fyo


@_jit
def rk4_loop(y, t0, dt, n_rec, every, P, cage, cph, sph, tx, td, tf, rec):
    """:func:`rk4_run` fused: the cage angle and its cosine and sine once per stage time (three
    per step instead of nine), the contact forces, the equations of motion and the record row in
    one pass over the elements (:func:`_stage`). Same arguments, same result to the bit.

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
        Output, shape ``(n_rec, REC_SIZE_FIXED + 2 Z + 1)``.

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
    xd = np.empty(z + 1)
    pitch = np.empty(z)
    for j in range(z):
        pitch[j] = 2.0 * math.pi * j / z          # as contact_forces: the same bits
    h2 = 0.5 * dt
    ct0 = P[CT0]
    cdt = P[CDT]
    for r in range(n_rec):
        for m in range(every):
            t = t0 + (r * every + m) * dt
            th, thd = cage_angle_at(t, cage, ct0, cdt)
            c0 = math.cos(th)
            s0 = math.sin(th)
            fdef, fx, fy = _stage(t, th, thd, c0, s0, y, P, cph, sph, pitch, tx, td, tf, qi, qo, xd, k1)
            if m == 0:
                _write_row(y, k1, fx, fy, fdef, xd[z], qo, z, rec[r])
            for i in range(n):
                tmp[i] = y[i] + h2 * k1[i]
            th, thd = cage_angle_at(t + h2, cage, ct0, cdt)
            c0 = math.cos(th)
            s0 = math.sin(th)
            _stage(t + h2, th, thd, c0, s0, tmp, P, cph, sph, pitch, tx, td, tf, qi, qo, xd, k2)
            for i in range(n):
                tmp[i] = y[i] + h2 * k2[i]
            _stage(t + h2, th, thd, c0, s0, tmp, P, cph, sph, pitch, tx, td, tf, qi, qo, xd, k3)
            for i in range(n):
                tmp[i] = y[i] + dt * k3[i]
            th, thd = cage_angle_at(t + dt, cage, ct0, cdt)
            c0 = math.cos(th)
            s0 = math.sin(th)
            _stage(t + dt, th, thd, c0, s0, tmp, P, cph, sph, pitch, tx, td, tf, qi, qo, xd, k4)
            for i in range(n):
                y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
    return t0 + n_rec * every * dt
