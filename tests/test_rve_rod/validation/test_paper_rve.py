"""Our RVE against the paper group's own RVE output (issue 27; docs/validation.md, "The paper
group's RVE"), at the default resolution (68 control points per quarter loop).

What holds: their picture-frame shear run, which loads the loop's bending and barely its
contacts, is reproduced by the default bending rigidity (the cotton fibres', free to slip):
within 25 % at 20 and 40 degrees at stitch 5.5 and 6.5, and closer than the paper's section
rigidity at all three stitch values and both angles (the section is 1.3 to 7 times too stiff).
The target of the issue (every ray within 20 %) is not met: the benchmark
benchmarks/paper_rve.py measures it, and docs/validation.md says why.
"""

import numpy as np
import pytest

from rve_rod.presets import load_preset
from rve_rod.rve.paper.comparison import axis_rays, compare_run, secant_at_rest
from rve_rod.rve.paper.data import STITCH_VALUES, shear_run
from rve_rod.rve.simulation import RveSettings
from rve_rod.rve.yarn import YarnSettings

pytestmark = pytest.mark.slow

TWENTY_DEGREES, FORTY_DEGREES = 5, 11  # their states 6 and 12 (3.3 degrees per state)


@pytest.fixture(scope="module")
def shear_errors():
    errors = {}
    for stitch in STITCH_VALUES:
        for bending in ("auto", "section"):
            settings = RveSettings(yarn=YarnSettings(bending=bending))
            comparison = compare_run(
                load_preset("cotton-20s2", stitch), shear_run(stitch), settings, states=12
            )
            errors[stitch, bending] = comparison.errors()[[TWENTY_DEGREES, FORTY_DEGREES]]
    return errors


@pytest.mark.parametrize("stitch", [5.5, 6.5])
def test_the_default_bending_reproduces_their_shear_within_a_quarter(shear_errors, stitch):
    assert shear_errors[stitch, "auto"].max() <= 0.25


@pytest.mark.parametrize("stitch", STITCH_VALUES)
def test_the_section_rigidity_is_further_from_their_shear_than_the_fibres(shear_errors, stitch):
    assert (shear_errors[stitch, "auto"] < shear_errors[stitch, "section"]).all()
    assert shear_errors[stitch, "section"].min() >= 1.0  # at least twice their stress


def test_at_rest_their_course_wise_stretch_pulls_the_courses_together_and_ours_does_not():
    """The trade map's diagnosis (docs/validation.md, "Friction, a straight yarn, and the
    trade map"): the secant stiffness at rest through their two rays nearest the axes has C21
    about C11 at stitch 5.5 (1.24: a course-wise stretch at fixed course height makes as much
    wale-wise stress as course-wise), the default cell's about a fifth (0.22 at 68 control
    points, 0.19 at 28). A model change that couples the courses as theirs moves this pin:
    re-measure the diagnosis then."""
    fabric = load_preset("cotton-20s2", 5.5)
    rays = axis_rays(5.5)
    theirs = secant_at_rest(rays)
    ours = secant_at_rest(
        rays,
        [
            np.diagonal(compare_run(fabric, ray, RveSettings(), states=1).second_piola[0])
            for ray in rays
        ],
    )
    assert theirs[1, 0] / theirs[0, 0] == pytest.approx(1.24, abs=0.01)
    assert ours[1, 0] / ours[0, 0] == pytest.approx(0.22, abs=0.01)
