"""Numba kernels of the clearance search (`rve_rod.geometry.proximity`): the nearest sample
of another yarn's image to each sample of a yarn, and the Newton refinement of the closest
pairs.

A relaxed cell runs a few thousand clearance searches; as NumPy their per-call overhead and
full sample-distance matrices made most of its time (docs/benchmarks.md). The kernels do the
same arithmetic in the same order (distances as `scipy.spatial.distance.cdist`'s, B-spline
basis by The NURBS Book's A2.3 as `rve_rod.geometry.bspline.basis_functions`, sums over the
components and basis functions in index order, the Hessian's eigenpairs by LAPACK's dsyevd as
`numpy.linalg.eigh`), so their results are NumPy's bit for bit:
tests/test_rve_rod/unit/test_geometry_kernels.py checks them against plain NumPy references
(`basis_functions`; tests/support/proximity_reference.py for the others).

`_basis` is the one second copy of an algorithm here, A2.3 one point at a time with its work
space: `bspline.basis_functions` must stay NumPy (the surface reader imports without numba),
and that vectorized form compiled by numba as it is (tried: `njit(basis_functions)` called
with one point) allocates its temporaries at every call and made the relaxed cells 1.4-1.7
times slower (jersey 2.8 -> 3.8 s, moss 3.3 -> 5.5 s); the test keeps the two equal bit for
bit.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from rve_rod._kernels import record


@record
class Chain(NamedTuple):
    """A periodic chain of curves (`rve_rod.geometry.proximity._Chain`).

    Attributes:
        control_points: (curves, points, 3) the curves' control points, each curve on [0, 1]
            (mm).
        knots: (points + degree + 1,) the knot vector all the curves share.
        period: (3,) the shift from one period of the chain to the next (mm).
    """

    control_points: np.ndarray
    knots: np.ndarray
    period: np.ndarray


@record
class Pairs(NamedTuple):
    """Pairs of points of two chains, refined in place by `refine_pairs`.

    Attributes:
        first: (k,) chain parameter s of each pair on the first chain (in and out).
        second: (k,) chain parameter t on the second chain (in and out).
        offsets: (3, k) the image offset of each pair (mm).
        distances: (k,) output: |X(s) - Y(t) - offset| at the refined pairs (mm).
    """

    first: np.ndarray
    second: np.ndarray
    offsets: np.ndarray
    distances: np.ndarray


@record
class Samples(NamedTuple):
    """The sampled points of two yarns, for `nearest_samples`.

    Attributes:
        first: (a, 3) samples of the first yarn (mm).
        second: (b, 3) samples of the second yarn, before the image offset (mm).
        first_arcs: (a,) arc coordinate of each sample of the first yarn (mm).
        second_arcs: (b,) the same for the second yarn (mm).
    """

    first: np.ndarray
    second: np.ndarray
    first_arcs: np.ndarray
    second_arcs: np.ndarray


@record
class Images(NamedTuple):
    """Images of the second yarn, for `nearest_samples`.

    Attributes:
        offsets: (k, 3) the offset of each image (mm).
        shifts: (k,) added to the second yarn's arc coordinates: i L for the image i periods
            along the same yarn (L the period's arc length) (mm).
        adjacent_arcs: (k,) pairs with |arc_first - (arc_second + shift)| below it are
            skipped (0: none, for another yarn or an image across the courses) (mm).
    """

    offsets: np.ndarray
    shifts: np.ndarray
    adjacent_arcs: np.ndarray


@record
class Nearest(NamedTuple):
    """Output of `nearest_samples`: for each image and each sample of the first yarn, the
    nearest sample of the image.

    Attributes:
        distances: (k, a) the distance to it (mm); inf where every sample is adjacent.
        partners: (k, a) int64, its index, the first of equal distances (as numpy.argmin).
    """

    distances: np.ndarray
    partners: np.ndarray


class _Work(NamedTuple):
    """Work space of the basis functions (A2.3: ndu (p+1, p+1), a (2, p+1), left and right
    (p+1,)), their values (3, p+1), and two chain points with 2 derivatives (3, 3) each."""

    ndu: np.ndarray
    a: np.ndarray
    left: np.ndarray
    right: np.ndarray
    basis: np.ndarray
    x: np.ndarray
    y: np.ndarray


@njit(cache=True)
def nearest_samples(samples, images, chunk, out):
    """The nearest sample of each image (the second yarn's samples + an offset) to each sample
    of the first yarn: the row minima and their first indices of cdist(first, second +
    offset), with the pairs closer than the image's adjacent arc along the yarn skipped.

    Args:
        samples: the two yarns' samples (`Samples`).
        images: the images (`Images`).
        chunk: the second yarn's samples are taken in chunks of this many (a curve's), and a
            chunk whose bounding box is no nearer than the nearest sample found is skipped:
            its every distance is at least the box's, in floating point too (rounding is
            monotonic), so the minima and their first indices are the full matrix's.
        out: the output (`Nearest`), one row per image.
    """
    first, second = samples.first, samples.second
    count = second.shape[0]
    chunks = (count + chunk - 1) // chunk
    shifted = np.empty((count, 3))
    low = np.empty((chunks, 3))
    high = np.empty((chunks, 3))
    for k in range(images.shifts.size):
        offset, shift = images.offsets[k], images.shifts[k]
        adjacent_arc = images.adjacent_arcs[k]
        low[:] = np.inf
        high[:] = -np.inf
        for b in range(count):
            for c in range(3):
                shifted[b, c] = second[b, c] + offset[c]
                low[b // chunk, c] = min(low[b // chunk, c], shifted[b, c])
                high[b // chunk, c] = max(high[b // chunk, c], shifted[b, c])
        partner = 0
        for a in range(first.shape[0]):
            best, best_index = np.inf, 0
            # the previous row's partner first: a near distance that lets most chunks be
            # skipped
            for b in (partner, -1):
                start, stop = (b, b + 1) if b >= 0 else (0, count)
                for g in range(start // chunk, (stop - 1) // chunk + 1):
                    if b < 0:
                        bound = 0.0
                        for c in range(3):
                            gap = max(low[g, c] - first[a, c], first[a, c] - high[g, c], 0.0)
                            bound += gap * gap
                        if np.sqrt(bound) > best:
                            continue
                    for q in range(max(start, g * chunk), min(stop, (g + 1) * chunk)):
                        if adjacent_arc > 0.0 and (
                            abs(samples.first_arcs[a] - (samples.second_arcs[q] + shift))
                            < adjacent_arc
                        ):
                            continue
                        total = 0.0
                        for c in range(3):
                            d = first[a, c] - shifted[q, c]
                            total += d * d
                        distance = np.sqrt(total)
                        if distance < best or (distance == best and q < best_index):
                            best, best_index = distance, q
            out.distances[k, a], out.partners[k, a] = best, best_index
            partner = best_index


@njit(cache=True)
def _basis(knots, degree, u, derivatives, work):
    """Nonzero basis functions at u and their derivatives up to `derivatives` (A2.3).

    Writes work.basis[k, j] = k-th derivative of N_{span-p+j}(u) for k <= derivatives,
    j <= p, and returns the span (as `rve_rod.geometry.bspline.find_spans`, u within the
    domain).
    """
    ndu, a, left, right, out = work.ndu, work.a, work.left, work.right, work.basis
    p = degree
    n = knots.size - p - 1
    span = np.searchsorted(knots, u, side="right") - 1
    span = min(max(span, p), n - 1)
    ndu[0, 0] = 1.0
    for j in range(1, p + 1):
        left[j] = u - knots[span + 1 - j]
        right[j] = knots[span + j] - u
        saved = 0.0
        for r in range(j):
            ndu[j, r] = right[r + 1] + left[j - r]
            temp = ndu[r, j - 1] / ndu[j, r]
            ndu[r, j] = saved + right[r + 1] * temp
            saved = left[j - r] * temp
        ndu[j, j] = saved
    for r in range(p + 1):
        out[0, r] = ndu[r, p]
    for r in range(p + 1):
        s1, s2 = 0, 1
        a[0, 0] = 1.0
        for k in range(1, min(derivatives, p) + 1):
            d = 0.0
            rk, pk = r - k, p - k
            if r >= k:
                a[s2, 0] = a[s1, 0] / ndu[pk + 1, rk]
                d = a[s2, 0] * ndu[rk, pk]
            j1 = 1 if rk >= -1 else -rk
            j2 = k - 1 if r - 1 <= pk else p - r
            for j in range(j1, j2 + 1):
                a[s2, j] = (a[s1, j] - a[s1, j - 1]) / ndu[pk + 1, rk + j]
                d = d + a[s2, j] * ndu[rk + j, pk]
            if r <= pk:
                a[s2, k] = -a[s1, k - 1] / ndu[pk + 1, r]
                d = d + a[s2, k] * ndu[r, pk]
            out[k, r] = d
            s1, s2 = s2, s1
    factor = float(p)
    for k in range(1, min(derivatives, p) + 1):
        for r in range(p + 1):
            out[k, r] *= factor
        factor *= p - k
    return span


@njit(cache=True)
def _chain_point(chain, s, order, work, out):
    """X(s) of a periodic `chain` and its derivatives up to `order` into out (order+1, 3)
    (mm): s = curve index + curve parameter, continued by the period every len(curves)."""
    control_points, knots, period = chain
    curves, points = control_points.shape[0], control_points.shape[1]
    degree = knots.size - points - 1
    whole = np.floor(s)
    wraps = whole // curves
    index = int(whole - wraps * curves)
    span = _basis(knots, degree, s - whole, order, work)
    basis = work.basis
    for k in range(order + 1):
        for c in range(3):
            total = 0.0
            for j in range(degree + 1):
                total += basis[k, j] * control_points[index, span - degree + j, c]
            out[k, c] = total
    for c in range(3):
        out[0, c] += wraps * period[c]


@njit(cache=True)
def _pair_distance(first, second, s, t, offset, work):
    """|X(s) - Y(t) - offset| of two chains (mm)."""
    x, y = work.x, work.y
    _chain_point(first, s, 0, work, x)
    _chain_point(second, t, 0, work, y)
    total = 0.0
    for c in range(3):
        d = x[0, c] - y[0, c] - offset[c]
        total += d * d
    return np.sqrt(total)


@njit(cache=True)
def refine_pairs(first, second, pairs, limit, iterations):
    """Local minima of |X(s) - Y(t) - offset| near each pair (s, t): the saddle-free Newton
    method with a trust region and step halving of `rve_rod.geometry.proximity._refine`,
    pair by pair.

    Args:
        first, second: the two `Chain`s, X on the first, Y on the second (the same chain
            twice for a yarn against its own images).
        pairs: the sampled pairs (`Pairs`), refined in place.
        limit: the trust region, the largest change of a parameter per step.
        iterations: the most Newton steps per pair.
    """
    degree = max(
        first.knots.size - first.control_points.shape[1],
        second.knots.size - second.control_points.shape[1],
    )
    degree -= 1
    work = _Work(
        np.empty((degree + 1, degree + 1)),
        np.empty((2, degree + 1)),
        np.empty(degree + 1),
        np.empty(degree + 1),
        np.zeros((3, degree + 1)),  # derivatives above the degree are zero
        np.empty((3, 3)),
        np.empty((3, 3)),
    )
    x, y = work.x, work.y
    hessian = np.empty((2, 2))
    offset = np.empty(3)
    step = np.empty(2)
    for pair in range(pairs.first.size):
        for c in range(3):
            offset[c] = pairs.offsets[c, pair]
        u, v = pairs.first[pair], pairs.second[pair]
        current = _pair_distance(first, second, u, v, offset, work)
        for _ in range(iterations):
            _chain_point(first, u, 2, work, x)
            _chain_point(second, v, 2, work, y)
            # the sums over the components in index order, as NumPy's
            slope_s = slope_t = ss = tt = st = curve_s = curve_t = 0.0
            for c in range(3):
                d = x[0, c] - y[0, c] - offset[c]
                slope_s += d * x[1, c]
                slope_t += d * y[1, c]
                ss += x[1, c] * x[1, c]
                tt += y[1, c] * y[1, c]
                st += x[1, c] * y[1, c]
                curve_s += d * x[2, c]
                curve_t += d * y[2, c]
            slope_t = -slope_t
            hessian[0, 0] = ss + curve_s
            hessian[1, 1] = tt - curve_t
            hessian[0, 1] = hessian[1, 0] = -st
            # Newton's step with the eigenvalues replaced by their magnitudes
            curvature, axes = np.linalg.eigh(hessian)
            floor = 1e-12 * max(abs(curvature[0]), abs(curvature[1]))
            along_0 = (axes[0, 0] * slope_s + axes[1, 0] * slope_t) / max(
                abs(curvature[0]), floor, 1e-300
            )
            along_1 = (axes[0, 1] * slope_s + axes[1, 1] * slope_t) / max(
                abs(curvature[1]), floor, 1e-300
            )
            step[0] = -(axes[0, 0] * along_0 + axes[0, 1] * along_1)
            step[1] = -(axes[1, 0] * along_0 + axes[1, 1] * along_1)
            scale = min(1.0, limit / max(abs(step[0]), abs(step[1]), 1e-300))
            step[0] *= scale
            step[1] *= scale
            trial = _pair_distance(first, second, u + step[0], v + step[1], offset, work)
            for _ in range(6):  # halve a step that does not decrease the distance
                if not trial > current:
                    break
                step[0] *= 0.5
                step[1] *= 0.5
                trial = _pair_distance(first, second, u + step[0], v + step[1], offset, work)
            if not trial <= current:
                break
            improvement = current - trial
            u, v, current = u + step[0], v + step[1], trial
            if not (max(abs(step[0]), abs(step[1])) > 1e-12 and improvement > 1e-15 * current):
                break
        pairs.first[pair], pairs.second[pair], pairs.distances[pair] = u, v, current
