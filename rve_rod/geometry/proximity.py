"""Clearance of a periodic yarn: the smallest centreline distance to its lattice images and to
the non-adjacent parts of itself.

The yarn is a chain of B-spline curves (each on [0, 1]) that continues into the next period
shifted by the first lattice vector; images are shifted by i a1 + j a2. The search samples the
chain, takes the closest sample pair per image, and refines it by Newton's method on the two
chain parameters (distance between two smooth curves: the pair is a stationary point of
|X(s) - X(t) - o|^2). Pairs closer than `adjacent_arc` along the yarn are adjacent parts of
the same yarn, not a contact, and are skipped.
"""

from functools import cache
from typing import NamedTuple

import numpy as np

from rve_rod.errors import InputError, check_integer
from rve_rod.geometry._kernels import (
    Chain,
    Images,
    Nearest,
    Pairs,
    Samples,
    nearest_samples,
    refine_pairs,
)
from rve_rod.geometry.bspline import BasisValues, BSplineCurve, basis_functions

__all__ = [
    "CellClearance",
    "ChainClearance",
    "cell_clearance",
    "chain_clearance",
]

_SAMPLES_PER_CURVE = 48
_NEWTON_ITERATIONS = 40


class ChainClearance(NamedTuple):
    """The closest pair of the yarn and an image of it.

    Attributes:
        distance: centreline distance (mm).
        first: chain parameter s of the point on the yarn (curve index + curve parameter).
        second: chain parameter t of the point on the image.
        image: (i, j) lattice offset of the image.
    """

    distance: float
    first: float
    second: float
    image: tuple[int, int]


class CellClearance(NamedTuple):
    """The closest pair of the yarns of a cell and their images.

    Attributes:
        distance: centreline distance (mm).
        yarns: (m, n), the yarn of the first point and the yarn whose image holds the second.
        first: chain parameter of the point on yarn m (curve index + curve parameter).
        second: chain parameter of the point on the image of yarn n.
        image: (i, j) lattice offset of the image.
    """

    distance: float
    yarns: tuple[int, int]
    first: float
    second: float
    image: tuple[int, int]


class _Chain:
    """Evaluation of a periodic chain X(s), s = curve + u, continued by a1 per period.

    The curves must share degree and knot vector (the loop's curves do), so one basis
    evaluation serves all of them.
    """

    def __init__(self, curves: tuple[BSplineCurve, ...], period: np.ndarray):
        first = curves[0]
        for curve in curves[1:]:
            if curve.degree != first.degree or not np.array_equal(curve.knots, first.knots):
                raise InputError("the curves of a yarn chain must share degree and knots")
        self.degree = first.degree
        self.knots = first.knots
        self.control_points = np.stack([curve.control_points for curve in curves])
        self.period = period
        self.arrays = Chain(self.control_points, np.asarray(self.knots, dtype=float), period)
        """The chain as `rve_rod.geometry._kernels` takes it."""

    def evaluate(self, s: np.ndarray, basis: BasisValues) -> np.ndarray:
        """Points and derivatives with respect to s, shape (order+1, m, 3), from the basis
        functions (and their derivatives up to the order) at s - floor(s)."""
        n = self.control_points.shape[0]
        whole = np.floor(s)
        wraps = np.floor_divide(whole, n)
        index = (whole - wraps * n).astype(int)
        columns = basis.spans[:, None] - self.degree + np.arange(self.degree + 1)[None, :]
        local = self.control_points[index[:, None], columns]  # (m, p+1, 3)
        out = np.einsum("kma,mad->kmd", basis.values, local)
        out[0] += wraps[:, None] * self.period[None, :]
        return out


def chain_clearance(
    curves: tuple[BSplineCurve, ...] | list[BSplineCurve],
    lattice: np.ndarray,
    adjacent_arc: float,
    *,
    from_curve: int | None = None,
) -> ChainClearance:
    """Smallest distance between the chain and its images (or itself, non-adjacent parts).

    Args:
        curves: consecutive curves of one period of the yarn, each on [0, 1], sharing degree
            and knots (mm).
        lattice: (2, 3) lattice vectors a1 (along the yarn's period) and a2 (mm).
        adjacent_arc: parts of the yarn closer than this in arc length are skipped (mm).
        from_curve: only the pairs whose first point lies on this curve, against the images
            i a1 + j a2 with |i| <= 1, |j| <= 2: enough for a yarn whose symmetries map every
            curve onto this one (the loop's curve 2: docs/geometry.md).

    Without `from_curve` the images are (0, 0), (1, 0) and |i| <= 1, 1 <= j <= 2: the images
    (-i, -j) mirror (i, j) and are not searched separately.
    """
    lattice = np.asarray(lattice, dtype=float)
    chain = _Chain(tuple(curves), lattice[0])
    n = len(curves)
    s = (np.arange(n * _SAMPLES_PER_CURVE) + 0.5) / _SAMPLES_PER_CURVE
    points = chain.evaluate(s, _sample_basis(chain.degree, tuple(chain.knots), n))[0]
    steps = np.linalg.norm(np.diff(points, axis=0, append=points[:1] + lattice[0]), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(steps)[:-1]])
    period_length = steps.sum()
    if from_curve is None:
        images = [(0, 0), (1, 0), *((i, j) for j in (1, 2) for i in (-1, 0, 1))]
        chosen = np.arange(s.size)
    else:
        check_integer("from_curve", from_curve, 0, n - 1)
        images = [(i, j) for j in range(-2, 3) for i in (-1, 0, 1)]
        chosen = np.arange(_SAMPLES_PER_CURVE) + from_curve * _SAMPLES_PER_CURVE
    offsets = np.array([i * lattice[0] + j * lattice[1] for i, j in images])
    # along the yarn (j = 0) the image (i, 0) is the same yarn i periods further on
    sampled = _nearest_samples(
        Samples(points[chosen], points, arc[chosen], arc),
        Images(
            offsets,
            np.array([i * period_length for i, _ in images]),
            np.array([adjacent_arc if j == 0 else 0.0 for _, j in images]),
        ),
    )
    nearest = sampled.distances.T  # (samples, images): distance to the nearest image sample
    overall = nearest.min()
    # a sampled pair overestimates a distance by about spacing^2 / distance: every local
    # minimum along the yarn within that of the best may hide the true minimum
    slack = 2 * steps.max() ** 2 / max(overall, 1e-300) + 1e-3 * overall
    previous, following = np.roll(nearest, 1, axis=0), np.roll(nearest, -1, axis=0)
    if from_curve is not None:  # one open curve: its end samples have one neighbour
        previous[0] = following[-1] = np.inf
    local = (nearest <= previous) & (nearest <= following) & (nearest <= overall + slack)
    rows, columns = np.nonzero(local)
    shifts = np.array([images[k][0] for k in columns])
    partners = sampled.partners[columns, rows]
    offsets = np.array([images[k][1] * lattice[1] for k in columns])
    found, first, second = _refine(chain, chain, s[chosen][rows], s[partners] + shifts * n, offsets)
    best = int(np.argmin(found))
    return ChainClearance(
        float(found[best]),
        float(first[best]),
        float(second[best] - shifts[best] * n),
        images[columns[best]],
    )


def cell_clearance(
    yarns: list[tuple[BSplineCurve, ...]], lattice: np.ndarray, adjacent_arc: float
) -> CellClearance:
    """Smallest distance between the yarns of a periodic cell and their images i a1 + j a2,
    |i| <= 1, |j| <= 2 (and the non-adjacent parts of each yarn itself).

    Args:
        yarns: each yarn as the consecutive curves of one period along a1, each on [0, 1],
            all sharing degree and knots (mm).
        lattice: (2, 3) lattice vectors a1 (the yarns' period) and a2 (mm).
        adjacent_arc: parts of one yarn closer than this in arc length are skipped (mm).

    The same search as `chain_clearance` (sampled pairs, the local minima refined by Newton's
    method), over every pair of yarns.
    """
    lattice = np.asarray(lattice, dtype=float)
    chains, params, points, arcs, periods = [], [], [], [], []
    for yarn in yarns:
        chain = _Chain(tuple(yarn), lattice[0])
        n = len(yarn)
        s = (np.arange(n * _SAMPLES_PER_CURVE) + 0.5) / _SAMPLES_PER_CURVE
        sampled = chain.evaluate(s, _sample_basis(chain.degree, tuple(chain.knots), n))[0]
        steps = np.linalg.norm(np.diff(sampled, axis=0, append=sampled[:1] + lattice[0]), axis=1)
        chains.append(chain)
        params.append(s)
        points.append(sampled)
        arcs.append(np.concatenate([[0.0], np.cumsum(steps)[:-1]]))
        periods.append(steps.sum())
    spacing = max(np.linalg.norm(np.diff(p, axis=0), axis=1).max() for p in points)
    images = [(i, j) for j in range(-2, 3) for i in (-1, 0, 1)]
    offsets = np.array([i * lattice[0] + j * lattice[1] for i, j in images])
    best = CellClearance(np.inf, (0, 0), 0.0, 0.0, (0, 0))
    for m in range(len(yarns)):
        for n in range(m, len(yarns)):

            def block(k, m=m, n=n):
                """The nearest sample of image k of yarn n to each sample of yarn m."""
                i, j = images[k]
                along = m == n and j == 0  # the same yarn, i periods further on
                return _nearest_samples(
                    Samples(points[m], points[n], arcs[m], arcs[n]),
                    Images(
                        offsets[k : k + 1],
                        np.array([i * periods[n]]),
                        np.array([adjacent_arc if along else 0.0]),
                    ),
                )

            blocks = _near_images(
                block,
                _box_gaps(points[m], points[n], offsets),
                lambda overall: 2 * spacing**2 / max(overall, 1e-300) + 1e-3 * overall,
            )
            far = np.full(points[m].shape[0], np.inf)
            nearest = np.column_stack([far if b is None else b.distances[0] for b in blocks])
            overall = nearest.min()
            if not np.isfinite(overall):
                continue
            slack = 2 * spacing**2 / max(overall, 1e-300) + 1e-3 * overall
            local = (
                (nearest <= np.roll(nearest, 1, axis=0))
                & (nearest <= np.roll(nearest, -1, axis=0))
                & (nearest <= overall + slack)
            )
            rows, columns = np.nonzero(local)
            partners = np.array(
                [blocks[k].partners[0, a] for a, k in zip(rows, columns, strict=True)], dtype=int
            )
            found, first, second = _refine(
                chains[m],
                chains[n],
                params[m][rows],
                params[n][partners],
                offsets[columns],
            )
            if m == n:  # a refined pair may slide along the yarn onto an adjacent part
                shift = np.array([images[k][0] if images[k][1] == 0 else np.nan for k in columns])
                along = np.abs(
                    _arc_at(first, params[m], arcs[m], periods[m])
                    - _arc_at(second, params[m], arcs[m], periods[m])
                    - shift * periods[m]
                )
                found = np.where(along < adjacent_arc, np.inf, found)
            k = int(np.argmin(found))
            if not np.isfinite(found[k]):
                continue
            if found[k] < best.distance:
                best = CellClearance(
                    float(found[k]), (m, n), float(first[k]), float(second[k]), images[columns[k]]
                )
    return best


def _nearest_samples(samples: Samples, images: Images) -> Nearest:
    """The nearest sample of each image to each sample of a yarn (`_kernels.nearest_samples`,
    the samples taken a curve's at a time), (images, samples)."""
    shape = (images.shifts.size, samples.first.shape[0])
    nearest = Nearest(np.empty(shape), np.empty(shape, dtype=np.int64))
    nearest_samples(samples, images, _SAMPLES_PER_CURVE, nearest)
    return nearest


def _box_gaps(first: np.ndarray, second: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """A lower bound of the distance between the points `first` (a, 3) and each image of
    `second` (b, 3) shifted by `offsets` (k, 3): the gaps between their bounding boxes, less a
    round-off margin, (k,) (mm)."""
    low, high = first.min(axis=0), first.max(axis=0)
    shifted_low = second.min(axis=0) + offsets
    shifted_high = second.max(axis=0) + offsets
    gaps = np.maximum(np.maximum(shifted_low - high, low - shifted_high), 0.0)
    scale = np.abs(np.concatenate([first, second])).max() + np.abs(offsets).max()
    return np.maximum(np.linalg.norm(gaps, axis=1) - 1e-9 * scale, 0.0)


def _near_images(block, gaps: np.ndarray, slack) -> list[Nearest | None]:
    """The nearest samples of each image (`block(k)`), computed only for the images that can
    hold a pair within the search's reach, overall + slack(overall) (overall: the least sample
    distance); None for the others, whose distances all exceed it (their bounding boxes'
    `gaps` do). The least distance lies in the images no farther than the distance found in
    the nearest box, and an image beyond the reach has no local minimum the search takes: the
    search finds what it finds computing every image."""
    blocks: list[Nearest | None] = [None] * gaps.size

    def compute(chosen) -> float:
        for k in np.flatnonzero(chosen):
            if blocks[k] is None:
                blocks[k] = block(k)
        return min((found.distances.min() for found in blocks if found is not None), default=np.inf)

    found = compute(gaps == gaps.min())
    if not np.isfinite(found):
        compute(np.ones(gaps.size, dtype=bool))
        return blocks
    overall = compute(gaps <= found)
    compute(gaps <= overall + slack(overall))
    return blocks


def _arc_at(s: np.ndarray, params: np.ndarray, arcs: np.ndarray, period: float) -> np.ndarray:
    """Unwrapped arc coordinate (mm) at chain parameters s, interpolated between the samples
    (params, arcs) of one period of `params.size / _SAMPLES_PER_CURVE` curves."""
    curves = params.size // _SAMPLES_PER_CURVE
    turns = np.floor(s / curves)
    xp = np.concatenate([params - curves, params, params + curves])
    fp = np.concatenate([arcs - period, arcs, arcs + period])
    return np.interp(s - turns * curves, xp, fp) + turns * period


@cache
def _sample_basis(degree: int, knots: tuple[float, ...], curves: int) -> BasisValues:
    """Basis functions at the sample parameters of every curve (the same for each search)."""
    u = np.tile((np.arange(_SAMPLES_PER_CURVE) + 0.5) / _SAMPLES_PER_CURVE, curves)
    return basis_functions(np.array(knots), degree, u)


def _refine(
    first: _Chain, second: _Chain, s: np.ndarray, t: np.ndarray, offsets: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Local minima of |X(s) - Y(t) - offset| near each pair (s, t), X on the chain `first`,
    Y on `second` (the same chain for a yarn against its own images), offsets (k, 3) (mm).

    Newton's method (saddle-free: the Hessian's eigenvalues by their magnitudes) with a trust
    region of four sample spacings and step halving: nearly parallel or wrapping yarns make
    the distance flat along a valley, so a minimum may lie several samples away from its
    sampled pair. A yarn wrapping around another at about the distance gives long, curved
    valleys in which steepest descent crawls; where the distance is convex the step is
    Newton's. Compiled, pair by pair (`rve_rod.geometry._kernels.refine_pairs`). Returns
    (distances, s, t), each of shape (k,).
    """
    pairs = Pairs(
        s.astype(float),
        t.astype(float),
        np.ascontiguousarray(offsets.T, dtype=float),
        np.empty(s.size),
    )
    refine_pairs(first.arrays, second.arrays, pairs, 4.0 / _SAMPLES_PER_CURVE, _NEWTON_ITERATIONS)
    return pairs.distances, pairs.first, pairs.second
