"""Contact layout: span polynomials, collocation data, arc lengths, strands, input checks."""

import numpy as np
import pytest
from support.contact_scenes import crossed_rods, knit_loop

from rve_rod.contact import Patch, PeriodicLattice, YarnChain
from rve_rod.contact.layout import build_layout
from rve_rod.errors import InputError
from rve_rod.geometry.bspline import BSplineCurve, basis_functions, open_knot_vector


def curved_patches(rng):
    patches, points, curves = [], [], []
    for degree, n in ((3, 9), (3, 14)):
        knots = open_knot_vector(degree, n)
        knots[degree + 1 : n] = np.sort(rng.uniform(0.05, 0.95, n - degree - 1))
        t = np.linspace(0, 3, n)
        cps = np.stack([np.cos(t), np.sin(t), 0.3 * t], axis=1) + 0.02 * rng.normal(size=(n, 3))
        patches.append(Patch(degree, knots, collocation_parameters=rng.uniform(0, 1, 5)))
        points.append(cps)
        curves.append(BSplineCurve(degree, knots, cps))
    return patches, np.vstack(points), curves


def test_span_polynomials_reproduce_the_bspline_toolkit():
    rng = np.random.default_rng(0)
    patches, points, curves = curved_patches(rng)
    layout = build_layout(patches, [YarnChain((0, 1))], points)
    coefficients = layout.coefficients(points)
    for s in range(layout.n_spans):
        patch = layout.span_patch[s]
        tau = rng.uniform(0, 1, 6)
        u = layout.span_start[s] + tau * layout.span_length[s]
        powers = tau[None, :] ** np.arange(layout.degree + 1)[:, None]
        np.testing.assert_allclose(coefficients[:, :, s] @ powers, curves[patch](u).T, atol=1e-12)
        basis = basis_functions(patches[patch].knots, layout.degree, u).values[0]
        np.testing.assert_allclose(layout.basis(np.full(6, s), tau), basis, atol=1e-13)
        derivative = basis_functions(patches[patch].knots, layout.degree, u, 1).values[1]
        np.testing.assert_allclose(
            layout.basis(np.full(6, s), tau, 1), derivative * layout.span_length[s], atol=1e-12
        )


def test_collocation_points_and_arc_lengths():
    rng = np.random.default_rng(1)
    patches, points, curves = curved_patches(rng)
    layout = build_layout(patches, [YarnChain((0,)), YarnChain((1,))], points)
    expected = np.vstack(
        [curve(patch.collocation_parameters) for patch, curve in zip(patches, curves, strict=True)]
    )
    np.testing.assert_allclose(layout.collocation_positions(points).T, expected, atol=1e-12)
    lengths = [curve.arc_length(points_per_span=20) for curve in curves]
    np.testing.assert_allclose(layout.yarn_length, lengths, rtol=1e-7)
    assert list(layout.span_closed_end.nonzero()[0]) == [
        np.flatnonzero(layout.span_patch == 0)[-1],
        layout.n_spans - 1,
    ]


def test_collocation_weights_integrate_splines_exactly():
    # A straight rod of length 2 along x: int x^2 ds = 2/3 on [-1, 1]; x^2 is a spline of
    # degree 2, so Greville-point values weighted by w integrate it exactly.
    scene = crossed_rods(separation=0.3, length=2.0, n_control_points=12)
    layout = build_layout(scene.patches, scene.yarns, scene.positions)
    x = layout.collocation_positions(scene.positions)[0]
    weights = layout.collocation_weights
    np.testing.assert_allclose(weights.sum(), 4.0, rtol=1e-12)
    np.testing.assert_allclose(np.sum((weights * x**2)[:12]), 2.0 / 3.0, rtol=1e-12)


def test_knit_strands_continue_through_the_wale_images(cotton_loop):
    scene = knit_loop(cotton_loop)
    layout = build_layout(scene.patches, scene.yarns, scene.positions)
    images = np.array([[0, 0], [1, 0], [-2, 0], [0, 1], [1, 1], [0, -1]])
    keys, shifts = layout.strands(np.zeros(6, dtype=np.int64), images)
    length = layout.yarn_length[0]
    assert keys[0] == keys[1] == keys[2]
    assert len({keys[0], keys[3], keys[5]}) == 3
    assert keys[4] == keys[3]  # image (1, 1) continues the yarn of image (0, 1)
    np.testing.assert_allclose(shifts, [0, length, -2 * length, 0, length, 0])
    # One period of the loop is its four quarter patches: the last span ends at the yarn length.
    last = layout.n_spans - 1
    assert layout.span_arc_start[last] + layout.span_arc_length[last] == pytest.approx(length)


def test_invalid_layouts_are_rejected():
    knots = open_knot_vector(3, 6)
    points = np.zeros((12, 3))
    with pytest.raises(InputError, match="exactly one yarn chain"):
        build_layout([Patch(3, knots), Patch(3, knots)], [YarnChain((0,))], points)
    with pytest.raises(InputError, match="one degree"):
        build_layout(
            [Patch(3, knots), Patch(2, open_knot_vector(2, 6))], [YarnChain((0, 1))], points
        )
    with pytest.raises(InputError, match=r"reference positions must be a finite \(12, 3\)"):
        build_layout([Patch(3, knots), Patch(3, knots)], [YarnChain((0, 1))], points[:5])
    with pytest.raises(InputError, match="outside the curve domain"):
        Patch(3, knots, collocation_parameters=[0.5, 1.5])
    with pytest.raises(InputError, match="period"):
        YarnChain((0,), period=(1, 1))
    with pytest.raises(InputError, match="x-y plane"):
        PeriodicLattice(np.array([[1.0, 0, 0.1], [0, 1.0, 0]]))
    with pytest.raises(InputError, match="parallel"):
        PeriodicLattice(np.array([[1.0, 0, 0], [2.0, 0, 0]]))
