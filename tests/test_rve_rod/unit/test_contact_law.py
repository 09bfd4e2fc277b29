"""Compressible-yarn contact law and friction parameters against their closed forms."""

import numpy as np
import pytest

from rve_rod.contact import MINIMUM_EXPONENT, CompressibleYarnLaw, CoulombFriction
from rve_rod.errors import InputError
from rve_rod.presets import load_preset


@pytest.mark.parametrize("exponent", [1.0, 1.25, 1.5, 2.0, 2.6])
def test_line_load_stiffness_and_energy_against_closed_form(exponent):
    law = CompressibleYarnLaw(stiffness=7.0, exponent=exponent, yarn_radius=0.15)
    gaps = np.array([-0.02, 0.0, 1e-4, 0.01, 0.05, 0.15])
    expected = [0.0, 0.0] + [7.0 * (0.15 / exponent) * (g / 0.15) ** exponent for g in gaps[2:]]
    np.testing.assert_allclose(law.line_load(gaps), expected, rtol=1e-14, atol=0)
    slopes = [0.0, 0.0] + [7.0 * (g / 0.15) ** (exponent - 1.0) for g in gaps[2:]]
    np.testing.assert_allclose(law.line_stiffness(gaps), slopes, rtol=1e-14, atol=0)
    energies = [0.0, 0.0] + [
        7.0 * 0.15**2 * (g / 0.15) ** (exponent + 1) / (exponent * (exponent + 1)) for g in gaps[2:]
    ]
    np.testing.assert_allclose(law.line_energy(gaps), energies, rtol=1e-14, atol=0)


@pytest.mark.parametrize("exponent", [1.0, 1.4, 2.0])
def test_derivatives_against_finite_differences(exponent):
    law = CompressibleYarnLaw(stiffness=3.0, exponent=exponent, yarn_radius=0.2)
    gaps = np.linspace(0.01, 0.2, 7)
    h = 1e-7
    slope_fd = (law.line_load(gaps + h) - law.line_load(gaps - h)) / (2 * h)
    np.testing.assert_allclose(law.line_stiffness(gaps), slope_fd, rtol=1e-7)
    energy_fd = (law.line_energy(gaps + h) - law.line_energy(gaps - h)) / (2 * h)
    np.testing.assert_allclose(law.line_load(gaps), energy_fd, rtol=1e-7)


def test_exponent_one_is_the_linear_penalty():
    law = CompressibleYarnLaw(stiffness=5.0, exponent=1.0, yarn_radius=0.1)
    gaps = np.array([1e-9, 0.003, 0.07])
    np.testing.assert_allclose(law.line_load(gaps), 5.0 * gaps, rtol=1e-14)
    np.testing.assert_allclose(law.line_stiffness(gaps), 5.0, rtol=1e-14)


@pytest.mark.parametrize("stitch", [4.5, 5.5, 7.0])
def test_paper_scalings_for_the_cotton_presets(stitch):
    fabric = load_preset("cotton-20s2", stitch)
    r0, e0 = fabric.yarn.minimal_radius, fabric.yarn.youngs_modulus
    r = min(r0, fabric.knit.wale_width / 8)
    law = CompressibleYarnLaw.from_yarn(r0, r, e0)
    assert law.yarn_radius == r
    assert law.stiffness == pytest.approx(0.01 * e0 * (r0 / r) ** 8, rel=1e-14)
    assert law.exponent == pytest.approx(3.0 - (r0 / r) ** 3, rel=1e-14)
    # Every cotton fabric is squeezed (w/8 < r0) but stays above the exponent limit.
    assert 1.0 < law.exponent < 2.0


def test_uncompressed_yarn_has_exponent_two_and_base_stiffness():
    law = CompressibleYarnLaw.from_yarn(0.0923, 0.0923, 800.0)
    assert law.exponent == pytest.approx(2.0, abs=1e-14)
    assert law.stiffness == pytest.approx(8.0, rel=1e-14)


def test_approaching_the_exponent_limit_keeps_a_finite_tangent():
    r0 = 0.2
    limit_ratio = 2.0 ** (1.0 / 3.0)  # p = 1 exactly
    for ratio in (1.2, 1.25, 1.259, limit_ratio):
        law = CompressibleYarnLaw.from_yarn(r0, r0 / ratio, 80.0)
        assert law.exponent >= MINIMUM_EXPONENT
        assert law.exponent == pytest.approx(max(1.0, 3.0 - ratio**3), abs=1e-12)
        # df/dg -> k (g/r)^(p-1) <= k at tiny penetration: Lipschitz at first touch.
        assert 0.0 < law.line_stiffness(1e-12)[()] <= law.stiffness


@pytest.mark.parametrize("ratio", [1.27, 1.35, 3.0 ** (1.0 / 3.0), 1.6])
def test_exponent_below_one_is_an_input_error_naming_the_valid_range(ratio):
    with pytest.raises(
        InputError, match=r"yarn_radius=.*p=3-\(r0/r\)\^3=.*needs p >= 1.*\[0\.15874"
    ):
        CompressibleYarnLaw.from_yarn(0.2, 0.2 / ratio, 80.0)


def test_invalid_parameters_are_rejected():
    with pytest.raises(InputError, match=r"yarn_radius=0\.3 mm is outside the valid range"):
        CompressibleYarnLaw.from_yarn(0.2, 0.3, 80.0)
    with pytest.raises(InputError, match="youngs_modulus"):
        CompressibleYarnLaw.from_yarn(0.2, 0.2, -1.0)
    with pytest.raises(InputError, match=r"contact exponent=0\.5"):
        CompressibleYarnLaw(stiffness=1.0, exponent=0.5, yarn_radius=0.1)
    with pytest.raises(InputError, match="friction_coefficient"):
        CoulombFriction(coefficient=-0.1, tangential_stiffness=1.0)
    with pytest.raises(InputError, match="tangential_stiffness"):
        CoulombFriction(coefficient=0.1, tangential_stiffness=0.0)


def test_friction_for_law_scales_the_normal_stiffness():
    law = CompressibleYarnLaw(stiffness=4.0, exponent=1.5, yarn_radius=0.1)
    friction = CoulombFriction.for_law(law, 0.15, stiffness_ratio=0.5)
    assert friction.coefficient == 0.15
    assert friction.tangential_stiffness == 2.0
