"""Contact regions: close distance minima of one slave point share one contact, continuously.

Scene: a rod wrapped around another (`wrapped_rods`), whose distance from a slave point has two
close minima and a maximum between them; a tilt makes one minimum shallower until it meets the
maximum and vanishes (a fold).
"""

import numpy as np
import pytest
from support.contact_scenes import wrapped_rods

from rve_rod.contact import CompressibleYarnLaw, ContactModel, ContactOptions, _kernels
from rve_rod.contact.regions import (
    StrandGeometry,
    StrandPoints,
    prominences,
    separating_maxima,
)
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
    """Weights p_i^2 / sum p^2 from a dense sampling of the distance from `point` to rod 1 (its
    two minima and the maximum M between them), with the two-minimum case of the prominence
    written out: the shallower minimum j climbs to the barrier, p_j = M - h_j; the deeper one
    i climbs to the barrier, and further towards 2r as j is shallower by up to its own depth
    M - h_j: p_i = M - h_i + (2r - M) S(x), x = (h_j - h_i) / (M - h_j), S the smooth step
    3x^2 - 2x^3 on [0, 1] (1 beyond)."""
    degree = scene.patches[1].degree
    curve = BSplineCurve(degree, scene.patches[1].knots, scene.positions[17:])
    params = np.linspace(0.0, 1.0, 400_001)
    distance = np.linalg.norm(curve(params) - point, axis=1)
    inner = distance[1:-1]
    minima = np.flatnonzero((inner < distance[:-2]) & (inner < distance[2:])) + 1
    assert minima.size == 2
    touch = 2 * LAW.yarn_radius
    barrier = min(distance[minima[0] : minima[1]].max(), touch)
    depth = np.minimum(distance[minima], touch)
    deep, shallow = np.argsort(depth)
    prominence = np.empty(2)
    prominence[shallow] = barrier - depth[shallow]
    x = min(1.0, (depth[shallow] - depth[deep]) / (barrier - depth[shallow]))
    prominence[deep] = barrier - depth[deep] + (touch - barrier) * x * x * (3 - 2 * x)
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


def load_sweep(options, tilts):
    """Line loads of all points (tilts, 3, points) for the given tilts of rod 1."""
    loads = []
    for tilt in tilts:
        scene = wrapped_rods(tilt=tilt)
        loads.append(model_of(scene, options).evaluate(scene.positions, tangent=False).line_load)
    return np.array(loads)


def largest_changes(options):
    """Largest change of a load between neighbouring tilts of 0 ... 0.04 (through the fold near
    0.026) in 81 states, and again in 11 sub-steps of the interval where it occurred."""
    tilts = np.linspace(0.0, 0.04, 81)
    changes = np.abs(np.diff(load_sweep(options, tilts), axis=0)).max(axis=(1, 2))
    worst = int(np.argmax(changes))
    finer = np.linspace(tilts[worst], tilts[worst + 1], 11)
    refined = np.abs(np.diff(load_sweep(options, finer), axis=0)).max(axis=(1, 2))
    return changes.max(), refined.max()


def test_load_is_continuous_through_the_fold():
    """With regions the largest change of a load between neighbouring tilts shrinks with the
    tilt step (ten times finer steps: at most 0.2 of it, a continuous load; measured 0.10);
    counting every minimum as a full contact (regions of one minimum, region_arc_length tiny)
    jumps where a minimum is born, and the jump stays (measured 1.03)."""
    coarse, fine = largest_changes(None)
    assert fine < 0.2 * coarse
    coarse, fine = largest_changes(ContactOptions(region_arc_length=1e-6))
    assert fine > 0.9 * coarse


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


TOUCH = 0.4  # 2r (mm)


@pytest.mark.parametrize("seed", range(6))
def test_prominence_derivatives_match_finite_differences(seed):
    rng = np.random.default_rng(seed)
    n = 2 + seed % 3
    minima = rng.uniform(0.30, 0.39, n)
    maxima = np.maximum(minima[:-1], minima[1:]) + rng.uniform(0.001, 0.02, n - 1)
    values = np.concatenate([minima, maxima])
    _, derivative = prominences(minima, maxima, TOUCH)
    step = 1e-7
    for column in range(values.size):
        plus, minus = values.copy(), values.copy()
        plus[column] += step
        minus[column] -= step
        difference = (
            prominences(plus[:n], plus[n:], TOUCH)[0] - prominences(minus[:n], minus[n:], TOUCH)[0]
        ) / (2 * step)
        np.testing.assert_allclose(derivative[:, column], difference, atol=1e-6)


def test_prominence_is_continuous_when_a_neighbouring_minimum_vanishes():
    """Three minima: a shallow one (0.38) with its barrier (0.395), the minimum j (h_j) that
    meets its other neighbouring maximum (0.35) and vanishes, and a deep one (0.33). As h_j
    rises to 0.35 the deep minimum's prominence becomes what it is once j and that maximum
    are gone (the climb to 2r: 0.07), and j's own tends to 0. Measured on the sweep shown by
    docs/contact.md: a prominence taken against the lower neighbouring maximum only (the
    model before) gave the deep minimum 0.35 - 0.33 = 0.02 just before and 0.07 just after."""
    shallow, barrier, deep = 0.38, 0.395, 0.33
    after, _ = prominences(np.array([shallow, deep]), np.array([barrier]), TOUCH)
    for gap in (1e-3, 1e-5, 1e-8):
        h_j = 0.35 - gap
        before, _ = prominences(np.array([shallow, h_j, deep]), np.array([barrier, 0.35]), TOUCH)
        # j is shallower than the deep minimum by more than its own depth 0.35 - h_j as soon
        # as gap < 0.01: from there it caps nothing, and the others are what they are after.
        np.testing.assert_allclose(before[[0, 2]], after, atol=1e-12)
        assert before[1] <= gap * (1 + 1e-9)
    np.testing.assert_allclose(after, [0.395 - 0.38, TOUCH - 0.33])


def test_equal_minima_have_equal_prominence_and_a_deeper_one_climbs_to_touch():
    equal, _ = prominences(np.array([0.34, 0.34]), np.array([0.36]), TOUCH)
    np.testing.assert_allclose(equal, [0.02, 0.02])
    # j shallower by more than its own depth (0.36 - 0.35 < 0.35 - 0.30): i climbs to 2r.
    apart, _ = prominences(np.array([0.30, 0.35]), np.array([0.36]), TOUCH)
    np.testing.assert_allclose(apart, [TOUCH - 0.30, 0.01])
    # Minima that do not penetrate (h = 2r) have none.
    none, _ = prominences(np.array([TOUCH, TOUCH]), np.array([TOUCH]), TOUCH)
    np.testing.assert_allclose(none, 0.0)


# -- kernels against their NumPy twins ---------------------------------------------------------


def reference_prominences(minima, maxima, touch):
    """NumPy twin of `_kernels.prominences` (the formula of `regions.prominences`)."""
    n = minima.size
    p = touch - minima
    derivative = np.zeros((n, 2 * n - 1))
    derivative[np.arange(n), np.arange(n)] = -1.0
    lower = np.full(n, np.inf)
    lower_gap = np.full(n, -1)
    for gap, value in enumerate(maxima):
        for j in (gap, gap + 1):
            if value < lower[j]:
                lower[j], lower_gap[j] = value, gap
    for i in range(n):
        for j in range(n):
            if j == i:
                continue
            barrier_gap = max(range(min(i, j), max(i, j)), key=lambda g: maxima[g])
            barrier = maxima[barrier_gap]
            rise = minima[j] - minima[i]
            depth = lower[j] - minima[j]
            row = np.zeros(2 * n - 1)
            row[i] = -1.0
            row[n + barrier_gap] = 1.0
            step = 0.0
            if rise > 0.0 and depth <= rise:
                step = 1.0
            elif rise > 0.0:
                x = rise / depth
                step = x * x * (3.0 - 2.0 * x)
                slope = 6.0 * x * (1.0 - x) * (touch - barrier)
                row[i] -= slope / depth
                row[j] += slope * (lower[j] - minima[i]) / depth**2
                row[n + lower_gap[j]] -= slope * rise / depth**2
            value = barrier - minima[i] + (touch - barrier) * step
            row[n + barrier_gap] -= step
            if value < p[i]:
                p[i] = value
                derivative[i] = row
    negative = p < 0.0
    p[negative] = 0.0
    derivative[negative] = 0.0
    return p, derivative


def random_region(rng, n):
    """Capped distances of n minima (some at 2r) and the n - 1 maxima between them."""
    minima = np.minimum(rng.uniform(0.28, 0.42, n), TOUCH)
    maxima = np.minimum(np.maximum(minima[:-1], minima[1:]) + rng.uniform(0.0, 0.03, n - 1), TOUCH)
    return minima, maxima


@pytest.mark.parametrize("seed", range(12))
def test_prominence_kernel_matches_its_numpy_twin(seed):
    rng = np.random.default_rng(100 + seed)
    minima, maxima = random_region(rng, 2 + seed % 4)
    p, derivative = prominences(minima, maxima, TOUCH)
    expected_p, expected_derivative = reference_prominences(minima, maxima, TOUCH)
    np.testing.assert_array_equal(p, expected_p)
    np.testing.assert_array_equal(derivative, expected_derivative)


def reference_region_weights(distance, maximum, order, gap_pair, *, bounds, touch):
    """NumPy twin of `_kernels.region_weights`: weights of the region members and the terms
    (contact, kind, index, coefficient) of their derivatives."""
    weight = np.ones(distance.size)
    terms = []
    for first, count in bounds.T:
        members = order[first : first + count]
        gaps = gap_pair[first : first + count - 1]
        p, derivative = reference_prominences(
            np.minimum(distance[members], touch), np.minimum(maximum[gaps], touch), touch
        )
        power = p**2
        total = power.sum()
        if total <= 0.0:
            weight[members] = 1.0 / count
            continue
        weight[members] = power / total
        dw_dp = (np.eye(count) - (power / total)[:, None]) * (2.0 * p / total)[None, :]
        dw_dh = dw_dp @ derivative
        for i in range(count):
            for kind, index, coefficients in (
                (0, members, dw_dh[i, :count]),
                (1, gaps, dw_dh[i, count:]),
            ):
                stationary = (distance, maximum)[kind][index]
                for q in np.flatnonzero((stationary < touch) & (coefficients != 0.0)):
                    terms.append((members[i], kind, index[q], coefficients[q]))
    return weight, terms


@pytest.mark.parametrize("seed", range(4))
def test_region_weight_kernel_matches_its_numpy_twin(seed):
    """Regions of 1 to 4 minima in a shuffled order, some without penetration."""
    rng = np.random.default_rng(seed)
    sizes = rng.integers(1, 5, 7)
    k = int(sizes.sum())
    distance = np.empty(k)
    maximum = np.full(k, np.inf)
    gap_pair = np.full(k, -1)
    order = rng.permutation(k)
    first = 0
    for size in sizes:
        minima, maxima = random_region(rng, size)
        distance[order[first : first + size]] = minima
        maximum[first : first + size - 1] = maxima
        gap_pair[first : first + size - 1] = np.arange(first, first + size - 1)
        first += size
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    shared = sizes > 1
    bounds = np.stack([starts[shared], sizes[shared]]).astype(np.int64)
    capacity = int(np.sum(sizes * (2 * sizes - 1)))
    out = _kernels.RegionTerms(
        *(np.empty(capacity, dtype=np.int64) for _ in range(3)), np.empty(capacity)
    )
    weight = np.ones(k)
    count = _kernels.region_weights(
        (distance, maximum), _kernels.Regions(order, gap_pair, bounds), TOUCH, weight, out
    )
    expected_weight, expected_terms = reference_region_weights(
        distance, maximum, order, gap_pair, bounds=bounds, touch=TOUCH
    )
    np.testing.assert_allclose(weight, expected_weight, rtol=1e-14)
    assert count == len(expected_terms) > 0
    contact, kind, index, coefficient = (field[:count] for field in out)
    np.testing.assert_array_equal(contact, [term[0] for term in expected_terms])
    np.testing.assert_array_equal(kind, [term[1] for term in expected_terms])
    np.testing.assert_array_equal(index, [term[2] for term in expected_terms])
    np.testing.assert_allclose(coefficient, [term[3] for term in expected_terms], rtol=1e-12)


def reference_maxima(layout, points, slave_point, *, yarn, start, stop, samples=16):
    """NumPy twin of `_kernels.separating_maxima` for one pair on an open yarn in image
    (0, 0): the distance sampled at `samples` interior arc coordinates, then Newton on its
    slope in the arc coordinate, bisecting when a step leaves the bracket. Returns the arc
    coordinate and the distance of the maximum."""
    spans = np.flatnonzero(layout.span_yarn == yarn)

    def geometry(arc, order):
        local = np.clip(arc, 0.0, layout.yarn_length[yarn])
        span = spans[
            np.clip(np.searchsorted(layout.span_arc_start[spans], local, "right") - 1, 0, None)
        ]
        tau = np.clip((local - layout.span_arc_start[span]) / layout.span_arc_length[span], 0, 1)
        basis = layout.basis(np.array([span]), np.array([tau]), order)[0]
        return basis @ points[layout.span_control_points[span]], layout.span_arc_length[span]

    arcs = start + np.arange(samples + 2) / (samples + 1) * (stop - start)
    values = [np.sum((geometry(arc, 0)[0] - slave_point) ** 2) for arc in arcs[1:-1]]
    best = 1 + int(np.argmax(values))
    low, high, arc = arcs[best - 1], arcs[best + 1], arcs[best]
    for _ in range(60):
        point, length = geometry(arc, 0)
        first, second = geometry(arc, 1)[0], geometry(arc, 2)[0]
        slope = (point - slave_point) @ first / length
        curvature = (first @ first + (point - slave_point) @ second) / length**2
        low, high = (arc, high) if slope >= 0.0 else (low, arc)
        step = arc - slope / curvature if curvature < 0.0 else np.nan
        step = step if low < step < high else 0.5 * (low + high)
        done = abs(step - arc) <= 1e-12 * (1.0 + abs(start))
        arc = step
        if done:
            break
    return arc, np.linalg.norm(geometry(arc, 0)[0] - slave_point)


@pytest.mark.parametrize("tilt", [0.0, 0.005, 0.01])
def test_separating_maximum_kernel_matches_its_numpy_twin_and_a_dense_sampling(tilt):
    """The maximum of the distance from the origin to rod 1 between its two minima."""
    scene = wrapped_rods(tilt=tilt, lean=0.0)
    model = model_of(scene)
    layout = model.layout
    on_rod_1 = np.flatnonzero(layout.span_yarn == 1)
    length = layout.yarn_length[1]
    # the minima lie near t = +-0.8 of t in [-1.8, 1.8] (arc fractions about 0.28, 0.72),
    # the maximum between them at t = 0
    start, stop = 0.32 * length, 0.68 * length
    geometry = StrandGeometry(layout, layout.coefficients(scene.positions), np.zeros((2, 3)))
    ends = [
        StrandPoints(
            slave=np.array([MIDDLE]),
            span=on_rod_1[:1],
            tau=np.zeros(1),
            image=np.zeros((1, 2), dtype=np.int64),
            arc=np.array([arc]),
            strand=np.zeros(1, dtype=np.int64),
            distance=np.zeros(1),
            normal=np.zeros((3, 1)),
        )
        for arc in (start, stop)
    ]
    slave_points = layout.collocation_positions(scene.positions)
    found = separating_maxima(geometry, slave_points, *ends)
    arc, distance = reference_maxima(
        layout, scene.positions, slave_points[:, MIDDLE], yarn=1, start=start, stop=stop
    )
    assert found.arc[0] == pytest.approx(arc, abs=1e-11)
    assert found.distance[0] == pytest.approx(distance, rel=1e-13)
    assert np.linalg.norm(found.normal[:, 0]) == pytest.approx(1.0, abs=1e-14)
    curve = BSplineCurve(layout.degree, scene.patches[1].knots, scene.positions[17:])
    dense = curve(np.linspace(0.0, 1.0, 400_001))
    arcs = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(dense, axis=0), axis=1))])
    inside = dense[(arcs >= start) & (arcs <= stop)]
    sampled = np.linalg.norm(inside - slave_points[:, MIDDLE], axis=1)
    assert 0.37 < found.distance[0] == pytest.approx(sampled.max(), abs=1e-9)
