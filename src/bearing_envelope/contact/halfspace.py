"""Elastic half-space: influence coefficients and the non-periodic (DC-FFT) surface displacement.

Grid convention (docs/interfaces.md): arrays are indexed ``[i, j]``, axis 0 = ``x`` (rolling,
spacing ``dx``), axis 1 = ``y`` (axial, spacing ``dy``); cell ``[i, j]`` is the rectangle of
size ``dx x dy`` centred on its node. Surface displacement ``u`` (m) is the combined normal
displacement of both bodies, positive into the bodies, so it opens the gap: the deformed gap is
``g + u - approach``.
"""

from __future__ import annotations

import math
import os
from collections import OrderedDict
from threading import Lock, get_ident

import numpy as np
import scipy.fft as sfft

#: Pressure element of the influence coefficients when none is named: ``uniform`` (piecewise
#: constant over a cell, Love 1929).
DEFAULT_ELEMENT = "uniform"
#: FFT backend when none is named: ``auto`` (pyFFTW where installed and checked, else scipy).
DEFAULT_FFT_BACKEND = "auto"
#: Threads of one FFT when none is named (the sweep runs one case per core).
FFT_WORKERS = 1

__all__ = [
    "DEFAULT_ELEMENT",
    "DEFAULT_FFT_BACKEND",
    "FFT_WORKERS",
    "composite_modulus",
    "influence_coefficients",
    "influence_coefficients_linear",
    "kernel_spectrum",
    "subcell_displacement",
    "ElasticHalfSpace",
    "get_halfspace",
    "clear_kernel_cache",
    "checked_pocketfft",
    "HAVE_PYFFTW",
]

try:  # optional, faster FFTs; never required
    import pyfftw  # type: ignore

    HAVE_PYFFTW = True
except Exception:  # pragma: no cover - depends on the environment
    pyfftw = None
    HAVE_PYFFTW = False


def checked_pocketfft(module=None):
    """The pocketfft module behind :mod:`scipy.fft` (a private module of scipy), if its calls as
    made here give scipy.fft's numbers.

    Why call it directly: scipy.fft's backend dispatch and argument handling cost 5-10 us a
    call and a contact solve makes two convolutions (8 transforms) per iteration on small grids
    (a CWRU ball case: 47,000 transforms, 0.5-0.9 CPU s). A scipy whose private module moved or
    changed its signature falls back to the public functions, at import, instead of failing in
    a solve.

    Parameters
    ----------
    module : module-like, optional
        The candidate (default: ``scipy.fft._pocketfft.pypocketfft``, imported here).

    Returns
    -------
    module or None
        ``module`` when it imports and ``r2c``, ``c2c`` and ``c2r`` (positional arguments, as
        this module calls them) equal ``scipy.fft.rfft2``, ``fft`` and ``irfft2`` bit for bit
        on a small array; None otherwise (any exception included).
    """
    try:
        if module is None:
            from scipy.fft._pocketfft import pypocketfft as module
        x = np.arange(12.0).reshape(3, 4) ** 1.5
        a = module.r2c(x, (0, 1), True, 0, None, 1)
        b = module.c2c(a, (0,), True, 0, None, 1)
        c = module.c2r(a, (0, 1), 4, False, 0, None, 1)
        ok = (np.array_equal(a, sfft.rfft2(x)) and np.array_equal(b, sfft.fft(a, axis=0))
              and np.array_equal(c, sfft.irfft2(a, s=(3, 4), norm="forward")))
    except Exception:  # noqa: BLE001 - any failure of a private module means: do not use it
        return None
    return module if ok else None


#: The pocketfft module behind :mod:`scipy.fft` (None: absent, or not as this module calls it;
#: scipy.fft is used).
POCKETFFT = checked_pocketfft()


def composite_modulus(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """Composite (contact) modulus of two elastic bodies.

    Parameters
    ----------
    E1, E2 : float
        Young's moduli (Pa), > 0 (``math.inf`` allowed for a rigid body).
    nu1, nu2 : float
        Poisson's ratios, in (-1, 0.5].

    Returns
    -------
    float
        ``E*`` (Pa) with :math:`1/E^* = (1-\\nu_1^2)/E_1 + (1-\\nu_2^2)/E_2`.

    Examples
    --------
    >>> round(composite_modulus(210e9, 0.3, 210e9, 0.3) / 1e9, 2)
    115.38
    """
    for name, e in (("E1", E1), ("E2", E2)):
        if not (e > 0) or math.isnan(e):
            raise ValueError(f"{name} must be > 0 (Pa), got {e!r}")
    for name, nu in (("nu1", nu1), ("nu2", nu2)):
        if not (-1.0 < nu <= 0.5):
            raise ValueError(f"{name} must be in (-1, 0.5], got {nu!r}")
    c = (1.0 - nu1 * nu1) / E1 + (1.0 - nu2 * nu2) / E2
    if c <= 0:
        raise ValueError("both bodies rigid: composite modulus is infinite")
    return 1.0 / c


def _primitive(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``F(x, y) = x asinh(y/|x|) + y asinh(x/|y|)``: ``d^2F/dxdy = 1/sqrt(x^2 + y^2)`` up to terms
    in ``x`` or ``y`` alone (which cancel in the patch integral); ``F(0, .) = 0``."""
    ax, ay = np.abs(x), np.abs(y)
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = np.where(ax > 0.0, x * np.arcsinh(y / np.where(ax > 0.0, ax, 1.0)), 0.0)
        t2 = np.where(ay > 0.0, y * np.arcsinh(x / np.where(ay > 0.0, ay, 1.0)), 0.0)
    return t1 + t2


def influence_coefficients(x, y, dx: float, dy: float, e_star: float) -> np.ndarray:
    """Surface displacement at ``(x, y)`` under a unit uniform pressure on a ``dx x dy`` patch.

    Parameters
    ----------
    x, y : array_like
        Position relative to the patch centre (m).
    dx, dy : float
        Patch size (m).
    e_star : float
        Composite modulus (Pa).

    Returns
    -------
    ndarray
        Displacement per unit pressure (m/Pa).

    Notes
    -----
    Love (1929); Johnson (1985) eq. 3.25. With the point-load solution
    :math:`u = P/(\\pi E^* r)` integrated over the patch
    :math:`|\\xi| \\le a = dx/2`, :math:`|\\eta| \\le b = dy/2`:

    .. math::

        K(x, y) = \\frac{1}{\\pi E^*}\\left[F(x+a, y+b) - F(x+a, y-b)
                   - F(x-a, y+b) + F(x-a, y-b)\\right],

    :math:`F(s, t) = s\\,\\mathrm{asinh}(t/|s|) + t\\,\\mathrm{asinh}(s/|t|)`.
    At the centre of a square patch (``dx = dy = 2a``), :math:`K = 8a\\ln(1+\\sqrt2)/(\\pi E^*)`.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    a, b = 0.5 * dx, 0.5 * dy
    f = _primitive(x + a, y + b) - _primitive(x + a, y - b) - _primitive(x - a, y + b) + _primitive(x - a, y - b)
    return f / (math.pi * e_star)


def _phi4(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """4th primitive of ``1/r``: ``d^4 Phi / dx^2 dy^2 = 1/sqrt(x^2 + y^2)`` up to terms of degree
    <= 1 in ``x`` or in ``y`` (which vanish under the second differences below).

    ``Phi = x^2 y/2 asinh(y/|x|) + x y^2/2 asinh(x/|y|) - r^3/6``.
    """
    ax, ay = np.abs(x), np.abs(y)
    r = np.hypot(x, y)
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = np.where(ax > 0.0, 0.5 * x * x * y * np.arcsinh(y / np.where(ax > 0.0, ax, 1.0)), 0.0)
        t2 = np.where(ay > 0.0, 0.5 * x * y * y * np.arcsinh(x / np.where(ay > 0.0, ay, 1.0)), 0.0)
    return t1 + t2 - r**3 / 6.0


# Gauss-Legendre, 3 points on each half of a tent
def _tent_rule(h: float):
    """Nodes and weights of int_{-h}^{h} (1 - |s|/h) f(s) ds, 3 Gauss points per half."""
    xg, wg = np.polynomial.legendre.leggauss(3)
    s = 0.5 * h * (xg + 1.0)  # on [0, h]
    w = 0.5 * h * wg * (1.0 - s / h)
    return np.concatenate([-s, s]), np.concatenate([w, w])


_FAR = 16.0  # switch to quadrature beyond this many cells (cancellation in Phi grows as (r/h)^4)


def influence_coefficients_linear(x, y, dx: float, dy: float, e_star: float) -> np.ndarray:
    r"""Displacement at ``(x, y)`` under a unit pyramidal (bilinear hat) pressure element at 0.

    The element is ``(1 - |xi|/dx)(1 - |eta|/dy)`` on ``|xi| <= dx, |eta| <= dy`` (total load
    ``dx dy``, like a uniform cell); a nodal field ``p_ij`` then describes the piecewise-bilinear
    pressure interpolating the nodes.

    Parameters
    ----------
    x, y : array_like
        Offsets from the element's node (m), broadcast together.
    dx, dy : float
        Node spacing (m): the element's half-widths.
    e_star : float
        Composite modulus ``E*`` (Pa).

    Returns
    -------
    numpy.ndarray
        Displacement (m) per unit nodal pressure (Pa), of the broadcast shape of ``x`` and ``y``.

    Notes
    -----
    Exact integration of the point-load solution against the tent functions: with the tent
    ``T(s) = (1 - |s|/h)^+``, ``int T(s) f(x - s) ds = [F2(x+h) - 2F2(x) + F2(x-h)]/h`` where
    ``F2'' = f``. In two dimensions

    .. math::

        K_{lin}(x, y) = \frac{1}{\pi E^*\,dx\,dy}\,\Delta^2_{x}\Delta^2_{y}\,\Phi(x, y),\quad
        \Phi = \frac{x^2 y}{2}\,\mathrm{asinh}\frac{y}{|x|} + \frac{x y^2}{2}\,\mathrm{asinh}\frac{x}{|y|}
                - \frac{r^3}{6},

    with ``Delta^2`` the central second difference of step ``dx`` (``dy``) and
    :math:`\partial^4\Phi/\partial x^2\partial y^2 = 1/r`. Beyond 16 cells, where the
    differences of ``Phi ~ r^3`` lose digits, the same integral is done by Gauss-Legendre
    quadrature (3 points per tent half, relative error < 1e-10 there).
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    x, y = np.broadcast_arrays(x, y)
    out = np.empty(x.shape)
    far = np.hypot(x / dx, y / dy) > _FAR
    near = ~far
    if near.any():
        xn, yn = x[near], y[near]
        acc = np.zeros(xn.shape)
        for cx, sx in ((1.0, dx), (-2.0, 0.0), (1.0, -dx)):
            for cy, sy in ((1.0, dy), (-2.0, 0.0), (1.0, -dy)):
                acc += (cx * cy) * _phi4(xn + sx, yn + sy)
        out[near] = acc / (dx * dy)
    if far.any():
        xf, yf = x[far], y[far]
        sx, wx = _tent_rule(dx)
        sy, wy = _tent_rule(dy)
        acc = np.zeros(xf.shape)
        for a, wa in zip(sx, wx):
            for b, wb in zip(sy, wy):
                acc += (wa * wb) / np.hypot(xf - a, yf - b)
        out[far] = acc
    return out / (math.pi * e_star)


def _padded_kernel(shape: tuple[int, int], dx: float, dy: float, e_star: float,
                   element: str = DEFAULT_ELEMENT) -> np.ndarray:
    """Influence coefficients on the ``(2nx, 2ny)`` wrap-around grid used by DC-FFT."""
    nx, ny = shape
    if element == "uniform":
        return _padded_uniform_kernel(nx, ny, dx, dy, e_star)
    ix = np.arange(2 * nx)
    iy = np.arange(2 * ny)
    ix = np.where(ix <= nx, ix, ix - 2 * nx)  # offsets 0..nx, -(nx-1)..-1
    iy = np.where(iy <= ny, iy, iy - 2 * ny)
    return influence_coefficients_linear(ix[:, None] * dx, iy[None, :] * dy, dx, dy, e_star)


def _padded_uniform_kernel(nx: int, ny: int, dx: float, dy: float, e_star: float) -> np.ndarray:
    """:func:`influence_coefficients` on the ``(2nx, 2ny)`` wrap-around grid (offsets ``0..nx``,
    ``-(nx-1)..-1`` cells), its primitives evaluated on the non-negative offsets only.

    ``F`` is odd in each argument to the bit (``asinh`` is, and ``fl(-u + a) = -fl(u - a)``), so
    ``F`` at a negative offset's corner is minus ``F`` at the mirrored corner of the quadrant:
    a quarter of the ``asinh`` calls, combined in :func:`influence_coefficients`' order, the
    same numbers (tests/contact/test_halfspace_fft.py)."""
    a, b = 0.5 * dx, 0.5 * dy
    u = np.arange(nx + 1) * dx
    v = np.arange(ny + 1) * dy
    xs = {1: (u + a)[:, None], -1: (u - a)[:, None]}
    ys = {1: (v + b)[None, :], -1: (v - b)[None, :]}
    g = {(sx, sy): _primitive(xs[sx], ys[sy]) for sx in (1, -1) for sy in (1, -1)}

    def corner(sx, sy):
        """``F(x + sx a, y + sy b)`` on the wrap-around grid."""
        out = np.empty((2 * nx, 2 * ny))
        out[:nx + 1, :ny + 1] = g[sx, sy]
        out[nx + 1:, :ny + 1] = -g[-sx, sy][nx - 1:0:-1]
        out[:nx + 1, ny + 1:] = -g[sx, -sy][:, ny - 1:0:-1]
        out[nx + 1:, ny + 1:] = g[-sx, -sy][nx - 1:0:-1, ny - 1:0:-1]
        return out

    f = corner(1, 1) - corner(1, -1) - corner(-1, 1) + corner(-1, -1)
    return f / (math.pi * e_star)


_PYFFTW_MEASURE_CELLS = 512 * 256
ELEMENTS = ("uniform", "linear")

_CACHE: "OrderedDict[tuple, np.ndarray]" = OrderedDict()
_CACHE_LOCK = Lock()
#: Spectra kept (LRU) and their total size: a rolling-element case cycles through about 30
#: grids (two contacts' global grids, windows, rim strips and their refined neighbourhoods);
#: with 8 entries a third of its spectra were computed again (0.4 CPU s).
KERNEL_CACHE_ENTRIES = 32
KERNEL_CACHE_BYTES = 64 * 2 ** 20


def kernel_spectrum(shape: tuple[int, int], dx: float, dy: float, e_star: float,
                    element: str = DEFAULT_ELEMENT) -> np.ndarray:
    """Real spectrum (``rfft2`` of the ``(2nx, 2ny)`` padded kernel, divided by ``4 nx ny``), cached.

    The kernel is even in both offsets, so its spectrum is real; it is stored as float64 of shape
    ``(2nx, ny + 1)`` and already carries the inverse-FFT normalisation. A small LRU cache
    (32 entries, at most 64 MiB) keyed by ``(shape, dx, dy, e_star, element)`` keeps it across solves.

    Parameters
    ----------
    shape : tuple of int
        Grid shape ``(nx, ny)``.
    dx, dy : float
        Cell size (m).
    e_star : float
        Composite modulus ``E*`` (Pa).
    element : {"uniform", "linear"}
        Pressure element: uniform cells or pyramidal (bilinear) elements.

    Returns
    -------
    numpy.ndarray
        Read-only float64 array of shape ``(2 nx, ny + 1)``.
    """
    if element not in ELEMENTS:
        raise ValueError(f"element must be one of {ELEMENTS}, got {element!r}")
    key = (tuple(int(s) for s in shape), float(dx), float(dy), float(e_star), element)

    def compute():
        k = _padded_kernel(key[0], key[1], key[2], key[3], element)
        # threads as the solves (OMP_NUM_THREADS: a Snakemake job its declared `threads`)
        return sfft.rfft2(k, workers=_default_workers()).real / (k.shape[0] * k.shape[1])

    return _cached_spectrum(key, compute)


def _cached_spectrum(key: tuple, compute) -> np.ndarray:
    """The LRU cache of :func:`kernel_spectrum` (bounded by :data:`KERNEL_CACHE_ENTRIES`
    entries and :data:`KERNEL_CACHE_BYTES`): ``key``'s array, ``compute()`` on a miss."""
    with _CACHE_LOCK:
        if key in _CACHE:
            _CACHE.move_to_end(key)
            return _CACHE[key]
    spec = compute()
    spec.setflags(write=False)
    with _CACHE_LOCK:
        _CACHE[key] = spec
        _CACHE.move_to_end(key)
        while len(_CACHE) > 1 and (len(_CACHE) > KERNEL_CACHE_ENTRIES or
                                   sum(v.nbytes for v in _CACHE.values()) > KERNEL_CACHE_BYTES):
            _CACHE.popitem(last=False)
    return spec


def _subcell_spectra(shape: tuple[int, int], dx: float, dy: float, e_star: float,
                     m: int) -> np.ndarray:
    """Spectra (``m``, ``2nx``, ``ny + 1``) of the displacement at the centres of the ``m``
    sub-rows of a cell (offsets ``(t + 1/2 - m/2) dx/m`` from its centre) under unit pressure
    on a whole ``dx x dy`` cell, on the DC-FFT wrap-around grid, with the inverse's 1/N."""
    nx, ny = shape

    def compute():
        ix = np.arange(2 * nx)
        iy = np.arange(2 * ny)
        ix = np.where(ix <= nx, ix, ix - 2 * nx)
        iy = np.where(iy <= ny, iy, iy - 2 * ny)
        out = np.empty((m, 2 * nx, ny + 1), dtype=complex)
        for t in range(m):
            k = influence_coefficients(ix[:, None] * dx + (t + 0.5 - 0.5 * m) * dx / m,
                                       iy[None, :] * dy, dx, dy, e_star)
            out[t] = sfft.rfft2(k, workers=1) / (4 * nx * ny)
        return out

    return _cached_spectrum(("subcell", (int(nx), int(ny)), float(dx), float(dy),
                             float(e_star), int(m)), compute)


def subcell_displacement(pressure: np.ndarray, dx: float, dy: float, e_star: float, m: int,
                         rows: tuple[int, int] | None = None) -> np.ndarray:
    """Surface displacement (m) at the centres of the ``m`` sub-rows of every cell, under a
    pressure uniform on each ``dx x dy`` cell: what :class:`ElasticHalfSpace` gives on the grid
    refined ``m`` times along ``x`` (spacing ``dx/m``) for the pressure repeated on each cell's
    sub-rows, with ``m`` convolutions on the coarse grid (a cell is the union of its sub-cells:
    the influence of the whole cell at each sub-row's offset) instead of one ``m`` times larger.

    Parameters
    ----------
    pressure : numpy.ndarray
        Pressure (Pa) on the coarse grid, shape ``(nx, ny)``, finite.
    dx, dy : float
        Coarse cell size (m).
    e_star : float
        Composite modulus (Pa).
    m : int
        Sub-rows per cell (>= 1).
    rows : tuple of int, optional
        Coarse rows ``[r0, r1)`` whose sub-rows are returned (default: every row).

    Returns
    -------
    numpy.ndarray
        Displacement (m), shape ``(m (r1 - r0), ny)``: sub-row ``t`` of coarse row ``i`` at
        ``m (i - r0) + t``.
    """
    p = np.asarray(pressure, dtype=float)
    nx, ny = p.shape
    r0, r1 = (0, nx) if rows is None else (int(rows[0]), int(rows[1]))
    spec = _subcell_spectra((nx, ny), float(dx), float(dy), float(e_star), int(m))
    buf = np.zeros((2 * nx, ny + 1), dtype=complex)
    buf[:nx] = sfft.rfft(p, n=2 * ny, axis=1, workers=1)
    a = sfft.fft(buf, axis=0, workers=1, overwrite_x=True)
    out = np.empty(((r1 - r0) * m, ny))
    for t in range(m):
        b = sfft.ifft(a * spec[t], axis=0, workers=1, overwrite_x=True, norm="forward")
        out[t::m] = sfft.irfft(b[r0:r1], n=2 * ny, axis=1, workers=1, norm="forward")[:, :ny]
    return out


def rfft2(x: np.ndarray, workers: int = FFT_WORKERS) -> np.ndarray:
    """``scipy.fft.rfft2(x, workers=workers)`` (unnormalised), by pocketfft directly when it is
    importable (the same numbers, without scipy.fft's per-call dispatch).

    Parameters
    ----------
    x : numpy.ndarray
        Real 2-D array (float64, C-contiguous).
    workers : int
        FFT threads.

    Returns
    -------
    numpy.ndarray
        The half spectrum, shape ``(nx, ny // 2 + 1)``.
    """
    if POCKETFFT is None:
        return sfft.rfft2(x, workers=workers)
    return POCKETFFT.r2c(x, (0, 1), True, 0, None, workers)


def irfft2(a: np.ndarray, shape: tuple[int, int], workers: int = FFT_WORKERS) -> np.ndarray:
    """``scipy.fft.irfft2(a, s=shape, norm="forward", workers=workers)`` (no ``1/n`` on the
    inverse), by pocketfft directly when it is importable.

    Parameters
    ----------
    a : numpy.ndarray
        Half spectrum, shape ``(shape[0], shape[1] // 2 + 1)``, complex128.
    shape : (int, int)
        The real output's shape.
    workers : int
        FFT threads.

    Returns
    -------
    numpy.ndarray
        Real array of ``shape``.
    """
    if POCKETFFT is None:
        return sfft.irfft2(a, s=shape, norm="forward", workers=workers)
    return POCKETFFT.c2r(a, (0, 1), int(shape[1]), False, 0, None, workers)


def clear_kernel_cache() -> None:
    """Empty the cache of :func:`kernel_spectrum` (a benchmark times a solve from cold).

    Returns
    -------
    None
    """
    with _CACHE_LOCK:
        _CACHE.clear()


def _default_workers() -> int:
    env = os.environ.get("OMP_NUM_THREADS")
    if env and env.isdigit() and int(env) > 0:
        return int(env)
    return os.cpu_count() or 1


class ElasticHalfSpace:
    """Linear elastic half-space on a uniform grid with non-periodic (DC-FFT) convolution.

    Parameters
    ----------
    shape : (int, int)
        ``(nx, ny)`` of the pressure grid.
    dx, dy : float
        Grid spacing (m) along ``x`` (axis 0) and ``y`` (axis 1).
    e_star : float
        Composite modulus (Pa).
    workers : int, optional
        FFT threads (default: ``OMP_NUM_THREADS`` if set, else all cores).
    backend : {"auto", "scipy", "pyfftw"}
        ``"auto"`` uses pyfftw when importable (FFTW_MEASURE plans from 512 x 256 cells up,
        FFTW_ESTIMATE below), else :mod:`scipy.fft` (pocketfft). Both reuse their work arrays:
        fresh multi-MB arrays per call cost page faults that doubled the in-solver convolution
        time at 256^2.
    element : {"uniform", "linear"}
        Pressure element: uniform over each ``dx x dy`` cell (:func:`influence_coefficients`)
        or piecewise bilinear between nodes (pyramidal elements,
        :func:`influence_coefficients_linear`).

    Notes
    -----
    ``u = K * p`` (discrete linear convolution of the influence coefficients
    :func:`influence_coefficients` with the pressure) computed by DC-FFT: zero-pad to
    ``(2nx, 2ny)``, multiply the spectra, keep the first ``(nx, ny)`` block; exact (no periodic
    images). Because the pressure only fills one quadrant of the padded array, the transforms
    skip the all-zero half: the forward transform does the ``y`` pass (rfft of length ``2ny``)
    on the ``nx`` data rows only, and the inverse does the final ``y`` pass only on the ``nx``
    rows that are kept.
    """

    def __init__(
        self, shape, dx: float, dy: float, e_star: float, *, workers: int | None = None,
        backend: str = DEFAULT_FFT_BACKEND, element: str = DEFAULT_ELEMENT,
    ):
        if len(shape) != 2 or min(shape) < 1:
            raise ValueError(f"shape must be (nx, ny) with nx, ny >= 1, got {shape!r}")
        for name, v in (("dx", dx), ("dy", dy), ("e_star", e_star)):
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
        self.shape = (int(shape[0]), int(shape[1]))
        self.dx, self.dy, self.e_star = float(dx), float(dy), float(e_star)
        self.workers = int(workers) if workers else _default_workers()
        if backend not in ("auto", "scipy", "pyfftw"):
            raise ValueError(f"backend must be 'auto', 'scipy' or 'pyfftw', got {backend!r}")
        if backend == "pyfftw" and not HAVE_PYFFTW:
            raise ValueError("backend='pyfftw' but pyfftw is not importable")
        if backend == "auto":
            backend = "pyfftw" if HAVE_PYFFTW else "scipy"
        self.backend = backend
        self.element = element
        self.spectrum = kernel_spectrum(self.shape, self.dx, self.dy, self.e_star, element)
        fn = influence_coefficients if element == "uniform" else influence_coefficients_linear
        self.k0 = float(fn(0.0, 0.0, self.dx, self.dy, self.e_star))  # self-influence (m/Pa)
        self._plans = None
        self._buf = None
        self._real_in = None
        self._spectrum_ri = None

    # -- FFT backends -------------------------------------------------------------------------
    def _build_fftw(self):
        nx, ny = self.shape
        # FFTW_MEASURE planning (~0.1-1 s per grid) pays off only on large grids
        fl = ("FFTW_MEASURE",) if nx * ny >= _PYFFTW_MEASURE_CELLS else ("FFTW_ESTIMATE",)
        real_in = pyfftw.zeros_aligned((nx, 2 * ny), dtype="float64")
        half = pyfftw.zeros_aligned((2 * nx, ny + 1), dtype="complex128")
        full = pyfftw.zeros_aligned((2 * nx, ny + 1), dtype="complex128")
        real_out = pyfftw.zeros_aligned((nx, 2 * ny), dtype="float64")
        t = self.workers
        f_y = pyfftw.FFTW(real_in, half[:nx], axes=(1,), direction="FFTW_FORWARD", flags=fl, threads=t)
        f_x = pyfftw.FFTW(half, full, axes=(0,), direction="FFTW_FORWARD", flags=fl, threads=t)
        b_x = pyfftw.FFTW(full, half, axes=(0,), direction="FFTW_BACKWARD", flags=fl, threads=t)
        b_y = pyfftw.FFTW(half[:nx], real_out, axes=(1,), direction="FFTW_BACKWARD", flags=fl, threads=t)
        half[:] = 0
        real_in[:] = 0
        self._plans = (real_in, half, full, real_out, f_y, f_x, b_x, b_y)

    def displacement(self, pressure: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """Surface displacement ``u = K * p`` (m) for a pressure field (Pa) of shape ``(nx, ny)``.

        Non-finite pressure is not allowed; the result is a new array unless ``out`` is given.

        Parameters
        ----------
        pressure : numpy.ndarray
            Pressure (Pa) on the operator's grid, shape ``(nx, ny)``, finite.
        out : numpy.ndarray, optional
            Array of shape ``(nx, ny)`` to write the result into.

        Returns
        -------
        numpy.ndarray
            Surface displacement (m), shape ``(nx, ny)`` (``out`` when given).
        """
        p = np.asarray(pressure, dtype=float)
        if p.shape != self.shape:
            raise ValueError(f"pressure.shape must be {self.shape}, got {p.shape}")
        nx, ny = self.shape
        if self.backend == "pyfftw":
            if self._plans is None:
                self._build_fftw()
            real_in, half, full, real_out, f_y, f_x, b_x, b_y = self._plans
            real_in[:, :ny] = p
            f_y.execute()  # rows nx.. of `half` stay zero
            f_x.execute()
            np.multiply(full, self.spectrum, out=full)
            b_x.execute()  # overwrites all of half; re-zero the padding rows after b_y
            b_y.execute()
            half[nx:] = 0
            res = real_out[:, :ny]
        elif POCKETFFT is not None:
            res = self._displacement_pocketfft(p)
        else:
            w = self.workers
            buf = self._buf
            if buf is None:
                buf = self._buf = np.zeros((2 * nx, ny + 1), dtype=complex)
            buf[:nx] = sfft.rfft(p, n=2 * ny, axis=1, workers=w)
            buf[nx:] = 0.0
            a = sfft.fft(buf, axis=0, workers=w, overwrite_x=True)
            a *= self.spectrum
            a = sfft.ifft(a, axis=0, workers=w, overwrite_x=True, norm="forward")
            res = sfft.irfft(a[:nx], n=2 * ny, axis=1, workers=w, norm="forward")[:, :ny]
        if out is None:
            return np.array(res)
        out[...] = res
        return out

    def _displacement_pocketfft(self, p: np.ndarray) -> np.ndarray:
        """The scipy backend's transforms (``rfft`` of length ``2 ny`` along ``y``, ``fft`` and
        ``ifft`` along ``x``, ``irfft``; normalised on the inverse) by pocketfft directly, into
        reused arrays: ``rows nx..`` of the half-spectrum and columns ``ny..`` of the padded
        input stay zero between calls. The (real) kernel spectrum scales the real and imaginary
        parts as floats (each value stored twice): the products of ``a *= spectrum`` without
        its per-element cast to complex. Returns a view of the first ``(nx, ny)`` block."""
        nx, ny = self.shape
        w = self.workers
        if self._real_in is None:
            self._real_in = np.zeros((nx, 2 * ny))
            self._buf = np.zeros((2 * nx, ny + 1), dtype=complex)
            self._spectrum_ri = np.repeat(self.spectrum, 2, axis=1)
        real_in, buf = self._real_in, self._buf
        real_in[:, :ny] = p
        POCKETFFT.r2c(real_in, (1,), True, 0, buf[:nx], w)
        a = POCKETFFT.c2c(buf, (0,), True, 0, None, w)
        af = a.view(np.float64)                  # kernel_spectrum is real (float64)
        np.multiply(af, self._spectrum_ri, out=af)
        POCKETFFT.c2c(a, (0,), False, 0, a, w)
        return POCKETFFT.c2r(a[:nx], (1,), 2 * ny, False, 0, None, w)[:, :ny]

    def __repr__(self) -> str:
        return (
            f"ElasticHalfSpace(shape={self.shape}, dx={self.dx!r}, dy={self.dy!r}, e_star={self.e_star!r}, "
            f"backend={self.backend!r}, element={self.element!r})"
        )


_OPS: "OrderedDict[tuple, ElasticHalfSpace]" = OrderedDict()


def get_halfspace(
    shape, dx: float, dy: float, e_star: float, *, workers: int | None = None,
    backend: str = DEFAULT_FFT_BACKEND, element: str = DEFAULT_ELEMENT,
) -> ElasticHalfSpace:
    """Return a cached :class:`ElasticHalfSpace` (with its FFT plans and buffers) for this grid.

    Small LRU (4 operators); the same object is returned for the same arguments in the same
    thread (operators hold work arrays, so each thread gets its own; the kernel spectrum itself
    is shared).

    Parameters
    ----------
    shape : tuple of int
        Grid shape ``(nx, ny)``.
    dx, dy : float
        Cell size (m).
    e_star : float
        Composite modulus ``E*`` (Pa).
    workers : int, optional
        FFT threads (default: ``OMP_NUM_THREADS``, else every core).
    backend : {"auto", "scipy", "pyfftw"}
        FFT library (``auto``: pyfftw where installed).
    element : {"uniform", "linear"}
        Pressure element.

    Returns
    -------
    ElasticHalfSpace
        The operator ``p -> u`` of this grid.
    """
    w = int(workers) if workers else _default_workers()
    key = (tuple(int(s) for s in shape), float(dx), float(dy), float(e_star), w, backend, element, get_ident())
    with _CACHE_LOCK:
        op = _OPS.get(key)
        if op is not None:
            _OPS.move_to_end(key)
            return op
    op = ElasticHalfSpace(shape, dx, dy, e_star, workers=w, backend=backend, element=element)
    with _CACHE_LOCK:
        _OPS[key] = op
        while len(_OPS) > 4:
            _OPS.popitem(last=False)
    return op
