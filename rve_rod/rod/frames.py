"""Reference cross-section frames of a rod: rotation-minimizing frames along B-spline
centrelines, as quaternion control points on the centreline's knots.

The frame (d1, d2, d3) has d3 along the tangent. It is propagated along the curve by the
double-reflection method (Wang, Juttler, Zheng & Liu, ACM TOG 27(1), 2008), sampled at the
Greville abscissae, converted to quaternions with consistent signs and interpolated there by a
4D B-spline on the same knots. Between Greville points the interpolated frame is not exactly
orthonormal-tangent; this does not matter because rod strains are measured relative to this
same discrete reference (it is stress free by construction).
"""

from collections.abc import Sequence

import numpy as np

from rve_rod.errors import InputError
from rve_rod.geometry.bspline import BSplineCurve, collocation_solve
from rve_rod.rod import _kernels, quaternion

__all__ = [
    "quaternions_from_frames",
    "reference_quaternions",
]

_SAMPLES_PER_INTERVAL = 16
"""Double-reflection substeps between neighbouring Greville points (error ~ h^4 per step)."""


def rotation_minimizing_frames(
    points: np.ndarray, tangents: np.ndarray, initial_normal: np.ndarray
) -> np.ndarray:
    """Frames (m, 3, 3) with columns (d1, d2, d3) along a sampled curve, d3 = unit tangent
    (`_kernels.rotation_minimizing_normals`).

    Args:
        points: (m, 3) curve points (mm), in order.
        tangents: (m, 3) unit tangents at the points.
        initial_normal: (3,) d1 at the first point; must be orthogonal to tangents[0].
    """
    normals = np.empty((points.shape[0], 3))
    normals[0] = initial_normal
    _kernels.rotation_minimizing_normals(
        np.ascontiguousarray(points, dtype=float),
        np.ascontiguousarray(tangents, dtype=float),
        normals,
    )
    binormals = np.cross(tangents, normals)
    return np.stack([normals, binormals, tangents], axis=2)


def quaternions_from_frames(
    curve: BSplineCurve, frames: np.ndarray, previous: np.ndarray | None = None
) -> np.ndarray:
    """Quaternion control points (n, 4) interpolating `frames` (n, 3, 3) at the Greville points.

    Signs are made consistent along the sequence (and with the quaternion `previous`, e.g. the
    end of the preceding patch) before interpolation.
    """
    n = curve.n_control_points
    if frames.shape != (n, 3, 3):
        raise InputError(f"frames must have shape ({n}, 3, 3), one per Greville point")
    values = quaternion.align_signs(quaternion.from_matrix(frames), previous)
    return collocation_solve(curve.knots, curve.degree, curve.greville(), values)


def reference_quaternions(
    curves: Sequence[BSplineCurve], initial_normal: np.ndarray | None = None
) -> list[np.ndarray]:
    """Quaternion control points of a rotation-minimizing frame along consecutive curves.

    The curves form one rod (end of curve k at the start of curve k+1). The frame is carried
    across each joint (parallel-transported to the next start tangent if the tangent jumps), so
    the reference frames of joined patches agree.

    Args:
        curves: centrelines, each a 3D BSplineCurve (mm).
        initial_normal: d1 at the start of the first curve, projected onto the normal plane;
            default: the coordinate axis least aligned with the tangent.

    Returns:
        One (n_k, 4) array per curve.
    """
    result = []
    normal = None if initial_normal is None else np.asarray(initial_normal, dtype=float)
    previous_quaternion = None
    previous_tangent = None
    for k, curve in enumerate(curves):
        if curve.dim != 3:
            raise InputError(f"curve {k} has dimension {curve.dim}; rods need 3D centrelines")
        greville = curve.greville()
        fractions = np.arange(_SAMPLES_PER_INTERVAL) / _SAMPLES_PER_INTERVAL
        dense = np.concatenate(
            [(greville[:-1, None] + np.diff(greville)[:, None] * fractions).ravel(), greville[-1:]]
        )
        derivatives = curve.derivatives(dense, 1)
        speed = np.linalg.norm(derivatives[1], axis=1)
        if np.any(speed <= 0.0):
            raise InputError(f"curve {k} has a zero tangent; rods need regular centrelines")
        tangents = derivatives[1] / speed[:, None]
        if normal is None:
            normal = np.eye(3)[np.argmin(np.abs(tangents[0]))]
        elif previous_tangent is not None:
            normal = _transport(normal, previous_tangent, tangents[0])
        size = np.linalg.norm(normal)
        normal = normal - (normal @ tangents[0]) * tangents[0]
        length = np.linalg.norm(normal)
        if length < 1e-6 * size or size == 0.0:
            raise InputError("initial_normal is (nearly) parallel to the initial tangent")
        frames = rotation_minimizing_frames(derivatives[0], tangents, normal / length)
        at_greville = frames[::_SAMPLES_PER_INTERVAL]
        controls = quaternions_from_frames(curve, at_greville, previous_quaternion)
        result.append(controls)
        normal = frames[-1, :, 0]
        previous_tangent = tangents[-1]
        previous_quaternion = controls[-1]
    return result


def _transport(vector: np.ndarray, from_tangent: np.ndarray, to_tangent: np.ndarray) -> np.ndarray:
    """Rotate `vector` by the smallest rotation taking `from_tangent` to `to_tangent`."""
    axis = np.cross(from_tangent, to_tangent)
    sine = np.linalg.norm(axis)
    cosine = from_tangent @ to_tangent
    if sine < 1e-14:
        return vector
    angle = np.arctan2(sine, cosine)
    rotation = quaternion.rotation_matrix(quaternion.from_rotation_vector(axis / sine * angle))
    return rotation @ vector
