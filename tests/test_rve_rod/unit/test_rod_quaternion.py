"""Quaternion maps against their definitions: orthogonality, composition, finite differences."""

import numpy as np
import pytest

from rve_rod.rod import quaternion

RNG = np.random.default_rng(11)


def axial(skew_matrix):
    return np.array([skew_matrix[2, 1], skew_matrix[0, 2], skew_matrix[1, 0]])


def test_rotation_of_non_unit_quaternion_is_orthonormal_and_scale_invariant():
    q = RNG.normal(size=(20, 4))
    rotation = quaternion.rotation_matrix(q)
    np.testing.assert_allclose(
        rotation @ np.swapaxes(rotation, 1, 2),
        np.broadcast_to(np.eye(3), rotation.shape),
        atol=1e-13,
    )
    np.testing.assert_allclose(np.linalg.det(rotation), 1.0, atol=1e-14)
    np.testing.assert_allclose(quaternion.rotation_matrix(3.7 * q), rotation, atol=1e-14)
    np.testing.assert_allclose(quaternion.rotation_matrix(-q), rotation, atol=1e-14)


def test_rotation_about_z_by_known_angle():
    angle = 0.3
    q = quaternion.from_rotation_vector(np.array([0.0, 0.0, angle]))
    expected = np.array(
        [[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]]
    )
    np.testing.assert_allclose(quaternion.rotation_matrix(q), expected, atol=1e-15)


def test_product_composes_rotations_and_matrices_agree():
    p, q = RNG.normal(size=(2, 4))
    np.testing.assert_allclose(
        quaternion.rotation_matrix(quaternion.multiply(p, q)),
        quaternion.rotation_matrix(p) @ quaternion.rotation_matrix(q),
        atol=1e-14,
    )
    np.testing.assert_allclose(quaternion.left_matrix(p) @ q, quaternion.multiply(p, q))
    np.testing.assert_allclose(quaternion.right_matrix(q) @ p, quaternion.multiply(p, q))


def test_from_matrix_inverts_rotation_matrix_up_to_sign():
    q = RNG.normal(size=(50, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    back = quaternion.from_matrix(quaternion.rotation_matrix(q))
    sign = np.sign(np.sum(back * q, axis=1))
    np.testing.assert_allclose(back * sign[:, None], q, atol=1e-14)


@pytest.mark.parametrize("angle", [0.0, 1e-6, 1e-3, 2.0])
def test_rotation_vector_gives_unit_quaternion_of_right_angle(angle):
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    q = quaternion.from_rotation_vector(angle * axis)
    assert np.linalg.norm(q) == pytest.approx(1.0, abs=1e-15)
    rotation = quaternion.rotation_matrix(q)
    assert np.trace(rotation) == pytest.approx(1.0 + 2.0 * np.cos(angle), abs=1e-14)
    np.testing.assert_allclose(rotation @ axis, axis, atol=1e-15)


def test_curvature_is_axial_of_rt_dr_for_non_unit_quaternion_field():
    # q(u) = a + b u + c u^2, far from unit length; finite differences of R(q(u)).
    a, b, c = RNG.normal(size=(3, 4))
    u, h = 0.4, 1e-6

    def field(v):
        return a + b * v + c * v**2

    d_rotation = (
        quaternion.rotation_matrix(field(u + h)) - quaternion.rotation_matrix(field(u - h))
    ) / (2 * h)
    expected = axial(quaternion.rotation_matrix(field(u)).T @ d_rotation)
    np.testing.assert_allclose(
        quaternion.curvature(field(u), b + 2 * c * u), expected, rtol=1e-8, atol=1e-9
    )
    d_curvature = (
        quaternion.curvature(field(u + h), b + 2 * c * (u + h))
        - quaternion.curvature(field(u - h), b + 2 * c * (u - h))
    ) / (2 * h)
    np.testing.assert_allclose(
        quaternion.curvature_rate(field(u), b + 2 * c * u, 2 * c),
        d_curvature,
        rtol=1e-7,
        atol=1e-8,
    )


def test_align_signs_removes_jumps():
    q = np.tile([1.0, 0.0, 0.0, 0.0], (5, 1))
    q[[1, 3]] *= -1
    aligned = quaternion.align_signs(q, reference=np.array([-1.0, 0, 0, 0]))
    np.testing.assert_array_equal(aligned[:, 0], -1.0)
