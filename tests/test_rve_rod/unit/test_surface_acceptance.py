"""Acceptance checks of a new surface: sign, monotonicity and data coverage, each found on a
surface built to fail it and absent from one that passes."""

import dataclasses

import numpy as np
import pytest
from support.surface_cases import quadratic_in, two_quadratics_surface

from rve_rod.homogenize.acceptance import beyond_stopped_rays, surface_problems
from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.homogenize.generate import generate_surface
from rve_rod.homogenize.sampling import SamplingPlan
from rve_rod.presets import make_fabric


def test_a_sound_surface_has_no_problems():
    assert surface_problems(two_quadratics_surface(curvature_22=1.0)) == []


def test_compression_in_biaxial_tension_is_a_sign_problem():
    # S11 = -0.05 + 0.5 E11: compressive wherever E11 < 0.1, E = (0, 0) included
    negative = dataclasses.replace(
        two_quadratics_surface(1.0), s11=quadratic_in(0, -0.05, 0.5, 0.0)
    )
    (problem,) = surface_problems(negative)
    assert problem.startswith("sign: S11 = -0.05 N/mm at E = (0, ")


def test_softening_is_a_monotonicity_problem():
    # dS22/dE22 = 0.2 - E22: -0.1 at the domain's end E22 = 0.3 (S22 = 0.015 > 0 there)
    (problem,) = surface_problems(two_quadratics_surface(curvature_22=-1.0))
    assert problem.startswith("monotonicity: dS22/dE22 = -0.1 N/mm at E = (")


@pytest.mark.parametrize(("rays", "expected"), [(3, ["coverage: S22"]), (16, [])])
def test_too_few_rays_leave_the_fit_without_data(rays, expected):
    plan = SamplingPlan(rays=rays, steps_per_ray=5, shear_steps=5)
    generated = generate_surface(make_fabric("cotton-20s2", 5.5), AnalyticRve(), plan)
    checks = generated.surface.parameters["checks"]
    assert [problem[: len("coverage: S22")] for problem in checks] == expected


def test_only_the_shadow_of_a_ray_that_stopped_early_is_left_out_of_coverage():
    def green(e11, e22):  # engineering strains -> Green-Lagrange
        return [((1 + e11) ** 2 - 1) / 2, ((1 + e22) ** 2 - 1) / 2]

    box = np.array([green(-0.1, -0.1), green(0.2, 0.2)]).T  # [min, max] of E11, E22
    t = np.linspace(0.02, 1.0, 10)
    rays = [(0.2 * t, 0 * t), (0 * t, 0.2 * t)]  # course- and wale-wise, to the box
    diagonal = (0.2 * t, 0.2 * t)
    stopped = (0.1 * t, 0.1 * t)  # the 45 degree ray stopped at 10 %
    points = np.array([green(0.15, 0.15), green(0.05, 0.05), green(0.2, 0.01), green(0.01, 0.2)])
    for ray, expected in ((diagonal, [False] * 4), (stopped, [True, False, False, False])):
        runs = [*rays, ray]
        sampled = np.array([green(a, b) for x, y in runs for a, b in zip(x, y, strict=True)])
        assert beyond_stopped_rays(points, sampled, box).tolist() == expected
