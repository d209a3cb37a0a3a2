"""The table's interpolation-check errors are never NaN (an unloaded contact read as unloaded is
exact), and equal the hand-computed relative errors otherwise."""
import numpy as np

from bearing_envelope.physics.table import (CHECK_COLUMNS, interpolation_check_errors,
                                            relative_error)


def test_relative_error_known_values():
    got = relative_error(np.array([1.0, -2.0, 0.0, 3.0]), np.array([4.0, 8.0, 0.0, 0.0]))
    assert got[0] == 0.25 and got[1] == 0.25      # |diff| / scale
    assert got[2] == 0.0                          # 0 read where 0 was solved: exact
    assert np.isinf(got[3])                       # a reading where nothing was solved


def test_unloaded_check_row_is_exact_not_nan():
    # Q, x, P, P_d, P_interp, P_d_interp, P0: one loaded row (P read 2 % high, P_d 0.1 P0 off),
    # one row of a contact too light to carry the pit's rim (everything 0)
    rows = [(100.0, 1e-5, 1.0e9, 2.0e8, 1.02e9, 1.5e8, 5.0e8),
            (0.2, 2e-5, 0.0, 0.0, 0.0, 0.0, 0.0)]
    a, e_max, e_d_max, e_rms = interpolation_check_errors(rows)
    assert a.shape == (2, len(CHECK_COLUMNS))
    assert np.isclose(e_max, 0.02) and np.isclose(e_d_max, 0.1)
    assert np.isclose(e_rms, np.sqrt((0.02 ** 2 + 0.0) / 2))
    assert np.all(np.isfinite([e_max, e_d_max, e_rms]))


def test_no_rows():
    a, *errs = interpolation_check_errors([])
    assert a.shape == (0, len(CHECK_COLUMNS)) and errs == [0.0, 0.0, 0.0]
