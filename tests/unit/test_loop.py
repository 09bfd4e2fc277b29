"""The loop geometry: symmetries, C2 joins, refinement, clearance, optimality, bad input."""

import numpy as np
import pytest
from scipy.spatial.distance import cdist

from rve_rod.errors import InputError
from rve_rod.geometry.loop import LoopShape, single_jersey_loop
from rve_rod.presets import load_preset

COTTON = load_preset("cotton-20s2", 5.5).knit


@pytest.fixture(scope="module")
def loop():
    return single_jersey_loop(COTTON.wale_width, COTTON.course_height, 0.19)


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


def test_clearance_matches_brute_force_dense_sampling(loop):
    u = np.linspace(0, 1, 1501)[:-1]
    points = np.vstack([curve(u) for curve in loop.curves])
    steps = np.linalg.norm(np.diff(points, axis=0, append=points[:1] + loop.lattice[0]), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(steps)[:-1]])
    length = steps.sum()
    best = np.inf
    for i in (-1, 0, 1):
        for j in (0, 1, 2):
            distances = cdist(points, points + i * loop.lattice[0] + j * loop.lattice[1])
            if j == 0:
                along = np.abs(arc[:, None] - (arc[None, :] + i * length))
                distances[along < np.pi * loop.yarn_radius] = np.inf
            best = min(best, distances.min())
    # dense samples overestimate the distance by about spacing^2 / distance ~ 1e-5 mm
    assert best == pytest.approx(loop.min_clearance, abs=2e-5)
    assert best >= loop.min_clearance - 1e-12


def test_spline_follows_the_analytic_three_section_quarter(loop):
    shape = LoopShape(
        loop.wale_width, loop.course_height, loop.yarn_radius, loop.shape_parameter, loop.depth
    )
    analytic = shape.quarter_samples(np.linspace(0, 1, 4001)).points
    spline = loop.curves[2](np.linspace(0, 1, 400))
    deviation = cdist(spline, analytic).min(axis=1).max()
    assert deviation < 0.03 * loop.yarn_radius  # measured 2.1 % of r for cotton 5.5


def test_shape_parameter_minimizes_the_loop_length(loop):
    r = loop.yarn_radius
    for delta in (-0.05 * r, 0.05 * r):
        other = single_jersey_loop(
            loop.wale_width, loop.course_height, 0.19, loop.shape_parameter + delta
        )
        assert other.min_clearance >= 2 * r * (1 - 1e-3)
        assert other.loop_length > loop.loop_length


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ((0.0, 1.0, 0.1), "wale_width=0 mm must be > 0"),
        ((1.0, float("nan"), 0.1), "course_height=nan mm must be a finite number"),
        ((1.0, 1.0, -0.1), "yarn_radius=-0.1 mm must be > 0"),
        ((1.0, 0.05, 0.12), "no loop fits"),
    ],
)
def test_bad_input_is_refused(arguments, message):
    with pytest.raises(InputError, match=message):
        single_jersey_loop(*arguments)
