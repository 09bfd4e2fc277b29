"""The family of surfaces in NumPy: the graded law's weights, its members, its geometry."""

import numpy as np
import pytest
from support.design_cases import STITCHES, synthetic_family

from fabric_dolfinx.graded import stitch_weights
from rve_rod.errors import InputError


@pytest.fixture(scope="module")
def family():
    return synthetic_family()


def test_weights_at_many_points_are_those_of_each_point_and_constant_beyond_the_ends():
    """The membrane weights all its quadrature points at once: (n, m) for m stitch values."""
    stitches = np.array([4.0, 4.5, 4.8, 5.0, 5.25, 6.0, 6.99, 7.0, 7.5])
    weights = stitch_weights(STITCHES, stitches)
    assert weights.shape == (len(STITCHES), stitches.size)
    for column, stitch in enumerate(stitches):
        np.testing.assert_array_equal(weights[:, column], stitch_weights(STITCHES, stitch))
    np.testing.assert_array_equal(weights[:, [0, -1]].T, np.eye(6)[[0, -1]])


def test_weights_are_a_partition_of_unity_and_hats():
    for stitch in np.linspace(4.0, 7.5, 36):
        weights = stitch_weights(STITCHES, stitch)
        assert weights.sum() == pytest.approx(1.0, abs=1e-14)
        assert np.count_nonzero(weights) <= 2
    np.testing.assert_array_equal(stitch_weights(STITCHES, 5.5), np.eye(6)[2])
    np.testing.assert_allclose(stitch_weights(STITCHES, 5.6), [0, 0, 0.8, 0.2, 0, 0], atol=1e-14)
    with pytest.raises(InputError, match="increasing"):
        stitch_weights([5.0, 4.5], 4.8)


def test_the_law_at_a_member_is_that_member_and_linear_between(family):
    E = np.array([[0.1, 0.02, 0.01], [0.2, -0.03, 0.05]])
    member = family.surfaces[3].stress(E)
    at = family.law(6.0).stress(E)
    np.testing.assert_array_equal(at.S, member.S)
    np.testing.assert_array_equal(at.tangent, member.tangent)
    between = family.law(6.2).stress(E).S
    expected = 0.6 * member.S + 0.4 * family.surfaces[4].stress(E).S
    np.testing.assert_allclose(between, expected, rtol=1e-14)


def test_geometry_is_the_members_and_linear_between(family):
    assert family.wale_width(5.5) == pytest.approx(1.33, abs=1e-14)
    assert family.course_height(6.0) == pytest.approx(1.42, abs=1e-14)
    assert family.wale_width(5.75) == pytest.approx(0.5 * (1.33 + 1.381), abs=1e-14)


def test_stitch_outside_the_range_is_refused_naming_it(family):
    assert family.stitch_range == (4.5, 7.0)
    with pytest.raises(InputError, match=r"band=7.2 mm is outside the family's range \[4.5, 7\]"):
        family.check_stitch("band", 7.2)
