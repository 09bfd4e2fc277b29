"""Clearance search on cases with a known answer."""

import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.geometry import proximity
from rve_rod.geometry.bspline import BSplineCurve, open_knot_vector
from rve_rod.geometry.pattern_cell import pattern_geometry
from rve_rod.geometry.proximity import cell_clearance, chain_clearance


def straight_chain(direction):
    """A straight yarn along `direction` in 4 curves over one period a1 = direction."""
    knots = open_knot_vector(4, 6)
    return [
        BSplineCurve(4, knots, np.linspace(k / 4, (k + 1) / 4, 6)[:, None] * direction[None, :])
        for k in range(4)
    ]


@pytest.mark.parametrize("slope", [0.0, 0.3, 1.2])
def test_oblique_straight_courses_are_b_over_sqrt_1_plus_m2_apart(slope):
    period = np.array([2.0, 2.0 * slope, 0.0])
    lattice = np.array([period, [0.0, 0.7, 0.0]])
    result = chain_clearance(straight_chain(period), lattice, adjacent_arc=1.0)
    assert result.distance == pytest.approx(0.7 / np.sqrt(1 + slope**2), rel=1e-12)
    assert result.image[1] == 1


def test_curves_of_a_chain_must_share_knots():
    curves = straight_chain(np.array([2.0, 0.0, 0.0]))
    other = BSplineCurve(4, open_knot_vector(4, 10), np.zeros((10, 3)))
    with pytest.raises(InputError, match="share degree and knots"):
        chain_clearance([*curves[:3], other], np.eye(3)[:2], 1.0)


@pytest.mark.parametrize("curve", range(4))
def test_search_from_one_curve_of_a_symmetric_chain_finds_the_same_distance(curve):
    # a straight yarn: a shift along it by a quarter period maps every curve onto the next
    period = np.array([2.0, 0.6, 0.0])
    lattice = np.array([period, [0.0, 0.7, 0.0]])
    result = chain_clearance(straight_chain(period), lattice, 1.0, from_curve=curve)
    assert result.distance == pytest.approx(0.7 / np.sqrt(1 + 0.3**2), rel=1e-12)
    assert abs(result.image[1]) == 1


def test_from_curve_must_be_a_curve_of_the_chain():
    with pytest.raises(InputError, match="from_curve=4"):
        chain_clearance(straight_chain(np.array([2.0, 0.0, 0.0])), np.eye(3)[:2], 1.0, from_curve=4)


@pytest.mark.parametrize("pattern", ["garter", "seed", "moss"])
@pytest.mark.parametrize("flatten", [1.0, 0.5])
def test_cell_clearance_skips_only_images_beyond_its_reach(pattern, flatten, monkeypatch):
    """The cell search computes the sample distances only to the images whose bounding boxes
    come within its reach: the same closest pair, bit for bit, as computing every image
    (gaps all zero), for templates and for templates flattened into interpenetration."""
    cell = pattern_geometry(pattern, 0.86, 1.12, 0.19).periodic_yarns()
    yarns = [
        tuple(
            BSplineCurve(curve.degree, curve.knots, curve.control_points * [1.0, 1.0, flatten])
            for curve in yarn
        )
        for yarn in cell.yarns
    ]
    blocks = []
    nearest = proximity._nearest_samples
    monkeypatch.setattr(
        proximity, "_nearest_samples", lambda *args: blocks.append(1) or nearest(*args)
    )
    pruned = cell_clearance(yarns, cell.lattice, 0.6)
    computed = len(blocks)
    monkeypatch.setattr(proximity, "_box_gaps", lambda first, second, offsets: np.zeros(15))
    assert cell_clearance(yarns, cell.lattice, 0.6) == pruned
    pairs = len(yarns) * (len(yarns) + 1) // 2
    assert len(blocks) - computed == 15 * pairs  # every image of every pair of yarns
    assert computed < 0.5 * 15 * pairs  # the pruned search skipped most of them
