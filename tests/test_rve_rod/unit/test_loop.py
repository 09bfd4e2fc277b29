"""The loop geometry: the analytic quarter, symmetries, C2 joins, refinement, clearance,
optimality of the shape parameter, the depth search, bad input."""

import dataclasses
import math

import numpy as np
import pytest
from scipy.spatial import cKDTree
from scipy.spatial.distance import cdist

from rve_rod.errors import InputError
from rve_rod.geometry import loop as loop_module
from rve_rod.geometry.loop import (
    SHOULDER_ASPECT,
    LoopShape,
    _smallest_clear_depth,
    affine_length_gradient,
    loop_length_gradient,
    shoulder_radius_bounds,
    single_jersey_loop,
)
from rve_rod.geometry.proximity import chain_clearance
from rve_rod.presets import load_preset

COTTON = load_preset("cotton-20s2", 5.5).knit
TIGHT = load_preset("cotton-20s2", 4.5).knit


@pytest.fixture(scope="module")
def loop():
    return single_jersey_loop(COTTON.wale_width, COTTON.course_height, 0.19)


@pytest.fixture(scope="module")
def tight_loop():
    """Cotton 4.5 with a given shoulder radius: at its depth a crown meets the leg of the
    course above that wraps around it, a flat curved valley of the distance."""
    return single_jersey_loop(TIGHT.wale_width, TIGHT.course_height, 0.19, 1.35 * 0.1575)


def shape_of(loop, depth=None):
    return LoopShape(
        loop.wale_width,
        loop.course_height,
        loop.yarn_radius,
        loop.shape_parameter,
        loop.depth if depth is None else depth,
    )


def circle_through(points):
    """Centre (2,) and radius of the least-squares circle (x - a)^2 + (y - b)^2 = R^2."""
    matrix = np.column_stack([2 * points, np.ones(len(points))])
    solution = np.linalg.lstsq(matrix, np.sum(points**2, axis=1), rcond=None)[0]
    centre = solution[:2]
    return centre, math.sqrt(solution[2] + centre @ centre)


def test_sections_are_a_flat_crown_a_shoulder_ellipse_and_the_leg_arc_through_w(loop):
    w, c, r, rho = loop.wale_width, loop.course_height, loop.yarn_radius, loop.shape_parameter
    crown, shoulder, leg = shape_of(loop).sections()
    h = c / 2 + rho
    a = SHOULDER_ASPECT * rho
    np.testing.assert_allclose(crown[[0, -1]], [[0, h], [w / 4 + r - a, h]], atol=1e-15)
    np.testing.assert_allclose(crown[:, 1], h, atol=1e-15)
    # the shoulder: the ellipse (x - x0)^2 / a^2 + (y - c/2)^2 / rho^2 = 1, from the crown to W
    centred = shoulder - [w / 4 + r - a, c / 2]
    np.testing.assert_allclose((centred / [a, rho]) ** 2 @ [1, 1], 1.0, rtol=1e-12)
    np.testing.assert_allclose(shoulder[[0, -1]], [[w / 4 + r - a, h], [w / 4 + r, c / 2]])
    # the leg: the circle through W = (w/4 + r, c/2) and L = (w/4, 0) centred on y = c/2,
    # so (R - r)^2 + (c/2)^2 = R^2
    centre, radius = circle_through(leg)
    assert centre[1] == pytest.approx(c / 2, rel=1e-12)
    assert radius == pytest.approx((r**2 + c**2 / 4) / (2 * r), rel=1e-12)
    np.testing.assert_allclose(leg[[0, -1]], [[w / 4 + r, c / 2], [w / 4, 0]], atol=1e-14)
    # tangent-continuous: no chord turns by more than the sampling does inside a section
    quarter = shape_of(loop).projection()
    chords = np.diff(quarter, axis=0)
    turn = np.arccos(
        np.clip(
            np.sum(chords[1:] * chords[:-1], 1)
            / np.prod(np.linalg.norm([chords[1:], chords[:-1]], axis=2), axis=0),
            -1,
            1,
        )
    )
    assert turn.max() < 2 * np.pi / 2 / 399


def test_projection_follows_the_shoulder_aspect_an_experiment_sets(loop, monkeypatch):
    # the projection is remembered per shape: the shoulder aspect, a model constant that the
    # sensitivity table of docs/geometry.md varies, must be part of what it is remembered by
    shape = shape_of(loop)
    w, c, r, rho = loop.wale_width, loop.course_height, loop.yarn_radius, loop.shape_parameter
    for aspect in (SHOULDER_ASPECT, 1.0, SHOULDER_ASPECT):
        monkeypatch.setattr(loop_module, "SHOULDER_ASPECT", aspect)
        plane = shape.projection()
        crown = plane[plane[:, 1] == c / 2 + rho]  # the crown, from the apex to the shoulder
        assert crown[:, 0].max() == pytest.approx(w / 4 + r - aspect * rho, rel=1e-12)


def test_legs_lie_in_front_and_the_head_behind(loop):
    shape = shape_of(loop)
    c, rho, d = loop.course_height, loop.shape_parameter, loop.depth
    y = np.linspace(0, c / 2 + rho, 2001)
    z = shape.height(y)
    np.testing.assert_allclose(z[y <= c / 2 - rho], d / 2, rtol=1e-15)  # legs: |y| <= c - h
    assert z[-1] == pytest.approx(-d / 2, rel=1e-15)  # head apex
    slope = np.gradient(z, y)
    assert np.abs(np.diff(slope)).max() < 10 * d / rho**2 * (y[1] - y[0])  # z is C1


def test_radius_is_adjusted_to_an_eighth_of_the_wale_width(loop):
    assert loop.radius_adjusted
    assert loop.yarn_radius == pytest.approx(COTTON.wale_width / 8)


def test_curves_are_the_quarter_mirrored_by_the_two_symmetries(loop):
    u = np.linspace(0, 1, 37)
    w = loop.wale_width
    quarter = loop.curves[2](u)
    mirror = np.array([-1.0, 1.0, 1.0])
    turned = np.column_stack([w / 2 - quarter[:, 0], -quarter[:, 1], quarter[:, 2]])
    np.testing.assert_allclose(loop.curves[1](1 - u), quarter * mirror, atol=1e-13)
    np.testing.assert_allclose(loop.curves[3](1 - u), turned, atol=1e-13)
    np.testing.assert_allclose(loop.curves[0](u), turned * mirror, atol=1e-13)


@pytest.mark.parametrize("order", [0, 1, 2])
def test_joins_are_c2_including_the_periodic_cut(loop, order):
    scale = np.abs(loop.curves[2](np.linspace(0, 1, 9), order)).max()
    period = loop.lattice[0] if order == 0 else 0.0
    ends = [(loop.curves[k], loop.curves[k + 1], 0.0) for k in range(3)]
    ends.append((loop.curves[3], loop.curves[0], period))
    for before, after, shift in ends:
        end = before(np.array([1.0]), order)[0]
        start = after(np.array([0.0]), order)[0] + shift
        np.testing.assert_allclose(end, start, atol=1e-11 * scale)


def test_third_derivative_jumps_at_joins_so_the_c2_test_can_fail(loop):
    # guards the test above: the quarter's ends are not C3 by construction
    jump = loop.curves[2](np.array([0.0]), 3)[0] - loop.curves[1](np.array([1.0]), 3)[0]
    assert np.abs(jump).max() > 1e-3


def test_refinement_to_68_control_points_changes_no_point(loop):
    u = np.linspace(0, 1, 301)
    refined = loop.refined(68)
    assert [curve.n_control_points for curve in refined] == [68] * 4
    for coarse, fine in zip(loop.curves, refined, strict=True):
        np.testing.assert_allclose(fine(u), coarse(u), atol=1e-13)
    with pytest.raises(InputError, match="multiple of 8"):
        loop.refined(50)


def test_clearance_is_two_radii_where_yarns_touch(loop):
    assert loop.min_clearance == pytest.approx(2 * loop.yarn_radius, rel=1e-3)
    assert loop.min_clearance >= 2 * loop.yarn_radius * (1 - 1e-3)


def brute_force_clearance(loop, samples=1500):
    """Smallest distance between dense samples of all 4 curves and of the images |i| <= 1,
    0 <= j <= 2 ((-i, -j) mirrors (i, j)), skipping pairs closer than pi r along the yarn."""
    u = np.linspace(0, 1, samples, endpoint=False)
    points = np.vstack([curve(u) for curve in loop.curves])
    steps = np.linalg.norm(np.diff(points, axis=0, append=points[:1] + loop.lattice[0]), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(steps)[:-1]])
    tree = cKDTree(points)
    best = np.inf
    for i in (-1, 0, 1):
        for j in (0, 1, 2):
            image = cKDTree(points + i * loop.lattice[0] + j * loop.lattice[1])
            pairs = tree.sparse_distance_matrix(image, 3 * loop.yarn_radius, output_type="ndarray")
            if j == 0:
                along = np.abs(arc[pairs["i"]] - arc[pairs["j"]] - i * steps.sum())
                pairs = pairs[along >= np.pi * loop.yarn_radius]
            best = min(best, pairs["v"].min(initial=np.inf))
    return best


@pytest.mark.parametrize("which", ["loop", "tight_loop"])
def test_clearance_matches_brute_force_dense_sampling(which, request):
    loop = request.getfixturevalue(which)
    best = brute_force_clearance(loop)
    # dense samples overestimate a distance by about spacing^2 / distance ~ 1e-6 mm
    assert best == pytest.approx(loop.min_clearance, abs=1e-5)
    assert best >= loop.min_clearance - 1e-12
    assert best >= 2 * loop.yarn_radius * (1 - 1e-6)


@pytest.mark.parametrize("curve", range(4))
def test_search_from_one_curve_uses_the_loops_symmetries(loop, curve):
    # a shallower loop whose clearance is set by the crown passing behind the legs, not 2r
    curves = shape_of(loop, 0.9 * loop.depth).curves()
    full = chain_clearance(curves, loop.lattice, np.pi * loop.yarn_radius)
    assert full.distance < 0.98 * 2 * loop.yarn_radius
    one = chain_clearance(curves, loop.lattice, np.pi * loop.yarn_radius, from_curve=curve)
    assert one.distance == pytest.approx(full.distance, rel=1e-12)


def test_depth_is_the_smallest_that_clears(loop):
    shallower = shape_of(loop, loop.depth - 1e-3 * loop.yarn_radius).curves()
    distance = chain_clearance(shallower, loop.lattice, np.pi * loop.yarn_radius).distance
    assert distance < 2 * loop.yarn_radius * (1 - 1e-6)


def plateau(root, power):
    """An excess that rises to 0 at `root` like (d - root)^power and stays 0 above it."""
    return lambda depth: -(max(root - depth, 0.0) ** power)


@pytest.mark.parametrize(
    ("excess", "guess"),
    [
        (plateau(2.1, 1), 1.9),  # a contact that opens linearly with the depth
        (plateau(2.1, 1), 2.6),  # from a guess that clears
        (plateau(2.1, 2), 2.0),  # a contact met tangentially
        (lambda d: min(0.0, 0.3 * (d - 2.1) - 0.2 * (d - 2.1) ** 2), 1.2),
    ],
)
def test_depth_search_finds_the_edge_of_the_plateau(excess, guess):
    calls = []

    def counted(depth):
        calls.append(depth)
        return excess(depth)

    found = _smallest_clear_depth(counted, 1.0, guess)
    assert excess(found) >= -1e-9  # clears, up to the round-off accepted as contact
    assert found <= 2.1 + 1e-5
    assert len(calls) < 30


def test_depth_search_gives_up_beyond_the_largest_depth():
    assert _smallest_clear_depth(lambda depth: -1.0, 1.0, 2.0) == math.inf


def test_spline_follows_the_analytic_three_section_quarter(loop):
    analytic = shape_of(loop).quarter_samples(np.linspace(0, 1, 4001)).points
    spline = loop.curves[2](np.linspace(0, 1, 400))
    deviation = cdist(spline, analytic).min(axis=1).max()
    assert deviation < 0.03 * loop.yarn_radius  # 2.5 % of r (1.5-3.6 % for the fabrics)


@pytest.mark.parametrize("knit", [COTTON, load_preset("cotton-20s2", 7.0).knit])
def test_shoulder_radius_minimizes_the_loop_length(knit):
    """Admissible shoulder radii 5 % of r either side of the chosen one give longer loops (the
    optimum of cotton 5.5 is the smallest admissible radius, that of cotton 7.0 interior)."""
    loop = single_jersey_loop(knit.wale_width, knit.course_height, 0.19)
    r = loop.yarn_radius
    smallest, largest = shoulder_radius_bounds(loop.wale_width, loop.course_height, r)
    others = [
        rho
        for rho in loop.shape_parameter + np.array([-0.05, 0.05]) * r
        if smallest <= rho <= largest
    ]
    assert others
    for rho in others:
        other = single_jersey_loop(loop.wale_width, loop.course_height, 0.19, rho)
        assert other.min_clearance >= 2 * r * (1 - 1e-3)
        assert other.loop_length > loop.loop_length


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ((0.0, 1.0, 0.1), "wale_width=0 mm must be > 0"),
        ((1.0, float("nan"), 0.1), "course_height=nan mm must be a finite number"),
        ((1.0, 1.0, -0.1), "yarn_radius=-0.1 mm must be > 0"),
        ((1.0, 0.05, 0.12), "course_height must be >= 2.6 r = 0.312 mm"),
        ((1.33, 0.5, 0.19), "needs course_height >= about 4 r = 0.665 mm"),
        ((1.33, 1.26, 0.19, 0.1), r"shoulder_radius=0.1 mm is outside .*\[0.216125, 0.383654\]"),
    ],
)
def test_bad_input_is_refused(arguments, message):
    with pytest.raises(InputError, match=message):
        single_jersey_loop(*arguments)


@pytest.mark.parametrize("profile", ["band", "parabolic"])
def test_the_loop_length_gradient_obeys_eulers_relation_of_a_scale_free_loop(profile):
    """The loop has no length scale but w, c and r: L(s w, s c, s r) = s L, so
    w dL/dw + c dL/dc + r dL/dr = L (r dL/dr by a central difference here, r below w/8)."""
    w, c = 1.33, 1.26
    r = 0.9 * w / 8
    gradient = loop_length_gradient(w, c, r, profile=profile)
    assert np.all(gradient > 0)
    h = 0.01

    def length(radius):
        return single_jersey_loop(w, c, radius, profile=profile).loop_length

    along_r = (length(r * (1 + h)) - length(r * (1 - h))) / (2 * h)
    assert gradient.sum() + along_r == pytest.approx(length(r), rel=0.005)


def test_the_loop_length_gradient_refuses_a_yarn_wider_than_the_loop_holds():
    with pytest.raises(InputError, match=r"yarn_radius=0\.2 mm is out of range"):
        loop_length_gradient(1.33, 1.26, 0.2)


@pytest.mark.parametrize("profile", ["band", "parabolic"])
def test_the_affine_length_gradient_is_the_affinely_stretched_loops_growth(profile):
    """a_i = dL/dE_ii of the loop stretched affinely (B-splines map with their control points),
    against central differences in E11 and E22."""
    loop = single_jersey_loop(1.33, 1.26, 0.19, profile=profile)
    gradient = affine_length_gradient(loop.curves)
    h = 1e-4

    def length(e11, e22):
        stretch = np.array([np.sqrt(1 + 2 * e11), np.sqrt(1 + 2 * e22), 1.0])
        return sum(
            dataclasses.replace(curve, control_points=curve.control_points * stretch).arc_length()
            for curve in loop.curves
        )

    along = [(length(h, 0) - length(-h, 0)) / (2 * h), (length(0, h) - length(0, -h)) / (2 * h)]
    assert gradient == pytest.approx(along, rel=1e-6)
