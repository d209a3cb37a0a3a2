"""Fused element-wise passes of the Polonsky-Keer iteration (numba, with a numpy reference).

One CG iteration needs about thirty masked numpy passes over the grid (means and dot products on
the contact set, clipping, the entering cells, rescaling); fused into five loops they cost a
fraction of that (see ``docs/benchmarks.md``). Every function works on flat (raveled,
C-contiguous) float64 arrays; ``mat`` is a bool array (material cells). The CG works on the free
set ``0 < p < H`` (``H = inf`` without a hardness bound: then the contact set ``p > 0``); cells at
``p = H`` are plastic and, like ``p = 0`` cells, fixed during a CG step. The numpy versions define
the semantics and are used when numba is unavailable or ``BEARING_ENVELOPE_NO_NUMBA=1``.
"""

from __future__ import annotations

import math
import os

import numpy as np

__all__ = ["KERNELS", "NUMPY", "HAVE_NUMBA"]


# ----------------------------------------------------------------------------------- numpy
def np_gap_stats(gz, u, p, ny, H):
    """Return ``(sum_{I}(g+u), count_{I}, max u, i0, i1, j0, j1)`` over the free set
    ``I = {0 < p < H}``; the last four bound ``I`` on the ``(-1, ny)`` grid (rows ``i0..i1``,
    columns ``j0..j1``, inclusive; ``-1`` if empty)."""
    ic = (p > 0) & (p < H)
    n = int(ic.sum())
    if n == 0:
        return 0.0, 0, float(u.max()), -1, -1, -1, -1
    ic2 = ic.reshape(-1, ny)
    rows = np.flatnonzero(ic2.any(axis=1))
    cols = np.flatnonzero(ic2.any(axis=0))
    return float((gz[ic] + u[ic]).sum()), n, float(u.max()), int(rows[0]), int(rows[-1]), int(cols[0]), int(cols[-1])


def np_gap_eval(gz, u, p, mat, alpha, h, H):
    """``h = g + u - alpha`` (``+inf`` off material); return ``(max_{I}|h|, max_{p=0}(-h)+,
    sum_{I} h^2, max_{p>=H} h+)`` with the free set ``I = {0 < p < H}``."""
    np.add(gz, u, out=h)
    h -= alpha
    h[~mat] = np.inf
    ic = (p > 0) & (p < H)
    hc = h[ic]
    err_in = float(np.abs(hc).max()) if hc.size else 0.0
    off = h[p <= 0]
    err_out = float(max(0.0, -off.min())) if off.size else 0.0
    sat = h[p >= H]
    err_sat = float(max(0.0, sat.max())) if sat.size else 0.0
    return err_in, err_out, float(np.dot(hc, hc)), err_sat


def np_dir_stats(z, h, p, H):
    """Return ``(sum z, count, sum h z, sum h)`` over ``0 < p < H``."""
    ic = (p > 0) & (p < H)
    zc, hc = z[ic], h[ic]
    return float(zc.sum()), int(ic.sum()), float(np.dot(hc, zc)), float(hc.sum())


def np_dir_update(z, p, t, zbar, beta, H):
    """``t = (z - zbar) + beta t`` on ``0 < p < H``, 0 elsewhere."""
    ic = (p > 0) & (p < H)
    t *= beta
    t[ic] += z[ic] - zbar
    t[~ic] = 0.0


def np_step_dots(r, t, h, p, H):
    """Return ``(sum r, sum t, sum r t, sum h t, count)`` over ``0 < p < H``."""
    ic = (p > 0) & (p < H)
    rc, tc = r[ic], t[ic]
    return float(rc.sum()), float(tc.sum()), float(np.dot(rc, tc)), float(np.dot(h[ic], tc)), int(ic.sum())


def np_update(p, t, h, tau, seed, pnew, H):
    """``pnew = clip(p - tau t, 0, H)``; cells with ``pnew == 0`` and ``h < 0`` get
    ``min(-seed h, H)`` (enter the contact). (Plastic cells leave the plastic set in the solver,
    between CG cycles.)

    Return ``(entered, sum pnew, modified)``: ``entered`` if any cell entered the contact,
    ``modified`` if ``pnew != p - tau t`` anywhere (a cell clipped or entered)."""
    np.subtract(p, tau * t, out=pnew)
    clipped = bool((pnew < 0.0).any()) or bool((pnew > H).any())
    np.maximum(pnew, 0.0, out=pnew)
    np.minimum(pnew, H, out=pnew)
    iol = (pnew == 0.0) & (h < 0.0)
    entered = bool(iol.any())
    if entered:
        pnew[iol] = np.minimum(-seed * h[iol], H)
    return entered, float(pnew.sum()), entered or clipped


def np_release(p, h, H, Hm, ny):
    """Plastic cells (``p >= H``) with ``h > 0`` get ``Hm`` (the largest float below ``H``): they
    rejoin the free set. Return ``(released, count, sum h^2, i0, i1, j0, j1)`` over the new free
    set ``0 < p < H`` (bounds as :func:`np_gap_stats`)."""
    rel = (p >= H) & (h > 0.0)
    p[rel] = Hm
    ic = (p > 0) & (p < H)
    n = int(ic.sum())
    if n == 0:
        return int(rel.sum()), 0, 0.0, -1, -1, -1, -1
    ic2 = ic.reshape(-1, ny)
    rows = np.flatnonzero(ic2.any(axis=1))
    cols = np.flatnonzero(ic2.any(axis=0))
    hc = h[ic]
    return (int(rel.sum()), n, float(np.dot(hc, hc)), int(rows[0]), int(rows[-1]), int(cols[0]),
            int(cols[-1]))


def np_axpy_scale(u, r, tau, s):
    """``u = s (u - tau r)`` in place."""
    u -= tau * r
    u *= s


def np_rescale(pnew, p, s):
    """``pnew *= s``; return ``sum |pnew - p|``."""
    pnew *= s
    return float(np.abs(pnew - p).sum())


def np_free_block(h, p, H, i0, j0, out):
    """The preconditioner's input (2-D arrays): ``out = h`` on the free set ``0 < p < H`` of the
    block of ``out``'s shape at ``(i0, j0)``, 0 elsewhere in it."""
    mx, my = out.shape
    pb = p[i0:i0 + mx, j0:j0 + my]
    out[...] = np.where((pb > 0) & (pb < H), h[i0:i0 + mx, j0:j0 + my], 0.0)


def np_place_block(z, zb, p, H, i0, j0, prev):
    """The preconditioner's output (2-D arrays): zero the block ``prev = (i0, j0, mx, my)`` of
    ``z`` (the last one written; ``mx = 0``: none), then ``z = zb`` on the free set
    ``0 < p < H`` of the block of ``zb``'s shape at ``(i0, j0)``, 0 elsewhere in it."""
    z[prev[0]:prev[0] + prev[2], prev[1]:prev[1] + prev[3]] = 0.0
    mx, my = zb.shape
    pb = p[i0:i0 + mx, j0:j0 + my]
    z[i0:i0 + mx, j0:j0 + my] = np.where((pb > 0) & (pb < H), zb, 0.0)


HAVE_NUMBA = False
NUMPY = dict(
    gap_stats=np_gap_stats, gap_eval=np_gap_eval, dir_stats=np_dir_stats, dir_update=np_dir_update,
    step_dots=np_step_dots, update=np_update, rescale=np_rescale, axpy_scale=np_axpy_scale,
    release=np_release, free_block=np_free_block, place_block=np_place_block,
)
KERNELS = NUMPY

if os.environ.get("BEARING_ENVELOPE_NO_NUMBA", "") not in ("1", "true", "yes"):
    try:
        import numba
    except Exception:  # pragma: no cover - numba is a dependency, but stay usable without it
        numba = None
    if numba is not None:
        _jit = numba.njit(cache=True, nogil=True, fastmath=False)

        @_jit
        def nb_gap_stats(gz, u, p, ny, H):  # pragma: no cover - compiled
            s = 0.0
            n = 0
            umax = -math.inf
            nx = p.size // ny
            i0 = nx
            i1 = -1
            j0 = ny
            j1 = -1
            for ii in range(nx):
                base = ii * ny
                for jj in range(ny):
                    k = base + jj
                    uk = u[k]
                    if uk > umax:
                        umax = uk
                    if p[k] > 0.0 and p[k] < H:
                        s += gz[k] + uk
                        n += 1
                        if ii < i0:
                            i0 = ii
                        i1 = ii
                        if jj < j0:
                            j0 = jj
                        if jj > j1:
                            j1 = jj
            if n == 0:
                return s, n, umax, -1, -1, -1, -1
            return s, n, umax, i0, i1, j0, j1

        @_jit
        def nb_gap_eval(gz, u, p, mat, alpha, h, H):  # pragma: no cover - compiled
            err_in = 0.0
            err_out = 0.0
            err_sat = 0.0
            G = 0.0
            for i in range(p.size):
                if mat[i]:
                    hi = gz[i] + u[i] - alpha
                    h[i] = hi
                    if p[i] > 0.0 and p[i] < H:
                        a = abs(hi)
                        if a > err_in:
                            err_in = a
                        G += hi * hi
                    elif p[i] <= 0.0:
                        if -hi > err_out:
                            err_out = -hi
                    elif hi > err_sat:
                        err_sat = hi
                else:
                    h[i] = math.inf
            return err_in, err_out, G, err_sat

        @_jit
        def nb_dir_stats(z, h, p, H):  # pragma: no cover - compiled
            sz = 0.0
            shz = 0.0
            sh = 0.0
            n = 0
            for i in range(p.size):
                if p[i] > 0.0 and p[i] < H:
                    sz += z[i]
                    shz += h[i] * z[i]
                    sh += h[i]
                    n += 1
            return sz, n, shz, sh

        @_jit
        def nb_dir_update(z, p, t, zbar, beta, H):  # pragma: no cover - compiled
            for i in range(p.size):
                if p[i] > 0.0 and p[i] < H:
                    t[i] = (z[i] - zbar) + beta * t[i]
                else:
                    t[i] = 0.0

        @_jit
        def nb_step_dots(r, t, h, p, H):  # pragma: no cover - compiled
            sr = 0.0
            st = 0.0
            srt = 0.0
            sht = 0.0
            n = 0
            for i in range(p.size):
                if p[i] > 0.0 and p[i] < H:
                    ti = t[i]
                    sr += r[i]
                    st += ti
                    srt += r[i] * ti
                    sht += h[i] * ti
                    n += 1
            return sr, st, srt, sht, n

        @_jit
        def nb_update(p, t, h, tau, seed, pnew, H):  # pragma: no cover - compiled
            entered = False
            clipped = False
            s = 0.0
            for i in range(p.size):
                v = p[i] - tau * t[i]
                if v <= 0.0:
                    if v < 0.0:
                        clipped = True
                    v = 0.0
                    if h[i] < 0.0:
                        v = min(-seed * h[i], H)
                        entered = True
                elif v >= H:
                    if v > H:
                        clipped = True
                    v = H
                pnew[i] = v
                s += v
            return entered, s, entered or clipped

        @_jit
        def nb_release(p, h, H, Hm, ny):  # pragma: no cover - compiled
            nrel = 0
            n = 0
            G = 0.0
            nx = p.size // ny
            i0 = nx
            i1 = -1
            j0 = ny
            j1 = -1
            for ii in range(nx):
                base = ii * ny
                for jj in range(ny):
                    k = base + jj
                    if p[k] >= H and h[k] > 0.0:
                        p[k] = Hm
                        nrel += 1
                    if p[k] > 0.0 and p[k] < H:
                        n += 1
                        G += h[k] * h[k]
                        if ii < i0:
                            i0 = ii
                        i1 = ii
                        if jj < j0:
                            j0 = jj
                        if jj > j1:
                            j1 = jj
            if n == 0:
                return nrel, n, G, -1, -1, -1, -1
            return nrel, n, G, i0, i1, j0, j1

        @_jit
        def nb_axpy_scale(u, r, tau, s):  # pragma: no cover - compiled
            for i in range(u.size):
                u[i] = s * (u[i] - tau * r[i])

        @_jit
        def nb_rescale(pnew, p, s):  # pragma: no cover - compiled
            d = 0.0
            for i in range(p.size):
                v = pnew[i] * s
                pnew[i] = v
                d += abs(v - p[i])
            return d

        @_jit
        def nb_free_block(h, p, H, i0, j0, out):  # pragma: no cover - compiled
            mx, my = out.shape
            for i in range(mx):
                for j in range(my):
                    v = p[i0 + i, j0 + j]
                    out[i, j] = h[i0 + i, j0 + j] if (v > 0.0 and v < H) else 0.0

        @_jit
        def nb_place_block(z, zb, p, H, i0, j0, prev):  # pragma: no cover - compiled
            for i in range(prev[0], prev[0] + prev[2]):
                for j in range(prev[1], prev[1] + prev[3]):
                    z[i, j] = 0.0
            mx, my = zb.shape
            for i in range(mx):
                for j in range(my):
                    v = p[i0 + i, j0 + j]
                    z[i0 + i, j0 + j] = zb[i, j] if (v > 0.0 and v < H) else 0.0

        HAVE_NUMBA = True
        NUMBA = dict(
            gap_stats=nb_gap_stats, gap_eval=nb_gap_eval, dir_stats=nb_dir_stats, dir_update=nb_dir_update,
            step_dots=nb_step_dots, update=nb_update, rescale=nb_rescale, axpy_scale=nb_axpy_scale,
            release=nb_release, free_block=nb_free_block, place_block=nb_place_block,
        )
        KERNELS = NUMBA
