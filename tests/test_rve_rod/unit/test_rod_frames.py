"""Reference frames: d3 along the tangent, no twist (rotation minimizing), continuous joints."""

import itertools

import numpy as np
import pytest
from support.rod_cases import arc, helix, straight

from rve_rod.errors import InputError
from rve_rod.geometry.bspline import BSplineCurve
from rve_rod.rod import _kernels, reference_quaternions
from rve_rod.rod.quaternion import curvature, rotation_matrix


def frames_at(curve, controls, params):
    return rotation_matrix(BSplineCurve(curve.degree, curve.knots, controls)(params))


def test_helix_frame_has_tangent_d3_and_no_twist():
    curve = helix(radius=1.0, pitch=0.8, turns=1.5, degree=4, n=40)
    (controls,) = reference_quaternions([curve])
    greville = curve.greville()
    frames = frames_at(curve, controls, greville)
    tangents = curve(greville, 1)
    tangents /= np.linalg.norm(tangents, axis=1, keepdims=True)
    np.testing.assert_allclose(frames[:, :, 2], tangents, atol=1e-12)
    # Bishop frame: the material curvature has no component about d3 (torsion of the frame),
    # although the helix itself has geometric torsion pitch/(2 pi) / (R^2 + (pitch/2pi)^2).
    field = BSplineCurve(curve.degree, curve.knots, controls)
    k = curvature(field(greville), field(greville, 1))
    assert np.abs(k[:, 2]).max() < 1e-5 * np.abs(k).max()


def test_planar_arc_keeps_the_out_of_plane_normal():
    curve = arc(radius=2.0, angle=2.0, degree=3, n=20)
    (controls,) = reference_quaternions([curve], initial_normal=np.array([0.0, 0.0, 5.0]))
    frames = frames_at(curve, controls, curve.greville())
    np.testing.assert_allclose(frames[:, :, 0], np.tile([0.0, 0.0, 1.0], (20, 1)), atol=1e-12)


def test_frames_are_continuous_across_joints():
    pieces = [arc(1.5, 3.0, 4, 12, start=a, stop=b) for a, b in ((0, 0.3), (0.3, 0.7), (0.7, 1))]
    controls = reference_quaternions(pieces)
    for left, right in itertools.pairwise(controls):
        np.testing.assert_allclose(left[-1], right[0], atol=1e-12)


def test_initial_normal_along_tangent_is_rejected():
    curve = straight(length=2.0, degree=3, n=8)
    with pytest.raises(InputError, match="parallel"):
        reference_quaternions([curve], initial_normal=np.array([1.0, 0.0, 0.0]))


def reference_normals(points, tangents, initial_normal):
    """NumPy twin of `_kernels.rotation_minimizing_normals` (double reflection)."""
    normals = [np.asarray(initial_normal, dtype=float)]
    for i in range(points.shape[0] - 1):
        chord = points[i + 1] - points[i]
        c1 = chord @ chord
        normal = normals[i] - (2.0 / c1) * (chord @ normals[i]) * chord
        tangent = tangents[i] - (2.0 / c1) * (chord @ tangents[i]) * chord
        v2 = tangents[i + 1] - tangent
        c2 = v2 @ v2
        normal = normal - (2.0 / c2) * (v2 @ normal) * v2 if c2 > 0 else normal
        normal = normal - (normal @ tangents[i + 1]) * tangents[i + 1]
        normals.append(normal / np.linalg.norm(normal))
    return np.array(normals)


def test_double_reflection_kernel_matches_its_numpy_twin():
    t = np.linspace(0.0, 4.0, 400)
    points = np.stack([np.cos(t), np.sin(2 * t), 0.3 * t], axis=1)
    derivative = np.stack([-np.sin(t), 2 * np.cos(2 * t), np.full_like(t, 0.3)], axis=1)
    tangents = derivative / np.linalg.norm(derivative, axis=1)[:, None]
    start = np.cross(tangents[0], [0.0, 0.0, 1.0])
    start /= np.linalg.norm(start)
    normals = np.empty_like(points)
    normals[0] = start
    _kernels.rotation_minimizing_normals(points, tangents, normals)
    np.testing.assert_allclose(normals, reference_normals(points, tangents, start), atol=1e-14)
    np.testing.assert_allclose(np.einsum("ic,ic->i", normals, tangents), 0.0, atol=1e-14)
