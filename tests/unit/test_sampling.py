"""Sampling plans: ray directions, ray ends on the strain box, prescribed deformation gradients."""

import math

import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.homogenize.sampling import LoadPath, SamplingPlan


def test_default_plan_full_circle_rays_end_on_the_box():
    plan = SamplingPlan()
    paths = plan.load_paths()
    rays = [path for path in paths if path.kind == "biaxial"]
    np.testing.assert_allclose([ray.angle_deg for ray in rays], np.arange(16) * 22.5)
    for ray in rays:
        final = ray.deformation_gradients()[-1]
        strains = np.diag(final) - 1.0
        limits = np.where(strains > 0, plan.max_tension, plan.max_compression)
        # the first component to reach its limit ends the ray
        assert np.max(np.abs(strains) / limits) == pytest.approx(1.0, rel=1e-12)
        ratio = math.atan2(strains[1], strains[0])
        assert math.degrees(ratio) % 360 == pytest.approx(ray.angle_deg, abs=1e-9)
    assert paths[-1] == LoadPath("shear", 0.0, 0.30, 15)


def test_load_path_deformation_gradients():
    ray = LoadPath("biaxial", 30.0, 0.2, 4)
    F = ray.deformation_gradients()
    t = np.array([0.05, 0.1, 0.15, 0.2])
    np.testing.assert_allclose(F[:, 0, 0], 1 + t * math.cos(math.pi / 6), atol=1e-15)
    np.testing.assert_allclose(F[:, 1, 1], 1 + t * 0.5, atol=1e-15)
    np.testing.assert_array_equal(F[:, 0, 1], 0.0)
    shear = LoadPath("shear", 0.0, 0.3, 3).deformation_gradients()
    np.testing.assert_allclose(shear[:, 0, 1], [0.1, 0.2, 0.3], atol=1e-15)
    np.testing.assert_array_equal(shear[:, 0, 1], shear[:, 1, 0])


def test_tension_quadrant_plan_includes_both_ends():
    plan = SamplingPlan(rays=7, angle_range_deg=(0, 90), max_compression=0.0)
    angles = [path.angle_deg for path in plan.load_paths() if path.kind == "biaxial"]
    np.testing.assert_allclose(angles, np.arange(0, 91, 15))


def test_rays_without_room_are_left_out():
    plan = SamplingPlan(rays=4, max_compression=0.0)
    angles = [path.angle_deg for path in plan.load_paths() if path.kind == "biaxial"]
    np.testing.assert_allclose(angles, [0.0, 90.0])


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"rays": 2}, "rays=2"),
        ({"angle_range_deg": (0, 400)}, "angle_range_deg"),
        ({"max_tension": -0.1}, "max_tension"),
        ({"steps_per_ray": 0}, "steps_per_ray"),
        ({"max_shear": 1.2}, "max_shear"),
    ],
)
def test_bad_plans(kwargs, fragment):
    with pytest.raises(InputError, match=fragment):
        SamplingPlan(**kwargs)


def test_bad_load_paths():
    with pytest.raises(InputError, match="kind"):
        LoadPath("uniaxial", 0.0, 0.2, 10)
    with pytest.raises(InputError, match="det F"):
        LoadPath("biaxial", 180.0, 1.5, 10)
