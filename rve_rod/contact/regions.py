"""Contact regions: the distance minima of one slave point on one strand that share one contact.

A slave point next to a yarn that wraps tightly around it has a distance to that yarn that is
nearly constant along an arc, hence several close local minima. They appear and vanish in pairs
(fold bifurcation: a minimum is born together with a maximum at the same point), so counting
each minimum as a full contact makes the point's load jump when a pair appears, and Newton
cycles. Instead, the minima of one slave point on one strand whose reference arc coordinates
lie within `window` of their neighbour's form a region and share one contact: minimum i gets
the weight

    w_i = p_i^2 / sum_j p_j^2   (sum over the region),

p_i its prominence measured in penetration, with h(d) = min(d, 2r) (`prominences`): the climb
from i to the nearest deeper minimum of the region (over the highest maximum between them),
or to 2r if there is none, made smooth where two minima are equally deep and continuous where a
minimum vanishes. A newborn minimum coincides with its maximum (p = 0) and enters with weight
0; two equal minima share equally; a minimum that does not penetrate has p = 0; the weights of
a region sum to one. A region of one minimum has weight 1 (the contact as before). If no
minimum of a region penetrates, its weights are 1/n (its loads are 0). The prominence taken
against the lower neighbouring maximum alone (the definition before) jumps when a neighbouring
minimum vanishes with the maximum between them; on the free-fibre cell in shear that stopped
the run at 10 % (docs/contact.md).

Derivatives. Distances at stationary points (minima and maxima) change with the positions at
fixed parameter (envelope theorem): dd_q = n_q.(dx_s - dx_q), n_q = (x_s - x_q) / d_q, x_q the
stationary point on the master (with its image translation F L_q). So dw_i = sum_q c_iq dd_q,
where c_iq = dw_i/dd_q (`WeightTerms`), over the minima and maxima of i's region.
"""

import functools
from typing import NamedTuple

import numpy as np

from rve_rod.contact import _kernels
from rve_rod.contact.layout import ContactLayout

__all__ = [
    "RegionWeights",
    "StrandGeometry",
    "StrandPoints",
    "WeightTerms",
    "region_weights",
]

_SAMPLES = 16
"""Interior samples of the distance between two neighbouring minima, to bracket the maximum."""

_MAX_ITERATIONS = 60


class StrandPoints(NamedTuple):
    """Points on the master strands (arrays over k points).

    Attributes:
        slave: (k,) collocation point the distance is measured from.
        span: (k,) master span; tau: (k,) local span parameter.
        image: (k, 2) lattice image of the master point.
        arc: (k,) unwrapped reference arc coordinate of the master point on its strand (mm).
        strand: (k,) strand key of the master.
        distance: (k,) d = |x_s - x_m| (mm).
        normal: (3, k) n = (x_s - x_m) / d.
    """

    slave: np.ndarray
    span: np.ndarray
    tau: np.ndarray
    image: np.ndarray
    arc: np.ndarray
    strand: np.ndarray
    distance: np.ndarray
    normal: np.ndarray

    def subset(self, rows: np.ndarray) -> "StrandPoints":
        """The points `rows` (an index array)."""
        return StrandPoints(*(field[rows] for field in self[:-1]), normal=self.normal[:, rows])


class WeightTerms(NamedTuple):
    """Derivative terms of the weights: dw_contact += coefficient * n.(dx_s - dx_q).

    Attributes:
        contact: (t,) index of the weighted minimum (into the minima given to region_weights).
        span, tau: (t,) master point x_q of the stationary distance the term differentiates.
        image: (t, 2) lattice image of x_q.
        normal: (3, t) n_q.
        coefficient: (t,) dw / dd_q (1/mm).
    """

    contact: np.ndarray
    span: np.ndarray
    tau: np.ndarray
    image: np.ndarray
    normal: np.ndarray
    coefficient: np.ndarray

    @classmethod
    def empty(cls) -> "WeightTerms":
        none = np.zeros(0, dtype=np.int64)
        return cls(
            none, none, np.zeros(0), np.zeros((0, 2), np.int64), np.zeros((3, 0)), np.zeros(0)
        )


class RegionWeights(NamedTuple):
    """Weights of the distance minima of one evaluation.

    Attributes:
        weight: (k,) w_i in [0, 1]; 1 for a minimum alone in its region.
        terms: their derivatives.
        shared: minima in regions of more than one minimum.
    """

    weight: np.ndarray
    terms: WeightTerms
    shared: int


class StrandGeometry:
    """The master strands by unwrapped reference arc coordinate, as the kernels take them.

    Args:
        layout: the contact layout.
        coefficients: (3, p+1, S) power-basis coefficients of the spans at the control points'
            positions (`ContactLayout.coefficients`) (mm).
        image_vectors: (2, 3) the deformed lattice vectors F a1, F a2 (mm): image (i, j) is
            translated by i F a1 + j F a2 (zeros without a lattice).

    Attributes:
        layout: as given.
        arcs: the `_kernels.StrandArcs` record.
    """

    def __init__(self, layout: ContactLayout, coefficients: np.ndarray, image_vectors: np.ndarray):
        self.layout = layout
        self._coefficients = coefficients
        self._image_vectors = image_vectors

    @functools.cached_property
    def arcs(self) -> _kernels.StrandArcs:
        """The kernels' record (made on first use: most evaluations need no maximum)."""
        layout = self.layout
        length = layout.yarn_length
        yarn_offset = np.concatenate([[0.0], np.cumsum(length + 1.0)[:-1]])
        keys = yarn_offset[layout.span_yarn] + layout.span_arc_start
        order = np.argsort(keys, kind="stable")
        keys = keys[order]
        first = np.searchsorted(keys, yarn_offset, side="left")
        return _kernels.StrandArcs(
            coefficients=np.ascontiguousarray(self._coefficients),
            span_yarn=layout.span_yarn,
            span_arc_start=layout.span_arc_start,
            span_arc_length=layout.span_arc_length,
            keys=keys,
            order=order.astype(np.int64),
            yarn_offset=yarn_offset,
            yarn_length=length,
            yarn_period=layout.yarn_period,
            yarn_first_span=order[np.clip(first, 0, keys.size - 1)].astype(np.int64),
            image_vectors=np.ascontiguousarray(self._image_vectors, dtype=float),
        )


def separating_maxima(
    geometry: StrandGeometry,
    slave_points: np.ndarray,
    left: StrandPoints,
    right: StrandPoints,
) -> StrandPoints:
    """The largest distance maximum between neighbouring minima `left` and `right` on a strand.

    The distance from the slave point is sampled at `_SAMPLES` interior arc coordinates; the
    largest sample's neighbours bracket a maximum, found by safeguarded Newton on the slope of
    |x_m - x_s|^2 / 2 in the arc coordinate (bisection whenever a step would leave the bracket;
    `_kernels.separating_maxima`).
    """
    k = left.slave.size
    pairs = _kernels.StrandPairs(
        slave_points=np.ascontiguousarray(slave_points[:, left.slave]),
        yarn=geometry.layout.span_yarn[left.span],
        image=np.ascontiguousarray(left.image, dtype=np.int64),
        start=np.ascontiguousarray(left.arc, dtype=float),
        stop=np.ascontiguousarray(right.arc, dtype=float),
    )
    out = _kernels.StrandLocations(
        span=np.empty(k, dtype=np.int64),
        tau=np.empty(k),
        image=np.empty((k, 2), dtype=np.int64),
        arc=np.empty(k),
        distance=np.empty(k),
        normal=np.empty((3, k)),
    )
    _kernels.separating_maxima(geometry.arcs, pairs, _SAMPLES, _MAX_ITERATIONS, out)
    return StrandPoints(
        slave=left.slave,
        span=out.span,
        tau=out.tau,
        image=out.image,
        arc=out.arc,
        strand=left.strand,
        distance=out.distance,
        normal=out.normal,
    )


def _far(points: StrandPoints) -> StrandPoints:
    """Copies of points at infinite distance."""
    return StrandPoints(
        *(np.array(field, copy=True) for field in points[:-2]),
        distance=np.full(points.distance.size, np.inf),
        normal=np.zeros_like(points.normal),
    )


def region_weights(
    geometry: StrandGeometry,
    slave_points: np.ndarray,
    minima: StrandPoints,
    radius: float,
    window: float,
) -> RegionWeights:
    """Weights of the distance minima (see the module docstring) and their derivative terms.

    Args:
        geometry: the master strands in the current configuration.
        slave_points: (3, m) collocation points (mm).
        minima: the distance minima of the evaluation.
        radius: yarn radius r (mm); penetration starts at d = 2r.
        window: largest reference arc distance between neighbouring minima of a region (mm).
    """
    k = minima.slave.size
    order = np.lexsort((minima.arc, minima.strand, minima.slave))
    linked = (
        (minima.slave[order[1:]] == minima.slave[order[:-1]])
        & (minima.strand[order[1:]] == minima.strand[order[:-1]])
        & (minima.arc[order[1:]] - minima.arc[order[:-1]] < window)
    )
    weight = np.ones(k)
    if not np.any(linked):
        return RegionWeights(weight, WeightTerms.empty(), 0)
    pairs = np.flatnonzero(linked)
    left, right = order[pairs], order[pairs + 1]
    touch = 2.0 * radius
    # A maximum between two minima that do not penetrate changes no prominence (both are 0):
    # it is searched only next to a penetrating minimum, else taken as infinitely far.
    needed = (minima.distance[left] < touch) | (minima.distance[right] < touch)
    maxima = _far(minima.subset(left))
    if np.any(needed):
        found = separating_maxima(
            geometry,
            slave_points,
            minima.subset(left[needed]),
            minima.subset(right[needed]),
        )
        for field, values in zip(maxima[:-1], found[:-1], strict=True):
            field[needed] = values
        maxima.normal[:, needed] = found.normal
    region = np.concatenate([[0], np.cumsum(~linked)])  # region of each sorted position
    size = np.bincount(region)
    starts = np.concatenate([[0], np.cumsum(size)[:-1]])
    gap_pair = np.full(k, -1)
    gap_pair[pairs] = np.arange(pairs.size)
    shared = size > 1
    regions = np.stack([starts[shared], size[shared]]).astype(np.int64)
    capacity = int(np.sum(size[shared] * (2 * size[shared] - 1)))
    out = _kernels.RegionTerms(
        contact=np.empty(capacity, dtype=np.int64),
        kind=np.empty(capacity, dtype=np.int64),
        index=np.empty(capacity, dtype=np.int64),
        coefficient=np.empty(capacity),
    )
    count = _kernels.region_weights(
        (minima.distance, maxima.distance),
        _kernels.Regions(order, gap_pair, regions),
        touch,
        weight,
        out,
    )
    contact, kind, index, coefficient = (field[:count] for field in out)
    stationary = np.where(kind == 1, k + index, index)  # into the minima, then the maxima
    return RegionWeights(
        weight=weight,
        terms=WeightTerms(
            contact=contact,
            span=np.concatenate([minima.span, maxima.span])[stationary],
            tau=np.concatenate([minima.tau, maxima.tau])[stationary],
            image=np.concatenate([minima.image, maxima.image])[stationary],
            normal=np.concatenate([minima.normal, maxima.normal], axis=1)[:, stationary],
            coefficient=coefficient,
        ),
        shared=int(size[shared].sum()),
    )


def prominences(minima: np.ndarray, maxima: np.ndarray, touch: float):
    """Prominences of the minima of one region and their derivatives.

    Args:
        minima: (n,) capped distances h_i = min(d_i, 2r) of the minima in arc order (mm).
        maxima: (n-1,) capped distances of the maxima between neighbouring minima (mm).
        touch: 2r (mm).

    Returns p (n,) and dp/dh (n, 2n-1): columns the minima, then the maxima.

    p_i = min(2r - h_i, min over j != i of t_ij),  t_ij = B_ij - h_i + (2r - B_ij) S(x_ij):
    B_ij the highest maximum between i and j (the barrier to climb from i to j); x_ij =
    (h_j - h_i) / q_j how much shallower j is than i, in units of q_j = A_j - h_j, j's own
    depth below its lower neighbouring maximum A_j; S the smooth step (0 for x <= 0,
    3x^2 - 2x^3 on [0, 1], 1 beyond). A deeper or equal j caps i's prominence at the barrier
    to it (the topographic prominence: the climb to the nearest deeper minimum, or to 2r); a
    j shallower by q_j or more does not cap it; in between the cap rises smoothly. So the
    prominence is continuous, with a continuous slope, where two minima are equally deep
    (S = S' = 0) and when a minimum vanishes with its neighbouring maximum (q_j -> 0 makes
    S = 1 for every deeper i, so j stops capping others before it disappears, while its own
    p_j <= q_j -> 0). Kinks remain where two caps of a minimum cross (three or more minima).
    """
    n = minima.size
    p = np.empty(n)
    derivative = np.empty((n, 2 * n - 1))
    _kernels.prominences(
        np.ascontiguousarray(minima, dtype=float),
        np.ascontiguousarray(maxima, dtype=float),
        float(touch),
        p,
        derivative,
    )
    return p, derivative
