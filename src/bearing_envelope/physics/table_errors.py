"""The errors of a contact table's interpolation checks: relative errors that are never NaN
(:func:`relative_error`) and the summary of a table's check rows
(:func:`interpolation_check_errors`, the rows' columns :data:`CHECK_COLUMNS`); read by
:mod:`.table` when it builds a table."""

from __future__ import annotations

import numpy as np

__all__ = ["CHECK_COLUMNS", "relative_error", "interpolation_check_errors"]


#: Columns of one interpolation check row (:func:`interpolation_check_errors`): roller load
#: (N), offset (m), solved P and P_d (Pa), their table readings (Pa), the no-defect P0 (Pa).
CHECK_COLUMNS = ("Q", "x", "P", "P_d", "P_interp", "P_d_interp", "P0")


def relative_error(diff: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """``|diff| / scale`` element-wise, never NaN.

    Parameters
    ----------
    diff : numpy.ndarray
        Differences (reading minus solved value), in the unit of ``scale``.
    scale : numpy.ndarray
        The reference magnitudes (>= 0; the unit of the values compared).

    Returns
    -------
    numpy.ndarray
        The relative errors; 0 where ``scale`` and ``diff`` are both 0 (an unloaded contact read
        as unloaded), ``inf`` where only ``scale`` is 0 (a reading where nothing was solved).
    """
    diff, scale = np.abs(np.asarray(diff, float)), np.asarray(scale, float)
    out = np.full(diff.shape, np.inf)
    np.divide(diff, scale, out=out, where=scale > 0)
    out[(scale <= 0) & (diff == 0)] = 0.0
    return out


def interpolation_check_errors(rows) -> tuple[np.ndarray, float, float, float]:
    """The errors of the table's interpolation checks.

    Parameters
    ----------
    rows : sequence of tuple
        Check rows with the columns :data:`CHECK_COLUMNS` (Q, x, P, P_d, their table readings,
        the no-defect P0).

    Returns
    -------
    tuple
        ``(rows as an (n, 7) array, max relative error of P, max error of P_d / P0, rms relative
        error of P)``, by :func:`relative_error` (0 where a solve and its reading are both 0, as
        in an unloaded contact; never NaN). No rows: zeros.
    """
    a = np.array(rows, dtype=float).reshape(-1, len(CHECK_COLUMNS))
    if not len(a):
        return a, 0.0, 0.0, 0.0
    e = relative_error(a[:, 4] - a[:, 2], a[:, 2])
    e_d = relative_error(a[:, 5] - a[:, 3], a[:, 6])
    return a, float(e.max()), float(e_d.max()), float(np.sqrt(np.mean(e ** 2)))
