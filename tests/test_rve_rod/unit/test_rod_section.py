"""Section stiffness of circles against hand-computed values and the knit scalings."""

import math

import pytest

from rve_rod.errors import InputError
from rve_rod.rod import PAPER_CIRCLE, SectionStiffness
from rve_rod.rod.section import free_fibre_rigidity


def test_circular_section_values():
    r, e, nu = 0.2, 80.0, 0.3
    section = SectionStiffness.circular(r, e, rotational_modulus=40.0, poissons_ratio=nu)
    area, inertia = math.pi * r**2, math.pi * r**4 / 4
    cowper = 6 * 1.3 / (7 + 1.8)
    assert section.axial == pytest.approx(e * area)
    assert section.shear_1 == pytest.approx(cowper * e / 2.6 * area)
    assert section.bending_2 == pytest.approx(40.0 * inertia)
    assert section.torsion == pytest.approx(40.0 / 2.6 * 2 * inertia)


def test_paper_second_moment_is_one_third_of_solid():
    solid = SectionStiffness.circular(0.19, 80.0)
    paper = SectionStiffness.circular(0.19, 80.0, second_moment=PAPER_CIRCLE)
    assert paper.bending_1 == pytest.approx(solid.bending_1 / 3)
    assert paper.torsion == pytest.approx(solid.torsion / 3)
    assert paper.axial == solid.axial


def test_knit_scalings_multiply_a_and_c():
    section = SectionStiffness.circular(0.166, 80.0, rotational_modulus=40.0)
    ratio = 0.19 / 0.166
    scaled = section.scaled(translational=ratio**4, rotational=ratio**6)
    assert scaled.shear_2 == pytest.approx(section.shear_2 * ratio**4)
    assert scaled.axial == pytest.approx(section.axial * ratio**4)
    assert scaled.torsion == pytest.approx(section.torsion * ratio**6)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"radius": -1.0, "youngs_modulus": 1.0}, "radius=-1 mm must be > 0"),
        ({"radius": 1.0, "youngs_modulus": 1.0, "poissons_ratio": 0.7}, "poissons_ratio=0.7"),
        ({"radius": 1.0, "youngs_modulus": 1.0, "second_moment": "hollow"}, "second_moment"),
        ({"radius": 1.0, "youngs_modulus": 1.0, "shear_correction": 0.0}, "shear_correction"),
    ],
)
def test_bad_input_names_parameter(kwargs, message):
    with pytest.raises(InputError, match=message):
        SectionStiffness.circular(**kwargs)


def test_free_fibre_rigidity_is_the_sum_over_circular_fibres():
    # Independent: n = T / T_f circular fibres of modulus E and density rho, each of area
    # a = T_f / rho, bending E pi a_r^4 / 4 = E a^2 / (4 pi); the specific rigidity of such a
    # fibre is R = E / (4 pi rho^2) in consistent units.
    E = 7700.0  # MPa (cotton's tensile modulus, Morton & Hearle Table 17.2)
    rho = 1.52e-3  # g/mm^3
    t_f, t = 0.17, 59.1  # tex = g/km = 1e-6 g/mm
    area = t_f * 1e-6 / rho  # mm^2
    one_fibre = E * area**2 / (4 * math.pi)  # N mm^2
    n = t / t_f
    specific = one_fibre / t_f**2 * 1e3  # mN mm^2 / tex^2
    assert free_fibre_rigidity(specific, t_f, t) == pytest.approx(n * one_fibre, rel=1e-12)
    # and against the solid yarn of the same fibre area: n times smaller
    solid = E * (n * area) ** 2 / (4 * math.pi)
    assert free_fibre_rigidity(specific, t_f, t) == pytest.approx(solid / n, rel=1e-12)


@pytest.mark.parametrize("argument", [0, 1, 2])
def test_free_fibre_rigidity_refuses_non_positive_values(argument):
    values = [0.53, 0.17, 59.1]
    values[argument] = 0.0
    name = ("specific_rigidity", "fibre_linear_density", "yarn_linear_density")[argument]
    with pytest.raises(InputError, match=f"{name}=0 .* must be > 0"):
        free_fibre_rigidity(*values)
