"""S = F^-1 P and E = (F^T F - I)/2 against hand-computed states, objectivity and symmetry."""

import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.stress_measures import green_lagrange, membrane_state, second_piola_kirchhoff, voigt

RNG = np.random.default_rng(5)


def random_states(m=50):
    F = np.eye(2) + 0.3 * RNG.uniform(-1, 1, (m, 2, 2))
    S = RNG.normal(size=(m, 2, 2))
    S = 0.5 * (S + np.swapaxes(S, 1, 2))
    return F, S


def test_uniaxial_stretch_by_hand():
    F = np.array([[1.2, 0.0], [0.0, 0.9]])
    P = np.array([[0.6, 0.0], [0.0, -0.09]])
    state = membrane_state(F, P)
    np.testing.assert_allclose(state.E, [(1.2**2 - 1) / 2, (0.9**2 - 1) / 2, 0.0], atol=1e-15)
    np.testing.assert_allclose(state.S, [0.5, -0.1, 0.0], atol=1e-15)
    assert state.asymmetry == 0.0


def test_simple_shear_by_hand():
    # F = [[1, g], [g, 1]] (design.md pure shear): E = [[g^2/2, g], [g, g^2/2]]
    g = 0.3
    E = green_lagrange(np.array([[1.0, g], [g, 1.0]]))
    np.testing.assert_allclose(voigt(E), [g**2 / 2, g**2 / 2, g], atol=1e-15)


def test_recovers_symmetric_stress_from_first_piola():
    F, S = random_states()
    state = membrane_state(F, F @ S)
    np.testing.assert_allclose(state.S, voigt(S), atol=1e-13)
    assert state.asymmetry.max() < 1e-13
    np.testing.assert_allclose(second_piola_kirchhoff(F, F @ S), S, atol=1e-13)


def test_objectivity_under_superposed_rotation():
    F, S = random_states()
    angle = RNG.uniform(0, 2 * np.pi, F.shape[0])
    R = np.stack([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]).transpose(
        2, 0, 1
    )
    reference = membrane_state(F, F @ S)
    rotated = membrane_state(R @ F, R @ F @ S)
    np.testing.assert_allclose(rotated.E, reference.E, atol=1e-14)
    np.testing.assert_allclose(rotated.S, reference.S, atol=1e-13)


def test_asymmetry_of_a_non_equilibrium_stress_is_reported():
    F, S = random_states(5)
    skew = np.array([[0.0, 0.2], [-0.2, 0.0]])
    state = membrane_state(F, F @ (S + skew))
    np.testing.assert_allclose(state.asymmetry, 0.4, atol=1e-13)
    np.testing.assert_allclose(state.S, voigt(S), atol=1e-13)


def test_bad_input():
    with pytest.raises(InputError, match="det F > 0"):
        second_piola_kirchhoff(np.diag([1.0, -1.0]), np.eye(2))
    with pytest.raises(InputError, match="shape"):
        green_lagrange(np.eye(3))
    with pytest.raises(InputError, match="finite"):
        voigt(np.full((2, 2), np.nan))
