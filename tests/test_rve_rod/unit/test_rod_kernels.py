"""Numba kernels against plain NumPy references.

The reference residual is the library's `rve_rod.rod.strains.collocation_equations`: it follows
a different route from the kernel (spatial form n' = R' N + R N' with R' = R [k]x, moment
balance m' + r' x n, rotation matrix from the Rodrigues form) and works on complex numbers, so
its derivatives come from the complex step (exact to round-off): the kernel's analytic
Jacobian is compared with them.
"""

import numpy as np
import pytest
import scipy.sparse

from rve_rod.geometry.bspline import basis_functions, basis_matrix, open_knot_vector
from rve_rod.rod import _kernels
from rve_rod.rod.strains import collocation_equations as reference_equations


def random_point_data(seed, m=7):
    rng = np.random.default_rng(seed)
    kinematics = rng.normal(size=(18, m))
    if seed % 2:  # near a physical state: unit quaternions, moderate gradients
        kinematics[6:10] /= np.linalg.norm(kinematics[6:10], axis=0)
        kinematics[10:] *= 0.1
    reference = rng.normal(size=(14, m))
    reference[12] = 0.5 + rng.random(m)
    stiffness = np.concatenate([rng.uniform(1, 1e3, (3, m)), rng.uniform(1e-3, 1, (3, m))])
    return kinematics, reference, stiffness


def kernel_equations(kinematics, reference, stiffness, with_jacobian=True):
    m = kinematics.shape[1]
    out = _kernels.PointEquations(
        kinematics, np.empty((7, m)), np.empty((6, m)), np.zeros((7, 18, m)), np.zeros((6, 18, m))
    )
    _kernels.collocation_equations(out, reference, stiffness, with_jacobian)
    return out[1:]


@pytest.mark.parametrize("seed", range(6))
def test_collocation_residual_matches_numpy_reference(seed):
    kinematics, reference, stiffness = random_point_data(seed)
    residual, section, _, _ = kernel_equations(kinematics, reference, stiffness, False)
    expected_residual, expected_section = reference_equations(kinematics, reference, stiffness)
    scale = np.abs(expected_residual).max(axis=1, keepdims=True)
    np.testing.assert_allclose(residual / scale, expected_residual / scale, atol=1e-13)
    np.testing.assert_allclose(section, expected_section, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("seed", range(6))
def test_collocation_jacobian_matches_complex_step(seed):
    kinematics, reference, stiffness = random_point_data(seed)
    _, _, d_residual, d_section = kernel_equations(kinematics, reference, stiffness)
    step = 1e-30
    for variable in range(18):
        perturbed = kinematics.astype(complex)
        perturbed[variable] += 1j * step
        residual, section = reference_equations(perturbed, reference, stiffness)
        scale = np.abs(d_residual).max(axis=(1, 2))[:, None] + 1e-300
        np.testing.assert_allclose(
            d_residual[:, variable] / scale, residual.imag / step / scale, atol=1e-12
        )
        np.testing.assert_allclose(d_section[:, variable], section.imag / step, atol=1e-10)


@pytest.mark.parametrize("degree", [2, 3, 4])
def test_gather_kinematics_matches_basis_matrices(degree):
    rng = np.random.default_rng(degree)
    n = 9
    knots = open_knot_vector(degree, n)
    params = rng.uniform(0, 1, 13)
    control = rng.normal(size=(7, n))
    basis = basis_functions(knots, degree, params, derivatives=2)
    out = np.empty((18, params.size))
    _kernels.gather_kinematics(
        control, basis.spans - degree, np.ascontiguousarray(basis.values.transpose(0, 2, 1)), out
    )
    matrices = [basis_matrix(knots, degree, params, k) for k in range(3)]
    np.testing.assert_allclose(out[0:3], (matrices[1] @ control[:3].T).T, atol=1e-12)
    np.testing.assert_allclose(out[3:6], (matrices[2] @ control[:3].T).T, atol=1e-10)
    for k in range(3):
        np.testing.assert_allclose(
            out[6 + 4 * k : 10 + 4 * k], (matrices[k] @ control[3:].T).T, atol=1e-10
        )


@pytest.mark.parametrize("degree", [2, 4])
def test_scatter_jacobian_matches_dense_chain_rule(degree):
    rng = np.random.default_rng(degree)
    n = 8
    knots = open_knot_vector(degree, n)
    params = np.linspace(0, 1, n)
    basis = basis_functions(knots, degree, params, derivatives=2)
    values = np.ascontiguousarray(basis.values.transpose(0, 2, 1))
    d_local = rng.normal(size=(7, 18, n))
    matrices = [basis_matrix(knots, degree, params, k).toarray() for k in range(3)]
    # dense: d res_r(j) / d x_c(i) = d_local[r, c] B1[j, i] + d_local[r, 3 + c] B2[j, i], etc.
    dense = np.zeros((7 * n, 7 * n))
    for r in range(7):
        for c in range(3):
            dense[r::7, c::7] = (
                d_local[r, c][:, None] * matrices[1] + d_local[r, 3 + c][:, None] * matrices[2]
            )
        for c in range(4):
            dense[r::7, 3 + c :: 7] = sum(
                d_local[r, 6 + 4 * k + c][:, None] * matrices[k] for k in range(3)
            )
    # a CSR pattern holding exactly the (p+1)-wide blocks, rows 0..5 of point 0 left out
    first = basis.spans - degree
    rows = np.broadcast_to(
        7 * np.arange(n)[None, None, None, :] + np.arange(7)[:, None, None, None],
        (7, 7, degree + 1, n),
    ).copy()
    rows[:6, :, :, 0] = -1
    columns = np.broadcast_to(
        7 * (first[None, None, None, :] + np.arange(degree + 1)[None, None, :, None])
        + np.arange(7)[None, :, None, None],
        (7, 7, degree + 1, n),
    )
    mask = rows >= 0
    pattern = scipy.sparse.csr_matrix(
        (np.ones(mask.sum()), (rows[mask], columns[mask])), shape=(7 * n, 7 * n)
    )
    pattern.sort_indices()
    keys = np.repeat(np.arange(7 * n), np.diff(pattern.indptr)) * 7 * n + pattern.indices
    index = np.full(rows.shape, -1, dtype=np.int64)
    index[mask] = np.searchsorted(keys, rows[mask] * 7 * n + columns[mask])
    data = np.full(pattern.nnz, np.nan)  # every position of the pattern must be written
    _kernels.scatter_jacobian(d_local, values, index, data)
    assembled = scipy.sparse.csr_matrix((data, pattern.indices, pattern.indptr)).toarray()
    dense[:6] = 0.0
    np.testing.assert_allclose(assembled, dense, atol=1e-12)


@pytest.mark.parametrize("seed", range(4))
def test_add_entries_matches_scipys_sum(seed):
    """A (CSR, sorted) + B (COO with repeated entries, inside and outside A's pattern, some
    cancelling entries of A exactly): the same matrix as scipy's sum, sorted, no zeros."""
    rng = np.random.default_rng(seed)
    n = 40
    matrix = scipy.sparse.random(n, n, density=0.1, format="csr", random_state=seed)
    matrix.sort_indices()
    k = 300
    rows, columns = rng.integers(0, n, k), rng.integers(0, n, k)
    values = rng.normal(size=k)
    stored = matrix.tocoo()
    cancel = rng.choice(stored.nnz, 5, replace=False)  # entries of B that cancel A's
    rows = np.concatenate([rows, stored.row[cancel]])
    columns = np.concatenate([columns, stored.col[cancel]])
    values = np.concatenate([values, -stored.data[cancel]])
    capacity = matrix.nnz + values.size
    out = (np.empty(n + 1, np.int32), np.empty(capacity, np.int32), np.empty(capacity))
    count = _kernels.add_entries(
        (matrix.indptr, matrix.indices, matrix.data), rows, columns, values, out
    )
    expected = matrix + scipy.sparse.coo_matrix((values, (rows, columns)), shape=(n, n))
    expected.sort_indices()
    expected.eliminate_zeros()
    np.testing.assert_array_equal(out[0], expected.indptr)
    np.testing.assert_array_equal(out[1][:count], expected.indices)
    np.testing.assert_allclose(out[2][:count], expected.data, rtol=1e-13, atol=1e-15)
