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

from typing import NamedTuple

import numpy as np

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
    """Evaluation of the master strands by unwrapped reference arc coordinate.

    Args:
        layout: the contact layout.
        points: (n, 3) control points (mm).
        translations: callable mapping images (k, 2) to their translations F L, (k, 3) (mm).
    """

    def __init__(self, layout: ContactLayout, points: np.ndarray, translations):
        self.layout = layout
        self.span_points = layout.span_points(points)
        self.translations = translations
        length = layout.yarn_length
        self._yarn_offset = np.concatenate([[0.0], np.cumsum(length + 1.0)[:-1]])
        keys = self._yarn_offset[layout.span_yarn] + layout.span_arc_start
        self._order = np.argsort(keys, kind="stable")
        self._keys = keys[self._order]

    def locate(self, yarn, reference_image, reference_arc, arc):
        """Span, tau and image (k, 2) of the points at unwrapped arc coordinates `arc` on the
        strands through the reference points (yarn, image, arc), all (k,)."""
        layout = self.layout
        length = layout.yarn_length[yarn]
        period = layout.yarn_period[yarn]
        periodic = np.any(period != 0, axis=1)
        turns = np.where(periodic, np.floor(arc / length), 0.0)
        reference_turns = np.where(periodic, np.floor(reference_arc / length), 0.0)
        local = np.clip(arc - turns * length, 0.0, length)
        position = np.searchsorted(self._keys, self._yarn_offset[yarn] + local, side="right") - 1
        span = self._order[np.clip(position, 0, self._keys.size - 1)]
        span = np.where(layout.span_yarn[span] == yarn, span, self._first_span(yarn))
        tau = np.clip(
            (local - layout.span_arc_start[span]) / layout.span_arc_length[span], 0.0, 1.0
        )
        image = reference_image + (turns - reference_turns).astype(np.int64)[:, None] * period
        return span, tau, image

    def _first_span(self, yarn):
        starts = np.searchsorted(self._keys, self._yarn_offset[yarn], side="left")
        return self._order[np.clip(starts, 0, self._keys.size - 1)]

    def evaluate(self, span, tau, image, values_only=False):
        """Point, d/dtau and d2/dtau2 of the master curve, each (3, k), images translated
        (the point alone if values_only)."""
        values = [
            np.einsum("ka,kac->ck", self.layout.basis(span, tau, order), self.span_points[span])
            for order in range(1 if values_only else 3)
        ]
        values[0] = values[0] + self.translations(image).T
        return values[0] if values_only else values


def separating_maxima(
    geometry: StrandGeometry,
    slave_points: np.ndarray,
    left: StrandPoints,
    right: StrandPoints,
) -> StrandPoints:
    """The largest distance maximum between neighbouring minima `left` and `right` on a strand.

    The distance from the slave point is sampled at `_SAMPLES` interior arc coordinates; the
    largest sample's neighbours bracket a maximum, found by safeguarded Newton on the slope of
    |x_m - x_s|^2 / 2 in the arc coordinate (bisection whenever a step would leave the bracket).
    """
    layout = geometry.layout
    yarn = layout.span_yarn[left.span]
    start, stop = left.arc, right.arc
    x_s = slave_points[:, left.slave]

    fractions = np.arange(_SAMPLES + 2) / (_SAMPLES + 1)
    samples = start[None, :] + fractions[:, None] * (stop - start)[None, :]  # (S + 2, k)
    k = start.size
    repeat = np.tile(np.arange(k), _SAMPLES)
    span, tau, image = geometry.locate(
        yarn[repeat], left.image[repeat], start[repeat], samples[1:-1].ravel()
    )
    point = geometry.evaluate(span, tau, image, values_only=True)
    values = np.sum((point - x_s[:, repeat]) ** 2, axis=0).reshape(_SAMPLES, k)
    best = 1 + np.argmax(values, axis=0)
    columns = np.arange(start.size)
    low = samples[best - 1, columns]
    high = samples[best + 1, columns]
    arc = samples[best, columns]
    tolerance = 1e-12 * (1.0 + np.abs(start))
    for _ in range(_MAX_ITERATIONS):
        span, tau, image = geometry.locate(yarn, left.image, start, arc)
        point, first, second = geometry.evaluate(span, tau, image)
        scale = 1.0 / layout.span_arc_length[span]
        offset = point - x_s
        slope = np.sum(offset * first, axis=0) * scale
        curvature = (np.sum(first * first, axis=0) + np.sum(offset * second, axis=0)) * scale**2
        low = np.where(slope >= 0.0, arc, low)
        high = np.where(slope >= 0.0, high, arc)
        safe_curvature = np.where(curvature < 0.0, curvature, -1.0)
        step = np.where(curvature < 0.0, arc - slope / safe_curvature, np.nan)
        inside = (step > low) & (step < high)
        step = np.where(inside, step, 0.5 * (low + high))
        done = np.abs(step - arc) <= tolerance
        arc = step
        if np.all(done):
            break
    span, tau, image = geometry.locate(yarn, left.image, start, arc)
    point = geometry.evaluate(span, tau, image, values_only=True)
    gap = x_s - point
    distance = np.linalg.norm(gap, axis=0)
    return StrandPoints(
        slave=left.slave,
        span=span,
        tau=tau,
        image=image,
        arc=arc,
        strand=left.strand,
        distance=distance,
        normal=gap / distance,
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
    capped_minimum = np.minimum(minima.distance, touch)
    capped_maximum = np.minimum(maxima.distance, touch)
    region = np.concatenate([[0], np.cumsum(~linked)])  # region of each sorted position
    size = np.bincount(region)
    starts = np.concatenate([[0], np.cumsum(size)[:-1]])
    gap_pair = np.full(max(k - 1, 0), -1)
    gap_pair[pairs] = np.arange(pairs.size)
    weight_terms = []  # (weighted minimum, stationary points, their indices, dw/dh)
    shared = 0
    for first, count in zip(starts[size > 1], size[size > 1], strict=True):
        shared += int(count)
        members = order[first : first + count]
        gaps = gap_pair[first : first + count - 1]
        prominence, derivative = prominences(capped_minimum[members], capped_maximum[gaps], touch)
        power = prominence**2
        total = power.sum()
        if total <= 0.0:
            weight[members] = 1.0 / count
            continue
        weight[members] = power / total
        # dw_i/dp_j = (delta_ij - w_i) 2 p_j / total; chained to the capped distances.
        dw_dp = (np.eye(count) - (power / total)[:, None]) * (2.0 * prominence / total)[None, :]
        dw_dh = dw_dp @ derivative  # (count, 2 count - 1): minima, then maxima
        for i in range(count):
            weight_terms.append((members[i], minima, members, dw_dh[i, :count]))
            weight_terms.append((members[i], maxima, gaps, dw_dh[i, count:]))
    # h(d) = min(d, 2r) changes only where the stationary point penetrates.
    terms = []
    for contact, points, index, coefficient in weight_terms:
        moving = (points.distance[index] < touch) & (coefficient != 0.0)
        terms.append(
            (np.full(np.count_nonzero(moving), contact), points, index[moving], coefficient[moving])
        )
    if not terms:
        return RegionWeights(weight, WeightTerms.empty(), shared)
    return RegionWeights(
        weight=weight,
        terms=WeightTerms(
            contact=np.concatenate([contact for contact, _, _, _ in terms]),
            span=np.concatenate([points.span[index] for _, points, index, _ in terms]),
            tau=np.concatenate([points.tau[index] for _, points, index, _ in terms]),
            image=np.concatenate([points.image[index] for _, points, index, _ in terms]),
            normal=np.concatenate([points.normal[:, index] for _, points, index, _ in terms], 1),
            coefficient=np.concatenate([value for _, _, _, value in terms]),
        ),
        shared=shared,
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
            depth = lower[j] - minima[j]  # q_j
            row = np.zeros(2 * n - 1)
            row[i] = -1.0
            row[n + barrier_gap] = 1.0
            step = 0.0
            if rise > 0.0 and depth <= rise:
                step = 1.0
            elif rise > 0.0:
                x = rise / depth
                step = x * x * (3.0 - 2.0 * x)
                slope = 6.0 * x * (1.0 - x) * (touch - barrier)  # d/dx of (2r - B) S
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
