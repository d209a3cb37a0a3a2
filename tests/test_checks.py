"""The shared scalar checks (bearing_envelope/checks.py): what they accept and refuse."""

import math

import numpy as np
import pytest

from bearing_envelope.checks import check_number, check_positive


@pytest.mark.parametrize("value", [1, 2.5, np.float32(0.25), np.int64(3)])
def test_numbers_accepted_as_floats(value):
    out = check_positive(value, "x")
    assert isinstance(out, float) and out == float(value)
    assert check_number(-float(value), "x") == -float(value)


@pytest.mark.parametrize("value", [True, False, "1", "0.5", b"2", None, [1.0], "nan"])
def test_non_numbers_refused_naming_the_argument(value):
    for check in (check_number, check_positive):
        with pytest.raises(ValueError, match=r"^depth_um must be a number, got "):
            check(value, "depth_um")


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_non_finite_refused(value):
    with pytest.raises(ValueError, match="x must be finite"):
        check_number(value, "x")
    with pytest.raises(ValueError, match=r"x must be a finite number > 0"):
        check_positive(value, "x")


def test_range_of_check_positive():
    with pytest.raises(ValueError, match=r"x must be a finite number > 0, got 0"):
        check_positive(0, "x")
    assert check_positive(0, "x", allow_zero=True) == 0.0
    with pytest.raises(ValueError, match=r">= 0, got -1"):
        check_positive(-1, "x", allow_zero=True)
    assert check_positive(None, "x", allow_none=True) is None
