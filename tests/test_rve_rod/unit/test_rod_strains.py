"""The NumPy strain measures of the rod in closed form: a circular arc bent about y, and the
invariance of the strains under a rigid rotation of the whole rod."""

import numpy as np
import pytest

from rve_rod.rod import quaternion
from rve_rod.rod.strains import collocation_equations, strains

RADIUS = 2.5  # mm


def circular_arc(u):
    """Kinematics (18, m) of the arc r(u) = rho (1 - cos u, 0, sin u) whose frame turns about y
    by the angle u (q = (cos u/2, 0, sin u/2, 0)), so d3 = R e3 is the tangent."""
    q = np.stack([np.cos(u / 2), 0 * u, np.sin(u / 2), 0 * u])
    qd = 0.5 * np.stack([-np.sin(u / 2), 0 * u, np.cos(u / 2), 0 * u])
    ru = RADIUS * np.stack([np.sin(u), 0 * u, np.cos(u)])
    ruu = RADIUS * np.stack([np.cos(u), 0 * u, -np.sin(u)])
    return np.concatenate([ru, ruu, q, qd, -0.25 * q])


def straight_reference(m):
    """Reference data (14, m) of a straight rod along d3 with J = rho (s = rho u)."""
    reference = np.zeros((14, m))
    reference[2] = RADIUS
    reference[12] = RADIUS
    return reference


def test_circular_arc_has_curvature_one_over_radius_and_no_stretch():
    u = np.linspace(-1.0, 2.0, 7)
    result = strains(circular_arc(u), straight_reference(u.size))
    np.testing.assert_allclose(result.stretch, 0.0, atol=1e-15)
    expected = np.zeros((3, u.size))
    expected[1] = 1.0 / RADIUS
    np.testing.assert_allclose(result.bending, expected, atol=1e-15)
    np.testing.assert_allclose(result.stretch_rate, 0.0, atol=1e-15)
    np.testing.assert_allclose(result.bending_rate, 0.0, atol=1e-15)
    # The bending moment M = C K is constant along the arc: m' = 0 and n = 0 balance.
    residual, section = collocation_equations(
        circular_arc(u), straight_reference(u.size), np.ones((6, u.size))
    )
    np.testing.assert_allclose(residual, 0.0, atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(section[3:], axis=0), 1.0 / RADIUS, rtol=1e-14)


@pytest.mark.parametrize("seed", range(3))
def test_strains_are_invariant_under_a_rigid_rotation(seed):
    rng = np.random.default_rng(seed)
    m = 5
    kinematics = rng.normal(size=(18, m))
    reference = rng.normal(size=(14, m))
    reference[12] = 0.5 + rng.random(m)
    turn = quaternion.from_rotation_vector(rng.normal(size=3))
    rotation = quaternion.rotation_matrix(turn)
    moved = kinematics.copy()
    moved[0:3], moved[3:6] = rotation @ kinematics[0:3], rotation @ kinematics[3:6]
    for block in (slice(6, 10), slice(10, 14), slice(14, 18)):
        moved[block] = quaternion.multiply(turn, kinematics[block].T).T
    before, after = strains(kinematics, reference), strains(moved, reference)
    for name in ("stretch", "stretch_rate", "bending", "bending_rate"):
        np.testing.assert_allclose(getattr(after, name), getattr(before, name), atol=1e-12)
