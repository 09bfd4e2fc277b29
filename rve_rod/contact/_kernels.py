"""Numba kernels of contact: box sweep, closest points, loads with tangents, COO assembly.

Arrays are components first, batch last. Each kernel writes into preallocated outputs and is
checked against a plain NumPy/SciPy reference in tests/test_rve_rod/unit/test_contact_kernels.py.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from rve_rod._kernels import record


@njit(cache=True)
def compressible_yarn_law(penetration, parameters, out):
    """The compressible-yarn law (`rve_rod.contact.law`, Weeger et al.) at k penetrations.

    f_n(g) = k (r/p) (g/r)^p and f_n'(g) = k (g/r)^(p-1) for g > 0, both 0 for g <= 0.

    Args:
        penetration: (k,) g = 2r - d (mm).
        parameters: (3,) stiffness k (MPa), exponent p (-), yarn radius r (mm).
        out: (2, k) output: f_n (N/mm) and f_n' (N/mm^2).
    """
    stiffness, exponent, radius = parameters[0], parameters[1], parameters[2]
    for c in range(penetration.size):
        g = penetration[c]
        f = 0.0
        slope = 0.0
        if g > 0.0:
            f = stiffness * (radius / exponent) * (g / radius) ** exponent
            slope = stiffness * (g / radius) ** (exponent - 1.0)
        out[0, c] = f
        out[1, c] = slope


@njit(cache=True)
def box_overlaps(slave_boxes, master_boxes, order, out_slave, out_master):
    """All pairs of overlapping axis-aligned boxes (closed intervals) by a sweep along x.

    Args:
        slave_boxes: (6, a) boxes as (x_lo, y_lo, z_lo, x_hi, y_hi, z_hi).
        master_boxes: (6, b) boxes, same layout.
        order: (b,) master indices sorted by x_lo.
        out_slave, out_master: (capacity,) int64 outputs for the pair indices.

    Returns the number of overlapping pairs; only the first `capacity` are written, so a
    caller whose buffer was too small calls again with a larger one.
    """
    n_master = order.size
    sorted_lo = np.empty(n_master)
    extent = 0.0
    for t in range(n_master):
        m = order[t]
        sorted_lo[t] = master_boxes[0, m]
        extent = max(extent, master_boxes[3, m] - master_boxes[0, m])
    capacity = out_slave.size
    count = 0
    for a in range(slave_boxes.shape[1]):
        first = np.searchsorted(sorted_lo, slave_boxes[0, a] - extent)
        last = np.searchsorted(sorted_lo, slave_boxes[3, a], side="right")
        for t in range(first, last):
            m = order[t]
            if (
                master_boxes[3, m] >= slave_boxes[0, a]
                and master_boxes[1, m] <= slave_boxes[4, a]
                and master_boxes[4, m] >= slave_boxes[1, a]
                and master_boxes[2, m] <= slave_boxes[5, a]
                and master_boxes[5, m] >= slave_boxes[2, a]
            ):
                if count < capacity:
                    out_slave[count] = a
                    out_master[count] = m
                count += 1
    return count


@njit(cache=True)
def span_coefficients(positions, control_points, basis, out):
    """Power-basis coefficients of the spans (`ContactLayout.coefficients`):
    out[c, k, s] = sum_a positions[control_points[s, a], c] basis[s, a, k], summed over a in
    order (as einsum sums them, in a third of its time on these sums of p+1 terms).

    Args:
        positions: (n, 3) control points (mm).
        control_points: (S, p+1) int64 the control points of each span.
        basis: (S, p+1, p+1) the spans' basis functions in the power basis.
        out: (3, p+1, S) the coefficients (mm).
    """
    width = control_points.shape[1]
    for s in range(control_points.shape[0]):
        for c in range(3):
            for k in range(width):
                total = positions[control_points[s, 0], c] * basis[s, 0, k]
                for a in range(1, width):
                    total += positions[control_points[s, a], c] * basis[s, a, k]
                out[c, k, s] = total


@njit(cache=True)
def point_positions(positions, first, basis, out):
    """Centreline points out[c, j] = sum_a basis[j, a] positions[first[j] + a, c], summed over
    a in order (`ContactLayout.collocation_positions`).

    Args:
        positions: (n, 3) control points (mm).
        first: (m,) int64 the first of the p+1 control points acting at each point.
        basis: (m, p+1) their basis values at the point.
        out: (3, m) the points (mm).
    """
    for j in range(first.size):
        for c in range(3):
            total = basis[j, 0] * positions[first[j], c]
            for a in range(1, basis.shape[1]):
                total += basis[j, a] * positions[first[j] + a, c]
            out[c, j] = total


@njit(cache=True)
def control_point_boxes(positions, span_first, group_spans, width, out):
    """Axis-aligned boxes of the control points of groups of spans (`broad_phase.group_boxes`).

    Args:
        positions: (n, 3) control points (mm).
        span_first: (S,) int64 the first of each span's `width` control points.
        group_spans: (2, B) int64 first span and number of spans of each group.
        width: control points per span (p+1).
        out: (2, B, 3) the low and the high corner of each group's box (mm).
    """
    for g in range(group_spans.shape[1]):
        first = group_spans[0, g]
        for c in range(3):
            low = np.inf
            high = -np.inf
            for s in range(first, first + group_spans[1, g]):
                for a in range(width):
                    value = positions[span_first[s] + a, c]
                    low = min(low, value)
                    high = max(high, value)
            out[0, g, c] = low
            out[1, g, c] = high


@record
class MasterStrands(NamedTuple):
    """Where the master boxes of the sweep lie along their strands (`apart_pairs`).

    Attributes:
        strand: (B,) int64 strand key of each box; box b is group b % G in image b // G.
        shift: (B,) arc shift of each box's image along its strand (mm).
        arc_start, arc_end: (G,) reference arc interval of each group (mm).
    """

    strand: np.ndarray
    shift: np.ndarray
    arc_start: np.ndarray
    arc_end: np.ndarray


@record
class PointStrands(NamedTuple):
    """The collocation points along their strands: arc (m,) coordinate (mm), strand (m,)
    int64 key."""

    arc: np.ndarray
    strand: np.ndarray


@njit(cache=True)
def apart_pairs(slave, master, masters, points, exclusion, out):
    """The (point, master box) pairs of the sweep minus those of a point's own strand whose
    group lies entirely within the exclusion arc length of it (`broad_phase.find_candidates`).

    Args:
        slave, master: (k,) int64 pairs of collocation point and master box.
        masters: `MasterStrands` of the boxes; points: `PointStrands` of the points.
        exclusion: the exclusion arc length (mm).
        out: (3, k) int64: the kept pairs' point, group and image, in the pairs' order.

    Returns the number of pairs kept.
    """
    n_groups = masters.arc_start.size
    count = 0
    for t in range(slave.size):
        point = slave[t]
        box = master[t]
        image = box // n_groups
        group = box - image * n_groups
        arc = points.arc[point]
        along = max(
            abs(masters.arc_start[group] + masters.shift[box] - arc),
            abs(masters.arc_end[group] + masters.shift[box] - arc),
        )
        if masters.strand[box] != points.strand[point] or along >= exclusion:
            out[0, count] = point
            out[1, count] = group
            out[2, count] = image
            count += 1
    return count


@njit(cache=True)
def _span_geometry(coefficients, span, tau, out):
    """C, dC/dtau, d2C/dtau2 of a span polynomial at tau (Horner), into out (3, 3)."""
    degree = coefficients.shape[1] - 1
    for c in range(3):
        value = coefficients[c, degree, span]
        first = 0.0
        second = 0.0
        for k in range(degree - 1, -1, -1):
            second = second * tau + first
            first = first * tau + value
            value = value * tau + coefficients[c, k, span]
        out[0, c] = value
        out[1, c] = first
        out[2, c] = 2.0 * second


@njit(cache=True)
def _start_slope(coefficients, span, target):
    """Slope C'.(C - x) of the squared distance from x (3,) at the start (tau = 0) of a span."""
    return (
        coefficients[0, 1, span] * (coefficients[0, 0, span] - target[0])
        + coefficients[1, 1, span] * (coefficients[1, 0, span] - target[1])
        + coefficients[2, 1, span] * (coefficients[2, 0, span] - target[2])
    )


@njit(cache=True)
def _end_slope(coefficients, span, target):
    """Slope C'.(C - x) of the squared distance from x (3,) at the end (tau = 1) of a span."""
    slope = 0.0
    for c in range(3):
        value = 0.0
        derivative = 0.0
        for k in range(coefficients.shape[1]):
            value += coefficients[c, k, span]
            derivative += k * coefficients[c, k, span]
        slope += derivative * (value - target[c])
    return slope


@record
class SpanGroups(NamedTuple):
    """The spans of all patches as the projection kernel takes them.

    Attributes:
        coefficients: (3, p+1, S) power-basis coefficients of the spans.
        group_spans: (2, B) first span and number of spans of each group.
        span_next: (S,) next span of the same patch, -1 for a patch's last span.
        closed_end: (S,) True for spans that own their end point (end of an open yarn).
    """

    coefficients: np.ndarray
    group_spans: np.ndarray
    span_next: np.ndarray
    closed_end: np.ndarray


@record
class Minima(NamedTuple):
    """Preallocated outputs of `project_on_groups` (capacity minima).

    Attributes:
        index: (2, capacity) int64: target and span of each minimum found.
        values: (10, capacity): tau, then C, dC/dtau, d2C/dtau2 (3 each) at tau.
    """

    index: np.ndarray
    values: np.ndarray


@njit(cache=True)
def project_on_groups(spans, groups, targets, tolerance, reach, out):
    """Closest points of targets on groups of spans: every local minimum of distance.

    The squared distance f(tau) = |C(tau) - x|^2 / 2 has slope g = C'.(C - x), a polynomial
    of degree 2p - 1 on each span. The span's [0, 1] is split into pieces on each of which g
    has at most one root (`_slope_pieces`); a piece owns a minimum when g <= 0 at its start
    and g > 0 at its end (>= 0 at the end of the last span of an open yarn). The span's end
    slope is taken at the start of the next span of the same patch so that a minimum exactly
    on a knot belongs to one span only. Inside the piece, Newton steps on g with bisection
    whenever a step would leave the bracket (safeguarded Newton: it always converges,
    quadratically near the root).

    A span whose bounding box (that of its Bernstein control points, which holds the span by
    the convex hull property) lies farther than `reach` from the target holds no point within
    reach, so it is skipped, and so is a group whose spans' boxes all do: the minima within
    reach are the same with or without these tests.

    Args:
        spans: `SpanGroups`.
        groups: (k,) group of each target.
        targets: (3, k) points to project (slave point minus the image translation).
        tolerance: convergence tolerance on tau (the iteration limit follows from it).
        reach: minima farther than this from their target may be left out (mm; inf: none).
        out: `Minima` buffers.

    Returns the number of minima found; only the first `capacity` are written.
    """
    coefficients, group_spans = spans.coefficients, spans.group_spans
    local = np.empty((3, 3))
    n_slope = 2 * coefficients.shape[1] - 2  # coefficients of g, degree 2p - 1
    bernstein = np.empty((coefficients.shape[2], 4, n_slope))
    _slope_bernstein(coefficients, bernstein)
    boxes = np.empty((coefficients.shape[2], 2, 3))
    _span_boxes(coefficients, boxes)
    group_boxes = np.empty((group_spans.shape[1], 2, 3))
    for g in range(group_spans.shape[1]):
        first = group_spans[0, g]
        for c in range(3):
            group_boxes[g, 0, c] = boxes[first : first + group_spans[1, g], 0, c].min()
            group_boxes[g, 1, c] = boxes[first : first + group_spans[1, g], 1, c].max()
    pieces = np.empty((3, _MAX_PIECES))
    stack = np.empty((_MAX_PIECES, 2 + n_slope))
    capacity = out.values.shape[1]
    count = 0
    for c in range(groups.size):
        target = targets[:, c]
        if _box_distance(group_boxes, groups[c], target) > reach:
            continue
        first = group_spans[0, groups[c]]
        slope_low = _start_slope(coefficients, first, target)
        for s in range(first, first + group_spans[1, groups[c]]):
            following = spans.span_next[s]
            if following >= 0:
                slope_high = _start_slope(coefficients, following, target)
            else:
                slope_high = _end_slope(coefficients, s, target)
            if _box_distance(boxes, s, target) > reach:
                slope_low = slope_high
                continue
            for k in range(n_slope):
                stack[0, 2 + k] = bernstein[s, 0, k] - (
                    target[0] * bernstein[s, 1, k]
                    + target[1] * bernstein[s, 2, k]
                    + target[2] * bernstein[s, 3, k]
                )
            n_pieces = _slope_pieces(coefficients, s, target, slope_low, (stack, pieces))
            for q in range(n_pieces):
                low, high = pieces[0, q], pieces[1, q]
                start_slope = pieces[2, q]
                end_slope = pieces[2, q + 1] if q + 1 < n_pieces else slope_high
                owned = start_slope <= 0.0 and (
                    end_slope > 0.0 or (spans.closed_end[s] and high == 1.0 and end_slope >= 0.0)
                )
                if not owned:
                    continue
                t = _safeguarded_newton(
                    coefficients, s, target, (low, high, start_slope, end_slope), tolerance
                )
                if count < capacity:
                    _span_geometry(coefficients, s, t, local)
                    out.index[0, count] = c
                    out.index[1, count] = s
                    out.values[0, count] = t
                    for row in range(3):
                        for col in range(3):
                            out.values[1 + 3 * row + col, count] = local[row, col]
                count += 1
            slope_low = slope_high
    return count


@njit(cache=True)
def _span_boxes(coefficients, out):
    """Bounding boxes (S, 2, 3) (lower and upper corner) of the spans' Bernstein control
    points, from their power-basis coefficients (3, p+1, S) on [0, 1]."""
    p = coefficients.shape[1] - 1
    for span in range(coefficients.shape[2]):
        for c in range(3):
            low = np.inf
            high = -np.inf
            for k in range(p + 1):
                value = 0.0
                ratio = 1.0  # binom(k, i) / binom(p, i)
                for i in range(k + 1):
                    value += ratio * coefficients[c, i, span]
                    ratio *= (k - i) / (p - i) if i < p else 0.0
                low = min(low, value)
                high = max(high, value)
            out[span, 0, c] = low
            out[span, 1, c] = high


@njit(cache=True)
def _box_distance(boxes, index, target):
    """Distance (mm) from a point (3,) to the box `index` of boxes (k, 2, 3) (lower and upper
    corner)."""
    total = 0.0
    for c in range(3):
        gap = max(boxes[index, 0, c] - target[c], target[c] - boxes[index, 1, c], 0.0)
        total += gap * gap
    return np.sqrt(total)


_MAX_PIECES = 64
"""Bound on the pieces of one span (and on the subdivision stack): a split keeps at most
1 - _SPLIT of a piece, so the depth is at most log(_MIN_PIECE) / log(1 - _SPLIT) = 24, each
level pushing one piece."""

_SPLIT = 0.4375
"""Where a piece is split (fraction of its width)."""

_MIN_PIECE = 1e-6
"""Pieces narrower than this (in tau) are not split further: two minima that close have a
prominence of order (width)^3 of the distance scale, i.e. none."""


@njit(cache=True)
def _slope_bernstein(coefficients, out):
    """Bernstein coefficients on [0, 1] of degree 2p - 1 of every span's C'.C and of the
    components of C', into out (S, 4, 2p): the slope g = C'.(C - x) of the squared distance
    from a target x has the coefficients out[s, 0] - sum_c x_c out[s, 1 + c]."""
    p = coefficients.shape[1] - 1
    n = out.shape[2] - 1
    power = np.empty((4, n + 1))
    for span in range(coefficients.shape[2]):
        power[:, :] = 0.0
        for c in range(3):
            for i in range(p + 1):
                for j in range(1, p + 1):
                    power[0, i + j - 1] += coefficients[c, i, span] * j * coefficients[c, j, span]
            for j in range(1, p + 1):
                power[1 + c, j - 1] = j * coefficients[c, j, span]
        for row in range(4):
            for k in range(n + 1):
                value = 0.0
                ratio = 1.0  # binom(k, i) / binom(n, i)
                for i in range(k):
                    value += ratio * power[row, i]
                    ratio *= (k - i) / (n - i)
                value += ratio * power[row, k]
                out[span, row, k] = value


@njit(cache=True)
def _slope_at(coefficients, span, target, tau):
    """Slope C'.(C - x) of the squared distance at tau, as `_safeguarded_newton` has it."""
    local = np.empty((3, 3))
    _span_geometry(coefficients, span, tau, local)
    return (
        local[1, 0] * (local[0, 0] - target[0])
        + local[1, 1] * (local[0, 1] - target[1])
        + local[1, 2] * (local[0, 2] - target[2])
    )


@njit(cache=True)
def _sign_changes(values):
    """Sign changes of a sequence, zeros skipped."""
    changes = 0
    last = 0.0
    for value in values:
        if value != 0.0:
            if last != 0.0 and (value > 0.0) != (last > 0.0):
                changes += 1
            last = value
    return changes


@njit(cache=True)
def _slope_pieces(coefficients, span, target, slope_low, buffers):
    """Split a span's [0, 1] into pieces on which the slope has at most one root.

    Descartes' rule for the Bernstein form: g has at most as many roots in a piece as its
    Bernstein coefficients there have sign changes, so a piece with at most one change is
    kept and a piece with more is split (de Casteljau at `_SPLIT` of its width) until it has
    at most one or is narrower than `_MIN_PIECE`. The common span (one change or none) is one
    piece at no extra cost beyond its coefficients. The split is off-centre so that a
    stationary point which a symmetric configuration puts at a span's middle does not fall on
    a piece end (where its sign would decide for both neighbours).

    slope_low is the slope at the span's start as the caller has it (its knot convention);
    buffers = (stack, pieces): the subdivision stack (_MAX_PIECES, 2p + 2), whose first row
    holds the span's Bernstein coefficients after its first two entries, and the output
    (3, _MAX_PIECES). Writes the pieces left to right into pieces: start, end and the slope
    at the start (slope_low for the first piece, else the slope evaluated as
    `_safeguarded_newton` evaluates it, so that both agree on the bracket), and returns their
    count. The slope at a piece's end is the next piece's start slope, or the caller's at the
    span's end.
    """
    stack, pieces = buffers
    n = stack.shape[1] - 3
    coefficient = stack[0, 2:]
    if _sign_changes(coefficient) <= 1:
        pieces[0, 0], pieces[1, 0], pieces[2, 0] = 0.0, 1.0, slope_low
        return 1
    stack[0, 0], stack[0, 1] = 0.0, 1.0
    depth = 1
    count = 0
    work = np.empty(n + 1)
    left = np.empty(n + 1)
    right = np.empty(n + 1)
    while depth > 0:
        depth -= 1
        low, high = stack[depth, 0], stack[depth, 1]
        coefficient = stack[depth, 2:]
        if (
            _sign_changes(coefficient) <= 1
            or high - low < _MIN_PIECE
            or depth + 2 > stack.shape[0]
            or count + 2 > pieces.shape[1]
        ):
            pieces[0, count], pieces[1, count] = low, high
            start = slope_low if low == 0.0 else _slope_at(coefficients, span, target, low)
            pieces[2, count] = start
            count += 1
            continue
        # de Casteljau at _SPLIT: the left and right parts' coefficients.
        work[:] = coefficient
        for level in range(n + 1):
            left[level] = work[0]
            right[n - level] = work[n - level]
            for i in range(n - level):
                work[i] = (1.0 - _SPLIT) * work[i] + _SPLIT * work[i + 1]
        middle = low + _SPLIT * (high - low)
        # Push the right part first so that the left one is taken next (pieces in order).
        stack[depth, 0], stack[depth, 1] = middle, high
        stack[depth, 2:] = right
        stack[depth + 1, 0], stack[depth + 1, 1] = low, middle
        stack[depth + 1, 2:] = left
        depth += 2
    return count


@njit(cache=True)
def _safeguarded_newton(coefficients, span, target, piece, tolerance):
    """Root of the slope in a piece = (low, high, slope_low, slope_high) of [0, 1] given the
    slopes at its ends (slope_low <= 0 < slope_high)."""
    local = np.empty((3, 3))
    max_iterations = 2 * int(np.log2(1.0 / tolerance)) + 10
    low, high, slope_low, slope_high = piece
    t = low
    if slope_low != slope_high:
        t = low + (high - low) * slope_low / (slope_low - slope_high)
    for _ in range(max_iterations):
        _span_geometry(coefficients, span, t, local)
        d0 = local[0, 0] - target[0]
        d1 = local[0, 1] - target[1]
        d2 = local[0, 2] - target[2]
        slope = local[1, 0] * d0 + local[1, 1] * d1 + local[1, 2] * d2
        curvature = (
            local[1, 0] ** 2
            + local[1, 1] ** 2
            + local[1, 2] ** 2
            + local[2, 0] * d0
            + local[2, 1] * d1
            + local[2, 2] * d2
        )
        if slope <= 0.0:
            low = t
        else:
            high = t
        step = t - slope / curvature if curvature > 0.0 else -1.0
        if not low <= step <= high:
            step = 0.5 * (low + high)
        done = abs(step - t) <= tolerance
        t = step
        if done:
            break
    return t


@record
class SpanChain(NamedTuple):
    """How the derivative blocks of k loads chain to the control points of their spans.

    Attributes:
        first: (3, k) int64 first control point of the slave span, the master span and the
            anchor span (-1: no anchor) of each load.
        basis: (4, p+1, k) the values chaining each block to the span's control points:
            N_a(slave tau), N_b(master tau), dN_b/dtau(master tau), N_c(anchor tau).
    """

    first: np.ndarray
    basis: np.ndarray


@record
class CooEntries(NamedTuple):
    """COO entries: (capacity,) rows, columns (int32: scipy's index type for matrices of
    fewer than 2^31 rows and columns, taken without a copy), values; preallocated outputs of
    `block_entries`."""

    rows: np.ndarray
    columns: np.ndarray
    values: np.ndarray

    @classmethod
    def empty(cls, capacity: int) -> "CooEntries":
        """Buffers for `capacity` entries."""
        return cls(
            np.empty(capacity, dtype=np.int32),
            np.empty(capacity, dtype=np.int32),
            np.empty(capacity),
        )


@njit(cache=True)
def block_entries(blocks, rows, columns, chain, out):
    """COO entries of the contact-load derivative with respect to the control points, in the
    numbering of the caller's matrix.

    Args:
        blocks: (4, 3, 3, k) derivative blocks of each load w.r.t. x_s, x_m, C' and x_a.
        rows: (3, k) int64 matrix row of component i of load c, -1: the row is left out.
        columns: (n, 3) int64 matrix column of coordinate j of control point a.
        chain: `SpanChain` of the k loads.
        out: `CooEntries`, capacity >= 9 * 3 (p+1) k.

    Block b of span control point a goes to columns[first + a, j]; the master span takes
    blocks 1 and 2 together. Entries are written load by load, span by span (slave, master,
    anchor), control point by control point, row by row. Returns the number of entries written.
    """
    first, basis = chain.first, chain.basis
    out_rows, out_columns, values = out.rows, out.columns, out.values
    n_basis = basis.shape[1]
    count = 0
    for c in range(rows.shape[1]):
        for part in range(3):
            start = first[part, c]
            if start < 0:
                continue
            for a in range(n_basis):
                for i in range(3):
                    row = rows[i, c]
                    if row < 0:
                        continue
                    for j in range(3):
                        if part == 0:
                            value = blocks[0, i, j, c] * basis[0, a, c]
                        elif part == 1:
                            value = (
                                blocks[1, i, j, c] * basis[1, a, c]
                                + blocks[2, i, j, c] * basis[2, a, c]
                            )
                        else:
                            value = blocks[3, i, j, c] * basis[3, a, c]
                        out_rows[count] = row
                        out_columns[count] = columns[start + a, j]
                        values[count] = value
                        count += 1
    return count


@record
class ContactGeometry(NamedTuple):
    """Closest-point geometry of k contacts as `contact_loads` takes it (contacts last).

    Attributes:
        gap_vector: (3, k) v = x_s - x_m (mm).
        tangent: (3, k) C' = dC/dtau at the closest point (mm).
        metric: (k,) H = C'.C' - C''.v (mm^2).
        slip_vector: (3, k) w = x_s - x_a - o relative to the stick anchor (mm).
        anchored: (k,) True where the contact has an anchor (friction applies).
    """

    gap_vector: np.ndarray
    tangent: np.ndarray
    metric: np.ndarray
    slip_vector: np.ndarray
    anchored: np.ndarray


@record
class LoadOutput(NamedTuple):
    """Preallocated outputs of `contact_loads` for k contacts.

    Attributes:
        load: (3, k) line load (N/mm).
        blocks: (4, 3, 3, k) derivatives of the load w.r.t. x_s, x_m, C' and the anchor point
            x_a (N/mm^2).
        state: (k,) int8: 0 no friction, 1 stick, 2 slip.
    """

    load: np.ndarray
    blocks: np.ndarray
    state: np.ndarray


@record
class _Contact(NamedTuple):
    """One contact inside `contact_loads`: n, C', v (3,), d, H, f_n, f_n' and P = I - n n^T."""

    normal: np.ndarray
    tangent: np.ndarray
    gap_vector: np.ndarray
    distance: float
    metric: float
    force: float
    slope: float
    projector: np.ndarray


@njit(cache=True)
def contact_loads(geometry, normal_law, friction, out):
    """Line loads of k contacts (a normal law, Coulomb friction) and their derivatives.

    Per contact: v = x_s - x_m, d = |v|, n = v/d; the normal line load f_n and its slope
    f_n' = df_n/dg on the penetration g = 2r - d come from the law (`rve_rod.contact.law`).
    Normal load f_n n with derivative blocks
    K (dx_s - dx_m) - (f_n/H) C' n^T dC', K = -f_n' n n^T + (f_n/d) P - f_n/(d H) C' C'^T,
    P = I - n n^T. Friction on anchored contacts: slip g_T = P w, trial -k_t g_T, stick or
    slip to mu f_n (return mapping) with dg_T = P dw + G dv, G = -[(n.w) P + n g_T^T]/d,
    dv = Q (dx_s - dx_m) - C' v.dC'/H, Q = I - C' C'^T/H (docs/contact.md).

    Args:
        geometry: `ContactGeometry` of the k contacts.
        normal_law: (2, k) f_n (N/mm) and f_n' (N/mm^2) of each contact.
        friction: (2,) coefficient mu and tangential stiffness k_t (MPa); mu = 0: none.
        out: `LoadOutput` buffers, overwritten.
    """
    mu = friction[0]
    gap_vector, tangent = geometry.gap_vector, geometry.tangent
    n = np.empty(3)
    t = np.empty(3)
    v = np.empty(3)
    projector = np.empty((3, 3))
    for c in range(geometry.metric.size):
        d = np.sqrt(gap_vector[0, c] ** 2 + gap_vector[1, c] ** 2 + gap_vector[2, c] ** 2)
        for i in range(3):
            v[i] = gap_vector[i, c]
            n[i] = v[i] / d
            t[i] = tangent[i, c]
        h = geometry.metric[c]
        f = normal_law[0, c]
        slope = normal_law[1, c]
        for i in range(3):
            out.load[i, c] = f * n[i]
            for j in range(3):
                projector[i, j] = (1.0 if i == j else 0.0) - n[i] * n[j]
                k_ij = -slope * n[i] * n[j] + f / d * projector[i, j] - f / (d * h) * t[i] * t[j]
                out.blocks[0, i, j, c] = k_ij
                out.blocks[1, i, j, c] = -k_ij
                out.blocks[2, i, j, c] = -f / h * t[i] * n[j]
                out.blocks[3, i, j, c] = 0.0
        out.state[c] = 0
        if mu > 0.0 and geometry.anchored[c]:
            contact = _Contact(n, t, v, d, h, f, slope, projector)
            _friction(c, contact, geometry.slip_vector, friction, out)


@njit(cache=True)
def _friction(c, contact, slip_vector, friction, out):
    """Return mapping of contact c; adds its load and derivative blocks (see contact_loads)."""
    n, t, v = contact.normal, contact.tangent, contact.gap_vector
    d, h, f, slope = contact.distance, contact.metric, contact.force, contact.slope
    projector = contact.projector
    mu, k_t = friction[0], friction[1]
    w = slip_vector[:, c]
    normal_part = n[0] * w[0] + n[1] * w[1] + n[2] * w[2]
    slip = np.empty(3)
    for i in range(3):
        slip[i] = w[i] - normal_part * n[i]
    # G = -[(n.w) P + n g_T^T] / d and Q = I - C' C'^T / H.
    g_matrix = np.empty((3, 3))
    q_matrix = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            g_matrix[i, j] = -(normal_part * projector[i, j] + n[i] * slip[j]) / d
            q_matrix[i, j] = (1.0 if i == j else 0.0) - t[i] * t[j] / h
    gq = g_matrix @ q_matrix
    g_tangent = g_matrix @ t
    trial = -k_t * slip
    trial_norm = np.sqrt(trial[0] ** 2 + trial[1] ** 2 + trial[2] ** 2)
    limit = mu * f
    sliding = trial_norm > limit
    scale = limit / trial_norm if sliding else 1.0
    direction = trial / trial_norm if trial_norm > 0.0 else np.zeros(3)
    # Stick: df_t = -k_t dg_T. Slip: df_t = -mu f_n' t n^T (dx_s - dx_m) + T dg_T with
    # T = -k_t mu f_n / |trial| (I - t t^T), t the slip direction.
    factor = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            identity = 1.0 if i == j else 0.0
            factor[i, j] = (
                -k_t * scale * (identity - (direction[i] * direction[j] if sliding else 0.0))
            )
    d_slave = projector + gq
    d_master = -gq
    t_slave = factor @ d_slave
    t_master = factor @ d_master
    t_anchor = -(factor @ projector)
    for i in range(3):
        out.load[i, c] += scale * trial[i]
        for j in range(3):
            normal_term = -mu * slope * direction[i] * n[j] if sliding else 0.0
            out.blocks[0, i, j, c] += t_slave[i, j] + normal_term
            out.blocks[1, i, j, c] += t_master[i, j] - normal_term
            out.blocks[3, i, j, c] = t_anchor[i, j]
    for i in range(3):
        for j in range(3):
            # d/dC': -T G C' v^T / H
            value = 0.0
            for a in range(3):
                value += factor[i, a] * g_tangent[a]
            out.blocks[2, i, j, c] -= value * v[j] / h
    out.state[c] = 2 if sliding else 1


@record
class StrandArcs(NamedTuple):
    """The master strands by unwrapped reference arc coordinate, as `separating_maxima` takes
    them (`rve_rod.contact.regions.StrandGeometry` builds it).

    Attributes:
        coefficients: (3, p+1, S) power-basis coefficients of the spans (mm).
        span_yarn: (S,) int64 yarn of each span.
        span_arc_start, span_arc_length: (S,) reference arc interval of each span (mm).
        keys: (S,) sorted search keys yarn_offset[yarn] + arc start of the spans.
        order: (S,) int64 the spans in key order.
        yarn_offset: (Y,) key offset of each yarn (mm).
        yarn_length: (Y,) reference length of each yarn (mm).
        yarn_period: (Y, 2) int64 lattice period of each yarn ((0, 0) for an open yarn).
        yarn_first_span: (Y,) int64 the first span of each yarn along its arc.
        image_vectors: (2, 3) the deformed lattice vectors F a1, F a2 (zeros without a lattice).
    """

    coefficients: np.ndarray
    span_yarn: np.ndarray
    span_arc_start: np.ndarray
    span_arc_length: np.ndarray
    keys: np.ndarray
    order: np.ndarray
    yarn_offset: np.ndarray
    yarn_length: np.ndarray
    yarn_period: np.ndarray
    yarn_first_span: np.ndarray
    image_vectors: np.ndarray


@record
class StrandPairs(NamedTuple):
    """Neighbouring distance minima of one slave point on one strand (arrays over k pairs).

    Attributes:
        slave_points: (3, k) the slave point of each pair (mm).
        yarn: (k,) int64 yarn of the strand.
        image: (k, 2) int64 lattice image of the left minimum.
        start, stop: (k,) unwrapped reference arc coordinates of the left and right minimum.
    """

    slave_points: np.ndarray
    yarn: np.ndarray
    image: np.ndarray
    start: np.ndarray
    stop: np.ndarray


@record
class StrandLocations(NamedTuple):
    """Preallocated outputs of `separating_maxima` for k pairs: the maxima's span (k,) int64,
    tau (k,), image (k, 2) int64, arc (k,) (mm), distance (k,) (mm) and normal (3, k)."""

    span: np.ndarray
    tau: np.ndarray
    image: np.ndarray
    arc: np.ndarray
    distance: np.ndarray
    normal: np.ndarray


@njit(cache=True)
def _locate(strands, yarn, reference, arc, image):
    """Span and tau of the point at unwrapped arc coordinate `arc` on the strand through
    the yarn's point reference = (image (2,), arc); writes the point's image into image (2,)."""
    reference_image, reference_arc = reference
    length = strands.yarn_length[yarn]
    period = strands.yarn_period[yarn]
    turns = 0.0
    reference_turns = 0.0
    if period[0] != 0 or period[1] != 0:
        turns = np.floor(arc / length)
        reference_turns = np.floor(reference_arc / length)
    local = min(max(arc - turns * length, 0.0), length)
    last = strands.keys.size - 1
    position = np.searchsorted(strands.keys, strands.yarn_offset[yarn] + local, side="right") - 1
    span = strands.order[min(max(position, 0), last)]
    if strands.span_yarn[span] != yarn:
        span = strands.yarn_first_span[yarn]
    tau = (local - strands.span_arc_start[span]) / strands.span_arc_length[span]
    tau = min(max(tau, 0.0), 1.0)
    shift = int(turns - reference_turns)
    image[0] = reference_image[0] + shift * period[0]
    image[1] = reference_image[1] + shift * period[1]
    return span, tau


@njit(cache=True)
def _strand_point(strands, span, tau, image, out):
    """C, dC/dtau and d2C/dtau2 of the span at tau (out (3, 3)), C translated to the image."""
    _span_geometry(strands.coefficients, span, tau, out)
    vectors = strands.image_vectors
    for c in range(3):
        out[0, c] += image[0] * vectors[0, c] + image[1] * vectors[1, c]


@njit(cache=True)
def separating_maxima(strands, pairs, samples, max_iterations, out):
    """The largest distance maximum between the two minima of each pair, along the strand.

    The squared distance from the slave point is sampled at `samples` interior arc
    coordinates evenly between the minima; the largest sample's neighbours bracket the
    maximum, found by Newton on the slope of |x_m - x_s|^2 / 2 in the arc coordinate with
    bisection whenever a step would leave the bracket, until a step is below 1e-12 (1 +
    |start|) mm or after `max_iterations` (`rve_rod.contact.regions`).

    Args:
        strands: `StrandArcs`.
        pairs: `StrandPairs`.
        samples: interior samples of the distance.
        max_iterations: bound on the Newton iterations.
        out: `StrandLocations` buffers.
    """
    local = np.empty((3, 3))
    image = np.empty(2, dtype=np.int64)
    for c in range(pairs.start.size):
        yarn = pairs.yarn[c]
        reference = pairs.image[c]
        start = pairs.start[c]
        width = pairs.stop[c] - start
        target = pairs.slave_points[:, c]
        best = 1
        largest = -1.0
        for k in range(1, samples + 1):
            arc = start + (k / (samples + 1)) * width
            span, tau = _locate(strands, yarn, (reference, start), arc, image)
            _strand_point(strands, span, tau, image, local)
            value = 0.0
            for i in range(3):
                value += (local[0, i] - target[i]) ** 2
            if value > largest:
                largest, best = value, k
        low = start + ((best - 1) / (samples + 1)) * width
        high = start + ((best + 1) / (samples + 1)) * width
        arc = start + (best / (samples + 1)) * width
        tolerance = 1e-12 * (1.0 + abs(start))
        for _ in range(max_iterations):
            span, tau = _locate(strands, yarn, (reference, start), arc, image)
            _strand_point(strands, span, tau, image, local)
            scale = 1.0 / strands.span_arc_length[span]
            slope = 0.0
            curvature = 0.0
            for i in range(3):
                offset = local[0, i] - target[i]
                slope += offset * local[1, i]
                curvature += local[1, i] * local[1, i] + offset * local[2, i]
            slope *= scale
            curvature *= scale * scale
            if slope >= 0.0:
                low = arc
            else:
                high = arc
            step = arc - slope / curvature if curvature < 0.0 else np.nan
            if not (low < step < high):
                step = 0.5 * (low + high)
            done = abs(step - arc) <= tolerance
            arc = step
            if done:
                break
        span, tau = _locate(strands, yarn, (reference, start), arc, image)
        _strand_point(strands, span, tau, image, local)
        distance = 0.0
        for i in range(3):
            distance += (target[i] - local[0, i]) ** 2
        distance = np.sqrt(distance)
        out.span[c] = span
        out.tau[c] = tau
        out.image[c, 0] = image[0]
        out.image[c, 1] = image[1]
        out.arc[c] = arc
        out.distance[c] = distance
        for i in range(3):
            out.normal[i, c] = (target[i] - local[0, i]) / distance


@njit(cache=True)
def prominences(minima, maxima, touch, p, derivative):
    """Prominences of the minima of one region and their derivatives
    (`rve_rod.contact.regions.prominences` states the formula).

    Args:
        minima: (n,) capped distances of the minima in arc order (mm).
        maxima: (n-1,) capped distances of the maxima between neighbours (mm).
        touch: 2r (mm).
        p: (n,) output prominences.
        derivative: (n, 2n-1) output dp/dh, columns the minima, then the maxima.
    """
    n = minima.size
    row = np.empty(2 * n - 1)
    lower = np.full(n, np.inf)
    lower_gap = np.full(n, -1)
    derivative[:, :] = 0.0
    for i in range(n):
        p[i] = touch - minima[i]
        derivative[i, i] = -1.0
    for gap in range(n - 1):
        value = maxima[gap]
        for j in (gap, gap + 1):
            if value < lower[j]:
                lower[j], lower_gap[j] = value, gap
    for i in range(n):
        for j in range(n):
            if j == i:
                continue
            barrier_gap = min(i, j)  # the first highest maximum between i and j
            for g in range(min(i, j), max(i, j)):
                if maxima[g] > maxima[barrier_gap]:
                    barrier_gap = g
            barrier = maxima[barrier_gap]
            rise = minima[j] - minima[i]
            depth = lower[j] - minima[j]
            row[:] = 0.0
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
                derivative[i, :] = row
    for i in range(n):
        if p[i] < 0.0:
            p[i] = 0.0
            derivative[i, :] = 0.0


@record
class Regions(NamedTuple):
    """The regions of more than one minimum, as `region_weights` takes them.

    Attributes:
        members: (k,) int64 the minima in region order (arc order within a region).
        gaps: (k,) int64 the maximum after each member (into the maxima; -1 after a region's
            last member).
        bounds: (2, R) int64 first member and size of each region.
    """

    members: np.ndarray
    gaps: np.ndarray
    bounds: np.ndarray


@record
class RegionTerms(NamedTuple):
    """Preallocated outputs of `region_weights`: the weight derivative terms dw_contact +=
    coefficient dh_q, q a stationary point (capacity terms).

    Attributes:
        contact: (capacity,) int64 the weighted minimum.
        kind: (capacity,) int64 0 where q is a minimum, 1 where it is a maximum.
        index: (capacity,) int64 q's index among the minima or the maxima.
        coefficient: (capacity,) dw / dh_q (1/mm).
    """

    contact: np.ndarray
    kind: np.ndarray
    index: np.ndarray
    coefficient: np.ndarray


@njit(cache=True)
def region_weights(distances, regions, touch, weight, out):
    """Weights of the minima of regions of more than one minimum, and their derivative terms
    (`rve_rod.contact.regions.region_weights`): w_i = p_i^2 / sum_j p_j^2, or 1/n where no
    minimum of the region penetrates, and the terms dw_i/dh_q of every stationary point q of
    the region whose distance is below 2r (h = min(d, 2r) changes only there), nonzero ones.

    Args:
        distances: (minimum, maximum): (k,) distances of all minima and (g,) of the maxima
            between linked neighbours (inf where none was searched) (mm).
        regions: `Regions`.
        touch: 2r (mm).
        weight: (k,) output, written for the members only.
        out: `RegionTerms` buffers, capacity sum of n (2n - 1) over the regions.

    Returns the number of terms written.
    """
    minimum, maximum = distances
    members, gaps, bounds = regions
    count = 0
    for r in range(bounds.shape[1]):
        first, n = bounds[0, r], bounds[1, r]
        capped_minimum = np.empty(n)
        capped_maximum = np.empty(n - 1)
        for a in range(n):
            capped_minimum[a] = min(minimum[members[first + a]], touch)
        for a in range(n - 1):
            capped_maximum[a] = min(maximum[gaps[first + a]], touch)
        p = np.empty(n)
        derivative = np.empty((n, 2 * n - 1))
        prominences(capped_minimum, capped_maximum, touch, p, derivative)
        total = 0.0
        for a in range(n):
            total += p[a] ** 2
        if total <= 0.0:
            for a in range(n):
                weight[members[first + a]] = 1.0 / n
            continue
        for i in range(n):
            weight[members[first + i]] = p[i] ** 2 / total
        for i in range(n):
            # dw_i/dp_j = (delta_ij - w_i) 2 p_j / total, chained to the capped distances
            share = p[i] ** 2 / total
            for q in range(2 * n - 1):
                value = 0.0
                for j in range(n):
                    dw_dp = ((1.0 if i == j else 0.0) - share) * (2.0 * p[j] / total)
                    value += dw_dp * derivative[j, q]
                if q < n:
                    kind, index = 0, members[first + q]
                    distance = minimum[index]
                else:
                    kind, index = 1, gaps[first + q - n]
                    distance = maximum[index]
                if distance < touch and value != 0.0:
                    out.contact[count] = members[first + i]
                    out.kind[count] = kind
                    out.index[count] = index
                    out.coefficient[count] = value
                    count += 1
    return count
