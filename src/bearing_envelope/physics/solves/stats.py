"""Counters of contact solves: :class:`SolveStats`, whose :meth:`~SolveStats.solve` is the zoom
route's one call of :func:`~bearing_envelope.contact.solve_contact`."""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field
from typing import Callable

from ...contact import ContactConvergenceError, solve_contact
from ..nodefect_cache import NoDefectCache

__all__ = ["SolveStats"]


@dataclass
class SolveStats:
    """Counters of contact solves (for the benchmark and the case file)."""

    n_solves: int = 0
    n_iterations: int = 0
    solver_seconds: float = 0.0
    n_failed: int = 0
    failed_seconds: float = 0.0
    n_stall_guard: int = 0     # solves whose preconditioner the solver's stall guard dropped
    #: defect window solves on the contact's rows (:func:`window_solve`) whose contact reached
    #: beyond them and were solved again on the whole window
    n_rows_fallback: int = 0
    callback: Callable[[], None] | None = field(default=None, repr=False)
    #: Where the global no-defect solves are looked up and stored (None: always solved).
    cache: NoDefectCache | None = field(default=None, repr=False)

    def solve(self, *args, **kwargs):
        """:func:`solve_contact` with its cost counted, also when it raises (stalled solves
        that a caller retries are part of the cost: ``n_failed``, ``failed_seconds``).

        Parameters
        ----------
        *args, **kwargs
            Passed to :func:`~bearing_envelope.contact.solve_contact`.

        Returns
        -------
        ContactSolution
            The solve's result.
        """
        t0 = _time.perf_counter()
        try:
            sol = solve_contact(*args, **kwargs)
        except ContactConvergenceError as exc:
            dt = _time.perf_counter() - t0
            self.solver_seconds += dt
            self.failed_seconds += dt
            self.n_solves += 1
            self.n_failed += 1
            self.n_iterations += len(exc.residual_history)
            raise
        self.solver_seconds += _time.perf_counter() - t0
        self.n_solves += 1
        self.n_iterations += sol.iterations
        self.n_stall_guard += sol.preconditioner_dropped_at is not None
        if self.callback is not None:
            self.callback()
        return sol
