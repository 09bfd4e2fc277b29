"""The cell relaxed by mechanics (`rve_rod.rve.relaxation`): a yarn that lets go of its whole
set, relaxed at zero macro stress, against the geometric relaxed cell (docs/patterns.md, "The
relaxed cell")."""

import pytest

from rve_rod.errors import InputError
from rve_rod.geometry.relaxed import relaxed_knit
from rve_rod.presets import load_preset
from rve_rod.rve.relaxation import relax_cell


def test_the_straight_yarn_relaxes_jersey_to_the_geometric_relaxed_cell():
    """Cotton 5.5 jersey, the straight yarn relaxed from the measured w = 1.33, c = 1.26 mm at
    100 control points (18 s): w 1.482 mm, c 1.031 mm, within 2 % of the template family's
    relaxed cell at the same loop length (1.491 / 1.044: hard contacts, no yarn model), an
    independent construction; l/c in Munden's dry-relaxed 5.0-5.5. (At 20 and 36 control
    points the cell collapses in width instead: the resolution's.)"""
    fabric = load_preset("cotton-20s2", 5.5)
    states = relax_cell(fabric, 100)
    assert states[0].natural_curvature == 1.0 and states[-1].natural_curvature == 0.0
    relaxed = states[-1]
    geometric = relaxed_knit("jersey", 5.5, fabric.yarn.minimal_radius)
    assert relaxed.wale_width == pytest.approx(geometric.wale_width, rel=0.02)
    assert relaxed.course_height == pytest.approx(geometric.course_height, rel=0.02)
    assert 5.0 < 5.5 / relaxed.course_height < 5.5
    assert 0.0 < relaxed.penetration < 0.5


def test_a_share_outside_zero_to_one_is_refused():
    with pytest.raises(InputError, match=r"share=1\.5 is outside the valid range"):
        relax_cell(load_preset("cotton-20s2", 5.5), 20, share=1.5)
