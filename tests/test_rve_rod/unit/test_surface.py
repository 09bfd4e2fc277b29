"""Spline evaluation of response surfaces: scipy as independent reference, the extension rule of
docs/surface-format.md in closed form, finite differences, C1 continuity across the boundary."""

import numpy as np
import pytest
import scipy.interpolate

from rve_rod.errors import InputError
from rve_rod.geometry.bspline import open_knot_vector
from rve_rod.surface import (
    ResponseSurface,
    Spline1D,
    Spline2D,
    energy_surface,
    tangent_asymmetry,
)

RNG = np.random.default_rng(11)


def random_knots(degree, n, low, high):
    """Open knots with interior knots jittered by up to 30 % of the uniform spacing."""
    knots = open_knot_vector(degree, n, (low, high))
    spacing = (high - low) / (n - degree)
    knots[degree + 1 : n] += RNG.uniform(-0.3, 0.3, n - degree - 1) * spacing
    return knots


def random_spline1d(degree=3, n=9, extension_order=1, domain=(-0.3, 0.3)):
    knots = random_knots(degree, n, *domain)
    return Spline1D(degree, knots, RNG.normal(size=n), extension_order)


def random_spline2d(
    degrees=(2, 3), shape=(7, 8), orders=(1, 1), domain=((-0.1, 0.25), (-0.05, 0.3))
):
    knots = tuple(random_knots(p, n, *d) for p, n, d in zip(degrees, shape, domain, strict=True))
    return Spline2D(degrees, knots, RNG.normal(size=shape), orders)


def bisplev(spline, x, y, dx=0, dy=0):
    """scipy's tensor-product evaluation (FITPACK), only inside the domain."""
    tck = [*spline.knots, spline.coefficients.ravel(), *spline.degrees]
    return np.array(
        [scipy.interpolate.bisplev(a, b, tck, dx, dy) for a, b in zip(x, y, strict=True)]
    )


def points_around(domain, m, margin=0.5):
    low, high = domain
    width = high - low
    return RNG.uniform(low - margin * width, high + margin * width, m)


@pytest.mark.parametrize("degree", [2, 3, 4])
def test_spline1d_matches_scipy_inside(degree):
    spline = random_spline1d(degree, 11)
    x = np.linspace(*spline.domain, 201)
    reference = scipy.interpolate.BSpline(spline.knots, spline.coefficients, degree)
    values = spline.derivatives(x, order=2)
    for r in range(3):
        np.testing.assert_allclose(values[r], reference(x, nu=r), rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("order", [1, 2])
def test_spline1d_extension_is_the_taylor_polynomial_of_the_doc(order):
    spline = random_spline1d(3, 10, extension_order=order)
    reference = scipy.interpolate.BSpline(spline.knots, spline.coefficients, 3)
    low, high = spline.domain
    for end, x in (
        (high, high + np.linspace(1e-3, 0.5, 40)),
        (low, low - np.linspace(1e-3, 0.5, 40)),
    ):
        d = x - end
        expected = reference(end) + reference(end, nu=1) * d
        slope = np.full_like(x, reference(end, nu=1))
        curvature = np.zeros_like(x)
        if order == 2:
            expected += reference(end, nu=2) * d**2 / 2
            slope += reference(end, nu=2) * d
            curvature += reference(end, nu=2)
        values = spline.derivatives(x, order=2)
        np.testing.assert_allclose(values[0], expected, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(values[1], slope, rtol=1e-12, atol=1e-11)
        np.testing.assert_allclose(values[2], curvature, rtol=1e-12, atol=1e-10)
        assert np.all(spline.outside(x)) and not np.any(spline.outside(np.array([low, high])))


def test_spline2d_matches_scipy_inside():
    spline = random_spline2d()
    (x_low, x_high), (y_low, y_high) = spline.domain
    x = RNG.uniform(x_low, x_high, 60)
    y = RNG.uniform(y_low, y_high, 60)
    values = spline.derivatives(x, y, order=1)
    for i, j in ((0, 0), (1, 0), (0, 1), (1, 1)):
        np.testing.assert_allclose(values[i, j], bisplev(spline, x, y, i, j), rtol=1e-11, atol=1e-9)


def test_spline2d_c1_extension_closed_form_of_the_doc():
    # f(c) + f_x(c) dx + f_y(c) dy + f_xy(c) dx dy with c the nearest point of the domain box.
    spline = random_spline2d(orders=(1, 1))
    (x_low, x_high), (y_low, y_high) = spline.domain
    x = points_around(spline.domain[0], 300, 1.0)
    y = points_around(spline.domain[1], 300, 1.0)
    cx, cy = np.clip(x, x_low, x_high), np.clip(y, y_low, y_high)
    dx, dy = x - cx, y - cy
    expected = (
        bisplev(spline, cx, cy)
        + bisplev(spline, cx, cy, 1, 0) * dx
        + bisplev(spline, cx, cy, 0, 1) * dy
        + bisplev(spline, cx, cy, 1, 1) * dx * dy
    )
    np.testing.assert_allclose(spline(x, y), expected, rtol=1e-11, atol=1e-10)
    # linear in every outward direction: the second derivative along the normal vanishes outside
    second = spline.derivatives(x, y, order=2)
    np.testing.assert_array_equal(second[2, 0][x > x_high], 0.0)
    np.testing.assert_array_equal(second[0, 2][y < y_low], 0.0)


def finite_difference_check(function, x, step=1e-6):
    return (function(x + step) - function(x - step)) / (2 * step)


@pytest.mark.parametrize("order", [1, 2])
def test_spline1d_derivatives_match_finite_differences_inside_and_outside(order):
    spline = random_spline1d(3, 10, extension_order=order)
    x = points_around(spline.domain, 200)
    values = spline.derivatives(x, order=2)
    scale = np.abs(values).max(axis=1)
    np.testing.assert_allclose(
        values[1], finite_difference_check(spline, x), rtol=1e-6, atol=1e-8 * scale[0]
    )
    slope = lambda z: spline.derivatives(z, 1)[1]  # noqa: E731
    np.testing.assert_allclose(
        values[2], finite_difference_check(slope, x), rtol=1e-5, atol=1e-8 * scale[1]
    )


@pytest.mark.parametrize("orders", [(1, 1), (1, 2), (2, 1), (2, 2)])
def test_spline2d_derivatives_match_finite_differences(orders):
    spline = random_spline2d(degrees=(3, 3), orders=orders)
    x = points_around(spline.domain[0], 200)
    y = points_around(spline.domain[1], 200)
    values = spline.derivatives(x, y, order=1)
    h = 1e-6
    fd_x = (spline(x + h, y) - spline(x - h, y)) / (2 * h)
    fd_y = (spline(x, y + h) - spline(x, y - h)) / (2 * h)
    fd_xy = (values_x(spline, x, y + h) - values_x(spline, x, y - h)) / (2 * h)
    np.testing.assert_allclose(values[1, 0], fd_x, rtol=1e-6, atol=1e-5)
    np.testing.assert_allclose(values[0, 1], fd_y, rtol=1e-6, atol=1e-5)
    np.testing.assert_allclose(values[1, 1], fd_xy, rtol=1e-5, atol=1e-4)


def values_x(spline, x, y):
    return spline.derivatives(x, y, 1)[1, 0]


@pytest.mark.parametrize("order", [1, 2])
def test_value_and_slope_continuous_across_the_boundary_c1(order):
    # Jumps across each end over [end - h, end + h] shrink at least linearly with h as h -> 0
    # (value and slope continuous: C1); measured on the finest pair of h, where the O(h) term
    # leads (at h = 1e-2 a large curvature inside can still cancel it: the order over all h
    # moved with the draw). A jump of a discontinuous value or slope would not shrink.
    spline = random_spline1d(2, 8, extension_order=order)
    steps = np.array([1e-2, 1e-3, 1e-4, 1e-5])
    for end in spline.domain:
        jumps = [spline.derivatives(np.array([end - h, end + h]), 2) for h in steps]
        value_jump = np.array([abs(j[0, 1] - j[0, 0]) for j in jumps])
        slope_jump = np.array([abs(j[1, 1] - j[1, 0]) for j in jumps])
        assert np.log10(value_jump[-2] / value_jump[-1]) > 0.95
        assert np.log10(slope_jump[-2] / slope_jump[-1]) > 0.95
        # mean value theorem: a jump over [end - h, end + h] is at most 2 h max|next derivative|
        slope, curvature = np.abs(jumps[-1][1]).max(), np.abs(jumps[-1][2]).max()
        assert value_jump[-1] <= 2 * steps[-1] * slope * (1 + 1e-6)
        assert slope_jump[-1] <= 2 * steps[-1] * curvature * (1 + 1e-6)


def test_spline2d_c1_across_faces_and_corners():
    spline = random_spline2d(orders=(1, 1))
    (x_low, x_high), (y_low, y_high) = spline.domain
    boundary = [
        (x_high, 0.1),
        (x_low, 0.0),
        (0.05, y_high),
        (0.0, y_low),
        (x_high, y_high),
        (x_low, y_low),
    ]
    directions = np.array([[1, 0], [0, 1], [1, 1], [1, -1]])

    def jumps(h):
        result = []
        for bx, by in boundary:
            inner = spline.derivatives(bx - h * directions[:, 0], by - h * directions[:, 1], 1)
            outer = spline.derivatives(bx + h * directions[:, 0], by + h * directions[:, 1], 1)
            result.append([np.abs(outer[i, j] - inner[i, j]) for i, j in ((0, 0), (1, 0), (0, 1))])
        return np.array(result)

    # a discontinuity would leave the jump finite as h -> 0; C1 makes it shrink like h
    coarse, fine = jumps(1e-4), jumps(1e-6)
    assert coarse.max() > 0
    assert np.all(fine <= 0.011 * coarse + 1e-12)


@pytest.mark.parametrize("degree", [2, 3])
def test_derivative_spline_equals_the_derivative_including_the_extension(degree):
    spline = random_spline1d(degree, 9, extension_order=2)
    x = points_around(spline.domain, 100)
    derivative = spline.derivative()
    assert derivative.extension_order == 1
    np.testing.assert_allclose(derivative(x), spline.derivatives(x, 1)[1], rtol=1e-12, atol=1e-12)
    surface = random_spline2d(degrees=(3, 2), orders=(2, 2))
    y = points_around(surface.domain[1], 100)
    x = points_around(surface.domain[0], 100)
    for axis in (0, 1):
        partial = surface.derivative(axis)
        expected = surface.derivatives(x, y, 1)[(1, 0) if axis == 0 else (0, 1)]
        np.testing.assert_allclose(partial(x, y), expected, rtol=1e-12, atol=1e-11)


def stress_surface():
    domain = ((-0.1, 0.25), (-0.05, 0.3))
    return ResponseSurface(
        kind="stress",
        s11=random_spline2d(domain=domain),
        s22=random_spline2d(domain=domain),
        s12=random_spline1d(2, 7),
    )


def random_energy_surface():
    psi = random_spline2d(degrees=(3, 3), orders=(2, 2))
    psi_shear = random_spline1d(3, 8, extension_order=2)
    return energy_surface(psi, psi_shear)


@pytest.mark.parametrize("make", [stress_surface, random_energy_surface])
def test_stress_tangent_matches_finite_differences_and_outside_flag(make):
    surface = make()
    domain = surface.domain
    E = np.stack([points_around(domain[a], 150) for a in range(3)], axis=1)
    result = surface.stress(E)
    h = 1e-6
    for b in range(3):
        step = np.zeros(3)
        step[b] = h
        fd = (surface.stress(E + step).S - surface.stress(E - step).S) / (2 * h)
        np.testing.assert_allclose(result.tangent[:, :, b], fd, rtol=1e-6, atol=1e-5)
    expected_outside = np.any((E < domain[:, 0]) | (E > domain[:, 1]), axis=1)
    np.testing.assert_array_equal(result.outside, expected_outside)
    assert 0 < expected_outside.sum() < len(E)


def test_stress_is_finite_far_outside_and_rejects_nan():
    surface = stress_surface()
    E = np.array([[10.0, -10.0, 5.0], [-3.0, 7.0, -9.0], [1e6, 1e6, -1e6]])
    result = surface.stress(E)
    assert np.all(np.isfinite(result.S)) and np.all(np.isfinite(result.tangent))
    assert result.outside.all()
    with pytest.raises(InputError, match="finite"):
        surface.stress(np.array([np.nan, 0.0, 0.0]))
    with pytest.raises(InputError, match="shape"):
        surface.stress(np.zeros((4, 2)))


def test_energy_surface_tangent_symmetric_to_roundoff_inside_and_outside():
    surface = random_energy_surface()
    E = np.stack([points_around(surface.domain[a], 400, 1.0) for a in range(3)], axis=1)
    result = surface.stress(E)
    assert result.outside.sum() > 100
    scale = np.abs(result.tangent).max()
    asymmetry = np.abs(result.tangent - result.tangent.transpose(0, 2, 1)).max()
    assert asymmetry < 1e-13 * scale
    assert tangent_asymmetry(surface) < 1e-13
    assert tangent_asymmetry(stress_surface()) > 1e-3


def test_energy_surface_stress_is_gradient_of_energy():
    # S = dW/dE with W = psi + 2 psi_shear and symmetric E: dW/dE12 (as one variable) = 2 S12.
    surface = random_energy_surface()
    E = np.stack([points_around(surface.domain[a], 100) for a in range(3)], axis=1)
    S = surface.stress(E).S
    h = 1e-6
    roundoff = 1e-15 * np.abs(surface.energy(E)).max() / h
    weights = np.array([1.0, 1.0, 2.0])
    for b in range(3):
        step = np.zeros(3)
        step[b] = h
        fd = (surface.energy(E + step) - surface.energy(E - step)) / (2 * h)
        np.testing.assert_allclose(fd, weights[b] * S[:, b], rtol=1e-6, atol=100 * roundoff)


def test_surface_rejects_inconsistent_parts():
    good = stress_surface()
    with pytest.raises(InputError, match="kind"):
        ResponseSurface(kind="hyper", s11=good.s11, s22=good.s22, s12=good.s12)
    with pytest.raises(InputError, match="extension orders"):
        ResponseSurface(
            kind="stress", s11=random_spline2d(orders=(2, 1)), s22=good.s22, s12=good.s12
        )
    with pytest.raises(InputError, match="share one domain"):
        ResponseSurface(
            kind="stress", s11=random_spline2d(domain=((0, 1), (0, 1))), s22=good.s22, s12=good.s12
        )
    energy = random_energy_surface()
    with pytest.raises(InputError, match="not the derivative"):
        ResponseSurface(
            kind="energy",
            s11=Spline2D(
                energy.s11.degrees,
                energy.s11.knots,
                energy.s11.coefficients * 1.001,
                energy.s11.extension_orders,
            ),
            s22=energy.s22,
            s12=energy.s12,
            psi=energy.psi,
            psi_shear=energy.psi_shear,
        )
    with pytest.raises(InputError, match="open"):
        Spline1D(2, np.array([0, 0, 0.5, 1, 1, 1.0]), np.zeros(3))
