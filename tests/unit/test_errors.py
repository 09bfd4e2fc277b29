"""Input checks: accepted values pass through, refused ones name parameter, value and range."""

import numpy as np
import pytest

from rve_rod.errors import InputError, check_integer, check_positive, check_range


@pytest.mark.parametrize("value", [3, 3.0, np.int64(3), np.int32(3), np.float64(3.0)])
def test_check_integer_accepts_integral_numbers_of_any_type(value):
    assert check_integer("count", value, 1) == 3


@pytest.mark.parametrize("value", [2.5, float("nan"), float("inf"), True, "3", None])
def test_check_integer_refuses_non_integers(value):
    with pytest.raises(InputError, match=r"count=.* must be an integer"):
        check_integer("count", value, 1)


def test_messages_name_parameter_value_and_range():
    with pytest.raises(InputError, match=r"steps=0 is outside the valid range \[2, 50\]"):
        check_integer("steps", 0, 2, 50)
    with pytest.raises(InputError, match=r"yarn_radius=-0.1 mm must be > 0"):
        check_positive("yarn_radius", -0.1, "mm")
    with pytest.raises(InputError, match=r"nu=0.7 is outside the valid range \[0, 0.5\]"):
        check_range("nu", 0.7, 0.0, 0.5)
    with pytest.raises(InputError, match="must be a finite number"):
        check_positive("wale_width", float("nan"), "mm")
