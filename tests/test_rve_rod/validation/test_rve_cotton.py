"""Validation of the knit-loop RVE against the trends of the reference fabrics (docs/validation.md).

The reference data has no force-strain numbers, only the fabrics; the paper's findings that
the model must reproduce are trends: course-wise force falls as the loop length grows (looser
knits), wale-wise curves stiffen with strain, and the Poisson ratios at 20 % are those of a
knit (lateral contraction; for stitch 5.5 within 25 % of the tests' 0.41 and 0.72, issue 14).
Runs at the default yarn model (the cotton's free-fibre bending rigidity; Vassiliadis sample 2,
without fibre data, falls back to the section's) and the paper's resolution, 68 control points
per quarter and 1 % steps; docs/validation.md has the tables, whose numbers are pinned
(tests/pins.py, RVE_PAPER_RESOLUTION): a drift that keeps the trends fails here.
"""

import numpy as np
import pytest
from pins import assert_pinned

from rve_rod.errors import ConvergenceError
from rve_rod.presets import load_preset, stitch_values
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import RveSettings, simulate
from rve_rod.rve.yarn import YarnSettings

pytestmark = pytest.mark.slow

SETTINGS = RveSettings()  # the paper's 68 control points per quarter, 21 states
SECTION = RveSettings(yarn=YarnSettings(bending="section"))


@pytest.fixture(scope="module")
def cotton_runs():
    runs = {}
    for stitch in stitch_values("cotton-20s2"):
        fabric = load_preset("cotton-20s2", stitch)
        for name in ("uniaxial-course", "uniaxial-wale"):
            runs[stitch, name] = simulate(fabric, load_case(name), SETTINGS)
    return runs


def test_every_cotton_run_converges_with_the_cut_free_of_contact(cotton_runs):
    for result in cotton_runs.values():
        assert result.complete
        assert result.series("contacts_at_cut").max() == 0
        loaded = abs(result.steps[-1].force_gf_per_cm)
        assert abs(result.steps[0].force_gf_per_cm) < 0.05 * loaded  # starts (nearly) unloaded


def test_course_wise_force_falls_as_the_loop_length_grows(cotton_runs):
    stitches = stitch_values("cotton-20s2")
    lengths = [load_preset("cotton-20s2", s).knit.measured_loop_length for s in stitches]
    assert np.all(np.diff(lengths) > 0)
    forces = [cotton_runs[s, "uniaxial-course"].steps[-1].force_gf_per_cm for s in stitches]
    assert np.all(np.diff(forces) < 0), forces


def test_wale_wise_curves_stiffen_with_strain_and_stay_stiffer_than_course_wise(cotton_runs):
    for stitch in stitch_values("cotton-20s2"):
        force = cotton_runs[stitch, "uniaxial-wale"].series("force_gf_per_cm")
        increments = np.diff(force)
        assert increments[-5:].mean() > 2 * increments[:5].mean(), (stitch, force)
        assert force[-1] > cotton_runs[stitch, "uniaxial-course"].steps[-1].force_gf_per_cm


TESTS = {"uniaxial-course": 0.41, "uniaxial-wale": 0.72}
"""The tests' effective Poisson ratios at 20 % (Weeger et al., section 3.1; video extensometer
at the sample's centre, 3-5 samples)."""


def test_poisson_ratios_of_cotton_5_5_are_within_a_quarter_of_the_tests(cotton_runs):
    """Issue 14's target, reached by the yarn's free-fibre bending rigidity (the default where
    the fibres are known; docs/validation.md, "The yarn's bending rigidity")."""
    for case, measured in TESTS.items():
        nu = cotton_runs[5.5, case].poisson_ratio
        assert abs(nu / measured - 1.0) <= 0.25, (case, nu, measured)
    # lateral contraction, stronger when pulled wale-wise: so in the paper's tests and RVE
    nu12, nu21 = (cotton_runs[5.5, case].poisson_ratio for case in TESTS)
    assert 0.0 < nu12 < nu21, (nu12, nu21)


def test_looser_knits_narrow_more_when_pulled_wale_wise(cotton_runs):
    nu21 = [cotton_runs[s, "uniaxial-wale"].poisson_ratio for s in stitch_values("cotton-20s2")]
    assert np.all(np.diff(nu21) > 0), nu21


def test_forces_and_poisson_ratios_at_20_percent_are_pinned(cotton_runs):
    measured = {}
    for stitch in stitch_values("cotton-20s2"):
        for direction, name in (("course", "nu12"), ("wale", "nu21")):
            result = cotton_runs[stitch, f"uniaxial-{direction}"]
            assert result.steps[-1].strain == pytest.approx(0.2)
            key = f"cotton {stitch:.1f}"
            measured[f"{key} {direction} force 20 %"] = result.steps[-1].force_gf_per_cm
            measured[f"{key} {name} 20 %"] = result.poisson_ratio
    assert_pinned("RVE_PAPER_RESOLUTION", measured)


def test_vassiliadis_sample_2_in_strip_biaxial_tension():
    fabric = load_preset("vassiliadis-sample2")
    measured = {}
    for name in ("strip-biaxial-course", "strip-biaxial-wale"):
        result = simulate(fabric, load_case(name), SETTINGS)
        force = result.series("force_gf_per_cm")
        assert result.complete and result.series("contacts_at_cut").max() == 0
        assert np.all(np.diff(force[1:]) > 0)  # tension grows with strain
        strain = result.series("strain")
        assert (strain[10], strain[20]) == pytest.approx((0.1, 0.2))
        measured[f"vassiliadis {name} force 10 %"] = force[10]
        measured[f"vassiliadis {name} force 20 %"] = force[20]
    assert_pinned("RVE_PAPER_RESOLUTION", measured)


def test_wale_wise_stretch_stops_at_the_penetration_limit_instead_of_passing_through():
    # Without the limit the head slips through the legs it holds between 38 and 39 %
    # (penetration 1.53 r at 38 %, then the force turns to -46 gf/cm) and the run "converges"
    # (docs/validation.md); with it the path stops where the penetration reaches r. The yarn
    # bending with its section's rigidity (the paper's model) presses hardest.
    fabric = load_preset("cotton-20s2", 5.5)
    with pytest.raises(ConvergenceError, match="penetration_limit") as caught:
        simulate(fabric, load_case("uniaxial-wale", 0.4), SECTION)
    history = caught.value.history
    penetration = history.series("max_penetration") / history.yarn.radius
    assert penetration.max() <= SECTION.cell.penetration_limit
    assert penetration[-1] > 0.9 * SECTION.cell.penetration_limit  # stopped at the limit
    assert np.all(np.diff(history.series("force_gf_per_cm")) > 0)  # no slip-through
    assert 0.2 < history.steps[-1].strain < 0.38
