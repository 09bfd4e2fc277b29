"""Acceptance checks of a new surface: sign, monotonicity and data coverage, each found on a
surface built to fail it and absent from one that passes."""

import dataclasses

import pytest
from test_surface_stability import quadratic_in, surface

from rve_rod.homogenize.acceptance import surface_problems
from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.homogenize.generate import generate_surface
from rve_rod.homogenize.sampling import SamplingPlan
from rve_rod.presets import make_fabric


def test_a_sound_surface_has_no_problems():
    assert surface_problems(surface(curvature_22=1.0)) == []


def test_compression_in_biaxial_tension_is_a_sign_problem():
    # S11 = -0.05 + 0.5 E11: compressive wherever E11 < 0.1, E = (0, 0) included
    negative = dataclasses.replace(surface(1.0), s11=quadratic_in(0, -0.05, 0.5, 0.0))
    (problem,) = surface_problems(negative)
    assert problem.startswith("sign: S11 = -0.05 N/mm at E = (0, ")


def test_softening_is_a_monotonicity_problem():
    # dS22/dE22 = 0.2 - E22: -0.1 at the domain's end E22 = 0.3 (S22 = 0.015 > 0 there)
    (problem,) = surface_problems(surface(curvature_22=-1.0))
    assert problem.startswith("monotonicity: dS22/dE22 = -0.1 N/mm at E = (")


@pytest.mark.parametrize(("rays", "expected"), [(3, ["coverage: S22"]), (16, [])])
def test_too_few_rays_leave_the_fit_without_data(rays, expected):
    plan = SamplingPlan(rays=rays, steps_per_ray=5, shear_steps=5)
    generated = generate_surface(make_fabric("cotton-20s2", 5.5), AnalyticRve(), plan)
    checks = generated.surface.parameters["checks"]
    assert [problem[: len("coverage: S22")] for problem in checks] == expected
