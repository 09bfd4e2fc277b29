"""The free lateral strain of homogeneous uniaxial tension is the root nearest to the reference
state, also when a fitted surface turns over far outside its data."""

import pytest

from rve_rod.errors import InputError
from rve_rod.surface.checks import _free_lateral_strain


@pytest.mark.parametrize(
    ("roots", "nearest"),
    [((0.02, -0.3), 0.02), ((-0.047, 0.26), -0.047), ((0.113, 0.4, -0.45), 0.113)],
)
def test_root_nearest_to_zero_is_found(roots, nearest):
    def lateral_stress(e):
        value = 1.0
        for root in roots:
            value *= e - root
        return value

    assert _free_lateral_strain(lateral_stress, 0.1) == pytest.approx(nearest, abs=1e-14)


def test_no_root_is_an_input_error_naming_the_strain():
    with pytest.raises(InputError, match=r"at strain 0.15 no lateral strain"):
        _free_lateral_strain(lambda e: 1.0 + e**2, 0.15)
