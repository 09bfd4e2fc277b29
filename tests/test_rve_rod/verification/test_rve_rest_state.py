"""The squeezed rest state (`YarnSettings.contact_radius = "measured"`, `LoopCell.rest_state`):
the contact law at the yarn's radius r0 > r squeezes the unloaded loop's contacts; the cell
starts from that equilibrium at F = I and measures its stresses from it. The taut rest state
(`YarnSettings.prestrain`): a yarn shorter than its loop, held by its contacts, the same way."""

import dataclasses

import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.geometry.bspline import BSplineCurve
from rve_rod.geometry.loop import loop_geometry
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import BiaxialRay, LoadCase, load_case
from rve_rod.rve.simulation import RveSettings, build_cell, loop_curves, simulate
from rve_rod.rve.yarn import YarnSettings, yarn_model
from rve_rod.units import n_per_mm_to_gf_per_cm

pytestmark = pytest.mark.slow

SQUEEZED = RveSettings(
    cell=CellSettings(control_points=28),
    yarn=YarnSettings(bending="free-fibres", contact_radius="measured"),
)


TAUT = RveSettings(
    cell=CellSettings(control_points=28), yarn=YarnSettings(bending="free-fibres", prestrain=0.02)
)


@pytest.fixture(scope="module", params=["squeezed", "taut"])
def course(request):
    """Cotton 5.5 course-wise to 10 %, from the squeezed rest or from the taut rest (the yarn
    2 % longer than its natural length)."""
    settings = {"squeezed": SQUEEZED, "taut": TAUT}[request.param]
    return simulate(load_preset("cotton-20s2", 5.5), load_case("uniaxial-course", 0.1, 5), settings)


def test_the_contact_law_acts_at_the_measured_radius():
    fabric = load_preset("cotton-20s2", 5.5)
    yarn = yarn_model(fabric, SQUEEZED.yarn)
    assert yarn.law.yarn_radius == fabric.yarn.minimal_radius > yarn.radius


def test_the_rest_state_is_pre_loaded_and_the_stresses_start_from_it(course):
    """At rest the squeezed contacts, or the prestrained yarn, load the cell (P0 of a few
    gf/cm, tensile along both axes: the yarn pulls the cell in, whether the interlocks pushed
    apart stretch it or it is shorter than its loop); the reported stress starts at zero,
    the course height stays the measured one, and the free direction keeps its rest load."""
    rest = n_per_mm_to_gf_per_cm(course.rest_stress)
    assert rest[0, 0] > 1.0 and rest[1, 1] > 1.0
    first = course.steps[0]
    np.testing.assert_allclose(first.first_piola, 0.0, atol=1e-8)
    assert first.lateral_strain == pytest.approx(0.0, abs=1e-9)
    for step in course.steps:
        assert abs(step.first_piola[1, 1]) <= 1e-8 + 1e-3 * abs(step.first_piola[0, 0])
    assert course.complete and course.steps[-1].force_gf_per_cm > 1.0


def test_the_stress_parts_sum_to_the_turned_rest_stress_plus_the_reported_stress(course):
    for step in course.steps:
        np.testing.assert_allclose(
            step.stress_parts.sum(axis=0),
            step.first_piola + step.deformation @ course.rest_stress,
            atol=1e-12,
        )


def test_a_yarn_that_fits_its_loop_has_no_squeeze():
    """Vassiliadis sample 2: r0 = 0.0923 mm < w/8, so r = r0 and "measured" is "adjusted"."""
    fabric = load_preset("vassiliadis-sample2")
    case = load_case("strip-biaxial-course", 0.05, 3)
    cell = CellSettings(control_points=20)
    runs = [
        simulate(fabric, case, RveSettings(cell=cell, yarn=YarnSettings(contact_radius=radius)))
        for radius in ("adjusted", "measured")
    ]
    np.testing.assert_array_equal(runs[0].rest_stress, 0.0)
    np.testing.assert_array_equal(runs[1].rest_stress, 0.0)
    np.testing.assert_array_equal(runs[0].series("first_piola"), runs[1].series("first_piola"))


def test_the_taut_rest_state_shortens_the_yarn_by_what_its_force_says():
    """At rest the loop gives up most of the yarn's excess length (its contacts hold little of
    the prestrain): the yarn length lies between the natural L / (1 + eps0) and the
    template's L, and its axial force, averaged along the yarn, is EA (L_rest / L -
    1 / (1 + eps0)), the force the prestrained strain measure gives for that length."""
    fabric = load_preset("cotton-20s2", 5.5)
    cell = build_cell(loop_curves(fabric), fabric, BiaxialRay(steps=2), TAUT)
    rest = cell.rest_state(TAUT.newton, TAUT.stepping)
    force = cell.model.evaluate(rest, 0.0, with_jacobian=False).section.force
    curve = cell.curve
    deformed = BSplineCurve(curve.degree, curve.knots, cell.positions(rest))
    tangent = deformed(cell.model.collocation[0].parameters, 1)
    axial = np.sum(force.T * tangent, axis=1) / np.linalg.norm(tangent, axis=1)
    weights = cell.model.tributary_lengths
    prestrain, length = TAUT.yarn.prestrain, curve.arc_length()
    stretch = deformed.arc_length() / length
    assert 1.0 / (1.0 + prestrain) < stretch < 1.0
    expected = cell.yarn.section.axial * (stretch - 1.0 / (1.0 + prestrain))
    assert np.sum(axial * weights) / np.sum(weights) == pytest.approx(expected, rel=1e-3)


@pytest.mark.parametrize("stitch", [4.5, 6.5])
def test_counted_from_the_measured_loop_length_the_prestrain_is_the_templates_excess(stitch):
    """natural_length="measured": the yarn's natural length is l / (1 + eps0), l the measured
    loop length, so the rods' prestrain is (1 + eps0) L / l - 1 with L the loop template's
    length (`loop_geometry`); a knit without a measured loop length is refused."""
    fabric = load_preset("cotton-20s2", stitch)
    yarn = YarnSettings(bending="free-fibres", prestrain=0.02, natural_length="measured")
    cell = build_cell(
        loop_curves(fabric), fabric, BiaxialRay(steps=2), RveSettings(cell=TAUT.cell, yarn=yarn)
    )
    template = loop_geometry(fabric.knit, fabric.yarn.minimal_radius).loop_length
    expected = 1.02 * template / fabric.knit.measured_loop_length - 1.0
    assert cell.prestrain == pytest.approx(expected, rel=1e-9)
    unmeasured = dataclasses.replace(
        fabric, knit=dataclasses.replace(fabric.knit, measured_loop_length=None)
    )
    with pytest.raises(InputError, match="natural_length='measured' needs"):
        build_cell(
            loop_curves(unmeasured),
            unmeasured,
            BiaxialRay(steps=2),
            RveSettings(cell=TAUT.cell, yarn=yarn),
        )


def test_a_straight_yarn_bent_into_its_loop_holds_moments_of_its_curvature():
    """natural_curvature = 0 (a yarn that keeps no set): at the bent rest state the rods'
    bending moment is EI times the centreline's curvature, m x t = EI t x t' (t' = dt/ds),
    instead of vanishing where the loop is as built; the contacts hold it, the cell stays at
    its measured w and c, and the stresses of the path start from the rest stress."""
    fabric = load_preset("cotton-20s2", 5.5)
    settings = RveSettings(
        cell=CellSettings(control_points=28),
        yarn=YarnSettings(bending="free-fibres", natural_curvature=0.0),
    )
    cell = build_cell(loop_curves(fabric), fabric, BiaxialRay(steps=2), settings)
    rest = cell.rest_state(settings.newton, settings.stepping)
    moment = cell.model.evaluate(rest, 0.0, with_jacobian=False).section.moment.T
    deformed = BSplineCurve(cell.curve.degree, cell.curve.knots, cell.positions(rest))
    parameters = cell.model.collocation[0].parameters
    first, second = deformed(parameters, 1), deformed(parameters, 2)
    speed = np.linalg.norm(first, axis=1)[:, None]
    tangent = first / speed
    bend = np.cross(first, second) / speed**3  # t x dt/ds, the curvature vector's binormal
    rigidity = cell.yarn.section.bending_1
    assert cell.yarn.section.bending_2 == rigidity
    perpendicular = moment - np.sum(moment * tangent, axis=1)[:, None] * tangent
    weights = cell.model.tributary_lengths
    error = np.linalg.norm(perpendicular - rigidity * bend, axis=1)
    scale = np.linalg.norm(rigidity * bend, axis=1)
    assert np.sum(error * weights) < 0.05 * np.sum(scale * weights)
    assert n_per_mm_to_gf_per_cm(np.abs(cell.rest_stress)).max() > 0.5


@dataclasses.dataclass(frozen=True)
class _InPlaneTurn(LoadCase):
    """F(t) = R(t a), a rigid turn of the cell about the fabric's normal (a test-only case)."""

    angle: float = 0.3

    def final_deformation(self):
        return self.prescribed(1.0)

    def prescribed(self, load_factor):
        c, s = np.cos(load_factor * self.angle), np.sin(load_factor * self.angle)
        return np.array([[c, -s], [s, c]])

    def load_direction(self):
        return np.array([[0.0, -1.0], [1.0, 0.0]]) / np.sqrt(2.0)

    def control(self):
        return self.angle


@pytest.mark.parametrize("friction", [False, True])
def test_a_rigid_turn_of_the_pre_loaded_cell_reports_no_stress(friction):
    """Objectivity: the squeezed rest turned rigidly in its plane by 0.3 rad carries its rest
    stress turned with it, P = R P0, so the reported S = S_total - S0 vanishes. A rest stress
    subtracted from P instead (P - P0) would report S = sym(P0 - R^T P0), S12 about -1.9 gf/cm
    for this cell's P0 of (8.8, 21) gf/cm; slip offsets that did not turn with the cell would
    make its pressed contacts slip and add up to 4.4 gf/cm (docs/contact.md, "Turning
    pairs")."""
    fabric = load_preset("cotton-20s2", 5.5)
    yarn = dataclasses.replace(SQUEEZED.yarn, friction=friction)
    run = simulate(fabric, _InPlaneTurn(steps=4), dataclasses.replace(SQUEEZED, yarn=yarn))
    assert run.complete
    rest = n_per_mm_to_gf_per_cm(run.rest_stress)
    assert min(rest[0, 0], rest[1, 1]) > 5.0
    for step in run.steps:
        turned = step.deformation @ run.rest_stress
        np.testing.assert_allclose(
            step.stress_parts.sum(axis=0), step.first_piola + turned, atol=1e-12
        )
        assert np.abs(n_per_mm_to_gf_per_cm(step.second_piola)).max() < 1e-3 * rest.max()


def test_the_free_directions_balance_jacobian_matches_central_differences():
    """The column of the free F22 of a course-wise run from the squeezed rest (frictionless),
    off the solution: every row's derivative, the macro equation P22 - (F P0)_22 = 0 with its
    P0_22 term (21 gf/cm) among them, equals central differences to 1e-6 of the column's
    largest entry (without the term the macro row is off by P0_22, 1e-2 of it)."""
    fabric = load_preset("cotton-20s2", 5.5)
    frictionless = dataclasses.replace(
        SQUEEZED, yarn=dataclasses.replace(SQUEEZED.yarn, friction=False)
    )
    case = load_case("uniaxial-course", 0.1, 3)
    cell = build_cell(loop_curves(fabric), fabric, case, frictionless)
    state = cell.rest_state(frictionless.newton, frictionless.stepping)
    column = cell.macro.columns[0]
    state[column] = -0.02  # off the solution: the lateral strain guessed
    problem = cell.problem()
    _, jacobian = problem.evaluate(state, 0.5)
    step = 1e-7
    plus, minus = state.copy(), state.copy()
    plus[column] += step
    minus[column] -= step
    differences = (problem.residual(plus, 0.5) - problem.residual(minus, 0.5)) / (2 * step)
    assert n_per_mm_to_gf_per_cm(abs(cell.rest_stress[1, 1])) > 10.0
    assert abs(cell.rest_stress[1, 1]) > 1e-2 * np.abs(differences).max()
    np.testing.assert_allclose(
        jacobian.toarray()[:, column], differences, atol=1e-6 * np.abs(differences).max()
    )
