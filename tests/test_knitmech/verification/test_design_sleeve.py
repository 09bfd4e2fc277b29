"""The sleeve's Laplace model and its design (NumPy), on families independent of the RVE.

* Laplace's law on a band in closed form: a family of Saint Venant-Kirchhoff members (exact
  bilinear surfaces), S11 = Q11 E11 + Q12 E22, T = lambda_1 S11 / lambda_2, p = T / r.
* The designed sleeve meets a graduated target within 5 % at every band (issue 30), with
  whole needles and courses; an infeasible target returns the best design and its misses.
"""

import numpy as np
import pytest
from support.design_cases import synthetic_family

from fabric_dolfinx.spec.revolution import RadiusProfile
from knitmech.design.family import FamilyMember, SurfaceFamily
from knitmech.design.sleeve import (
    PressureTarget,
    SleeveSpec,
    band_state,
    design_sleeve,
    laplace_pressure,
    relaxed_tube,
)
from knitmech.design.solve import SolverSettings
from rve_rod.surface import ResponseSurface, Spline1D, Spline2D
from rve_rod.units import MMHG

KNOTS = np.array([-0.5, -0.5, 0.5, 0.5])
ENDS = np.array([-0.5, 0.5])
LEG = RadiusProfile(
    (0, 50, 100, 150, 200, 250, 300, 350, 400), (35, 37, 41.5, 48, 54, 58, 59, 56, 52.5)
)


def svk_surface(q11, q12, q22):
    """S11 = q11 E11 + q12 E22, S22 = q12 E11 + q22 E22 exactly (degree-1 splines), N/mm."""
    return ResponseSurface(
        kind="stress",
        s11=Spline2D((1, 1), (KNOTS, KNOTS), q11 * ENDS[:, None] + q12 * ENDS[None, :]),
        s22=Spline2D((1, 1), (KNOTS, KNOTS), q12 * ENDS[:, None] + q22 * ENDS[None, :]),
        s12=Spline1D(1, KNOTS, 0.1 * ENDS),
    )


SVK_FAMILY = SurfaceFamily(
    (FamilyMember(5.0, "", 1.3, 1.1), FamilyMember(6.0, "", 1.4, 1.4)),
    (svk_surface(0.2, 0.05, 0.4), svk_surface(0.1, 0.03, 0.3)),
)


@pytest.mark.parametrize("stitch", [5.0, 5.3, 6.0])
def test_laplace_pressure_of_a_band_in_closed_form(stitch):
    theta = (stitch - 5.0) / 1.0  # the second member's weight
    q11, q12 = 0.2 + theta * (0.1 - 0.2), 0.05 + theta * (0.03 - 0.05)
    w = 1.3 + 0.1 * theta
    radius, needles, axial = 40.0, 170.0, 1.04
    hoop = 2 * np.pi * radius / (needles * w)
    S11 = q11 * (hoop**2 - 1) / 2 + q12 * (axial**2 - 1) / 2
    state = band_state(SVK_FAMILY, radius, (stitch, needles), axial)
    assert state.hoop_stretch == pytest.approx(hoop, rel=1e-14)
    assert state.axial_stretch == pytest.approx(axial, rel=1e-14)
    assert state.tension == pytest.approx(hoop * S11 / axial, rel=1e-12)
    assert state.pressure == pytest.approx(hoop * S11 / axial / radius, rel=1e-12)


def test_the_relaxed_tube_is_each_bands_knit_at_its_centre():
    stitches, needles, courses = (
        np.array([5.0, 5.6, 6.0]),
        np.array([150, 170, 160]),
        np.array([40, 42, 38]),
    )
    tube = relaxed_tube(SVK_FAMILY, 10.0, (stitches, needles, courses))
    lengths = courses * np.array([SVK_FAMILY.course_height(s) for s in stitches])
    np.testing.assert_allclose(np.diff(tube.edges), lengths, rtol=1e-14)
    assert tube.edges[0] == 10.0
    widths = np.array([SVK_FAMILY.wale_width(s) for s in stitches])
    np.testing.assert_allclose(
        tube.radius(tube.centres), needles * widths / (2 * np.pi), rtol=1e-14
    )


@pytest.fixture(scope="module")
def family():
    return synthetic_family()


def graduated(sleeve, ankle, knee):
    return np.interp(sleeve.centres, [0.0, 400.0], [ankle, knee]) * MMHG


@pytest.mark.parametrize("given", [False, True])
def test_the_designed_sleeve_meets_a_graduated_target_within_5_percent(family, given):
    """A 3:2 graduation (as 30 to 20 mmHg) within the synthetic family's reach, the needles
    designed, or given per band (12 % hoop strain at stitch 5.5)."""
    needles = None
    if given:
        radii = LEG.radius(SleeveSpec(LEG, 8).centres)
        needles = tuple(np.round(2 * np.pi * radii / (1.12 * family.wale_width(5.5))))
    sleeve = SleeveSpec(LEG, 8, needles)
    target = PressureTarget(graduated(sleeve, 15.0, 10.0))
    design = design_sleeve(family, sleeve, target, family.stitch_range, SolverSettings())
    assert design.met
    assert np.max(np.abs(design.misses)) < 0.05
    states = laplace_pressure(family, sleeve, design.stitches, design.needles, design.courses)
    pressure = np.array([state.pressure for state in states])
    np.testing.assert_array_less(np.abs(pressure / target.pressure - 1), 0.05)
    assert design.needles.dtype.kind == "i" and design.courses.dtype.kind == "i"
    pairs = zip(design.courses, design.stitches, strict=True)
    knitted = sum(n * family.course_height(s) for n, s in pairs)
    np.testing.assert_allclose([s.axial_stretch for s in states], 400.0 / knitted, rtol=1e-14)
    assert 400.0 / knitted == pytest.approx(sleeve.axial_stretch, abs=0.01)
    if not given:  # the needles aim at the hoop strain
        hoop = np.array([state.hoop_stretch for state in states]) - 1
        np.testing.assert_allclose(hoop, sleeve.hoop_strain, atol=0.01)
    assert design.evaluations < 400


def test_an_infeasible_target_returns_the_best_design_and_its_miss(family):
    sleeve = SleeveSpec(LEG, 6)
    target = PressureTarget(graduated(sleeve, 300.0, 200.0))
    design = design_sleeve(family, sleeve, target, family.stitch_range, SolverSettings())
    assert not design.met
    np.testing.assert_allclose(design.stitches, 4.5, atol=1e-6)  # the tightest the family has
    assert np.all(design.misses < -0.5)
    # the needles stop where the hoop strain leaves the family's data
    largest = np.sqrt(1 + 2 * family.domain[0, 1]) - 1
    hoop = np.array([state.hoop_stretch for state in design.states]) - 1
    assert np.all(hoop <= largest + 0.01)
