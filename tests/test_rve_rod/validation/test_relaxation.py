"""The cell relaxed by mechanics (`rve_rod.rve.relaxation`): a yarn that lets go of its whole
set, relaxed at zero macro stress, against the geometric relaxed cell (docs/patterns.md, "The
relaxed cell")."""

import pytest

from rve_rod.errors import InputError
from rve_rod.geometry.relaxed import relaxed_knit, settled_fabric
from rve_rod.presets import load_preset
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.relaxation import relax_cell
from rve_rod.rve.simulation import RveSettings, build_cell, loop_curves

STITCH = 5.5


def _loop_length(fabric):
    """The yarn per loop of the fabric's template (mm)."""
    return sum(curve.arc_length() for curve in loop_curves(fabric))


def _radius(fabric):
    """The yarn radius the cell of the fabric's template is given (mm)."""
    return build_cell(
        loop_curves(fabric), fabric, load_case("uniaxial-course", 0.1, 2), RveSettings()
    ).yarn.radius


@pytest.fixture(scope="module")
def from_measured():
    """Cotton 5.5 jersey, the straight yarn relaxed from the measured w = 1.33, c = 1.26 mm at
    100 control points (18 s)."""
    fabric = load_preset("cotton-20s2", STITCH)
    return fabric, relax_cell(fabric, 100)


def test_the_straight_yarn_relaxes_jersey_to_the_geometric_relaxed_cell(from_measured):
    """w 1.482 mm, c 1.031 mm, within 2 % of the template family's relaxed cell at the same
    loop length (1.491 / 1.044: hard contacts, no yarn model), an independent construction;
    l/c in Munden's dry-relaxed 5.0-5.5. (At 20 and 36 control points the cell collapses in
    width instead: the resolution's.)"""
    fabric, states = from_measured
    assert states[0].natural_curvature == 1.0 and states[-1].natural_curvature == 0.0
    relaxed = states[-1]
    geometric = relaxed_knit("jersey", STITCH, fabric.yarn.minimal_radius)
    assert relaxed.wale_width == pytest.approx(geometric.wale_width, rel=0.02)
    assert relaxed.course_height == pytest.approx(geometric.course_height, rel=0.02)
    assert 5.0 < 5.5 / relaxed.course_height < 5.5
    assert 0.0 < relaxed.penetration < 0.5


def test_from_the_geometric_cell_the_course_height_is_the_same_and_the_width_the_radius(
    from_measured,
):
    """Started at the geometric relaxed cell (w 1.491 mm, its yarn r = w/8 = 0.186 mm
    against the measured start's 0.166 mm; 11 s), the path changes no branch (w within 10 %
    of the start all the way) and ends at the measured start's l/c (5.34 and 5.34: the
    relaxed course height is the yarn's), with the wider loop of the thicker yarn (l/w 3.52
    against 3.72; docs/patterns.md, "From the geometric relaxed cell")."""
    measured, ends = from_measured
    geometric = settled_fabric(measured, relaxed=True)
    states = relax_cell(geometric, 100)
    start = states[0].wale_width
    assert all(abs(state.wale_width / start - 1) < 0.1 for state in states)
    assert _radius(geometric) > 1.05 * _radius(measured)
    ratios = [
        (_loop_length(fabric) / end.wale_width, _loop_length(fabric) / end.course_height)
        for fabric, end in ((geometric, states[-1]), (measured, ends[-1]))
    ]
    assert ratios[0][1] == pytest.approx(ratios[1][1], rel=0.01)
    assert ratios[0][0] < 0.97 * ratios[1][0]


def test_a_share_outside_zero_to_one_is_refused():
    with pytest.raises(InputError, match=r"share=1\.5 is outside the valid range"):
        relax_cell(load_preset("cotton-20s2", 5.5), 20, share=1.5)
