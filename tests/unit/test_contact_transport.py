"""The minimal rotation that carries the friction offset with the master's tangent."""

import numpy as np

from rve_rod.contact.transport import transport


def random_unit(rng, k):
    u = rng.normal(size=(3, k))
    return u / np.linalg.norm(u, axis=0)


def rotation(angle, axis):
    axis = axis / np.linalg.norm(axis)
    cross = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * cross + (1 - np.cos(angle)) * cross @ cross


def test_transport_is_the_rotation_about_the_normal_of_both_tangents():
    rng = np.random.default_rng(1)
    k = 20
    a = random_unit(rng, k)
    vectors = rng.normal(size=(3, k))
    for c in range(k):
        axis = np.cross(a[:, c], rng.normal(size=3))  # any axis normal to a
        turn = rotation(rng.uniform(-1.0, 1.0), axis)
        b = turn @ a[:, c]
        result = transport(a[:, [c]], 2.7 * b[:, None], vectors[:, [c]])
        np.testing.assert_allclose(result.vectors[:, 0], turn @ vectors[:, c], atol=1e-12)
    # it carries a onto b, keeps lengths, and is the identity when the tangent has not turned
    b = random_unit(rng, k)
    np.testing.assert_allclose(transport(a, 0.3 * b, a).vectors, b, atol=1e-12)
    np.testing.assert_allclose(
        np.linalg.norm(transport(a, b, vectors).vectors, axis=0),
        np.linalg.norm(vectors, axis=0),
        rtol=1e-12,
    )
    np.testing.assert_allclose(transport(a, 5.0 * a, vectors).vectors, vectors, atol=1e-14)


def test_transport_derivative_matches_central_differences():
    rng = np.random.default_rng(2)
    k = 12
    a = random_unit(rng, k)
    tangent = 1.7 * (a + 0.4 * rng.normal(size=(3, k)))
    vectors = rng.normal(size=(3, k))
    derivative = transport(a, tangent, vectors).derivative
    h = 1e-6
    for j in range(3):
        step = np.zeros((3, k))
        step[j] = h
        difference = (
            transport(a, tangent + step, vectors).vectors
            - transport(a, tangent - step, vectors).vectors
        ) / (2 * h)
        np.testing.assert_allclose(derivative[:, j, :], difference, atol=1e-8)
