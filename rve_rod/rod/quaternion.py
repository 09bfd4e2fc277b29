"""Quaternions as rotation parameters: products, rotation matrices, curvature, conversions.

A quaternion is an array q = (q0, q1, q2, q3) = (q0, v), scalar part first; arrays of
quaternions have the components on the last axis, shape (..., 4). Quaternions need not be
unit: the rotation of q is that of q/|q|,

    R(q) = I + 2/|q|^2 (q0 [v]x + [v]x^2)                      (Rodrigues, non-unit form)

and the material curvature (angular rate per unit parameter) of a quaternion field q(u) is

    k = axial(R^T R') = 2/|q|^2 (q0 v' - q0' v - v x v') = 2/|q|^2 vec(conj(q) * q').

These are the plain NumPy definitions used to build reference frames and to post-process;
the collocation kernels (`_kernels.py`) evaluate the same maps with their derivatives.
"""

import numpy as np

from rve_rod.errors import InputError

__all__ = [
    "align_signs",
    "conjugate",
    "curvature",
    "curvature_rate",
    "from_matrix",
    "from_rotation_vector",
    "left_matrix",
    "multiply",
    "right_matrix",
    "rotation_matrix",
    "skew",
]


def conjugate(q: np.ndarray) -> np.ndarray:
    """conj(q) = (q0, -v), shape (..., 4)."""
    q = np.asarray(q)
    return np.concatenate([q[..., :1], -q[..., 1:]], axis=-1)


def multiply(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product p * q, shape (..., 4); R(p * q) = R(p) R(q)."""
    p, q = np.asarray(p), np.asarray(q)
    p0, p1, p2, p3 = p[..., 0], p[..., 1], p[..., 2], p[..., 3]
    q0, q1, q2, q3 = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack(
        [
            p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
            p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
            p0 * q2 + p2 * q0 + p3 * q1 - p1 * q3,
            p0 * q3 + p3 * q0 + p1 * q2 - p2 * q1,
        ],
        axis=-1,
    )


def left_matrix(p: np.ndarray) -> np.ndarray:
    """The (4, 4) matrix L(p) with p * q = L(p) q, for one quaternion p."""
    p0, p1, p2, p3 = np.asarray(p, dtype=float)
    return np.array(
        [
            [p0, -p1, -p2, -p3],
            [p1, p0, -p3, p2],
            [p2, p3, p0, -p1],
            [p3, -p2, p1, p0],
        ]
    )


def right_matrix(q: np.ndarray) -> np.ndarray:
    """The (4, 4) matrix M(q) with p * q = M(q) p, for one quaternion q."""
    q0, q1, q2, q3 = np.asarray(q, dtype=float)
    return np.array(
        [
            [q0, -q1, -q2, -q3],
            [q1, q0, q3, -q2],
            [q2, -q3, q0, q1],
            [q3, q2, -q1, q0],
        ]
    )


def skew(a: np.ndarray) -> np.ndarray:
    """[a]x with [a]x b = a x b, shape (..., 3, 3)."""
    a = np.asarray(a)
    zero = np.zeros_like(a[..., 0])
    return np.stack(
        [
            np.stack([zero, -a[..., 2], a[..., 1]], axis=-1),
            np.stack([a[..., 2], zero, -a[..., 0]], axis=-1),
            np.stack([-a[..., 1], a[..., 0], zero], axis=-1),
        ],
        axis=-2,
    )


def rotation_matrix(q: np.ndarray) -> np.ndarray:
    """R(q) = I + 2/|q|^2 (q0 [v]x + [v]x^2), shape (..., 3, 3); q need not be unit."""
    q = np.asarray(q)
    v = q[..., 1:]
    vx = skew(v)
    norm2 = np.sum(q * q, axis=-1)[..., None, None]
    return np.eye(3) + 2.0 / norm2 * (q[..., :1, None] * vx + vx @ vx)


def curvature(q: np.ndarray, dq: np.ndarray) -> np.ndarray:
    """Material curvature axial(R^T dR/du) = 2/|q|^2 vec(conj(q) * dq/du), shape (..., 3)."""
    q, dq = np.asarray(q), np.asarray(dq)
    return 2.0 * multiply(conjugate(q), dq)[..., 1:] / np.sum(q * q, axis=-1, keepdims=True)


def from_rotation_vector(theta: np.ndarray) -> np.ndarray:
    """Unit quaternion of the rotation by |theta| about theta/|theta|, shape (..., 4)."""
    theta = np.asarray(theta, dtype=float)
    angle = np.linalg.norm(theta, axis=-1, keepdims=True)
    # sin(a/2)/a -> 1/2 as a -> 0 (Taylor to 4th order below 1e-4 rad)
    small = angle < 1e-4
    safe = np.where(small, 1.0, angle)
    factor = np.where(small, 0.5 - angle**2 / 48.0, np.sin(0.5 * safe) / safe)
    return np.concatenate([np.cos(0.5 * angle), factor * theta], axis=-1)


def from_matrix(rotation: np.ndarray) -> np.ndarray:
    """Unit quaternion of a rotation matrix (Shepperd's method), shape (..., 4).

    Of the two quaternions +-q of a rotation, the one computed from the largest of
    (q0^2, q1^2, q2^2, q3^2) is returned; use `align_signs` for a consistent sequence.
    """
    rotation = np.asarray(rotation, dtype=float)
    if rotation.shape[-2:] != (3, 3):
        raise InputError(f"rotation matrices must have shape (..., 3, 3), got {rotation.shape}")
    flat = rotation.reshape(-1, 3, 3)
    trace = np.trace(flat, axis1=1, axis2=2)
    # 4 q_i^2 for i = 0..3 from the diagonal; pick the largest for a well-conditioned division.
    squares = np.stack(
        [
            1.0 + trace,
            1.0 + 2.0 * flat[:, 0, 0] - trace,
            1.0 + 2.0 * flat[:, 1, 1] - trace,
            1.0 + 2.0 * flat[:, 2, 2] - trace,
        ],
        axis=1,
    )
    pick = np.argmax(squares, axis=1)
    out = np.empty((flat.shape[0], 4))
    # Off-diagonal combinations: 4 q0 q_i and 4 q_i q_j.
    r = flat
    w_x = r[:, 2, 1] - r[:, 1, 2]
    w_y = r[:, 0, 2] - r[:, 2, 0]
    w_z = r[:, 1, 0] - r[:, 0, 1]
    xy = r[:, 0, 1] + r[:, 1, 0]
    xz = r[:, 0, 2] + r[:, 2, 0]
    yz = r[:, 1, 2] + r[:, 2, 1]
    products = np.stack(
        [
            np.stack([squares[:, 0], w_x, w_y, w_z], axis=1),
            np.stack([w_x, squares[:, 1], xy, xz], axis=1),
            np.stack([w_y, xy, squares[:, 2], yz], axis=1),
            np.stack([w_z, xz, yz, squares[:, 3]], axis=1),
        ],
        axis=1,
    )  # products[:, i, :] = 4 q_i q
    rows = products[np.arange(flat.shape[0]), pick]
    out[:] = rows / (2.0 * np.sqrt(squares[np.arange(flat.shape[0]), pick]))[:, None]
    return out.reshape((*rotation.shape[:-2], 4))


def align_signs(quaternions: np.ndarray, reference: np.ndarray | None = None) -> np.ndarray:
    """Flip signs along a sequence (n, 4) so that neighbours have a positive dot product.

    The first quaternion is made to agree with `reference` if given. +-q are the same
    rotation; interpolating a sequence with sign jumps would pass through q = 0.
    """
    out = np.array(quaternions, dtype=float)
    previous = reference
    for i in range(out.shape[0]):
        if previous is not None and np.dot(out[i], previous) < 0.0:
            out[i] = -out[i]
        previous = out[i]
    return out


def curvature_rate(q: np.ndarray, dq: np.ndarray, ddq: np.ndarray) -> np.ndarray:
    """d/du of `curvature(q, dq)`: (2 vec(conj(q) * ddq) - 2 (q . dq) k) / |q|^2, shape (..., 3)."""
    q, dq, ddq = np.asarray(q), np.asarray(dq), np.asarray(ddq)
    norm2 = np.sum(q * q, axis=-1, keepdims=True)
    k = curvature(q, dq)
    return (
        2.0 * multiply(conjugate(q), ddq)[..., 1:]
        - 2.0 * np.sum(q * dq, axis=-1, keepdims=True) * k
    ) / norm2
