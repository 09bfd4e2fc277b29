"""Sampling plans: ray directions, ray ends on the strain box, prescribed deformation gradients."""

import math

import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.homogenize.samples import RveCase, RveRun
from rve_rod.homogenize.sampling import (
    CONTRACTION_MARGIN,
    MIN_COMPRESSION,
    LoadPath,
    SamplingPlan,
    compression_box,
    contraction,
)
from rve_rod.presets import make_fabric


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
        LoadPath("biaxial-strip", 0.0, 0.2, 10)
    with pytest.raises(InputError, match="0 or 90"):
        LoadPath("uniaxial", 45.0, 0.2, 10)
    with pytest.raises(InputError, match="det F"):
        LoadPath("biaxial", 180.0, 1.5, 10)


@pytest.mark.parametrize(
    ("narrowing", "box"),
    [(0.0, MIN_COMPRESSION), (0.04, MIN_COMPRESSION), (0.12, 0.15), (0.16, 0.20), (0.9, 0.5)],
)
def test_a_box_that_follows_the_fabric_reaches_beyond_its_contraction(narrowing, box):
    assert compression_box(narrowing) == pytest.approx(box, abs=1e-12)
    assert compression_box(narrowing) >= min(CONTRACTION_MARGIN * narrowing, 0.5)


def test_contraction_of_uniaxial_runs_extrapolates_a_run_that_stopped_early():
    course, wale = SamplingPlan(max_tension=0.2, steps_per_ray=4).contraction_paths()
    assert (course.kind, course.angle_deg, wale.angle_deg) == ("uniaxial", 0.0, 90.0)
    F = course.deformation_gradients()
    F[:, 1, 1] = 1 - 0.3 * (F[:, 0, 0] - 1)  # narrows by 0.3 of the strain
    G = wale.deformation_gradients()[:2]  # stopped at 10 %, narrowing by 0.6 of it
    G[:, 0, 0] = 1 - 0.6 * (G[:, 1, 1] - 1)
    runs = [RveRun(F, F), RveRun(G, G, complete=False)]
    assert contraction((course, wale), runs) == pytest.approx(0.6 * 0.2)
    empty = RveRun(np.zeros((0, 2, 2)), np.zeros((0, 2, 2)), complete=False)
    assert contraction((course, wale), [runs[0], empty]) == pytest.approx(0.3 * 0.2)


def test_a_plan_without_compression_limit_is_resolved_from_its_contraction_runs():
    law = AnalyticRve(coupling_11_22=0.07, coupling_22_11=0.07)
    plan = SamplingPlan(max_compression=None, max_tension=0.2)
    with pytest.raises(InputError, match="following"):
        plan.load_paths()
    fabric = make_fabric(
        None, wale_width=1.0, course_height=1.0, yarn_radius=0.1, youngs_modulus=1.0
    )
    runs = [law(RveCase(fabric, path)) for path in plan.contraction_paths()]
    for run, along in zip(runs, (0, 1), strict=True):  # the stress across vanishes
        across = 1 - along
        assert np.abs(run.first_piola[:, across, across]).max() < 1e-14
    # S22 = k2 (exp(b2 E22) - 1) / b2 + c E11 = 0 course-wise; likewise wale-wise
    E_load = ((1.2) ** 2 - 1) / 2
    narrowing = [
        1 - math.sqrt(1 + 2 * math.log(1 - b * 0.07 * E_load / k) / b)
        for k, b in ((law.wale_stiffness, law.wale_stiffening), (0.2, 8.0))
    ]
    assert contraction(plan.contraction_paths(), runs) == pytest.approx(max(narrowing))
    followed = plan.following(runs)
    assert followed.max_compression == compression_box(max(narrowing)) > MIN_COMPRESSION
    assert followed.slack_compression == MIN_COMPRESSION
    assert len(followed.load_paths()) == len(SamplingPlan().load_paths())


def test_rays_without_tension_end_at_the_slack_limit():
    plan = SamplingPlan(max_tension=0.25, max_compression=0.2, slack_compression=0.1)
    ends = {path.angle_deg: path.deformation_gradients()[-1] for path in plan.load_paths()[:-1]}
    # a component in tension: the compression box; none: the slack limit
    assert np.diag(ends[157.5]) - 1 == pytest.approx([-0.2, 0.2 * math.tan(math.radians(22.5))])
    assert np.diag(ends[180.0]) - 1 == pytest.approx([-0.1, 0.0], abs=1e-12)
    assert np.diag(ends[225.0]) - 1 == pytest.approx([-0.1, -0.1])
    assert np.diag(ends[292.5]) - 1 == pytest.approx([0.2 / math.tan(math.radians(67.5)), -0.2])
    same = SamplingPlan(max_tension=0.25, max_compression=0.2)  # no slack limit: the box
    assert same.ray_length(225.0) == pytest.approx(0.2 * math.sqrt(2))
