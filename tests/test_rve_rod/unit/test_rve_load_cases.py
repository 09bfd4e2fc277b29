"""Load cases of the knit RVE: prescribed paths, free components, load directions, bad input."""

import math

import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.rve.load_cases import (
    CASES,
    BiaxialRay,
    PictureFrameShear,
    Shear,
    UniaxialCourse,
    load_case,
)
from rve_rod.stress_measures import green_lagrange


def test_the_cases_of_the_design_and_the_picture_frame_shear():
    assert set(CASES) == {
        "uniaxial-course",
        "uniaxial-wale",
        "strip-biaxial-course",
        "strip-biaxial-wale",
        "biaxial",
        "shear",
        "picture-frame-shear",
    }
    assert load_case("uniaxial-course").free == ((1, 1),)
    assert load_case("uniaxial-wale").free == ((0, 0),)
    for name in ("strip-biaxial-course", "strip-biaxial-wale", "biaxial", "shear"):
        assert load_case(name).free == ()
    assert load_case("picture-frame-shear").free == ()


@pytest.mark.parametrize("angle", [0.3, -0.7, 1.15])
def test_picture_frame_shear_keeps_lengths_and_turns_the_wale_axis(angle):
    """E11 = E22 = 0 and E12 = sin(t a)/2 at every state; the angle between the deformed
    lattice vectors closes by t a; the measured force is P12."""
    case = load_case("picture-frame-shear", angle, steps=7)
    for t in case.load_factors():
        F = case.prescribed(t)
        E = green_lagrange(F)
        np.testing.assert_allclose([E[0, 0], E[1, 1]], 0.0, atol=1e-15)
        assert E[0, 1] == pytest.approx(math.sin(t * angle) / 2, abs=1e-15)
        cosine = F[:, 0] @ F[:, 1] / np.linalg.norm(F[:, 0]) / np.linalg.norm(F[:, 1])
        assert math.degrees(math.acos(cosine)) == pytest.approx(90 - math.degrees(t * angle))
    np.testing.assert_array_equal(
        case.load_direction(), math.copysign(1, angle) * np.array([[0, 1], [0, 0]])
    )


@pytest.mark.parametrize("angle", [0.0, 1.5, -2.0])
def test_picture_frame_shear_refuses_angles_it_cannot_take(angle):
    with pytest.raises(InputError, match="max_angle"):
        PictureFrameShear(max_angle=angle)


def test_default_path_is_the_papers_0_to_20_percent_in_21_steps():
    case = UniaxialCourse()
    strains = np.array([case.prescribed(t)[0, 0] - 1 for t in case.load_factors()])
    np.testing.assert_allclose(strains, np.arange(21) / 100, atol=1e-15)
    assert case.lateral == (1, 1)


@pytest.mark.parametrize(
    ("name", "final"),
    [
        ("uniaxial-course", [[1.1, 0], [0, 1]]),
        ("uniaxial-wale", [[1, 0], [0, 1.1]]),
        ("strip-biaxial-course", [[1.1, 0], [0, 1]]),
        ("strip-biaxial-wale", [[1, 0], [0, 1.1]]),
        ("shear", [[1, 0.1], [0.1, 1]]),
    ],
)
def test_final_deformation_and_load_direction(name, final):
    case = load_case(name, 0.1, steps=3)
    np.testing.assert_allclose(case.prescribed(1.0), final, atol=1e-15)
    np.testing.assert_allclose(
        case.prescribed(0.5) - np.eye(2), 0.5 * (np.array(final) - np.eye(2))
    )
    direction = case.load_direction()
    assert np.linalg.norm(direction) == pytest.approx(1.0)


def test_biaxial_ray_direction_and_compression():
    ray = BiaxialRay(angle_deg=210.0, max_load=0.1, steps=5)
    F = ray.prescribed(1.0)
    np.testing.assert_allclose(np.diag(F), [1 + 0.1 * math.cos(math.radians(210)), 0.95])
    np.testing.assert_allclose(np.diag(ray.load_direction()), [-math.sqrt(3) / 2, -0.5])
    compression = load_case("uniaxial-course", -0.1)
    assert compression.prescribed(1.0)[0, 0] == pytest.approx(0.9)
    np.testing.assert_allclose(compression.load_direction(), [[1, 0], [0, 0]])  # P11 itself


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"name": "twist"}, "case='twist' is unknown"),
        ({"name": "uniaxial-course", "strain": 0.0}, "max_strain=0"),
        ({"name": "uniaxial-wale", "strain": 1.5}, r"max_strain=1.5 is outside the valid range"),
        ({"name": "shear", "strain": float("nan")}, "max_shear=nan"),
        ({"name": "biaxial", "strain": -0.1}, r"max_load=-0.1 is outside"),
        ({"name": "strip-biaxial-course", "steps": 1}, r"steps=1 is outside the valid range"),
    ],
)
def test_bad_cases_are_refused_naming_the_parameter(kwargs, message):
    with pytest.raises(InputError, match=message):
        load_case(**kwargs)


def test_cases_are_frozen_and_hashable():
    assert Shear(max_shear=0.3) == Shear()
    assert len({Shear(), Shear(), UniaxialCourse()}) == 2
