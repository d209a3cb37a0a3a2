"""Frictionless normal contact of two elastic half-spaces on a uniform grid.

- :func:`solve_contact`: Polonsky-Keer constrained conjugate gradient with exact force control
  (or displacement control), warm start, stated convergence criterion;
- :class:`ElasticHalfSpace`: influence coefficients of uniform rectangular patches (Love) and the
  non-periodic DC-FFT displacement, kernel spectrum cached per grid;
- :func:`composite_modulus`: ``E*`` from both bodies;
- :mod:`hertz`: closed-form Hertz solutions (test oracles, grid sizing);
- :data:`NUMPY_KERNELS`: the numpy reference of the solver's element-wise passes
  (``solve_contact(..., kernels=NUMPY_KERNELS)``; the default is their numba version,
  :data:`DEFAULT_KERNELS`, the numpy one when numba is unavailable).

Grid convention: ``[i, j]`` with axis 0 = x = rolling (``dx``), axis 1 = y = axial (``dy``);
SI units. See ``docs/contact.md``.
"""

from . import hertz
from ._kernels import KERNELS as DEFAULT_KERNELS
from ._kernels import NUMPY as NUMPY_KERNELS
from .halfspace import (
    ElasticHalfSpace,
    composite_modulus,
    get_halfspace,
    influence_coefficients,
    influence_coefficients_linear,
    kernel_spectrum,
)
from .solver import (
    ContactConvergenceError,
    ContactGridError,
    ContactGridWarning,
    ContactSolution,
    solve_contact,
)

__all__ = [
    "solve_contact",
    "ContactSolution",
    "ContactGridError",
    "ContactGridWarning",
    "ContactConvergenceError",
    "ElasticHalfSpace",
    "composite_modulus",
    "influence_coefficients",
    "influence_coefficients_linear",
    "get_halfspace",
    "kernel_spectrum",
    "hertz",
    "NUMPY_KERNELS",
    "DEFAULT_KERNELS",
]
