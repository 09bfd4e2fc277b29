"""Numba kernels of the rod collocation: kinematics, equilibrium residual and its Jacobian.

Arrays are components first, collocation points last. The local variables of one collocation
point (18 per point, `kinematics[:, j]`) are

    r' (0:3), r'' (3:6), q (6:10), q' (10:14), q'' (14:18)      (' = d/du, u the curve parameter)

and its reference data (14 per point, `reference[:, j]`) are

    g0 = R0^T r0' (0:3), g0' (3:6), k0 (6:9), k0' (9:12), J = |r0'| (12), J' (13)

from which (Simo-Reissner rod, strains per reference arc length s, ds = J du)

    gamma = R^T r',  k = 2/|q|^2 vec(conj(q) q'),  Gamma = (gamma - g0)/J,  K = (k - k0)/J
    N = A Gamma, M = C K                        (material force and moment, A, C diagonal)
    n = R N, m = R M                            (spatial internal force and moment)
    force balance:   dn/ds + f = R (k x N + N') / J + f = 0
    moment balance:  dm/ds + dr/ds x n + l = R (k x M + M' + gamma x N) / J + l = 0
    gauge:           |q|^2 - 1 = 0

The kernels return the residual without the external loads f, l (added by the model) and its
derivative with respect to the 18 local variables; `scatter_jacobian` chains that with the
basis functions and adds it into a CSR data array with a fixed pattern.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from rve_rod._kernels import record


@njit(cache=True)
def gather_kinematics(control, first, basis, out):
    """Local variables at collocation points from control-point values.

    Args:
        control: (7, n_points) control values, rows x (0:3) and q (3:7).
        first: (m,) index of the first of the p+1 control points acting at point j.
        basis: (3, p+1, m) basis values, first and second derivatives at the points.
        out: (18, m) output, see the module docstring.
    """
    m = first.shape[0]
    width = basis.shape[1]
    for j in range(m):
        for c in range(18):
            out[c, j] = 0.0
        for a in range(width):
            g = first[j] + a
            b0 = basis[0, a, j]
            b1 = basis[1, a, j]
            b2 = basis[2, a, j]
            for c in range(3):
                out[c, j] += b1 * control[c, g]
                out[3 + c, j] += b2 * control[c, g]
            for c in range(4):
                value = control[3 + c, g]
                out[6 + c, j] += b0 * value
                out[10 + c, j] += b1 * value
                out[14 + c, j] += b2 * value


@njit(cache=True)
def _rotation(q, rot, d_rot):
    """R(q) (3, 3) and dR/dq_a (4, 3, 3) for a non-unit quaternion q (4,)."""
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    s = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3
    a = q0 * q0 - q1 * q1 - q2 * q2 - q3 * q3
    # P = (q0^2 - v.v) I + 2 v v^T + 2 q0 [v]x, R = P / |q|^2
    rot[0, 0] = (a + 2.0 * q1 * q1) / s
    rot[0, 1] = (2.0 * q1 * q2 - 2.0 * q0 * q3) / s
    rot[0, 2] = (2.0 * q1 * q3 + 2.0 * q0 * q2) / s
    rot[1, 0] = (2.0 * q1 * q2 + 2.0 * q0 * q3) / s
    rot[1, 1] = (a + 2.0 * q2 * q2) / s
    rot[1, 2] = (2.0 * q2 * q3 - 2.0 * q0 * q1) / s
    rot[2, 0] = (2.0 * q1 * q3 - 2.0 * q0 * q2) / s
    rot[2, 1] = (2.0 * q2 * q3 + 2.0 * q0 * q1) / s
    rot[2, 2] = (a + 2.0 * q3 * q3) / s
    # dP/dq_a, then dR/dq_a = (dP/dq_a - 2 q_a R) / |q|^2
    d_rot[0, 0, 0], d_rot[0, 0, 1], d_rot[0, 0, 2] = q0, -q3, q2
    d_rot[0, 1, 0], d_rot[0, 1, 1], d_rot[0, 1, 2] = q3, q0, -q1
    d_rot[0, 2, 0], d_rot[0, 2, 1], d_rot[0, 2, 2] = -q2, q1, q0
    d_rot[1, 0, 0], d_rot[1, 0, 1], d_rot[1, 0, 2] = q1, q2, q3
    d_rot[1, 1, 0], d_rot[1, 1, 1], d_rot[1, 1, 2] = q2, -q1, -q0
    d_rot[1, 2, 0], d_rot[1, 2, 1], d_rot[1, 2, 2] = q3, q0, -q1
    d_rot[2, 0, 0], d_rot[2, 0, 1], d_rot[2, 0, 2] = -q2, q1, q0
    d_rot[2, 1, 0], d_rot[2, 1, 1], d_rot[2, 1, 2] = q1, q2, q3
    d_rot[2, 2, 0], d_rot[2, 2, 1], d_rot[2, 2, 2] = -q0, q3, -q2
    d_rot[3, 0, 0], d_rot[3, 0, 1], d_rot[3, 0, 2] = -q3, -q0, q1
    d_rot[3, 1, 0], d_rot[3, 1, 1], d_rot[3, 1, 2] = q0, -q3, q2
    d_rot[3, 2, 0], d_rot[3, 2, 1], d_rot[3, 2, 2] = q1, q2, q3
    for b in range(4):
        for r in range(3):
            for c in range(3):
                d_rot[b, r, c] = (2.0 * d_rot[b, r, c] - 2.0 * q[b] * rot[r, c]) / s


@njit(cache=True)
def _w_matrix(q, out):
    """W(q) (3, 4) with vec(conj(q) * p) = W(q) p."""
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    out[0, 0], out[0, 1], out[0, 2], out[0, 3] = -q1, q0, q3, -q2
    out[1, 0], out[1, 1], out[1, 2], out[1, 3] = -q2, -q3, q0, q1
    out[2, 0], out[2, 1], out[2, 2], out[2, 3] = -q3, q2, -q1, q0


@njit(cache=True)
def _cross(a, b, out):
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@njit(cache=True)
def _add_cross_columns(a, columns, sign, out):
    """out[:, c] += sign * (a x columns[:, c]) for every column c of a (3, k) array."""
    for c in range(columns.shape[1]):
        x, y, z = columns[0, c], columns[1, c], columns[2, c]
        out[0, c] += sign * (a[1] * z - a[2] * y)
        out[1, c] += sign * (a[2] * x - a[0] * z)
        out[2, c] += sign * (a[0] * y - a[1] * x)


@record
class PointEquations(NamedTuple):
    """Local variables and equation buffers of m collocation points (`collocation_equations`).

    Attributes:
        kinematics: (18, m) local variables (input).
        residual: (7, m) output: force balance (N/mm), moment balance (N), gauge (-).
        section: (6, m) output: n (N) and m (N mm), spatial.
        d_residual: (7, 18, m) output, derivative of `residual` w.r.t. the local variables.
        d_section: (6, 18, m) output, derivative of `section`.
    """

    kinematics: np.ndarray
    residual: np.ndarray
    section: np.ndarray
    d_residual: np.ndarray
    d_section: np.ndarray


@njit(cache=True)
def collocation_equations(point, reference, stiffness, with_jacobian):
    """Equilibrium residual and section forces at m collocation points (module docstring).

    Args:
        point: `PointEquations`: the local variables, and the outputs it receives.
        reference: (14, m) reference data.
        stiffness: (6, m) diag(A) (0:3, N) and diag(C) (3:6, N mm^2) at each point.
        with_jacobian: also fill `d_residual` and `d_section`.

    `rve_rod.rod.strains` is the same residual in plain NumPy.
    """
    kinematics, residual, section = point.kinematics, point.residual, point.section
    d_residual, d_section = point.d_residual, point.d_section
    m_points = kinematics.shape[1]
    rot = np.empty((3, 3))
    d_rot = np.empty((4, 3, 3))
    w_q = np.empty((3, 4))
    w_d = np.empty((3, 4))
    w_dd = np.empty((3, 4))
    k = np.empty(3)
    ku = np.empty(3)
    gam = np.empty(3)
    gamu = np.empty(3)
    big_n = np.empty(3)
    big_nu = np.empty(3)
    big_m = np.empty(3)
    big_mu = np.empty(3)
    f_mat = np.empty(3)
    m_mat = np.empty(3)
    tmp = np.empty(3)
    d_gam = np.empty((3, 18))
    d_k = np.empty((3, 18))
    d_ku = np.empty((3, 18))
    d_gamu = np.empty((3, 18))
    d_n = np.empty((3, 18))
    d_nu = np.empty((3, 18))
    d_m = np.empty((3, 18))
    d_mu = np.empty((3, 18))
    d_f = np.empty((3, 18))
    d_mm = np.empty((3, 18))
    for j in range(m_points):
        ru = kinematics[0:3, j]
        ruu = kinematics[3:6, j]
        q = kinematics[6:10, j]
        qd = kinematics[10:14, j]
        qdd = kinematics[14:18, j]
        jac = reference[12, j]
        jac_u = reference[13, j]
        s = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]
        c = q[0] * qd[0] + q[1] * qd[1] + q[2] * qd[2] + q[3] * qd[3]
        _rotation(q, rot, d_rot)
        _w_matrix(q, w_q)
        # k = 2 W(q) q' / s ; k' = (2 W(q) q'' - 2 (q.q') k) / s
        for i in range(3):
            acc = 0.0
            acc2 = 0.0
            for b in range(4):
                acc += w_q[i, b] * qd[b]
                acc2 += w_q[i, b] * qdd[b]
            k[i] = 2.0 * acc / s
            ku[i] = (2.0 * acc2 - 2.0 * c * k[i]) / s
        # gamma = R^T r', gamma' = R^T r'' - k x gamma
        for i in range(3):
            gam[i] = rot[0, i] * ru[0] + rot[1, i] * ru[1] + rot[2, i] * ru[2]
        _cross(k, gam, tmp)
        for i in range(3):
            gamu[i] = rot[0, i] * ruu[0] + rot[1, i] * ruu[1] + rot[2, i] * ruu[2] - tmp[i]
        for i in range(3):
            strain = (gam[i] - reference[i, j]) / jac
            strain_u = (gamu[i] - reference[3 + i, j]) / jac - strain * jac_u / jac
            bend = (k[i] - reference[6 + i, j]) / jac
            bend_u = (ku[i] - reference[9 + i, j]) / jac - bend * jac_u / jac
            big_n[i] = stiffness[i, j] * strain
            big_nu[i] = stiffness[i, j] * strain_u
            big_m[i] = stiffness[3 + i, j] * bend
            big_mu[i] = stiffness[3 + i, j] * bend_u
        # F = k x N + N', Mm = k x M + M' + gamma x N
        _cross(k, big_n, f_mat)
        _cross(k, big_m, m_mat)
        _cross(gam, big_n, tmp)
        for i in range(3):
            f_mat[i] += big_nu[i]
            m_mat[i] += big_mu[i] + tmp[i]
        for i in range(3):
            acc_f = 0.0
            acc_m = 0.0
            acc_n = 0.0
            acc_mo = 0.0
            for b in range(3):
                acc_f += rot[i, b] * f_mat[b]
                acc_m += rot[i, b] * m_mat[b]
                acc_n += rot[i, b] * big_n[b]
                acc_mo += rot[i, b] * big_m[b]
            residual[i, j] = acc_f / jac
            residual[3 + i, j] = acc_m / jac
            section[i, j] = acc_n
            section[3 + i, j] = acc_mo
        residual[6, j] = s - 1.0
        if not with_jacobian:
            continue

        # --- derivatives with respect to the 18 local variables ---
        _w_matrix(qd, w_d)
        _w_matrix(qdd, w_dd)
        d_gam[:] = 0.0
        d_k[:] = 0.0
        d_ku[:] = 0.0
        d_gamu[:] = 0.0
        for i in range(3):
            for b in range(3):
                d_gam[i, b] = rot[b, i]
                d_gamu[i, 3 + b] = rot[b, i]
            for b in range(4):
                acc = 0.0
                acc2 = 0.0
                for r in range(3):
                    acc += d_rot[b, r, i] * ru[r]
                    acc2 += d_rot[b, r, i] * ruu[r]
                d_gam[i, 6 + b] = acc
                d_gamu[i, 6 + b] = acc2
                # dk/dq = (-2 W(q') - 2 k q^T)/s, dk/dq' = 2 W(q)/s  (vec(conj(q) p) = -W(p) q)
                d_k[i, 6 + b] = (-2.0 * w_d[i, b] - 2.0 * k[i] * q[b]) / s
                d_k[i, 10 + b] = 2.0 * w_q[i, b] / s
        for i in range(3):
            for b in range(4):
                d_ku[i, 14 + b] = 2.0 * w_q[i, b] / s
                d_ku[i, 10 + b] = (-2.0 * k[i] * q[b] - 2.0 * c * d_k[i, 10 + b]) / s
                d_ku[i, 6 + b] = (
                    -2.0 * w_dd[i, b]
                    - 2.0 * k[i] * qd[b]
                    - 2.0 * c * d_k[i, 6 + b]
                    - 2.0 * ku[i] * q[b]
                ) / s
        # gamma' = R^T r'' - k x gamma
        _add_cross_columns(k, d_gam, -1.0, d_gamu)
        _add_cross_columns(gam, d_k, 1.0, d_gamu)
        for i in range(3):
            a_i = stiffness[i, j]
            c_i = stiffness[3 + i, j]
            for col in range(18):
                d_strain = d_gam[i, col] / jac
                d_n[i, col] = a_i * d_strain
                d_nu[i, col] = a_i * (d_gamu[i, col] / jac - d_strain * jac_u / jac)
                d_bend = d_k[i, col] / jac
                d_m[i, col] = c_i * d_bend
                d_mu[i, col] = c_i * (d_ku[i, col] / jac - d_bend * jac_u / jac)
        d_f[:] = d_nu
        _add_cross_columns(k, d_n, 1.0, d_f)
        _add_cross_columns(big_n, d_k, -1.0, d_f)
        d_mm[:] = d_mu
        _add_cross_columns(k, d_m, 1.0, d_mm)
        _add_cross_columns(big_m, d_k, -1.0, d_mm)
        _add_cross_columns(gam, d_n, 1.0, d_mm)
        _add_cross_columns(big_n, d_gam, -1.0, d_mm)
        for i in range(3):
            for col in range(18):
                acc_f = 0.0
                acc_m = 0.0
                acc_n = 0.0
                acc_mo = 0.0
                for b in range(3):
                    acc_f += rot[i, b] * d_f[b, col]
                    acc_m += rot[i, b] * d_mm[b, col]
                    acc_n += rot[i, b] * d_n[b, col]
                    acc_mo += rot[i, b] * d_m[b, col]
                d_residual[i, col, j] = acc_f / jac
                d_residual[3 + i, col, j] = acc_m / jac
                d_section[i, col, j] = acc_n
                d_section[3 + i, col, j] = acc_mo
            for b in range(4):
                acc_f = 0.0
                acc_m = 0.0
                acc_n = 0.0
                acc_mo = 0.0
                for r in range(3):
                    acc_f += d_rot[b, i, r] * f_mat[r]
                    acc_m += d_rot[b, i, r] * m_mat[r]
                    acc_n += d_rot[b, i, r] * big_n[r]
                    acc_mo += d_rot[b, i, r] * big_m[r]
                d_residual[i, 6 + b, j] += acc_f / jac
                d_residual[3 + i, 6 + b, j] += acc_m / jac
                d_section[i, 6 + b, j] += acc_n
                d_section[3 + i, 6 + b, j] += acc_mo
        for col in range(18):
            d_residual[6, col, j] = 0.0
        for b in range(4):
            d_residual[6, 6 + b, j] = 2.0 * q[b]


@njit(cache=True)
def scatter_jacobian(d_local, basis, index, data):
    """Chain local derivatives with the basis and write them into CSR data.

    Args:
        d_local: (7, 18, m) derivative of the 7 equations w.r.t. the local variables.
        basis: (3, p+1, m) basis values, first and second derivatives.
        index: (7, 7, p+1, m) CSR data position of (equation r, control dof c of local control
            point a) at point j (each position at most once), or -1 where the row is not
            assembled (end-condition rows).
        data: (nnz,) CSR data; the positions of `index` are written, the others left as
            they are.
    """
    m = d_local.shape[2]
    width = basis.shape[1]
    for j in range(m):
        for a in range(width):
            b0 = basis[0, a, j]
            b1 = basis[1, a, j]
            b2 = basis[2, a, j]
            for r in range(7):
                if index[r, 0, a, j] < 0:
                    continue
                for c in range(3):
                    data[index[r, c, a, j]] = d_local[r, c, j] * b1 + d_local[r, 3 + c, j] * b2
                for c in range(4):
                    data[index[r, 3 + c, a, j]] = (
                        d_local[r, 6 + c, j] * b0
                        + d_local[r, 10 + c, j] * b1
                        + d_local[r, 14 + c, j] * b2
                    )


@njit(cache=True)
def add_entries(matrix, rows, columns, values, out):
    """The CSR matrix A + B, A in CSR with sorted column indices, B as COO entries (repeated
    entries summed), with sorted column indices and no explicit zeros: what scipy's
    `A + scipy.sparse.coo_matrix(B)` gives, without sorting A's entries again.

    Args:
        matrix: A as its CSR arrays (indptr (n+1,), indices (nnz,), data (nnz,)).
        rows, columns: (k,) int B's entries' row and column; values: (k,) their values.
        out: the sum's CSR arrays (indptr (n+1,), indices and data of capacity nnz + k).
    Returns the number of nonzeros of the sum.
    """
    indptr, indices, data = matrix
    out_indptr, out_indices, out_data = out
    n = indptr.size - 1
    # B's entries by row, then column: two stable counting sorts (column first)
    by_column = _counting_sort(columns, np.arange(rows.size), n)
    order = _counting_sort(rows, by_column, n)
    start = np.zeros(n + 1, dtype=np.int64)
    for entry in range(rows.size):
        start[rows[entry] + 1] += 1
    for row in range(n):
        start[row + 1] += start[row]
    count = 0
    out_indptr[0] = 0
    for row in range(n):
        a, end = indptr[row], indptr[row + 1]
        b, last = start[row], start[row + 1]
        while a < end or b < last:
            if b == last or (a < end and indices[a] < columns[order[b]]):
                column, total = indices[a], data[a]
                a += 1
            else:
                column, added = columns[order[b]], 0.0
                while b < last and columns[order[b]] == column:
                    added += values[order[b]]
                    b += 1
                total = added
                if a < end and indices[a] == column:
                    total = data[a] + added
                    a += 1
            if total != 0.0:
                out_indices[count] = column
                out_data[count] = total
                count += 1
        out_indptr[row + 1] = count
    return count


@njit(cache=True)
def _counting_sort(keys, items, n_keys):
    """`items` (indices into keys) stably sorted by their keys in [0, n_keys)."""
    start = np.zeros(n_keys + 1, dtype=np.int64)
    for item in items:
        start[keys[item] + 1] += 1
    for key in range(n_keys):
        start[key + 1] += start[key]
    out = np.empty(items.size, dtype=np.int64)
    for item in items:
        out[start[keys[item]]] = item
        start[keys[item]] += 1
    return out


@njit(cache=True)
def rotation_minimizing_normals(points, tangents, out):
    """Normals d1 of the rotation-minimizing frame along a sampled curve by double reflection
    (Wang, Juttler, Zheng & Liu, ACM TOG 27(1), 2008), after the first (given).

    Args:
        points: (m, 3) curve points (mm), in order.
        tangents: (m, 3) unit tangents at the points.
        out: (m, 3) normals; out[0] holds d1 at the first point (orthogonal to tangents[0]),
            the others are written.
    """
    for i in range(points.shape[0] - 1):
        chord = points[i + 1] - points[i]
        normal = out[i].copy()
        tangent = tangents[i].copy()
        c1 = chord @ chord
        if c1 > 0.0:
            normal -= (2.0 / c1) * (chord @ normal) * chord
            tangent -= (2.0 / c1) * (chord @ tangent) * chord
        v2 = tangents[i + 1] - tangent
        c2 = v2 @ v2
        if c2 > 0:
            normal -= (2.0 / c2) * (v2 @ normal) * v2
        # Remove the round-off drift from orthogonality before normalizing.
        normal -= (normal @ tangents[i + 1]) * tangents[i + 1]
        out[i + 1] = normal / np.sqrt(normal @ normal)
