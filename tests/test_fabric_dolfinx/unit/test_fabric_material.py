"""UFL material laws against independent evaluations: the numpy splines of rve_rod.surface,
scipy's B-splines, the extension rule in closed form and the orthotropic compliance matrix."""

import numpy as np
import pytest
import scipy.interpolate
import ufl
from dolfinx import fem, mesh
from mpi4py import MPI

from fabric_dolfinx.material import (
    OrthotropicSVK,
    piecewise_basis,
    spline_1d,
    spline_2d,
    svk_stress,
)
from fabric_dolfinx.membrane.forms import flat_frame, membrane_state
from rve_rod.errors import InputError
from rve_rod.surface import Spline1D, Spline2D

RNG = np.random.default_rng(5)
# Knots on a 0.025 grid so that mesh vertices land on them; a double knot at 0.1.
CUBIC_KNOTS = np.array([-0.1] * 4 + [-0.05, 0.025, 0.1, 0.1, 0.2] + [0.3] * 4)
QUADRATIC_KNOTS = np.array([-0.15] * 3 + [-0.1, 0.0, 0.05, 0.05, 0.175] + [0.25] * 3)
CUBIC = Spline1D(3, CUBIC_KNOTS, RNG.normal(size=9), extension_order=1)
QUADRATIC = Spline1D(2, QUADRATIC_KNOTS, RNG.normal(size=8), extension_order=2)
MIXED = Spline2D((3, 2), (CUBIC_KNOTS, QUADRATIC_KNOTS), RNG.normal(size=(9, 8)), (1, 2))
FLAT = Spline2D((2, 3), (QUADRATIC_KNOTS, CUBIC_KNOTS), RNG.normal(size=(8, 9)), (0, 1))
ALL_KNOTS = np.unique(np.concatenate([CUBIC_KNOTS, QUADRATIC_KNOTS]))


@pytest.fixture(scope="module")
def evaluated():
    """The UFL splines and their ufl.diff derivatives at the vertices and 3 x 3 Gauss points
    of a 28 x 28 grid over [-0.25, 0.45]^2 (inside and outside every domain).

    Returns (x, y, values) with values[name] of shape (m,); one compiled Expression.
    """
    domain = mesh.create_rectangle(
        MPI.COMM_SELF, [[-0.25, -0.25], [0.45, 0.45]], [28, 28], mesh.CellType.quadrilateral
    )
    coordinate = ufl.SpatialCoordinate(domain)
    x, y = ufl.variable(coordinate[0]), ufl.variable(coordinate[1])
    cubic, quadratic = spline_1d(CUBIC, x), spline_1d(QUADRATIC, y)
    mixed, flat = spline_2d(MIXED, x, y), spline_2d(FLAT, x, y)
    columns = {
        "x": coordinate[0],
        "y": coordinate[1],
        "cubic": cubic,
        "cubic_x": ufl.diff(cubic, x),
        "quadratic": quadratic,
        "quadratic_y": ufl.diff(quadratic, y),
        "mixed": mixed,
        "mixed_x": ufl.diff(mixed, x),
        "mixed_y": ufl.diff(mixed, y),
        "flat": flat,
        "flat_y": ufl.diff(flat, y),
    }
    gauss = np.polynomial.legendre.leggauss(3)[0] / 2 + 0.5
    points = np.array([[a, b] for a in [0.0, *gauss] for b in [0.0, *gauss]])
    expression = fem.Expression(ufl.as_vector(list(columns.values())), points)
    cells = np.arange(domain.topology.index_map(2).size_local, dtype=np.int32)
    table = expression.eval(cells).reshape(-1, len(columns))
    values = dict(zip(columns, table.T, strict=True))
    return values.pop("x"), values.pop("y"), values


def away_from_knots(t):
    return np.abs(t[:, None] - ALL_KNOTS[None, :]).min(axis=1) > 1e-9


def test_grid_reaches_knots_and_both_extensions(evaluated):
    x, y, _ = evaluated
    on_knot = np.isclose(x[:, None], ALL_KNOTS[None, :], rtol=0, atol=1e-14).any(axis=0)
    assert on_knot.all()
    assert x.min() < -0.15 and x.max() > 0.3 and y.min() < -0.15 and y.max() > 0.3


@pytest.mark.parametrize(
    ("name", "spline", "argument"), [("cubic", CUBIC, "x"), ("quadratic", QUADRATIC, "y")]
)
def test_1d_spline_matches_numpy_evaluation_everywhere(evaluated, name, spline, argument):
    x, y, values = evaluated
    t = x if argument == "x" else y
    reference = spline.derivatives(t, 1)
    np.testing.assert_allclose(values[name], reference[0], rtol=0, atol=1e-12)
    smooth = away_from_knots(t)
    np.testing.assert_allclose(
        values[f"{name}_{argument}"][smooth], reference[1][smooth], rtol=0, atol=1e-9
    )


@pytest.mark.parametrize(("name", "spline"), [("mixed", MIXED), ("flat", FLAT)])
def test_2d_spline_matches_numpy_evaluation_everywhere(evaluated, name, spline):
    x, y, values = evaluated
    reference = spline.derivatives(x, y, 1)
    np.testing.assert_allclose(values[name], reference[0, 0], rtol=0, atol=1e-11)
    smooth = away_from_knots(x) & away_from_knots(y)
    if name == "mixed":
        np.testing.assert_allclose(values["mixed_x"][smooth], reference[1, 0][smooth], atol=1e-8)
    np.testing.assert_allclose(values[f"{name}_y"][smooth], reference[0, 1][smooth], atol=1e-8)


def test_2d_spline_inside_matches_scipy(evaluated):
    """FITPACK's bisplev is an implementation independent of both evaluators."""
    x, y, values = evaluated
    inside = (np.abs(x - 0.1) <= 0.2) & (np.abs(y - 0.05) <= 0.2)
    tck = [*MIXED.knots, MIXED.coefficients.ravel(), *MIXED.degrees]
    reference = [
        scipy.interpolate.bisplev(a, b, tck) for a, b in zip(x[inside], y[inside], strict=True)
    ]
    np.testing.assert_allclose(values["mixed"][inside], reference, rtol=0, atol=1e-12)


def test_extension_is_the_taylor_polynomial_at_the_nearest_end(evaluated):
    """docs/surface-format.md: order k = 2 above and below the QUADRATIC domain [-0.15, 0.25]."""
    _, y, values = evaluated
    reference = scipy.interpolate.BSpline(QUADRATIC_KNOTS, QUADRATIC.coefficients, 2)
    for end, side in ((0.25, y > 0.25), (-0.15, y < -0.15)):
        d = y[side] - end
        taylor = reference(end) + reference(end, nu=1) * d + reference(end, nu=2) * d**2 / 2
        np.testing.assert_allclose(values["quadratic"][side], taylor, rtol=0, atol=1e-12)


@pytest.mark.parametrize("order", [0, 1, 2])
def test_piecewise_basis_is_a_partition_of_unity_on_every_piece(order):
    """sum_i N_i^ext = 1 inside and outside: constant term 1, all others 0 on every piece."""
    basis = piecewise_basis(CUBIC_KNOTS, 3, order)
    total = basis.coefficients.sum(axis=0)
    np.testing.assert_allclose(total[:, 0], 1.0, atol=1e-14)
    np.testing.assert_allclose(total[:, 1:], 0.0, atol=1e-12)
    assert basis.origins[0] == -0.1 and basis.origins[-1] == 0.3
    assert np.all(basis.coefficients[:, [0, -1], order + 1 :] == 0.0)


def test_svk_matrix_inverts_to_the_orthotropic_compliance():
    material = OrthotropicSVK(2.0, 0.5, 0.4, 0.3)
    C = material.plane_stress_matrix()
    E1, E2, nu12 = 2.0, 0.5, 0.4
    compliance = np.array([[1 / E1, -nu12 / E1], [-nu12 / E1, 1 / E2]])
    np.testing.assert_allclose(np.linalg.inv(C[:2, :2]), compliance, rtol=1e-14)
    assert C[2, 2] == pytest.approx(2 * 0.3)


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("course_stiffness", -1.0, "course_stiffness=-1 N/mm must be > 0"),
        ("shear_stiffness", 0.0, "shear_stiffness=0 N/mm must be > 0"),
        ("poissons_ratio", 1.5, "poissons_ratio=1.5 is outside the valid range (-1.41421"),
    ],
)
def test_svk_rejects_bad_parameters(field, value, message):
    with pytest.raises(InputError) as error:
        OrthotropicSVK(**{field: value, "wale_stiffness": 0.5})
    assert message in str(error.value)


def test_rotated_svk_stress_matches_numpy_rotation():
    """The membrane's law sees R^T E R and R S R^T is C(R^T E R) rotated back, for a constant
    angle and a homogeneous stretch u = (U - I) X, against a plain numpy evaluation."""
    material = OrthotropicSVK(1.0, 0.4, 0.3, 0.1)
    angle, strain = 0.7, np.array([[0.1, 0.03], [0.03, -0.02]])
    domain = mesh.create_unit_square(MPI.COMM_SELF, 1, 1, mesh.CellType.quadrilateral)
    values, vectors = np.linalg.eigh(np.eye(2) + 2 * strain)
    stretch = vectors @ np.diag(np.sqrt(values)) @ vectors.T  # U with U^T U = I + 2E
    u = fem.Function(fem.VectorFunctionSpace(domain, ("Lagrange", 1)))
    u.interpolate(lambda x: (stretch - np.eye(2)) @ x[:2])
    frame = flat_frame(domain, fem.Constant(domain, angle))
    state = membrane_state(u, lambda E: svk_stress(E, material), frame)
    T = frame.tangents
    S = T * state.second_piola_kirchhoff * T.T
    fields = ufl.as_vector(
        [state.reference_strain[0, 1]] + [S[i, j] for i in (0, 1) for j in (0, 1)]
    )
    table = fem.Expression(fields, np.array([[0.5, 0.5]])).eval(np.array([0], dtype=np.int32))
    assert table[0, 0] == pytest.approx(strain[0, 1], abs=1e-15)
    value = table[0, 1:].reshape(2, 2)
    c, s = np.cos(angle), np.sin(angle)
    R = np.array([[c, -s], [s, c]])
    local = R.T @ strain @ R
    voigt = material.plane_stress_matrix() @ [local[0, 0], local[1, 1], local[0, 1]]
    expected = R @ np.array([[voigt[0], voigt[2]], [voigt[2], voigt[1]]]) @ R.T
    np.testing.assert_allclose(value, expected, rtol=0, atol=1e-15)
