"""The RVE's effective Poisson ratios and what holds them (issue 14, docs/validation.md, "Why
the knit contracts too little"), at the coarse settings of the diagnosis: cotton 20s/2 stitch
5.5, 20 control points per quarter, 0-20 % in 11 states.

The mechanism: course-wise, the lateral macro stress P22 = 0 is a balance of the interlocks'
normal loads against friction, and without friction the courses close up; wale-wise, the yarn
through the cut resists the narrowing. The numbers themselves (nu12, nu21 and both forces at
10 and 20 %) are pinned in tests/pins.py (RVE_FAST, RVE_PAPER_RESOLUTION).
"""

import dataclasses

import numpy as np
import pytest

from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import RveSettings, simulate
from rve_rod.rve.yarn import YarnSettings
from rve_rod.units import n_per_mm_to_gf_per_cm

pytestmark = pytest.mark.slow

COARSE = RveSettings(cell=CellSettings(control_points=20), yarn=YarnSettings(bending="section"))
CASES = ("uniaxial-course", "uniaxial-wale")


@pytest.fixture(scope="module")
def runs():
    fabric = load_preset("cotton-20s2", 5.5)
    frictionless = dataclasses.replace(
        COARSE, yarn=dataclasses.replace(COARSE.yarn, friction=False)
    )
    return {
        (name, label): simulate(fabric, load_case(name, 0.2, 11), settings)
        for name in CASES
        for label, settings in (("friction", COARSE), ("frictionless", frictionless))
    }


def lateral_parts(result, a):
    """(cut, normal contact, friction) parts of the lateral P_aa at the last state (gf/cm)."""
    return n_per_mm_to_gf_per_cm(result.steps[-1].stress_parts[:, a, a])


def test_stress_parts_sum_to_the_macro_stress(runs):
    for result in runs.values():
        for step in result.steps:
            np.testing.assert_allclose(
                step.stress_parts.sum(axis=0), step.first_piola, atol=1e-12, rtol=1e-12
            )
        assert np.all(result.series("stress_parts")[:, 2] == 0) == (
            result.settings.yarn.friction is False
        )


def test_friction_at_the_interlocks_holds_the_course_wise_contraction(runs):
    course = runs["uniaxial-course", "friction"]
    force = course.steps[-1].force_gf_per_cm
    cut, normal, friction = lateral_parts(course, 1)
    # The yarn does not cross the cut along y; the interlocks pull the courses together
    # (normal loads act as a tension across the interlock) and friction holds them.
    assert cut == pytest.approx(0.0, abs=1e-9 * force)
    assert normal > 0.15 * force
    assert friction == pytest.approx(-normal, rel=1e-3)
    # Without friction the pull relaxes to nothing and the courses close up: 2.8x the
    # contraction, most of it at the first step (the unloaded cell has no lateral stiffness).
    free = runs["uniaxial-course", "frictionless"]
    assert abs(sum(lateral_parts(free, 1))) < 1e-4 * force  # = -kappa H, the regularization
    assert abs(lateral_parts(free, 1)[1]) < 1e-3 * force
    assert free.poisson_ratio > 2.5 * course.poisson_ratio
    assert free.steps[1].lateral_strain < -0.5 * free.steps[1].strain


def test_the_yarn_through_the_cut_resists_the_wale_wise_narrowing(runs):
    for label in ("friction", "frictionless"):
        wale = runs["uniaxial-wale", label]
        force = wale.steps[-1].force_gf_per_cm
        cut, normal, friction = lateral_parts(wale, 0)
        assert cut < -0.05 * force  # in compression along the course
        assert normal > 0.05 * force  # the interlocks with the diagonal images pull inwards
        assert cut + normal + friction == pytest.approx(0.0, abs=1e-4 * force)
    # Friction adds to the resistance, but the bending of the yarn holds most of it.
    assert (
        runs["uniaxial-wale", "frictionless"].poisson_ratio
        < 1.5 * runs["uniaxial-wale", "friction"].poisson_ratio
    )
