"""A body of revolution's radius profile from a table: through the points, C1, linear beyond."""

import numpy as np
import pytest

from fabric_dolfinx.spec.revolution import RadiusProfile, read_profile
from rve_rod.errors import InputError

LEG = RadiusProfile((0, 50, 100, 200, 300, 400), (35.0, 37.0, 41.5, 54.0, 59.0, 52.5))


def test_the_profile_passes_through_its_points_without_overshoot():
    np.testing.assert_allclose(LEG.radius(np.array(LEG.z)), LEG.r, rtol=1e-14)
    z = np.linspace(0, 400, 4001)
    r = LEG.radius(z)
    for i in range(len(LEG.z) - 1):
        inside = (z >= LEG.z[i]) & (z <= LEG.z[i + 1])
        low, high = sorted(LEG.r[i : i + 2])
        assert low - 1e-9 <= r[inside].min() and r[inside].max() <= high + 1e-9


def test_slope_is_the_derivative_and_continuous_at_the_points_and_beyond():
    z = np.array([-30.0, 0.0, 25.0, 100.0, 250.0, 400.0, 420.0])
    h = 1e-6
    numeric = (LEG.radius(z + h) - LEG.radius(z - h)) / (2 * h)
    np.testing.assert_allclose(LEG.slope(z), numeric, atol=1e-7)
    for knot in LEG.z:
        np.testing.assert_allclose(LEG.slope(knot - 1e-9), LEG.slope(knot + 1e-9), atol=1e-7)


def test_curvature_of_the_meridian():
    z = np.array([30.0, 120.0, 280.0])
    h = 1.0  # within one cubic piece the central difference is exact
    second = (LEG.radius(z + h) - 2 * LEG.radius(z) + LEG.radius(z - h)) / h**2
    expected = -second / (1 + LEG.slope(z) ** 2) ** 1.5
    np.testing.assert_allclose(LEG.curvature(z), expected, rtol=1e-9)
    assert LEG.curvature(280.0) > 0 > LEG.curvature(120.0)  # the calf bulges
    assert LEG.curvature(500.0) == 0.0


def test_beyond_the_table_the_radius_follows_the_end_tangents():
    start, end = LEG.end_slopes()
    assert LEG.radius(-10.0) == pytest.approx(35.0 - 10.0 * start, rel=1e-14)
    assert LEG.radius(410.0) == pytest.approx(52.5 + 10.0 * end, rel=1e-14)


def test_two_points_make_a_cone():
    cone = RadiusProfile((0.0, 100.0), (30.0, 40.0))
    np.testing.assert_allclose(cone.radius([-50.0, 25.0, 150.0]), [25.0, 32.5, 45.0])


def test_a_circumference_table_reads_as_radii(tmp_path):
    path = tmp_path / "leg.csv"
    path.write_text("# tape\nz_mm, circumference_mm\n0, 220\n400, 330\n")
    profile = read_profile(path)
    np.testing.assert_allclose(profile.r, np.array([220.0, 330.0]) / (2 * np.pi))


@pytest.mark.parametrize(
    ("z", "r", "message"),
    [((0.0,), (1.0,), ">= 2 points"), ((0, 0), (1, 2), "must increase"), ((0, 1), (1, 0), "> 0")],
)
def test_bad_profiles_are_refused(z, r, message):
    with pytest.raises(InputError, match=message):
        RadiusProfile(z, r)
