"""The comparison with the paper group's runs: the error measure on runs of known answer."""

import numpy as np
import pytest

from rve_rod.contact import CompressibleYarnLaw
from rve_rod.errors import InputError
from rve_rod.geometry.bspline import BSplineCurve
from rve_rod.geometry.loop import single_jersey_loop
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.paper.comparison import (
    RunComparison,
    axis_rays,
    compare_run,
    contact_directions,
    contact_points,
    first_increment_ratio,
    length_budget,
    loop_extents,
    loop_profile_runner,
    run_case,
    secant_at_rest,
    shear_share,
    taut_loop_split,
)
from rve_rod.rve.paper.data import biaxial_rays, shear_run
from rve_rod.rve.simulation import RveSettings
from rve_rod.stress_measures import green_lagrange
from rve_rod.units import n_per_mm_to_gf_per_cm


class _Step:
    def __init__(self, second):
        self.second_piola = second


class _Result:
    def __init__(self, steps):
        self.steps = steps


def echo(run, scale=1.0, stop=None):
    """A runner that returns their own S (times `scale`), stopping after `stop` states."""

    def runner(fabric, case, settings):
        count = case.steps - 1 if stop is None else stop
        steps = [_Step(np.zeros(3))]
        for S in run.second_piola[:count]:
            steps.append(_Step(scale * np.array([S[0, 0], S[1, 1], 0.5 * (S[0, 1] + S[1, 0])])))
        return _Result(steps)

    return runner


@pytest.mark.parametrize("kind", ["ray", "shear"])
def test_their_own_stresses_compare_with_zero_error_and_scaled_ones_with_the_scale(kind):
    run = biaxial_rays(5.5)[6] if kind == "ray" else shear_run(5.5)
    fabric = load_preset("cotton-20s2", 5.5)
    exact = compare_run(fabric, run, RveSettings(), runner=echo(run))
    assert exact.worst() == pytest.approx(0.0, abs=1e-15)
    assert exact.passed()
    # S scaled by 1.3 everywhere: the error at each state is 0.3 times the state's largest
    # compared component over the largest of the run so far, so 0.3 where it peaks
    scaled = compare_run(fabric, run, RveSettings(), runner=echo(run, 1.3))
    errors = scaled.errors()
    assert errors.max() == pytest.approx(0.3, rel=1e-12)
    assert np.all(errors <= 0.3 + 1e-12)
    assert not scaled.passed()


def test_a_run_that_stops_early_fails_with_its_missing_states_as_nan():
    run = biaxial_rays(5.5)[1]
    comparison = compare_run(
        load_preset("cotton-20s2", 5.5), run, RveSettings(), runner=echo(run, stop=5)
    )
    assert isinstance(comparison, RunComparison)
    assert (comparison.states, comparison.reached) == (run.converged, 5)
    assert np.isnan(comparison.errors()[5:]).all()
    assert comparison.worst() == np.inf


def test_runs_without_converged_states_are_not_compared():
    equibiaxial_compression = biaxial_rays(5.5)[0]
    assert equibiaxial_compression.converged == 0
    comparison = compare_run(
        load_preset("cotton-20s2", 5.5), equibiaxial_compression, RveSettings()
    )
    assert (comparison.states, comparison.worst()) == (0, 0.0)


def test_the_shear_share_is_the_largest_shear_over_the_largest_normal_stress():
    """Over the finite states, max |S12|, |S21| over max |S11|, |S22|; 0 for diagonal S, NaN
    without a finite state."""
    stresses = np.array([[[1.0, 0.02], [0.01, -2.0]], [[4.0, -0.1], [0.05, 3.0]]])
    assert shear_share(stresses) == pytest.approx(0.1 / 4.0)
    with_nan = np.concatenate([stresses, np.full((1, 2, 2), np.nan)])
    assert shear_share(with_nan) == pytest.approx(0.1 / 4.0)
    assert shear_share(np.array([np.diag([1.0, 2.0])])) == 0.0
    assert np.isnan(shear_share(np.full((2, 2, 2), np.nan)))


def test_the_secant_at_rest_of_a_linear_material_is_its_stiffness():
    """S = C E at the first states of their two rays nearest the axes returns C, and their own
    first states give the stiffness docs/validation.md quotes at 5.5 ([[280, 297], [348, 859]]
    gf/cm)."""
    rays = axis_rays(5.5)
    stiffness = np.array([[2.0, 0.7], [0.9, 5.0]])
    stresses = [stiffness @ np.diagonal(green_lagrange(ray.deformation[0])) for ray in rays]
    np.testing.assert_allclose(secant_at_rest(rays, stresses), stiffness, rtol=1e-12)
    secant = n_per_mm_to_gf_per_cm(secant_at_rest(rays))
    np.testing.assert_allclose(secant, [[280, 297], [348, 859]], atol=0.5)


def test_the_first_increment_ratio_is_one_when_linear_and_tells_stiffening_from_yielding():
    """Along a ray E_k = k e: S = C E gives 1; S = C E (1 + b |E|) gives (1 + b |e|) / (1 +
    3 b |e|) (below 1 for b > 0, stiffening; above 1 for b < 0, giving way)."""
    ray = biaxial_rays(5.5)[6]  # equibiaxial: E keeps its direction
    assert ray.angle_deg == pytest.approx(45.0)
    strains = np.array([np.diagonal(green_lagrange(f)) for f in ray.deformation[:2]])
    stiffness = np.array([[2.0, 0.7], [0.9, 5.0]])
    assert first_increment_ratio(ray.deformation, strains @ stiffness.T) == pytest.approx(1.0)
    e = np.linalg.norm(strains[0])
    ray_f = np.array([np.diag(np.sqrt(1 + 2 * k * strains[0])) for k in (1, 2)])
    for b in (5.0, -5.0):
        stresses = [stiffness @ (k * strains[0]) * (1 + b * k * e) for k in (1, 2)]
        expected = (1 + b * e) / (1 + 3 * b * e)
        assert first_increment_ratio(ray_f, stresses) == pytest.approx(expected, rel=1e-12)


def test_the_taut_loop_split_recovers_the_length_stiffness_and_the_rest():
    gradient = np.array([1.25, 2.4])  # mm
    k, rest = 3.0, np.array([0.7, 1.9])  # N/mm^3, N/mm
    stiffness = k * np.outer(gradient, gradient) + np.diag(rest)
    split = taut_loop_split(stiffness, gradient)
    assert split.stiffness == pytest.approx(k, rel=1e-12)
    np.testing.assert_allclose(split.rest, rest, rtol=1e-12)
    expected = (k * 1.25 * 2.4) ** 2 / (stiffness[0, 0] * stiffness[1, 1])
    assert split.coupling == pytest.approx(expected, rel=1e-12)
    # an inextensible loop (no rest) couples fully, an uncoupled cell not at all
    assert taut_loop_split(k * np.outer(gradient, gradient), gradient).coupling == pytest.approx(1)
    uncoupled = taut_loop_split(np.diag(rest), gradient)
    assert uncoupled.stiffness == 0.0 and uncoupled.coupling == 0.0
    np.testing.assert_array_equal(uncoupled.rest, rest)


def test_the_taut_loop_split_refuses_a_gradient_that_is_not_positive():
    with pytest.raises(InputError, match=r"gradient \[1.2, 0.0\]"):
        taut_loop_split(np.eye(2), np.array([1.2, 0.0]))


def test_the_loop_profile_runner_runs_the_loop_of_that_profile():
    """On the model's own profile it is the default run, to the bit; on the parabolic loop
    (bent out of plane over its whole height: another cell) the stresses differ."""
    fabric = load_preset("cotton-20s2", 5.5)
    ray = axis_rays(5.5)[0]
    settings = RveSettings(cell=CellSettings(control_points=20))
    default = compare_run(fabric, ray, settings, states=1).second_piola
    band = compare_run(fabric, ray, settings, states=1, runner=loop_profile_runner("band"))
    parabolic = compare_run(
        fabric, ray, settings, states=1, runner=loop_profile_runner("parabolic")
    ).second_piola
    np.testing.assert_array_equal(band.second_piola, default)
    assert np.all(np.isfinite(parabolic))
    assert abs(parabolic[0, 0, 0] / default[0, 0, 0] - 1) > 0.1


@pytest.mark.parametrize("profile", ["band", "parabolic"])
def test_the_loop_extents_at_rest_are_the_templates_depth_and_length(profile):
    """At rest the deformed loop is the template: its extent through the thickness is the
    depth d of the clearance search (legs at +d/2, head apex at -d/2) and its length the loop
    length, both up to the B-spline fit; the projection is shorter than the yarn."""
    fabric = load_preset("cotton-20s2", 5.5)
    knit = fabric.knit
    loop = single_jersey_loop(
        knit.wale_width, knit.course_height, fabric.yarn.minimal_radius, profile=profile
    )
    settings = RveSettings(cell=CellSettings(control_points=20))
    result = loop_profile_runner(profile)(fabric, run_case(axis_rays(5.5)[0], 1), settings)
    extent = loop_extents(result)
    assert extent.depth.shape == extent.length.shape == (len(result.steps),)
    assert extent.depth[0] == pytest.approx(loop.depth, rel=0.02)
    assert extent.length[0] == pytest.approx(loop.loop_length, rel=0.005)
    assert np.all(extent.in_plane_length < extent.length)


def _polyline(*points) -> BSplineCurve:
    """The degree-1 B-spline through `points` (a polyline; knots at equal parameter steps)."""
    inner = np.linspace(0.0, 1.0, len(points))[1:-1]
    knots = np.concatenate([[0.0, 0.0], inner, [1.0, 1.0]])
    return BSplineCurve(1, knots, np.array(points, dtype=float))


STRETCH = np.diag([1.2, 1.0])
"""A course-wise stretch by 20 %: the V's span grows from 1 to 1.2 mm."""


def test_an_affinely_stretched_loop_meets_the_demand_by_stretching():
    """The affine image itself is the deformed curve: all of the demand is the yarn's stretch.
    A straight yarn along x stretched by 20 % demands 20 %."""
    rest = _polyline((0, 0, 0), (0.5, 0, 0), (1, 0, 0))
    budget = length_budget(rest, _polyline((0, 0, 0), (0.6, 0, 0), (1.2, 0, 0)), STRETCH)
    assert budget.demand == pytest.approx(0.2, rel=1e-9)
    assert (budget.stretch, budget.depth, budget.shape) == pytest.approx((1, 0, 0), abs=1e-9)


@pytest.mark.parametrize(("axis", "share"), [(2, "depth"), (1, "shape")])
def test_a_v_that_opens_at_its_length_gives_up_its_depth_or_its_shape(axis, share):
    """A V of span 1 and height 0.6 (legs 0.781 mm) stretched to span 1.2 at its own length:
    its height falls to sqrt(0.61 - 0.36) = 0.5. Raised through the thickness (z), the yarn it
    needs comes from the depth; raised in the plane (y), from the in-plane shape (F22 = 1:
    the affine image keeps the height). The demand is the affine V's: 2 sqrt(0.36 + 0.36) / (2
    sqrt(0.61)) - 1."""

    def vee(half_span, height):
        apex = [half_span, 0.0, 0.0]
        apex[axis] = height
        return _polyline((0, 0, 0), apex, (2 * half_span, 0, 0))

    budget = length_budget(vee(0.5, 0.6), vee(0.6, 0.5), STRETCH)
    assert budget.demand == pytest.approx(np.sqrt(0.72 / 0.61) - 1, rel=1e-9)
    expected = {"stretch": 0.0, "depth": 0.0, "shape": 0.0, share: 1.0}
    assert budget._asdict() == pytest.approx({"demand": budget.demand, **expected}, abs=1e-9)


def test_a_deformation_that_demands_no_yarn_is_refused():
    rest = _polyline((0, 0, 0), (0.5, 0, 0), (1, 0, 0))
    with pytest.raises(InputError, match="longer than the rest loop"):
        length_budget(rest, rest, np.diag([0.9, 1.0]))


LAW = CompressibleYarnLaw(stiffness=1.0, exponent=1.5, yarn_radius=0.1)


def test_straight_courses_pressed_together_push_along_the_wale():
    """Straight yarns along the courses, 1.9 r apart along the wale: every contact normal is
    along y. Their own continuation along the course (the image (1, 0), which the yarn touches
    end to end) is no contact."""
    yarn = _polyline((0, 0, 0), (0.5, 0, 0), (1, 0, 0))
    lattice = np.array([[1.0, 0.0, 0.0], [0.0, 1.9 * LAW.yarn_radius, 0.0]])
    shares = contact_directions(yarn, lattice, LAW.yarn_radius, LAW)
    assert shares == pytest.approx([0.0, 1.0, 0.0], abs=1e-12)


@pytest.mark.parametrize("angle", [0.0, 30.0, 90.0])
def test_courses_stacked_at_an_angle_push_along_it(angle):
    """The same yarns with the next course 1.9 r away at `angle` degrees from the plane
    (towards z) and shifted 0.3 mm along the course (along the yarn: no change of direction):
    every normal along (0, cos, sin), up to the sampling: the image's samples fall between the
    yarn's (1500 samples a period, 6.7e-4 mm apart: a tilt of at most half a spacing over the
    gap, 0.0018)."""
    yarn = _polyline((0, 0, 0), (0.5, 0, 0), (1, 0, 0))
    a = np.radians(angle)
    gap = 1.9 * LAW.yarn_radius
    lattice = np.array([[1.0, 0.0, 0.0], [0.3, gap * np.cos(a), gap * np.sin(a)]])
    shares = contact_directions(yarn, lattice, LAW.yarn_radius, LAW)
    assert shares == pytest.approx([0.0, np.cos(a), np.sin(a)], abs=2e-3)


def test_the_contacts_of_straight_courses_are_with_the_next_courses_at_the_laws_load():
    """Straight courses 1.9 r apart: every point but the period's two ends touches the courses
    above and below, (0, 1) and (0, -1), pressed by 0.1 r: the law's load there, normals along
    -y and +y."""
    yarn = _polyline((0, 0, 0), (0.5, 0, 0), (1, 0, 0))
    lattice = np.array([[1.0, 0.0, 0.0], [0.0, 1.9 * LAW.yarn_radius, 0.0]])
    contacts = contact_points(yarn, lattice, LAW.yarn_radius, LAW, samples=101)
    assert sorted(map(tuple, np.unique(contacts.image, axis=0))) == [(0, -1), (0, 1)]
    assert contacts.load == pytest.approx(LAW.load_and_slope(0.1 * LAW.yarn_radius)[0])
    np.testing.assert_allclose(contacts.normal[:, 1], -np.sign(contacts.image[:, 1]), atol=1e-12)
    assert len(contacts.load) >= 2 * 99


def test_a_yarn_without_contact_is_refused():
    yarn = _polyline((0, 0, 0), (0.5, 0, 0), (1, 0, 0))
    lattice = np.array([[1.0, 0.0, 0.0], [0.0, 3 * LAW.yarn_radius, 0.0]])
    with pytest.raises(InputError, match="no point of the yarn is in contact"):
        contact_directions(yarn, lattice, LAW.yarn_radius, LAW)
