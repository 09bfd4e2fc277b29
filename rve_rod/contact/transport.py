"""Carrying a vector along with a turning curve tangent: the minimal rotation a -> b.

The friction anchor's offset is stored at a commit next to the master's unit tangent a there;
when the master has turned to the tangent b, the offset is turned with it by the smallest
rotation that takes a to b (about a x b),

    R(a, b) v = v + k x v + k x (k x v) / (1 + a.b),   k = a x b,

(Rodrigues' formula with sin = |k| and 1 - cos = |k|^2 / (1 + a.b)), so that a pair of yarns
that turns rigidly about any axis normal to the master's tangent keeps its offset in its own
frame and registers no slip (`rve_rod.contact.friction`). A turn about the tangent itself
(a twist of the pair about the master's axis) is not seen: the tangent does not move.
"""

from typing import NamedTuple

import numpy as np


class TransportedVectors(NamedTuple):
    """Vectors carried from tangent a to tangent b (arrays over k).

    Attributes:
        vectors: (3, k) R(a, b) v.
        derivative: (3, 3, k) d(R v) / dC', the derivative with respect to the unnormalized
            tangent C' with b = C' / |C'| (a and v held fixed).
    """

    vectors: np.ndarray
    derivative: np.ndarray


def _cross_matrix(u: np.ndarray) -> np.ndarray:
    """[u]x (3, 3, k) of vectors u (3, k): [u]x v = u x v."""
    zero = np.zeros(u.shape[1])
    return np.array(
        [[zero, -u[2], u[1]], [u[2], zero, -u[0]], [-u[1], u[0], zero]],
    )


def transport(start: np.ndarray, tangent: np.ndarray, vectors: np.ndarray) -> TransportedVectors:
    """Turn `vectors` (3, k) by the minimal rotation from the unit tangents `start` (3, k) to
    the directions of `tangent` (3, k, unnormalized, e.g. C' = dC/dtau), with the derivative.

    The tangents must not reverse (a.b > -1); they turn by a few degrees per load step.
    """
    length = np.linalg.norm(tangent, axis=0)
    b = tangent / length
    a = start
    k = np.cross(a, b, axis=0)
    scale = 1.0 / (1.0 + np.einsum("ik,ik->k", a, b))
    k_v = np.cross(k, vectors, axis=0)
    k_k_v = np.cross(k, k_v, axis=0)
    rotated = vectors + k_v + scale * k_k_v
    # d/db: dk = a x db, d(a.b) = a.db
    cross_a = _cross_matrix(a)
    dk_v = -np.einsum("ijk,jlk->ilk", _cross_matrix(vectors), cross_a)  # d(k x v) = -[v]x [a]x db
    dk_kv = -np.einsum("ijk,jlk->ilk", _cross_matrix(k_v), cross_a) + np.einsum(
        "ijk,jlk->ilk", _cross_matrix(k), dk_v
    )
    d_b = dk_v + scale * dk_kv - (scale**2 * k_k_v)[:, None, :] * a[None, :, :]
    projector = (np.eye(3)[:, :, None] - b[:, None, :] * b[None, :, :]) / length
    derivative = np.einsum("ijk,jlk->ilk", d_b, projector)
    return TransportedVectors(rotated, derivative)
