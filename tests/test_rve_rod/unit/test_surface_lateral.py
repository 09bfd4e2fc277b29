"""The free lateral strain of homogeneous uniaxial tension is the root nearest to the reference
state, also when a fitted surface turns over far outside its data."""

import numpy as np
import pytest
from support.design_cases import synthetic_family

from rve_rod.errors import InputError
from rve_rod.surface.checks import _free_lateral_strains


def polynomial(roots):
    """lateral_stress of `_free_lateral_strains`: prod (e - root) and its derivative."""

    def lateral_stress(e):
        value, slope = np.ones_like(e), np.zeros_like(e)
        for root in roots:
            value, slope = value * (e - root), slope * (e - root) + value
        return value, slope

    return lateral_stress


@pytest.mark.parametrize(
    ("roots", "nearest"),
    [((0.02, -0.3), 0.02), ((-0.047, 0.26), -0.047), ((0.113, 0.4, -0.45), 0.113)],
)
def test_root_nearest_to_zero_is_found(roots, nearest):
    found = _free_lateral_strains(polynomial(roots), np.array([0.1, 0.2]))
    np.testing.assert_allclose(found, nearest, atol=1e-14)


def test_each_strain_gets_its_own_root():
    """Strain i's lateral stress (e + 0.1 i)(e - 0.3): roots -0, -0.1, -0.2 (nearest to 0)."""

    def lateral_stress(e):
        shift = 0.1 * np.resize(np.arange(3.0), e.size)
        return (e + shift) * (e - 0.3), 2 * e + shift - 0.3

    found = _free_lateral_strains(lateral_stress, np.array([0.05, 0.1, 0.2]))
    np.testing.assert_allclose(found, [0.0, -0.1, -0.2], atol=1e-14)


def test_no_root_is_an_input_error_naming_the_strain():
    with pytest.raises(InputError, match=r"at strain 0.15 no lateral strain"):
        _free_lateral_strains(lambda e: (1.0 + e**2, 2 * e), np.array([0.15]))


@pytest.mark.parametrize("roots", [(0.02, -0.3), (-0.047, 0.26), (0.113, 0.4, -0.45)])
def test_newton_stops_at_round_off(roots):
    """Newton's method converges quadratically from the bracket of the scan (0.01 wide): a
    handful of evaluations after the scan and the bracket's end. A root on the scan's grid
    (0.02) was a bracket's end, approached by bisection from the other end: 43 more."""
    calls = []
    law = polynomial(roots)

    def lateral_stress(e):
        calls.append(e.size)
        return law(e)

    found = _free_lateral_strains(lateral_stress, np.array([0.1, 0.2]))
    np.testing.assert_allclose(found, roots[0], atol=1e-14)
    assert len(calls) <= 2 + 6


def test_a_laws_lateral_strain_takes_a_few_newton_steps():
    """The graded law of the synthetic design family at 6.0 mm, course- and wale-wise: Newton
    lands within round-off of the root, which becomes an end of the bracket; it was then
    bisected towards from the far end (29 evaluations a call on average, 50 at most; now 8)."""
    law = synthetic_family().law(6.0)
    strain = np.array([0.05, 0.1, 0.15, 0.2])
    for axis in (0, 1):
        other, calls = 1 - axis, []
        E_load = ((1.0 + strain) ** 2 - 1.0) / 2.0

        def lateral_stress(e, axis=axis, other=other, calls=calls, E_load=E_load):
            calls.append(e.size)
            E = np.zeros((e.size, 3))
            E[:, axis], E[:, other] = np.resize(E_load, e.size), e
            evaluated = law.stress(E)
            return evaluated.S[:, other], evaluated.tangent[:, other, other]

        found = _free_lateral_strains(lateral_stress, strain)
        assert np.all(np.abs(lateral_stress(found)[0]) < 1e-12)
        assert len(calls) <= 2 + 8
