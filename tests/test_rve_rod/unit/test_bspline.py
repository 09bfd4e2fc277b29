"""B-spline toolkit against textbook values, scipy's independent implementation and identities."""

import numpy as np
import pytest
import scipy.interpolate

from rve_rod.errors import InputError
from rve_rod.geometry.bspline import (
    BSplineCurve,
    basis_functions,
    basis_matrix,
    collocation_solve,
    greville_abscissae,
    interpolate,
    join,
    open_knot_vector,
)

RNG = np.random.default_rng(7)


def random_curve(degree, n, dim=3, nonuniform=True):
    knots = open_knot_vector(degree, n)
    if nonuniform:
        interior = np.sort(RNG.uniform(0.05, 0.95, n - degree - 1))
        knots[degree + 1 : n] = interior
    return BSplineCurve(degree, knots, RNG.normal(size=(n, dim)))


def test_nurbs_book_example_2_3():
    # The NURBS Book, Ex. 2.3 / 2.4: U = {0,0,0,1,2,3,4,4,5,5,5}, p = 2, u = 5/2.
    knots = np.array([0, 0, 0, 1, 2, 3, 4, 4, 5, 5, 5], dtype=float)
    basis = basis_functions(knots, 2, np.array([2.5]), derivatives=1)
    assert basis.spans[0] == 4
    np.testing.assert_allclose(basis.values[0, 0], [1 / 8, 6 / 8, 1 / 8], atol=1e-15)
    np.testing.assert_allclose(basis.values[1, 0], [-0.5, 0.0, 0.5], atol=1e-15)


@pytest.mark.parametrize("degree", [1, 2, 3, 4, 5])
def test_partition_of_unity_and_derivatives_sum_to_zero(degree):
    curve = random_curve(degree, 3 * degree + 4)
    params = np.linspace(0, 1, 301)
    basis = basis_functions(curve.knots, degree, params, derivatives=min(degree, 3))
    np.testing.assert_allclose(basis.values[0].sum(axis=1), 1.0, atol=1e-14)
    assert np.all(basis.values[0] >= -1e-15)
    for k in range(1, basis.values.shape[0]):
        scale = np.abs(basis.values[k]).max()
        np.testing.assert_allclose(basis.values[k].sum(axis=1), 0.0, atol=1e-12 * scale)


@pytest.mark.parametrize("degree", [2, 3, 4])
def test_curve_and_derivatives_match_scipy(degree):
    curve = random_curve(degree, 17)
    params = np.concatenate([np.linspace(0, 1, 97), curve.knots[degree + 1 : -degree - 1]])
    reference = scipy.interpolate.BSpline(curve.knots, curve.control_points, degree)
    derivatives = curve.derivatives(params, order=degree)
    for k in range(degree + 1):
        np.testing.assert_allclose(derivatives[k], reference(params, nu=k), atol=1e-9, rtol=1e-9)


def test_first_and_second_derivative_against_finite_differences():
    curve = random_curve(4, 12)
    params = np.linspace(0.02, 0.98, 41)
    h = 1e-5
    d1 = (curve(params + h) - curve(params - h)) / (2 * h)
    d2 = (curve(params + h, 1) - curve(params - h, 1)) / (2 * h)
    np.testing.assert_allclose(curve(params, 1), d1, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(curve(params, 2), d2, rtol=1e-5, atol=1e-5)


def test_basis_matrix_reproduces_curve_evaluation():
    curve = random_curve(3, 10)
    params = np.linspace(0, 1, 23)
    for k in range(3):
        matrix = basis_matrix(curve.knots, 3, params, derivative=k)
        assert matrix.shape == (23, 10)
        np.testing.assert_allclose(matrix @ curve.control_points, curve(params, k), atol=1e-12)


@pytest.mark.parametrize("degree", [2, 3, 4])
def test_knot_insertion_leaves_curve_unchanged(degree):
    curve = random_curve(degree, 9)
    params = np.linspace(0, 1, 211)
    refined = curve.insert_knot(0.37).insert_knot(0.37)
    refined = refined.insert_knot(float(curve.knots[degree + 2]))
    assert refined.n_control_points == curve.n_control_points + 3
    for k in range(3):
        np.testing.assert_allclose(refined(params, k), curve(params, k), atol=1e-10)


def test_subdivision_quarter_loop_sizes_and_invariance():
    curve = random_curve(4, 12, nonuniform=False)
    refined = curve.subdivide(8)
    assert refined.n_control_points == 68
    params = np.linspace(0, 1, 500)
    np.testing.assert_allclose(refined(params), curve(params), atol=1e-12)
    np.testing.assert_allclose(refined(params, 2), curve(params, 2), atol=1e-9)


@pytest.mark.parametrize("n", [12, 24, 36, 68, 136])
def test_refinement_to_a_count_keeps_the_curve(n):
    curve = random_curve(4, 12, nonuniform=False)
    refined = curve.refined_to(n)
    assert refined.n_control_points == n
    assert set(curve.knots) <= set(refined.knots)
    spans = np.diff(refined.breakpoints())
    assert spans.max() / spans.min() <= 1.5 + 1e-12
    params = np.linspace(0, 1, 500)
    np.testing.assert_allclose(refined(params), curve(params), atol=1e-12)
    np.testing.assert_allclose(refined(params, 2), curve(params, 2), atol=1e-8)
    np.testing.assert_array_equal(curve.refined_to(68).knots, curve.subdivide(8).knots)


@pytest.mark.parametrize("at", [0.37, 0.5])  # inside a span, and on a knot
def test_split_gives_two_pieces_of_the_same_curve(at):
    curve = random_curve(4, 10, nonuniform=False)
    pieces = curve.split(at)
    assert pieces.left.domain == (0.0, at) and pieces.right.domain == (at, 1.0)
    for piece in pieces:
        params = np.linspace(*piece.domain, 101)
        for k in range(3):
            np.testing.assert_allclose(piece(params, k), curve(params, k), atol=1e-9)
    with pytest.raises(InputError, match="outside the open curve domain"):
        curve.split(1.0)


def test_join_is_exact_and_smooth_at_the_joins():
    # a curve with simple knots (C3) cut into four pieces, joined again with C2 and C3 joins
    curve = random_curve(4, 20, nonuniform=False).reparametrized(2.0)
    pieces = []
    rest = curve
    for at in (2.25, 2.5, 2.75):
        split = rest.split(at)
        pieces.append(split.left.reparametrized(0.0))  # each piece on its own domain
        rest = split.right
    pieces.append(rest.reparametrized(0.0))
    params = np.linspace(2.0, 3.0, 777)
    for continuity, multiplicity in ((2, 2), (3, 1)):
        joined = join(pieces, continuity)
        assert joined.domain == (0.0, 1.0)
        assert joined.n_control_points == 20 + 3 * (multiplicity - 1)
        for value in (0.25, 0.5, 0.75):
            assert np.count_nonzero(np.abs(joined.knots - value) < 1e-14) == multiplicity
        for k in range(3):
            np.testing.assert_allclose(joined(params - 2.0, k), curve(params, k), atol=1e-9)
    np.testing.assert_allclose(join(pieces, 3).control_points, curve.control_points, atol=1e-12)


def test_join_refuses_curves_that_are_not_smooth_enough():
    curve = random_curve(4, 12)
    split = curve.split(0.4)
    moved = split.right.translated([0.0, 0.0, 1e-4])
    with pytest.raises(InputError, match="derivative 0"):
        join([split.left, moved], 0)
    kinked = curve.insert_knot(0.4, 4)  # C0 at 0.4: bending a control point kinks it
    bent = kinked.control_points.copy()
    position = int(np.flatnonzero(np.abs(kinked.knots - 0.4) < 1e-14)[0])
    bent[position - 2] += 0.1
    pieces = BSplineCurve(4, kinked.knots, bent).split(0.4)
    join(pieces, 0)
    with pytest.raises(InputError, match="derivative 1"):
        join(pieces, 1)


def test_insertion_beyond_degree_is_refused():
    curve = random_curve(2, 6)
    with pytest.raises(InputError, match="multiplicity"):
        curve.insert_knot(0.5, times=3)


def test_greville_abscissae_reproduce_linear_function():
    # The Greville points are the control points of the identity map u -> u.
    curve = random_curve(4, 15)
    greville = greville_abscissae(curve.knots, 4)
    identity = BSplineCurve(4, curve.knots, greville[:, None])
    params = np.linspace(0, 1, 57)
    np.testing.assert_allclose(identity(params)[:, 0], params, atol=1e-14)


@pytest.mark.parametrize("degree", [2, 3, 4])
def test_interpolation_hits_points_and_reproduces_polynomials(degree):
    params = np.sort(np.concatenate([[0.0, 1.0], RNG.uniform(0, 1, 10)]))
    points = np.stack([params**degree, 1 - 3 * params, np.cos(params)], axis=1)
    curve = interpolate(points, degree, params)
    np.testing.assert_allclose(curve(params), points, atol=1e-12)
    fine = np.linspace(0, 1, 101)
    np.testing.assert_allclose(
        curve(fine)[:, :2], np.stack([fine**degree, 1 - 3 * fine], 1), atol=1e-11
    )


def test_arc_length_of_helix_segment():
    # Helix (cos t, sin t, t/2) for t in [0, 1]: length sqrt(1 + 1/4) exactly.
    t = np.linspace(0, 1, 60)
    points = np.stack([np.cos(t), np.sin(t), t / 2], axis=1)
    curve = interpolate(points, 4, t)
    assert curve.arc_length() == pytest.approx(np.sqrt(1.25), rel=1e-9)


def test_arc_length_of_straight_line_is_exact():
    curve = BSplineCurve(3, open_knot_vector(3, 7), np.linspace([0, 0, 0], [3, 4, 12], 7))
    assert curve.arc_length() == pytest.approx(13.0, rel=1e-14)


def test_bad_knot_vectors_and_parameters_are_refused():
    with pytest.raises(InputError, match="needs 8"):
        BSplineCurve(3, np.zeros(5), np.zeros((4, 2)))
    with pytest.raises(InputError, match="non-decreasing"):
        BSplineCurve(1, np.array([0, 0, 1, 0.5, 1, 1.0]), np.zeros((4, 2)))
    # an interior knot p times is allowed (a C0 joint), p + 1 times is not
    cubic = [0, 0, 0, 0, 0.2, 0.5, 0.5, 0.5]
    BSplineCurve(3, np.array([*cubic, 0.7, 1, 1, 1, 1]), np.zeros((9, 2)))
    with pytest.raises(InputError, match="repeats more than degree=3"):
        BSplineCurve(3, np.array([*cubic, 0.5, 1, 1, 1, 1]), np.zeros((9, 2)))
    curve = random_curve(2, 5)
    with pytest.raises(InputError, match="outside the curve domain"):
        curve(np.array([1.5]))


@pytest.mark.parametrize("degree", [2, 3, 4, 5])
@pytest.mark.parametrize("transpose", [False, True])
def test_collocation_solve_matches_the_dense_solve(degree, transpose):
    curve = random_curve(degree, 40)
    greville = curve.greville()
    rhs = RNG.normal(size=(40, 3))
    matrix = basis_matrix(curve.knots, degree, greville).toarray()
    expected = np.linalg.solve(matrix.T if transpose else matrix, rhs)
    found = collocation_solve(curve.knots, degree, greville, rhs, transpose)
    np.testing.assert_allclose(found, expected, rtol=1e-12, atol=1e-12)
    # one right-hand side as a vector
    single = collocation_solve(curve.knots, degree, greville, rhs[:, 0], transpose)
    np.testing.assert_allclose(single, expected[:, 0], rtol=1e-12, atol=1e-12)


def test_collocation_solve_refuses_singular_and_non_square_systems():
    curve = random_curve(3, 12)
    params = curve.greville().copy()
    params[5] = params[6] = 0.5 * (params[5] + params[6])  # two rows alike: singular
    with pytest.raises(InputError, match="singular"):
        collocation_solve(curve.knots, 3, params, np.ones(12))
    # distinct and increasing, but the last functions vanish where their rows sit
    crowded = np.linspace(curve.knots[0], curve.knots[5], 12)
    with pytest.raises(InputError, match="singular"):
        collocation_solve(curve.knots, 3, crowded, np.ones(12))
    with pytest.raises(InputError, match="not square"):
        collocation_solve(curve.knots, 3, curve.greville()[:-1], np.ones(11))
