"""The single-jersey loop: a three-section quarter, mirrored into one periodic loop of 4 B-splines.

Construction (docs/geometry.md has the derivation and a figure). Axis x is course-wise (period
w, wale width), y wale-wise (period c, course height), z out of plane. A quarter of the yarn
centreline runs from the apex of the needle-loop head A = (0, h) to the leg point L = (w/4, 0)
where the loop crosses its mid-height. In the x/y projection it is made of three tangent-
continuous sections:

1. the crown, a circular arc of radius rho1 centred on x = 0, from A;
2. the shoulder, a circular arc of radius rho2 = 1.25 r whose outermost point lies at
   x = w/4 + r (so that the shoulder clears the sinker loop of the neighbouring wale by 2r);
   rho1 follows from the internal tangency of the two circles;
3. the leg, the straight line from the shoulder tangent to L.

Out of plane the yarn follows z = delta (1/2 - (y/h)^2): the heads and sinker loops lie behind
(z = -delta/2), the legs in front (z = delta/2) where they cross the heads of the neighbouring
courses. The head height h is the free shape parameter; for each h the depth delta is the
smallest one for which the yarn clears the loops of the courses above and below by 2r, and h
is chosen to minimize the loop length (the condition is then active: clearance = 2r where the
yarns touch).

The quarter is fitted by a degree-4 B-spline with 12 control points (least squares in arc
length, with the end conditions that make the mirrored loop C2) and mirrored by the loop's two
symmetries, x -> -x (about the head apex) and (x, y) -> (w/2 - x, -y) (about L), into the 4
curves of one loop from sinker to sinker. Each curve is parametrized on [0, 1]; the loop runs
through curve 0, 1, 2, 3 and continues into curve 0 of the next wale shifted by (w, 0, 0).
"""

import logging
import math
from dataclasses import dataclass
from functools import cache, lru_cache
from typing import NamedTuple

import numpy as np
import scipy.optimize

from rve_rod.errors import InputError, check_integer, check_positive
from rve_rod.geometry.bspline import BSplineCurve, basis_matrix, open_knot_vector
from rve_rod.geometry.proximity import ChainClearance, chain_clearance
from rve_rod.presets import Knit

logger = logging.getLogger(__name__)

DEGREE = 4
"""Degree of the loop curves (the paper's geometry)."""
CONTROL_POINTS = 12
"""Control points of each quarter curve before refinement."""
SHOULDER_RADIUS_FACTOR = 1.25
"""rho2 / r, a model constant (not a shape parameter): 1.15 to 1.35 change the loop length by
at most 1 % (docs/geometry.md), while rho2 = r makes the loop 8-10 % longer."""
ADJACENT_ARC_FACTOR = math.pi
"""Parts of the same yarn closer than this times r in arc length are adjacent, not in contact."""
_FIT_SAMPLES = 121
_HEIGHT_SCAN = 10
_POLYLINE_SAMPLES = 60
_CLEARANCE_TOLERANCE = 1e-4
"""Relative shortfall of 2r accepted where yarns touch (0.01 %, the issue allows 0.1 %)."""
_SECTION_SAMPLES = 400


@dataclass(frozen=True)
class LoopShape:
    """The analytic quarter loop (all lengths in mm).

    Attributes:
        wale_width: w.
        course_height: c.
        yarn_radius: r (already adjusted: r <= w/8).
        head_height: h, the y of the head apex (the free shape parameter).
        depth: delta, the out-of-plane amplitude (z from -delta/2 to delta/2).
    """

    wale_width: float
    course_height: float
    yarn_radius: float
    head_height: float
    depth: float

    @property
    def shoulder_radius(self) -> float:
        return SHOULDER_RADIUS_FACTOR * self.yarn_radius

    def projection(self) -> np.ndarray | None:
        """Dense x/y points of the quarter from A to L, shape (k, 2); None if it does not exist.

        Angles are measured clockwise from +y: a point of a circle of centre C and radius rho at
        angle t is C + rho (sin t, cos t), and the quarter turns clockwise from A towards L.
        """
        w, c, r, h = self.wale_width, self.course_height, self.yarn_radius, self.head_height
        rho2 = self.shoulder_radius
        shoulder_x = w / 4 + r - rho2  # the shoulder's outermost point is at x = w/4 + r
        rise = h - c / 2  # the shoulder centre sits at mid course height
        if shoulder_x <= 0 or rise <= rho2:
            return None
        rho1 = (shoulder_x**2 + rise**2 - rho2**2) / (2 * (rise - rho2))
        crown_centre = np.array([0.0, h - rho1])
        shoulder_centre = np.array([shoulder_x, c / 2])
        a1 = math.atan2(shoulder_x, c / 2 - crown_centre[1])
        to_leg = np.array([w / 4, 0.0]) - shoulder_centre
        distance = float(np.hypot(*to_leg))
        if distance <= rho2:
            return None
        # tangent from the shoulder circle through L: (L - C2) . (sin a2, cos a2) = rho2, with
        # L ahead along the clockwise tangent (cos a2, -sin a2); the first such angle after a1
        candidates = []
        for sign in (1.0, -1.0):
            angle = math.atan2(to_leg[0], to_leg[1]) + sign * math.acos(rho2 / distance)
            angle = a1 + (angle - a1) % (2 * math.pi)
            ahead = to_leg - rho2 * np.array([math.sin(angle), math.cos(angle)])
            if ahead @ np.array([math.cos(angle), -math.sin(angle)]) > 0:
                candidates.append(angle)
        if not candidates or min(candidates) > math.pi:
            return None
        a2 = min(candidates)
        t1 = np.linspace(0.0, a1, _SECTION_SAMPLES)
        t2 = np.linspace(a1, a2, _SECTION_SAMPLES)[1:]
        crown = crown_centre + rho1 * np.stack([np.sin(t1), np.cos(t1)], axis=1)
        shoulder = shoulder_centre + rho2 * np.stack([np.sin(t2), np.cos(t2)], axis=1)
        tangent_point = shoulder[-1]
        s = np.linspace(0.0, 1.0, _SECTION_SAMPLES)[1:, None]
        leg = tangent_point + s * (np.array([w / 4, 0.0]) - tangent_point)
        return np.concatenate([crown, shoulder, leg])

    def quarter_samples(self, fractions: np.ndarray) -> "QuarterSamples | None":
        """Points of the 3D quarter at fractions of its arc length, and where the shoulder
        reaches x = w/4 + r (the built-in contacts: docs/geometry.md)."""
        plane = self.projection()
        if plane is None:
            return None
        z = self.depth * (0.5 - (plane[:, 1] / self.head_height) ** 2)
        points = np.column_stack([plane, z])
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
        targets = fractions * arc[-1]
        samples = np.stack([np.interp(targets, arc, points[:, k]) for k in range(3)], axis=1)
        outermost = int(np.argmax(plane[:, 0]))
        shoulder = np.array([plane[outermost, 0], plane[outermost, 1], z[outermost]])
        return QuarterSamples(samples, arc[outermost] / arc[-1], shoulder)


class QuarterSamples(NamedTuple):
    """The analytic quarter sampled for the B-spline fit.

    Attributes:
        points: (m, 3) points at the requested arc-length fractions (mm).
        shoulder_fraction: arc-length fraction of the shoulder's outermost point.
        shoulder: (3,) that point, (w/4 + r, c/2, z) (mm).
    """

    points: np.ndarray
    shoulder_fraction: float
    shoulder: np.ndarray


@dataclass(frozen=True, eq=False)
class LoopGeometry:
    """One single-jersey loop as 4 B-spline curves (lengths in mm).

    Attributes:
        wale_width: w, period along x.
        course_height: c, period along y.
        minimal_radius: r0 as given.
        yarn_radius: r = min(r0, w/8), the radius the model uses.
        radius_adjusted: whether r < r0.
        shape_parameter: the head height h (mm), chosen to minimize the loop length.
        depth: delta, out-of-plane amplitude (mm), from the clearance condition.
        curves: the 4 curves of one loop (degree 4, 12 control points each, on [0, 1]).
        loop_length: length of the B-spline loop (mm).
        min_clearance: smallest centreline distance to the periodic neighbours and to the
            non-adjacent parts of the loop itself (mm); 2r where yarns touch.
        closest: where that distance occurs.
        lattice: (2, 3) lattice vectors [(w, 0, 0), (0, c, 0)].
    """

    wale_width: float
    course_height: float
    minimal_radius: float
    yarn_radius: float
    radius_adjusted: bool
    shape_parameter: float
    depth: float
    curves: tuple[BSplineCurve, ...]
    loop_length: float
    min_clearance: float
    closest: ChainClearance
    lattice: np.ndarray

    def refined(self, control_points: int) -> tuple[BSplineCurve, ...]:
        """The 4 curves h-refined to `control_points` each, unchanged in shape.

        The quarter has 8 knot spans; `control_points` - 4 must be a multiple of 8
        (e.g. 12, 20, 36, 68, 132), so that every span is split into equal parts.
        """
        check_integer("control_points", control_points, CONTROL_POINTS)
        spans = control_points - DEGREE
        base_spans = CONTROL_POINTS - DEGREE
        if spans % base_spans:
            raise InputError(
                f"control_points={control_points}: control_points - {DEGREE} must be a "
                f"multiple of {base_spans} (e.g. 12, 20, 36, 68, 132)"
            )
        return tuple(curve.subdivide(spans // base_spans) for curve in self.curves)

    def to_dict(self) -> dict:
        """Scalars of the loop for JSON reports (control points per curve as lists)."""
        return {
            "wale_width": self.wale_width,
            "course_height": self.course_height,
            "minimal_radius": self.minimal_radius,
            "adjusted_radius": self.yarn_radius,
            "radius_adjusted": self.radius_adjusted,
            "shape_parameter": self.shape_parameter,
            "depth": self.depth,
            "loop_length": self.loop_length,
            "min_clearance": self.min_clearance,
            "clearance_over_diameter": self.min_clearance / (2 * self.yarn_radius),
            "closest_image": list(self.closest.image),
            "control_points": [curve.control_points.tolist() for curve in self.curves],
        }


def loop_polylines(geometry: LoopGeometry, neighbours: int = 1) -> list[tuple[tuple, np.ndarray]]:
    """The loop and its periodic images as ((i, j), points (m, 3)) pairs, one loop each (mm)."""
    u = np.linspace(0.0, 1.0, _POLYLINE_SAMPLES)
    loop = np.vstack([curve(u if k == 0 else u[1:]) for k, curve in enumerate(geometry.curves)])
    span = range(-neighbours, neighbours + 1)
    return [
        ((i, j), loop + i * geometry.lattice[0] + j * geometry.lattice[1])
        for j in span
        for i in span
    ]


def adjusted_radius(minimal_radius: float, wale_width: float) -> float:
    """r = min(r0, w/8): the yarn radius the loop model can accommodate (mm)."""
    return min(minimal_radius, wale_width / 8.0)


def loop_geometry(knit: Knit, minimal_radius: float) -> LoopGeometry:
    """The loop of a knit (wale width, course height) with yarn radius r0 (mm)."""
    return single_jersey_loop(knit.wale_width, knit.course_height, minimal_radius)


@lru_cache(maxsize=64)
def single_jersey_loop(
    wale_width: float,
    course_height: float,
    minimal_radius: float,
    head_height: float | None = None,
) -> LoopGeometry:
    """Build the minimum-length loop for wale width w, course height c, yarn radius r0 (mm).

    With `head_height` (mm) the shape parameter is given instead of optimized (the depth still
    follows from the clearance condition). Takes about a second; results are remembered per
    process (they are immutable), since the RVE runs of one fabric all use the same loop.
    Raises InputError for non-positive or non-finite values and when no loop fits.
    """
    w = check_positive("wale_width", wale_width, "mm")
    c = check_positive("course_height", course_height, "mm")
    r0 = check_positive("yarn_radius", minimal_radius, "mm")
    r = adjusted_radius(r0, w)
    if r < r0:
        logger.info("yarn radius adjusted from r0 = %.4g mm to w/8 = %.4g mm", r0, r)
    lattice = np.array([[w, 0.0, 0.0], [0.0, c, 0.0]])

    depths: dict[float, float] = {}

    def length_for(height: float) -> float:
        guess = depths[min(depths, key=lambda h: abs(h - height))] if depths else None
        try:
            depths[height] = _depth_for_clearance(w, c, r, height, lattice, guess=guess)
        except InputError:
            return math.inf  # no depth clears the neighbours at this head height
        return 4 * _loop_curves(LoopShape(w, c, r, height, depths[height]))[2].arc_length()

    if head_height is not None:
        height = check_positive("head_height", head_height, "mm")
        depth = _depth_for_clearance(w, c, r, height, lattice)
    else:
        height = _shortest_head_height(w, c, r, length_for)
        depth = (
            depths[height] if height in depths else _depth_for_clearance(w, c, r, height, lattice)
        )
    curves = _loop_curves(LoopShape(w, c, r, height, depth))
    closest = chain_clearance(curves, lattice, ADJACENT_ARC_FACTOR * r)
    return LoopGeometry(
        wale_width=w,
        course_height=c,
        minimal_radius=r0,
        yarn_radius=r,
        radius_adjusted=r < r0,
        shape_parameter=height,
        depth=depth,
        curves=curves,
        loop_length=4 * curves[2].arc_length(),
        min_clearance=closest.distance,
        closest=closest,
        lattice=lattice,
    )


def _shortest_head_height(w: float, c: float, r: float, length_for) -> float:
    """The head height of the shortest loop: a scan, then Brent's method around its best point."""
    lowest = c / 2 + SHOULDER_RADIUS_FACTOR * r
    grid = lowest + r * np.linspace(0.02, 2.5, _HEIGHT_SCAN)
    lengths = np.array([length_for(height) for height in grid])
    if not np.isfinite(lengths).any():
        raise InputError(
            f"no loop fits: with yarn_radius={r:.4g} mm no loop clears its neighbours for "
            f"wale_width={w:.4g} mm and course_height={c:.4g} mm"
        )
    best = int(np.argmin(lengths))
    bracket = (grid[max(best - 1, 0)], grid[min(best + 1, grid.size - 1)])
    optimum = scipy.optimize.minimize_scalar(
        length_for, bounds=bracket, method="bounded", options={"xatol": 1e-4 * r}
    )
    return float(optimum.x) if optimum.fun <= lengths[best] else float(grid[best])


def _depth_for_clearance(
    w: float, c: float, r: float, height: float, lattice, *, guess: float | None = None
) -> float:
    """Smallest depth delta for which the loop clears all its neighbours by 2r (mm).

    The construction has contacts at exactly 2r built in (shoulder against the sinker loop of
    the course above, and against the next wale's head when r = w/8), so the clearance is at
    most 2r and the depth is the edge of the set where it equals 2r: found by bisection to
    1e-4 r, bracketed around `guess` when one is given.
    """

    def clears(depth: float) -> bool:
        curves = _loop_curves(LoopShape(w, c, r, height, depth))
        distance = chain_clearance(curves, lattice, ADJACENT_ARC_FACTOR * r).distance
        return distance >= 2 * r * (1 - _CLEARANCE_TOLERANCE)

    low, high = 0.5 * r, 12.0 * r
    if guess is not None and clears(min(guess + 0.2 * r, high)):
        high = min(guess + 0.2 * r, high)
        if not clears(max(guess - 0.2 * r, low)):
            low = max(guess - 0.2 * r, low)
    if not clears(high):
        raise InputError(
            f"no loop fits: with yarn_radius={r:.4g} mm no loop of head height {height:.4g} mm "
            f"clears its neighbours for wale_width={w:.4g} mm, course_height={c:.4g} mm"
        )
    if clears(low):
        return low
    while high - low > 1e-4 * r:
        middle = 0.5 * (low + high)
        low, high = (low, middle) if clears(middle) else (middle, high)
    return high


def _loop_curves(shape: LoopShape) -> tuple[BSplineCurve, ...]:
    quarter = _fit_quarter(shape)
    return mirrored_loop(quarter, shape.wale_width)


def mirrored_loop(quarter: BSplineCurve, wale_width: float) -> tuple[BSplineCurve, ...]:
    """The 4 curves of one loop from the quarter running from the head apex to L.

    Curve 2 is the quarter; curve 1 its mirror image in x = 0 (reversed, from L' to the apex);
    curve 3 its image under (x, y) -> (w/2 - x, -y) (reversed, from L to the sinker); curve 0
    the mirror image of curve 3 (from the previous sinker to L').
    """
    mirror = np.array([-1.0, 1.0, 1.0])
    points = quarter.control_points
    turned = np.column_stack([wale_width / 2 - points[:, 0], -points[:, 1], points[:, 2]])
    knots = 1.0 - quarter.knots[::-1]
    return (
        BSplineCurve(quarter.degree, knots, (turned * mirror)),
        BSplineCurve(quarter.degree, knots, (points * mirror)[::-1]),
        quarter,
        BSplineCurve(quarter.degree, knots, turned[::-1]),
    )


class Condition(NamedTuple):
    """A linear condition on one coordinate of the quarter: derivative `order` at parameter
    `at` equals `value` (mm)."""

    at: float
    order: int
    value: float


def symmetry_conditions(wale_width: float) -> tuple[tuple[Condition, ...], ...]:
    """The end conditions (x, y and z, one tuple each) that make the mirrored loop C2.

    At the apex (u = 0, mirror x -> -x) x = 0, x'' = 0, y' = 0, z' = 0; at the leg point
    (u = 1, symmetry (x, y, z) -> (w/2 - x, -y, z)) x = w/4, y = 0, x'' = y'' = 0, z' = 0
    (docs/geometry.md derives them).
    """
    return (
        (
            Condition(0.0, 0, 0.0),
            Condition(0.0, 2, 0.0),
            Condition(1.0, 0, wale_width / 4),
            Condition(1.0, 2, 0.0),
        ),
        (Condition(0.0, 1, 0.0), Condition(1.0, 0, 0.0), Condition(1.0, 2, 0.0)),
        (Condition(0.0, 1, 0.0), Condition(1.0, 1, 0.0)),
    )


def _fit_quarter(shape: LoopShape) -> BSplineCurve:
    """Constrained least-squares fit of the quarter: 12 control points, degree 4.

    The `symmetry_conditions` make the mirrored loop C2. The curve also passes through the
    shoulder's outermost point with x' = 0 there, so that the built-in contacts are exactly 2r
    in the spline as in the analytic model.
    """
    sampled = shape.quarter_samples(_fit_fractions())
    if sampled is None:
        raise InputError(
            f"no loop fits: head_height={shape.head_height:.4g} mm gives no three-section "
            f"quarter for wale_width={shape.wale_width:.4g} mm"
        )
    knots = open_knot_vector(DEGREE, CONTROL_POINTS)
    design = _design_matrix()
    at, point = sampled.shoulder_fraction, sampled.shoulder
    shoulder = (
        (Condition(at, 0, point[0]), Condition(at, 1, 0.0)),
        (Condition(at, 0, point[1]),),
        (Condition(at, 0, point[2]),),
    )
    conditions = symmetry_conditions(shape.wale_width)
    control = np.empty((CONTROL_POINTS, 3))
    n = CONTROL_POINTS
    for axis in range(3):
        axis_conditions = conditions[axis] + shoulder[axis]
        constraint = condition_rows(knots, axis_conditions)
        k = len(axis_conditions)
        kkt = np.zeros((n + k, n + k))
        kkt[:n, :n] = design.T @ design
        kkt[:n, n:] = constraint.T
        kkt[n:, :n] = constraint
        rhs = np.concatenate(
            [design.T @ sampled.points[:, axis], [condition.value for condition in axis_conditions]]
        )
        control[:, axis] = np.linalg.solve(kkt, rhs)[:n]
    return BSplineCurve(DEGREE, knots, control)


def condition_rows(knots: np.ndarray, conditions: tuple[Condition, ...]) -> np.ndarray:
    """The conditions as rows acting on one coordinate of the control points, (k, n)."""
    return np.vstack(
        [
            basis_matrix(knots, DEGREE, np.array([condition.at]), condition.order).toarray()
            for condition in conditions
        ]
    )


def _fit_fractions() -> np.ndarray:
    return np.linspace(0.0, 1.0, _FIT_SAMPLES)


@cache
def _design_matrix() -> np.ndarray:
    """Basis functions of the quarter at the fit samples, (samples, control points)."""
    knots = open_knot_vector(DEGREE, CONTROL_POINTS)
    return basis_matrix(knots, DEGREE, _fit_fractions()).toarray()
