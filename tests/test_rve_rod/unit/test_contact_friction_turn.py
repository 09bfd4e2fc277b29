"""The macro turn the friction offsets turn with (`rve_rod.contact.friction.MacroTurn`)."""

import numpy as np
import pytest

from rve_rod.contact.friction import MacroTurn


def _in_plane(block):
    F = np.eye(3)
    F[:2, :2] = block
    return F


@pytest.mark.parametrize("angle", [-1.2, -0.3, 0.0, 0.4, 1.5])
def test_the_turn_is_the_polar_rotation_of_f(angle):
    """F = R(angle) U with U symmetric positive definite: the turn is R(angle)."""
    c, s = np.cos(angle), np.sin(angle)
    R = np.array([[c, -s], [s, c]])
    U = np.array([[1.2, 0.15], [0.15, 0.9]])
    turn = MacroTurn.of(_in_plane(R @ U))
    np.testing.assert_allclose(turn.rotation, _in_plane(R), atol=1e-14)
    # a rigid turn on top adds its angle
    turned = MacroTurn.of(_in_plane(R @ R @ U)).rotation
    np.testing.assert_allclose(turned, _in_plane(R @ R), atol=1e-14)


def test_the_rate_and_the_gradient_match_central_differences():
    F = _in_plane([[1.05, 0.3], [-0.1, 0.92]])
    turn = MacroTurn.of(F)
    step = 1e-7
    for m, (a, b) in enumerate([(0, 0), (0, 1), (1, 0), (1, 1)]):
        plus, minus = F.copy(), F.copy()
        plus[a, b] += step
        minus[a, b] -= step
        difference = (MacroTurn.of(plus).rotation - MacroTurn.of(minus).rotation) / (2 * step)
        np.testing.assert_allclose(turn.rate * turn.gradient[m], difference, atol=1e-8)
