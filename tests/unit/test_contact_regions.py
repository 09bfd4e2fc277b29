"""Contact regions: close distance minima of one slave point share one contact, continuously.

Scene: a rod wrapped around another (`wrapped_rods`), whose distance from a slave point has two
close minima and a maximum between them; a tilt makes one minimum shallower until it meets the
maximum and vanishes (a fold).
"""

import numpy as np
import pytest
from contact_scenes import wrapped_rods

from rve_rod.contact import CompressibleYarnLaw, ContactModel, ContactOptions
from rve_rod.geometry.bspline import BSplineCurve

LAW = CompressibleYarnLaw(stiffness=10.0, exponent=1.5, yarn_radius=0.2)
MIDDLE = 8  # the collocation point of rod 0 at the origin (17 Greville points)


def model_of(scene, options=None):
    return ContactModel(scene.patches, scene.positions, LAW, yarns=scene.yarns, options=options)


def contacts_of_point(result, point):
    rows = np.flatnonzero(result.contacts.slave == point)
    return result.contacts.weight[rows], result.contacts.penetration[rows]


def test_two_equal_minima_share_equally():
    """lean = 0: rod 1 is symmetric about y = 0 as seen from the origin, so its two minima
    are equal: weights 1/2 each, and the point's load has no y component."""
    scene = wrapped_rods(tilt=0.0, lean=0.0)
    result = model_of(scene).evaluate(scene.positions, tangent=False)
    weight, penetration = contacts_of_point(result, MIDDLE)
    assert weight.size == 2
    assert np.all(penetration > 0.03)
    np.testing.assert_allclose(weight, 0.5, atol=1e-12)
    load = result.line_load[:, MIDDLE]
    assert abs(load[1]) < 1e-12 * np.abs(load).max()


def brute_force_weights(scene, point):
    """Weights p_i^2 / sum p^2 with p_i = min(d_max, 2r) - d_i from a dense sampling of the
    distance from `point` to rod 1 (its two minima and the maximum between them)."""
    degree = scene.patches[1].degree
    curve = BSplineCurve(degree, scene.patches[1].knots, scene.positions[17:])
    params = np.linspace(0.0, 1.0, 400_001)
    distance = np.linalg.norm(curve(params) - point, axis=1)
    inner = distance[1:-1]
    minima = np.flatnonzero((inner < distance[:-2]) & (inner < distance[2:])) + 1
    assert minima.size == 2
    ceiling = min(distance[minima[0] : minima[1]].max(), 2 * LAW.yarn_radius)
    prominence = ceiling - distance[minima]
    return prominence**2 / np.sum(prominence**2)


@pytest.mark.parametrize("tilt", [0.002, 0.006, 0.012])
def test_weights_follow_the_prominence_of_the_minima(tilt):
    scene = wrapped_rods(tilt=tilt, lean=0.0)
    result = model_of(scene).evaluate(scene.positions, tangent=False)
    weight, _ = contacts_of_point(result, MIDDLE)
    order = np.argsort(result.contacts.parameter[result.contacts.slave == MIDDLE])
    expected = brute_force_weights(scene, np.zeros(3))
    assert 0.01 < expected.min() < 0.49
    np.testing.assert_allclose(weight[order], expected, atol=1e-8)


def load_sweep(options):
    """Line loads of all points for tilts 0 ... 0.04 (through the fold near 0.026)."""
    loads = []
    for tilt in np.linspace(0.0, 0.04, 81):
        scene = wrapped_rods(tilt=tilt)
        loads.append(model_of(scene, options).evaluate(scene.positions, tangent=False).line_load)
    return np.array(loads)


def test_load_is_continuous_through_the_fold():
    """With regions the largest change of a load between neighbouring tilts stays within 3x
    the median change (measured 2.2x); counting every minimum as a full contact (regions of
    one minimum, region_arc_length tiny) jumps where a minimum is born (measured 17x)."""
    smooth = np.abs(np.diff(load_sweep(None), axis=0)).max(axis=(1, 2))
    assert smooth.max() < 3.0 * np.median(smooth)
    single = np.abs(np.diff(load_sweep(ContactOptions(region_arc_length=1e-6)), axis=0))
    single = single.max(axis=(1, 2))
    assert single.max() > 10.0 * np.median(single)


def test_a_newborn_minimum_enters_with_weight_zero():
    """Approaching the fold (for this point just above tilt 0.028), the weight of the
    vanishing minimum falls to 0 with its prominence, although it still penetrates."""
    weights = []
    tilts = np.array([0.024, 0.026, 0.028])
    for tilt in tilts:
        scene = wrapped_rods(tilt=tilt)
        result = model_of(scene).evaluate(scene.positions, tangent=False)
        weight, penetration = contacts_of_point(result, MIDDLE)
        assert weight.size == 2
        weights.append(weight.min())
        assert penetration.min() > 0.02
    assert weights[-1] < 1e-4
    assert np.all(np.diff(weights) < 0)
