"""Stitch patterns, geometry: the template loops of a pattern's periodic cell (free of
interpenetration, C2, with the pattern's symmetries), the jersey chart's loops are the jersey
loop, a purl loop is the knit loop mirrored, and the clearance of several yarns."""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from rve_rod.errors import InputError
from rve_rod.geometry.loop import ADJACENT_ARC_FACTOR, LoopShape, single_jersey_loop
from rve_rod.geometry.pattern_cell import QuarterSides, pattern_geometry, pattern_heights
from rve_rod.geometry.proximity import cell_clearance, chain_clearance
from rve_rod.pattern import periodic_cell
from rve_rod.presets import load_preset
from rve_rod.rve.cell import periodic_patch

COTTON = load_preset("cotton-20s2", 5.5).knit
R0 = 0.19
MIXED = ("rib1x1", "rib2x2", "garter", "seed", "moss")


def geometry(pattern):
    return pattern_geometry(pattern, COTTON.wale_width, COTTON.course_height, R0)


def points(curves, samples=60):
    u = np.linspace(0.0, 1.0, samples)
    return np.vstack([curve(u) for curve in curves])


def test_the_jersey_chart_is_the_jersey_loop():
    jersey = single_jersey_loop(COTTON.wale_width, COTTON.course_height, R0)
    cell = geometry("jersey")
    assert cell.yarns == (jersey.curves,)
    np.testing.assert_array_equal(cell.lattice, jersey.lattice)
    assert cell.depth == jersey.depth
    assert cell.loop_length == pytest.approx(jersey.loop_length, rel=1e-12)


def test_a_purl_loop_is_the_knit_loop_mirrored_through_the_mid_plane():
    knit, purl = geometry("jersey").yarns[0], geometry("reverse-jersey").yarns[0]
    for k, p in zip(knit, purl, strict=True):
        np.testing.assert_array_equal(p.control_points[:, :2], k.control_points[:, :2])
        np.testing.assert_array_equal(p.control_points[:, 2], -k.control_points[:, 2])


@pytest.mark.parametrize("pattern", MIXED)
def test_templates_clear_every_yarn_by_two_radii_and_join_c2(pattern):
    cell = geometry(pattern)
    r = cell.yarn_radius
    assert cell.min_clearance >= 2 * r * (1 - 1e-6)
    # an independent check of the clearance: dense samples, the adjacent arc excluded
    assert cell.depth >= 2 * r
    for yarn in cell.yarns:  # C2 joins and one period along a1 (periodic_patch checks both)
        periodic_patch(list(yarn), cell.lattice[0], 1.0, 12)
    assert len(cell.yarns) == cell.cell.courses
    assert all(len(yarn) == 4 * cell.cell.loops_per_course for yarn in cell.yarns)


@pytest.mark.parametrize("pattern", MIXED)
def test_templates_have_the_wale_mirror_symmetry_of_their_charts(pattern):
    """Every named pattern is mirror symmetric about a wale axis, through a loop or between
    two (x -> k w/2 - x maps the chart onto itself): so is its template, up to the lattice."""
    cell = geometry(pattern)
    samples = np.vstack([points(yarn) for yarn in cell.yarns])
    a1, a2 = cell.lattice
    images = np.vstack([samples + i * a1 + j * a2 for i in range(-3, 4) for j in range(-3, 4)])
    tree = cKDTree(images)
    mirrored = samples * np.array([-1.0, 1.0, 1.0])
    gaps = [
        tree.query(mirrored + np.array([0.5 * k * cell.wale_width, 0.0, 0.0]))[0].max()
        for k in range(2 * cell.cell.loops_per_course)
    ]
    assert min(gaps) < 1e-9


def test_patterns_of_crossing_sinkers_are_deeper_than_jersey():
    jersey = geometry("jersey")
    for pattern in ("rib1x1", "seed"):
        assert geometry(pattern).depth > 2 * jersey.depth


def test_heights_of_the_jersey_sides_are_the_jersey_band():
    loop = single_jersey_loop(COTTON.wale_width, COTTON.course_height, R0)
    shape = LoopShape(
        loop.wale_width, loop.course_height, loop.yarn_radius, loop.shape_parameter, loop.depth
    )
    plane = shape.projection()
    np.testing.assert_allclose(
        pattern_heights(shape, QuarterSides(1, 1), plane), shape.height(plane[:, 1]), atol=1e-15
    )
    np.testing.assert_allclose(
        pattern_heights(shape, QuarterSides(-1, -1), plane), -shape.height(plane[:, 1]), atol=1e-15
    )
    crossing = pattern_heights(shape, QuarterSides(1, 1, True), plane)
    assert crossing[0] == pytest.approx(0.0, abs=1e-15)  # the sinker lies in the mid-plane
    assert crossing[-1] == pytest.approx(0.5 * shape.depth)  # the leg is the knit's
    step = pattern_heights(shape, QuarterSides(-1, 1), plane)
    assert step[-1] == pytest.approx(0.0, abs=1e-15)  # the leg crosses at L
    assert step[0] == pytest.approx(0.5 * shape.depth)  # head apex behind a purl


def test_the_clearance_of_a_cell_of_one_yarn_is_the_chain_clearance():
    loop = single_jersey_loop(COTTON.wale_width, COTTON.course_height, R0)
    adjacent = ADJACENT_ARC_FACTOR * loop.yarn_radius
    one = cell_clearance([loop.curves], loop.lattice, adjacent)
    assert one.distance == pytest.approx(
        chain_clearance(loop.curves, loop.lattice, adjacent).distance, rel=1e-9
    )


def test_two_courses_of_jersey_clear_each_other_as_the_course_clears_its_images():
    cell = pattern_geometry(
        periodic_cell("jersey", ((1, 0), (0, 2))), COTTON.wale_width, COTTON.course_height, R0
    )
    assert len(cell.yarns) == 2
    found = cell_clearance(
        list(cell.yarns), cell.lattice, ADJACENT_ARC_FACTOR * cell.yarn_radius
    ).distance
    assert found == pytest.approx(2 * cell.yarn_radius, rel=1e-6)


def test_a_chart_given_as_a_list_is_the_chart_given_as_a_tuple():
    """Rows as a list (as JSON and TOML give them) are the same chart as a tuple, from the same
    cache; a list with a tuck is refused with the chart's one line, not a TypeError."""
    sizes = (COTTON.wale_width, COTTON.course_height, R0)
    assert pattern_geometry(["KP"], *sizes) is pattern_geometry(("KP",), *sizes)
    with pytest.raises(InputError, match="has a tuck"):
        pattern_geometry(["KT", "KK"], *sizes)
