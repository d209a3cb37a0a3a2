"""Contact solves of the zoom route: the global no-defect solve over the whole roller, the
local window solves with the defect, and the rim strips (see :mod:`bearing_envelope.physics.history`
for the model). Public entry points are used by :mod:`~bearing_envelope.physics.table` and
:mod:`~bearing_envelope.physics.pit`.

One concern per module:

- :mod:`.stats`: :class:`SolveStats`, the counted contact solve (the one call of
  :func:`~bearing_envelope.contact.solve_contact`);
- :mod:`.global_solve`: the global no-defect solve over the whole roller, its grid and the far
  field it leaves on the window; the window's size (:func:`window_spec`); solves without a window
  (:func:`outside_solve`, :func:`outside_max`);
- :mod:`.windows`: window solves on the contact's rows (:func:`contact_rows`, :func:`window_solve`)
  and the window's linear response to the far field (:func:`far_response`);
- :mod:`.load_node`: :class:`LoadNode`, the no-defect state at one roller load (:func:`solve_load`);
- :mod:`.defect`: the window solve with the defect (:func:`defect_solve`, :func:`far_uptake`);
- :mod:`.rims`: the refined rim and axial end strips (:class:`RimStrip`, :func:`end_intervals`,
  :func:`neighbourhood_max`).
"""

from .defect import DefectSolve, defect_solve, far_uptake
from .global_solve import GlobalGridError, global_solve, outside_max, outside_solve, window_spec
from .load_node import LoadNode, solve_load
from .rims import RimStrip, neighbourhood_max, end_intervals
from .stats import SolveStats
from .windows import contact_rows, far_response, fast_rows, window_solve

__all__ = ["SolveStats", "LoadNode", "DefectSolve", "RimStrip", "GlobalGridError",
           "global_solve", "solve_load", "outside_max", "outside_solve", "defect_solve",
           "neighbourhood_max", "window_spec", "far_uptake", "end_intervals", "contact_rows",
           "fast_rows", "window_solve", "far_response"]
