"""Contact kernels against plain NumPy/SciPy references."""

import numpy as np
import pytest
import scipy.optimize

from rve_rod.contact import CompressibleYarnLaw, _kernels
from rve_rod.contact.broad_phase import overlapping_boxes
from rve_rod.contact.closest_point import project
from rve_rod.contact.layout import Patch, YarnChain, build_layout
from rve_rod.geometry.bspline import BSplineCurve, open_knot_vector


def random_boxes(rng, count, spread):
    low = rng.uniform(0.0, spread, size=(3, count))
    return np.concatenate([low, low + rng.uniform(0.0, 1.0, size=(3, count))])


@pytest.mark.parametrize(
    ("slaves", "masters", "spread"), [(1, 1, 1.0), (40, 70, 4.0), (300, 200, 8.0)]
)
def test_box_sweep_finds_exactly_the_brute_force_pairs(slaves, masters, spread):
    rng = np.random.default_rng(slaves + masters)
    slave_boxes = random_boxes(rng, slaves, spread)
    master_boxes = random_boxes(rng, masters, spread)
    # Touching boxes count as overlapping: make a few share a face exactly.
    master_boxes[0, :3] = slave_boxes[3, : min(3, slaves)][: min(3, masters)]
    order = np.argsort(master_boxes[0], kind="stable")
    found = set(zip(*overlapping_boxes(slave_boxes, master_boxes, order), strict=True))
    overlap = np.all(
        (slave_boxes[:3, :, None] <= master_boxes[3:, None, :])
        & (master_boxes[:3, None, :] <= slave_boxes[3:, :, None]),
        axis=0,
    )
    expected = set(zip(*np.nonzero(overlap), strict=True))
    assert found == expected


def test_box_sweep_reports_the_count_beyond_its_buffer():
    rng = np.random.default_rng(3)
    boxes = random_boxes(rng, 30, 0.5)
    order = np.argsort(boxes[0], kind="stable")
    small = np.empty(5, dtype=np.int64)
    count = _kernels.box_overlaps(boxes, boxes, order, small, small.copy())
    assert count == len(set(zip(*overlapping_boxes(boxes, boxes, order), strict=True)))
    assert count > 5


def wavy_curve(degree, n, rng):
    """A smooth space curve with non-uniform knots; spans short against its curvature radius."""
    knots = open_knot_vector(degree, n)
    knots[degree + 1 : n] = np.sort(rng.uniform(0.02, 0.98, n - degree - 1))
    s = np.linspace(0, 1, n)
    points = np.stack([4 * s, 0.5 * np.sin(5 * s), 0.3 * np.cos(4 * s)], axis=1)
    return BSplineCurve(degree, knots, points + 0.003 * rng.normal(size=points.shape))


def reference_minima(curve, point):
    """All interior local minima of |C(u) - x| by dense sampling and Brent on the slope."""
    u = np.linspace(*curve.domain, 20001)
    slope = np.einsum("md,md->m", curve(u, 1), curve(u) - point)
    minima = []
    for a in np.flatnonzero((slope[:-1] <= 0) & (slope[1:] > 0)):
        root = scipy.optimize.brentq(
            lambda t: curve(np.array([t]), 1)[0] @ (curve(np.array([t]))[0] - point),
            u[a],
            u[a + 1],
            xtol=1e-15,
        )
        minima.append(root)
    return np.array(minima)


@pytest.mark.parametrize("degree", [2, 3, 4])
@pytest.mark.parametrize("spans_per_group", [1, 3, 64])
def test_projection_finds_every_local_minimum_once(degree, spans_per_group):
    # Points up to 0.7 from the curve: contact distances; an open end is not a minimum.
    rng = np.random.default_rng(10 * degree + spans_per_group)
    curve = wavy_curve(degree, 30, rng)
    layout = build_layout([Patch(degree, curve.knots)], [YarnChain((0,))], curve.control_points)
    groups = np.array(
        [
            [first, min(spans_per_group, layout.n_spans - first)]
            for first in range(0, layout.n_spans, spans_per_group)
        ]
    ).T
    targets = (curve(rng.uniform(0, 1, 12)) + rng.uniform(-0.4, 0.4, (12, 3))).T
    candidates = np.repeat(np.arange(12), groups.shape[1])
    group_of = np.tile(np.arange(groups.shape[1]), 12)
    found = project(
        layout.coefficients(curve.control_points),
        groups,
        layout.span_next,
        layout.span_closed_end,
        groups=group_of,
        targets=targets[:, candidates],
    )
    parameter = layout.span_start[found.span] + found.tau * layout.span_length[found.span]
    for j in range(12):
        mine = np.sort(parameter[candidates[found.candidate] == j])
        expected = reference_minima(curve, targets[:, j])
        np.testing.assert_allclose(mine, expected, atol=1e-12)
    # The reported geometry is the curve's: point, first and second derivative (in tau).
    scale = layout.span_length[found.span]
    np.testing.assert_allclose(found.point.T, curve(parameter), atol=1e-12)
    np.testing.assert_allclose(found.tangent.T, curve(parameter, 1) * scale[:, None], atol=1e-11)
    np.testing.assert_allclose(
        found.curvature.T, curve(parameter, 2) * scale[:, None] ** 2, atol=1e-10
    )


@pytest.mark.parametrize("reach", [0.2, 0.35, 0.5])
def test_projection_within_reach_keeps_every_minimum_within_reach(reach):
    # Spans whose bounding box lies beyond the reach are skipped: the minima within reach are
    # exactly those of the search without it (same spans, same parameters, bit for bit), and
    # minima beyond it are left out.
    rng = np.random.default_rng(7)
    curve = wavy_curve(4, 60, rng)
    layout = build_layout([Patch(4, curve.knots)], [YarnChain((0,))], curve.control_points)
    groups = np.array([[0], [layout.n_spans]])
    targets = (curve(rng.uniform(0, 1, 40)) + rng.uniform(-0.4, 0.4, (40, 3))).T
    search = {
        "coefficients": layout.coefficients(curve.control_points),
        "group_spans": groups,
        "span_next": layout.span_next,
        "closed_end": layout.span_closed_end,
        "groups": np.zeros(40, dtype=np.int64),
        "targets": targets,
    }
    every = project(**search)
    near = project(**search, reach=reach)

    def within(found):
        distance = np.linalg.norm(targets[:, found.candidate] - found.point, axis=0)
        keep = distance < reach
        return found.candidate[keep], found.span[keep], found.tau[keep]

    for mine, expected in zip(within(near), within(every), strict=True):
        np.testing.assert_array_equal(mine, expected)
    assert within(every)[0].size > 0
    assert near.candidate.size < every.candidate.size


def one_span_projection(control_points, target):
    """Minima (sorted parameters) of the distance from target (3,) to one Bezier span."""
    degree = len(control_points) - 1
    knots = open_knot_vector(degree, degree + 1)
    points = np.asarray(control_points, dtype=float)
    layout = build_layout([Patch(degree, knots)], [YarnChain((0,))], points)
    found = project(
        layout.coefficients(points),
        np.array([[0], [1]]),
        layout.span_next,
        layout.span_closed_end,
        groups=np.array([0]),
        targets=np.asarray(target, dtype=float)[:, None],
    )
    curve = BSplineCurve(degree, knots, points)
    return np.sort(found.tau), reference_minima(curve, np.asarray(target, dtype=float))


@pytest.mark.parametrize(
    ("shoulder", "middle", "expected_count"),
    [
        # Two bulges toward the target: slope -, +, -, + (minimum, maximum, minimum) inside the
        # span with the usual bracket at its ends; one bracket search finds one of the two.
        (0.3, -0.2, 2),
        (0.12, -0.2, 2),
        (-0.1, -0.2, 2),
        # One bulge in the middle: one minimum.
        (0.0, 0.2, 1),
    ],
)
def test_projection_finds_two_minima_inside_one_span(shoulder, middle, expected_count):
    control_points = [
        [0.0, 0.0, 0.0],
        [0.25, shoulder, 0.0],
        [0.5, middle, 0.0],
        [0.75, shoulder, 0.0],
        [1.0, 0.0, 0.0],
    ]
    found, expected = one_span_projection(control_points, [0.5, 1.0, 0.0])
    assert expected.size == expected_count
    np.testing.assert_allclose(found, expected, atol=1e-12)


def test_projection_finds_a_pair_born_inside_a_span_whose_end_slopes_agree():
    # The slope is positive at both ends of the span and dips below zero in between: a
    # maximum and a minimum, which a bracket of the end slopes alone cannot see.
    control_points = [
        [0.0, 0.3, 0.0],
        [-0.2, 1.0, 0.0],
        [-0.2, -0.4, 0.0],
        [0.6, -0.1, 0.0],
        [-0.5, -0.4, 0.0],
    ]
    curve = BSplineCurve(4, open_knot_vector(4, 5), np.array(control_points, dtype=float))
    ends = np.array([0.0, 1.0])
    assert np.all(np.einsum("md,md->m", curve(ends, 1), curve(ends)) > 0)  # target: origin
    found, expected = one_span_projection(control_points, [0.0, 0.0, 0.0])
    assert expected.size == 1
    np.testing.assert_allclose(found, expected, atol=1e-12)


def test_minimum_on_a_knot_is_owned_by_exactly_one_span():
    degree, n = 3, 8
    knots = open_knot_vector(degree, n)
    s = np.linspace(0, 1, n)
    curve = BSplineCurve(degree, knots, np.stack([s, 0 * s, 0 * s], axis=1))
    layout = build_layout([Patch(degree, knots)], [YarnChain((0,))], curve.control_points)
    knot = knots[degree + 2]
    target = np.array([[curve(np.array([knot]))[0, 0]], [0.3], [0.0]])
    groups = np.array([[0], [layout.n_spans]])
    found = project(
        layout.coefficients(curve.control_points),
        groups,
        layout.span_next,
        layout.span_closed_end,
        groups=np.array([0]),
        targets=target,
    )
    assert found.candidate.size == 1
    assert layout.span_start[found.span[0]] == knot
    assert found.tau[0] == 0.0


@pytest.mark.parametrize("contacts", [0, 1, 17])
def test_block_entries_match_a_dense_numpy_assembly(contacts):
    """Entries in the caller's numbering (rows of a permuted per-point layout, some left out;
    columns of a 7-dof state) against a dense assembly of the chained blocks."""
    rng = np.random.default_rng(contacts)
    degree, n_points, n_control = 3, 11, 25
    blocks = rng.normal(size=(4, 3, 3, contacts))
    slave = rng.integers(0, n_points, contacts)
    first = rng.integers(0, n_control - degree, size=(3, contacts))
    first[2, ::3] = -1  # some contacts without friction anchor
    basis = rng.normal(size=(4, degree + 1, contacts))
    point_rows = rng.permutation(3 * n_points).reshape(3, n_points)
    point_rows[:, 0] = -1  # a point whose rows are left out
    rows = point_rows[:, slave]
    columns = 7 * np.arange(n_control)[:, None] + np.arange(3)[None, :]
    out = _kernels.CooEntries.empty(9 * 3 * (degree + 1) * contacts)
    chain = _kernels.SpanChain(first, basis)
    count = _kernels.block_entries(blocks, rows, columns, chain, out)
    assembled = np.zeros((3 * n_points, 7 * n_control))
    np.add.at(assembled, (out.rows[:count], out.columns[:count]), out.values[:count])

    expected = np.zeros((n_points, 3, n_control, 3))
    for c in range(contacts):
        for a in range(degree + 1):
            expected[slave[c], :, first[0, c] + a] += blocks[0, ..., c] * basis[0, a, c]
            expected[slave[c], :, first[1, c] + a] += (
                blocks[1, ..., c] * basis[1, a, c] + blocks[2, ..., c] * basis[2, a, c]
            )
            if first[2, c] >= 0:
                expected[slave[c], :, first[2, c] + a] += blocks[3, ..., c] * basis[3, a, c]
    expected[0] = 0.0
    dense = np.zeros((3 * n_points, 7 * n_control))
    for i in range(3):
        for j in range(3):
            dense[point_rows[i, 1:, None], columns[None, :, j]] = expected[1:, i, :, j]
    np.testing.assert_allclose(assembled, dense, atol=1e-13)


IDENTITY = np.eye(3)[:, :, None]


def outer(a, b):
    return a[:, None, :] * b[None, :, :]


def matmul(a, b):
    return np.einsum("ijk,jlk->ilk", a, b)


def reference_contact_loads(v, tangent, metric, w, anchored, *, law, mu, k_t):
    """Plain NumPy loads and blocks (4, 3, 3, k) over all contacts at once."""
    d = np.linalg.norm(v, axis=0)
    n = v / d
    g = 2 * law.yarn_radius - d
    force, slope = law.line_load(g), law.line_stiffness(g)
    nn = outer(n, n)
    projector = IDENTITY - nn
    stiffness = -slope * nn + force / d * projector - force / (d * metric) * outer(tangent, tangent)
    blocks = np.stack([stiffness, -stiffness, -(force / metric) * outer(tangent, n), 0 * stiffness])
    load = force * n
    if mu == 0:
        return load, force, blocks, np.zeros(d.size)
    normal_part = np.einsum("ck,ck->k", n, w)
    slip = w - normal_part * n
    g_matrix = -(normal_part * projector + outer(n, slip)) / d
    gq = matmul(g_matrix, IDENTITY - outer(tangent, tangent) / metric)
    d_tangent = -outer(np.einsum("ijk,jk->ik", g_matrix, tangent), v) / metric
    trial = -k_t * slip
    trial_norm = np.linalg.norm(trial, axis=0)
    sliding = trial_norm > mu * force
    scale = np.where(sliding, mu * force / trial_norm, 1.0)
    direction = trial / trial_norm
    tangential = -k_t * scale * (IDENTITY - sliding * outer(direction, direction))
    normal_term = np.where(sliding, -mu * slope, 0.0) * outer(direction, n)
    friction = np.stack(
        [
            matmul(tangential, projector + gq) + normal_term,
            matmul(tangential, -gq) - normal_term,
            matmul(tangential, d_tangent),
            matmul(tangential, -projector),
        ]
    )
    blocks = blocks + anchored * friction
    load = load + anchored * scale * trial
    state = np.where(anchored, np.where(sliding, 2, 1), 0)
    return load, force, blocks, state


@pytest.mark.parametrize("exponent", [1.0, 1.5, 2.4])
@pytest.mark.parametrize(("mu", "slip_size"), [(0.0, 0.0), (0.3, 1e-4), (0.3, 0.05)])
def test_contact_loads_kernel_matches_numpy(exponent, mu, slip_size):
    rng = np.random.default_rng(int(10 * exponent) + int(1e4 * slip_size))
    k, radius = 40, 0.2
    law = CompressibleYarnLaw(stiffness=4.0, exponent=exponent, yarn_radius=radius)
    v = rng.normal(size=(3, k))
    v *= rng.uniform(0.05, 0.39, k) / np.linalg.norm(v, axis=0)  # penetrations 0.01 .. 0.35
    tangent = rng.normal(size=(3, k))
    tangent -= np.einsum("ck,ck->k", tangent, v) / np.einsum("ck,ck->k", v, v) * v
    metric = np.einsum("ck,ck->k", tangent, tangent) * rng.uniform(0.5, 2.0, k)
    w = slip_size * rng.normal(size=(3, k))
    anchored = rng.uniform(size=k) < 0.7
    out = _kernels.LoadOutput(np.empty((3, k)), np.empty((4, 3, 3, k)), np.empty(k, np.int8))
    g = 2 * radius - np.linalg.norm(v, axis=0)
    normal_law = np.stack([law.line_load(g), law.line_stiffness(g)])
    geometry = _kernels.ContactGeometry(v, tangent, metric, w, anchored)
    _kernels.contact_loads(geometry, normal_law, np.array([mu, 2.0]), out)
    load, _, blocks, state = reference_contact_loads(
        v, tangent, metric, w, anchored, law=law, mu=mu, k_t=2.0
    )
    for actual, reference in zip(out, (load, blocks, state), strict=True):
        np.testing.assert_allclose(actual, reference, rtol=1e-12, atol=1e-14)
    if mu > 0:  # both paths are exercised: stick for small slips, slip for large ones
        assert (1 if slip_size < 1e-3 else 2) in set(out.state)


def test_apart_pairs_keeps_exactly_the_pairs_beyond_the_own_strand_exclusion():
    rng = np.random.default_rng(11)
    n_groups, n_images, n_points, k = 7, 3, 40, 500
    boxes = n_groups * n_images
    slave = rng.integers(0, n_points, k)
    master = rng.integers(0, boxes, k)
    masters = _kernels.MasterStrands(
        strand=rng.integers(0, 3, boxes),
        shift=rng.choice([-10.0, 0.0, 10.0], boxes),
        arc_start=np.sort(rng.uniform(0.0, 10.0, n_groups)),
        arc_end=np.sort(rng.uniform(0.0, 10.0, n_groups)) + 1.0,
    )
    points = _kernels.PointStrands(rng.uniform(0.0, 10.0, n_points), rng.integers(0, 3, n_points))
    exclusion = 2.5
    kept = np.empty((3, k), dtype=np.int64)
    count = _kernels.apart_pairs(slave, master, masters, points, exclusion, kept)
    # NumPy reference: group and image of each box, the reach of its group along the strand
    image, group = np.divmod(master, n_groups)
    shift = masters.shift[master]
    arc = points.arc[slave]
    along = np.maximum(
        np.abs(masters.arc_start[group] + shift - arc), np.abs(masters.arc_end[group] + shift - arc)
    )
    keep = (masters.strand[master] != points.strand[slave]) | (along >= exclusion)
    assert 0 < count < k
    np.testing.assert_array_equal(kept[:, :count], np.stack([slave, group, image])[:, keep])


@pytest.mark.parametrize("degree", [2, 4])
def test_span_coefficients_and_point_positions_match_numpy_bit_for_bit(degree):
    rng = np.random.default_rng(degree)
    n, spans, points = 30, 20, 25
    positions = rng.normal(size=(n, 7))[:, :3]  # a strided view, as the state's positions
    control_points = rng.integers(0, n - degree, spans)[:, None] + np.arange(degree + 1)
    basis = rng.normal(size=(spans, degree + 1, degree + 1))
    out = np.empty((3, degree + 1, spans))
    _kernels.span_coefficients(positions, control_points, basis, out)
    # the same sums in the same order as NumPy's, and einsum's result
    expected = positions[control_points[:, 0]][:, :, None] * basis[:, 0, None, :]
    for a in range(1, degree + 1):
        expected = expected + positions[control_points[:, a]][:, :, None] * basis[:, a, None, :]
    np.testing.assert_array_equal(out, expected.transpose(1, 2, 0))
    np.testing.assert_allclose(
        out, np.einsum("sac,sak->cks", positions[control_points], basis), rtol=1e-14, atol=1e-14
    )
    first = rng.integers(0, n - degree, points)
    point_basis = rng.uniform(size=(points, degree + 1))
    found = np.empty((3, points))
    _kernels.point_positions(positions, first, point_basis, found)
    local = positions[first[:, None] + np.arange(degree + 1)]  # (m, p+1, 3)
    np.testing.assert_array_equal(found, np.einsum("ma,mac->cm", point_basis, local))


def test_control_point_boxes_bound_exactly_the_groups_control_points():
    rng = np.random.default_rng(5)
    degree, spans = 4, 23
    span_first = np.cumsum(rng.integers(0, 3, spans))  # repeated knots skip control points
    positions = rng.normal(size=(int(span_first[-1]) + degree + 1, 3))
    counts = np.array([5, 5, 5, 5, 3])
    group_spans = np.stack([np.concatenate([[0], np.cumsum(counts)[:-1]]), counts])
    out = np.empty((2, counts.size, 3))
    _kernels.control_point_boxes(positions, span_first, group_spans, degree + 1, out)
    for g, (first, count) in enumerate(group_spans.T):
        points = positions[
            (span_first[first : first + count, None] + np.arange(degree + 1)).ravel()
        ]
        np.testing.assert_array_equal(out[0, g], points.min(axis=0))
        np.testing.assert_array_equal(out[1, g], points.max(axis=0))
