"""numba kernels of the per-sample table reading and synthesis (numpy fallbacks live beside
their callers in :mod:`~bearing_envelope.physics.table` and :mod:`~bearing_envelope.physics.history`)."""

from __future__ import annotations

import numpy as np

__all__ = ["HAVE_NUMBA", "decimate_kernel", "ratio_kernel", "synth_kernel"]


try:  # pragma: no cover - numba optional at import time
    import numba

    @numba.njit(cache=True, fastmath=False)
    def _row(T, i, xn, xr, fill):
        nx = xn.size
        if xr >= xn[nx - 1]:
            return fill
        # uniform offset nodes: direct index
        step = xn[1] - xn[0]
        j = int(xr / step)
        if j > nx - 2:
            j = nx - 2
        tx = (xr - xn[j]) / step
        if tx < 0.0:
            tx = 0.0
        elif tx > 1.0:
            tx = 1.0
        return (1.0 - tx) * T[i, j] + tx * T[i, j + 1]

    @numba.njit(cache=True, fastmath=False)
    def _row_x(x, q, qn, i, ka, s0):
        ax = abs(x)
        if q >= qn[0]:
            v = ax + ka * (qn[i] - q)
            return v if v > 0.0 else 0.0
        return ax * (ka * qn[i] + s0) / (ka * q + s0)

    @numba.njit(cache=True, fastmath=False)
    def synth_kernel(t, theta_c, fr, z, ri, K, dr, c, ca, n, discrete, qn, xn, p0, R, Rd, ka,
                      s0, qo, po, P, Pd, Qo, Xo):
        """Per-sample inner-race synthesis into ``P, Pd, Qo, Xo``: the roller at the defect,
        its load from the load-zone law, the table read at that load and offset.

        The compiled loop of :func:`~.locations.inner_race.synthesize` (its numpy twin:
        :func:`~.locations.inner_race.synthesize_numpy`); all arrays C-contiguous float64.

        Parameters
        ----------
        t : ndarray (n,)
            Sample times (s).
        theta_c : ndarray (n,)
            Cage angle at those times (rad).
        fr : float
            Shaft rate (Hz); the defect on the inner ring is at angle ``2 pi fr t``.
        z : int
            Rollers per row.
        ri : float
            Inner-race radius (m): arc length = ``ri`` x angle from the nearest roller.
        K : float
            Load-deflection stiffness of one roller (N m^-n).
        dr : float
            Radial displacement of the inner ring (m).
        c : float
            Radial internal clearance (m).
        ca : float
            Cosine of the contact angle.
        n : float
            Load-deflection exponent (10/9 for a line contact).
        discrete : bool
            Load of the roller at its own angle (True) or at the defect's angle (False: the
            continuous load-zone law).
        qn, xn, p0, R, Rd, ka, s0, qo, po
            :meth:`~.table.PressureTable.args`: cube roots of the node loads (N^1/3), node
            offsets (m), ``P0`` at the nodes (Pa), the ratio tables ``W/W0`` and ``P_d/W0``
            (nq, nx), ``kappa a_coef`` (m N^-1/3), ``s_const`` (m), cube roots of the dense
            outside loads (N^1/3) and the outside pressure there (Pa).
        P, Pd : ndarray (n,)
            Out: maximum contact pressure and the pressure at the defect (Pa).
        Qo, Xo : ndarray (n,)
            Out: load of the roller at the defect (N) and the defect's arc-length offset from
            its contact centre (m).
        """
        pitch = 2.0 * np.pi / z
        nq = qn.size
        for k in range(t.size):
            th = 2.0 * np.pi * fr * t[k]
            rel = th - theta_c[k]
            m = np.floor((rel + 0.5 * pitch) / pitch)
            x = ri * (rel - m * pitch)
            psi = th - (rel - m * pitch) if discrete else th
            d = (dr * np.cos(psi) - 0.5 * c) * ca
            Q = K * d ** n if d > 0.0 else 0.0
            Qo[k] = Q
            Xo[k] = x
            q = np.cbrt(Q)
            qc = min(max(q, qn[0]), qn[nq - 1])
            i = 0
            while i < nq - 2 and qn[i + 1] <= qc:
                i += 1
            tq = (qc - qn[i]) / (qn[i + 1] - qn[i])
            if q < qn[0]:
                p0q = p0[0] * q / qn[0]
            else:
                p0q = p0[i] * (1 - tq) + p0[i + 1] * tq
            x0 = _row_x(x, q, qn, i, ka, s0)
            x1 = _row_x(x, q, qn, i + 1, ka, s0)
            if q < qo[0]:
                pout = po[0] * q / qo[0]
            elif q >= qo[qo.size - 1]:
                pout = po[qo.size - 1]
            else:
                m2 = min(max(np.searchsorted(qo, q, side="right") - 1, 0), qo.size - 2)
                f = (q - qo[m2]) / (qo[m2 + 1] - qo[m2])
                pout = (1.0 - f) * po[m2] + f * po[m2 + 1]
            w = p0q * ((1 - tq) * _row(R, i, xn, x0, 1.0) + tq * _row(R, i + 1, xn, x1, 1.0))
            P[k] = w if w > pout else pout
            Pd[k] = p0q * ((1 - tq) * _row(Rd, i, xn, x0, 0.0) + tq * _row(Rd, i + 1, xn, x1, 0.0))

    @numba.njit(cache=True, fastmath=False)
    def ratio_kernel(Qa, Xa, qn, xn, ka, s0, T, out):
        """A ratio table read at loads ``Qa`` and offsets ``Xa`` into ``out``, the rule of
        :class:`~.table.PressureTable` (rows at equal distance to the contact edge, linear in
        ``Q^(1/3)``; 0 beyond the last offset); the compiled twin of ``table._ratio_eval``.

        Parameters
        ----------
        Qa : ndarray (n,)
            Roller loads (N).
        Xa : ndarray (n,)
            Defect offsets from the contact centre (m).
        qn, xn : ndarray
            Cube roots of the node loads (N^1/3) and node offsets (m, uniform).
        ka : float
            ``kappa a_coef``: solved half-width per ``Q^(1/3)`` (m N^-1/3).
        s0 : float
            ``s_const`` of the table (m).
        T : ndarray (nq, nx)
            The ratio table (dimensionless).
        out : ndarray (n,)
            Out: the ratios read (dimensionless).
        """
        nq = qn.size
        for k in range(Qa.size):
            Q = Qa[k]
            q = np.cbrt(Q) if Q > 0.0 else 0.0
            qc = min(max(q, qn[0]), qn[nq - 1])
            i = 0
            while i < nq - 2 and qn[i + 1] <= qc:
                i += 1
            tq = (qc - qn[i]) / (qn[i + 1] - qn[i])
            out[k] = ((1 - tq) * _row(T, i, xn, _row_x(Xa[k], q, qn, i, ka, s0), 0.0)
                      + tq * _row(T, i + 1, xn, _row_x(Xa[k], q, qn, i + 1, ka, s0), 0.0))

    @numba.njit(cache=True, fastmath=False)
    def decimate_kernel(h, x, n, out):
        """:func:`~.acquisition.decimate_centred` into ``out``: the same sums in the same order
        (last tap first, one pass per tap over every output), without numpy's temporaries.

        Parameters
        ----------
        h : ndarray (m,)
            FIR taps (odd length, centred; dimensionless).
        x : ndarray
            The oversampled signal (any unit), long enough for every output's taps.
        n : int
            Decimation factor: output ``i`` is centred on input ``i n + (m - 1) / 2``.
        out : ndarray
            Out: the filtered, decimated samples (unit of ``x``).
        """
        c = (h.size - 1) // 2
        for i in range(out.size):
            out[i] = 0.0
        for j in range(h.size - 1, -1, -1):
            hj = h[j]
            base = 2 * c - j
            for i in range(out.size):
                out[i] += x[base + i * n] * hj

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover
    HAVE_NUMBA = False
