"""Dynamic lumped-parameter model of a rolling-element bearing (``docs/dynamics.md``).

Inner ring with the shaft and outer ring with the housing (x, y), every rolling element's
radial degree of freedom, a resonator for the sensor's structure; Hertz contacts with damping,
clearance, centrifugal force, element positions from the cage (with slip), and a defect contact
read from a force law ``F(x, delta)`` (:class:`~.params.DefectLaw`). Sawalhi & Randall 2008;
Petersen et al. 2015; Moazen-Ahmadi & Howard 2016.

- :mod:`.layout`: the state vector, the kernels' parameter vector, the record's columns;
- :mod:`.params`: :class:`~.params.DynamicParams`, the defect law, the step rule;
- :mod:`.kernels`: numba contact laws, right-hand side, RK4;
- :mod:`.model`: :func:`~.model.rhs` (``solve_ivp``), :func:`~.model.simulate_dynamics`.
"""

from .layout import StateLayout
from .model import DynamicResult, initial_state, linearised_frequencies_hz, rhs, simulate_dynamics
from .params import (DefectLaw, DynamicParams, ElementPit, contact_stiffness, element_pit_from_scene,
                     highest_frequency_hz, params_from_scene, quasi_static, slot_drop, slot_law,
                     step_size)

__all__ = ["StateLayout", "DynamicResult", "initial_state", "linearised_frequencies_hz", "rhs",
           "simulate_dynamics", "DefectLaw", "DynamicParams", "ElementPit", "element_pit_from_scene",
           "contact_stiffness",
           "highest_frequency_hz", "params_from_scene", "quasi_static", "slot_drop", "slot_law",
           "step_size"]
