"""The single-jersey loop: a three-section quarter, mirrored into one periodic loop of 4 B-splines.

Construction (docs/geometry.md has the derivation and a figure). Axis x is course-wise (period
w, wale width), y wale-wise (period c, course height), z out of plane; r is the yarn radius. A
quarter of the yarn centreline runs from the apex of the needle-loop head A = (0, h) to the leg
point L = (w/4, 0) where the loop crosses its mid-height. In the x/y projection it is made of
three tangent-continuous sections:

1. the crown, the straight segment y = h from A to x = w/4 + r - a;
2. the shoulder, a quarter ellipse of semi-axes a = 1.3 rho (along x) and rho (along y) centred
   at (w/4 + r - a, c/2) that ends at the widest point W = (w/4 + r, c/2) with its tangent along
   y;
3. the leg, the circular arc through W and L with its centre on the line y = c/2 (so that it is
   tangent to the shoulder at W), of radius (r^2 + c^2/4) / (2 r).

Hence h = c/2 + rho. W lies one radius outside the neck line x = w/4: the head rests against the
sinker loop of the course above (widest point (w/4 - r, c/2)) and, when r = w/8, against the
head of the next wale, both exactly 2r away. Out of plane z depends on y only: the legs lie in
the front plane z = +d/2 while |y| <= c - h; across the band c - h <= |y| <= h, where the loops
of neighbouring courses overlap, z falls as a parabola to the back plane z = -d/2 at the head
apex (and by symmetry at the sinker). The shoulder radius rho (`shoulder_radius_bounds`) is the
free shape parameter; for each rho the depth d is the smallest for which the yarn clears its
neighbours by 2r (a secant search), and rho is chosen to minimize the loop length.

The quarter is fitted by a degree-4 B-spline with 12 control points and mirrored into the 4
curves of one loop from sinker to sinker (`rve_rod.geometry.loop_spline`). Each curve is
parametrized on [0, 1]; the loop runs through curve 0, 1, 2, 3 and continues into curve 0 of
the next wale shifted by (w, 0, 0).
"""

import logging
import math
from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np
import scipy.optimize

from rve_rod.errors import InputError, check_integer, check_positive, check_range
from rve_rod.geometry.bspline import BSplineCurve
from rve_rod.geometry.loop_spline import CONTROL_POINTS, DEGREE, fit_quarter, mirrored_loop
from rve_rod.geometry.proximity import ChainClearance, chain_clearance
from rve_rod.presets import Knit

__all__ = [
    "ADJACENT_ARC_FACTOR",
    "OUT_OF_PLANE_PROFILES",
    "SHOULDER_ASPECT",
    "LoopGeometry",
    "LoopShape",
    "QuarterSamples",
    "adjusted_radius",
    "affine_length_gradient",
    "loop_geometry",
    "loop_length_gradient",
    "loop_polylines",
    "shoulder_radius_bounds",
    "single_jersey_loop",
]

logger = logging.getLogger(__name__)

ADJACENT_ARC_FACTOR = math.pi
"""Parts of the same yarn closer than this times r in arc length are adjacent, not in contact."""
RADIUS_PER_WALE_WIDTH = 1.0 / 8.0
"""r <= w/8: the largest radius a loop of wale width w holds (four yarn diameters per wale)."""
MAX_DEPTH_FACTOR = 12.0
"""Depths beyond 12 r count as no fit (the optimal loops have d = 2.0-2.1 r)."""
_POLYLINE_SAMPLES = 60
_SECTION_SAMPLES = 400
SHOULDER_ASPECT = 1.3
"""a / rho, the shoulder ellipse's semi-axis along x over the one along y: a model constant, not
a shape parameter. 1.0 (a circle) leaves the two tightest cotton knits 4.1 and 4.7 % long, 1.2
and 1.3 bring every fabric within 4 %, 1.4 does not (its bound rho >= 1.4 r on the tightest bend
is active); docs/geometry.md has the table. The shortest loops of the spline space have the
same flattened shoulder (benchmarks/shortest_loop.py)."""
_SHOULDER_SCAN = (1.3, 1.45, 1.6)
"""Shoulder radii (in r) scanned before Brent's method: the optimum of the fabrics tried lies at
1.3-1.34 r."""
_FINE_SHOULDER_SCAN = tuple(np.linspace(1.3, 1.9, 13))
"""Scanned when no loop of _SHOULDER_SCAN fits: tight knits (c near 4 r) fit only in a narrow
window of shoulder radii."""
_SHOULDER_TOLERANCE = 5e-3
"""Brent's tolerance on the shoulder radius, in r (the length is flat at the optimum)."""
_DEPTH_TOLERANCE = 1e-5
"""Width, in r, of the final bracket of the depth search."""
_DEPTH_ITERATIONS = 60
_ROUND_OFF = 1e-9
"""Relative shortfall of 2r accepted as contact: the contacts at W are exact by construction."""
OUT_OF_PLANE_PROFILES = ("band", "parabolic", "helical")
"""How z runs along the loop. "band" is the model (legs flat, a parabola across the overlap
band); the others are an EXPERIMENT for issue 14 (the knit contracts too little), not used by
any shipped result: more three-dimensional loops of the literature, with the same projection,
symmetries and clearance rule (docs/validation.md, "Literature loop shapes").

- "parabolic": z = (d/2) (1 - 2 (y/h)^2) over the whole loop height, the out-of-plane shape of
  Crane's parametric plain-knit yarn (K. Crane, "A simple parametric model of plain-knit
  yarns", 2023: y = h cos t, z = d cos 2t = d (2 (y/h)^2 - 1)): no flat legs, the head and the
  sinker loop lean out of plane all the way from the leg point.
- "helical": z = -(d/2) cos(pi s), s the arc-length fraction of the quarter from the head apex
  (0) to the leg point (1): the yarn climbs through the thickness at a steady rate along the
  whole leg, like the legs wound on cylinders (helices) of Kurbak's plain-knit model (Kurbak &
  Alpyildiz, Text. Res. J. 2009, whose heads lean towards the thickness direction)."""


@dataclass(frozen=True)
class LoopShape:
    """The analytic quarter loop (all lengths in mm).

    Attributes:
        wale_width: w.
        course_height: c.
        yarn_radius: r (already adjusted: r <= w/8).
        shoulder_radius: rho, the free shape parameter, within `shoulder_radius_bounds`; the
            shoulder is an ellipse of semi-axes SHOULDER_ASPECT rho (x) and rho (y).
        depth: d, the legs lie at z = d/2, head apex and sinker at z = -d/2.
        profile: how z runs between them, one of OUT_OF_PLANE_PROFILES; "band" (the model)
            unless running the issue-14 experiment.
    """

    wale_width: float
    course_height: float
    yarn_radius: float
    shoulder_radius: float
    depth: float
    profile: str = "band"

    def __post_init__(self):
        for name in ("wale_width", "course_height", "yarn_radius", "depth"):
            check_positive(name, getattr(self, name), "mm")
        _check_profile(self.profile)
        bounds = shoulder_radius_bounds(self.wale_width, self.course_height, self.yarn_radius)
        check_range("shoulder_radius", self.shoulder_radius, *bounds, "mm")

    @property
    def widest_x(self) -> float:
        """x of the widest point W = (w/4 + r, c/2) (mm)."""
        return self.wale_width / 4 + self.yarn_radius

    @property
    def head_height(self) -> float:
        """h = c/2 + rho, the y of the head apex (mm)."""
        return self.course_height / 2 + self.shoulder_radius

    @property
    def leg_radius(self) -> float:
        """(r^2 + c^2/4) / (2 r): the circle through W and L centred on y = c/2 (mm)."""
        r, c = self.yarn_radius, self.course_height
        return (r**2 + c**2 / 4) / (2 * r)

    def sections(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Dense x/y points of crown, shoulder and leg, each (k, 2), from A through W to L.

        Angles are measured clockwise from +y: a point of a circle of centre C and radius R at
        angle t is C + R (sin t, cos t); shoulder and leg both turn clockwise, the shoulder from
        t = 0 to pi/2 (W), the leg from pi/2 to the angle of L. Consecutive sections share
        their end points.
        """
        c, rho, big = self.course_height, self.shoulder_radius, self.leg_radius
        across = SHOULDER_ASPECT * rho
        corner = self.widest_x - across
        crown = np.column_stack(
            [np.linspace(0.0, corner, _SECTION_SAMPLES), np.full(_SECTION_SAMPLES, c / 2 + rho)]
        )
        t = np.linspace(0.0, math.pi / 2, _SECTION_SAMPLES)
        shoulder = np.column_stack([corner + across * np.sin(t), c / 2 + rho * np.cos(t)])
        shoulder[-1] = [self.widest_x, c / 2]  # exactly W
        at_leg = math.atan2(big - self.yarn_radius, -c / 2)  # L - centre = big (sin t, cos t)
        t = np.linspace(math.pi / 2, at_leg, _SECTION_SAMPLES)
        leg = np.column_stack([self.widest_x - big + big * np.sin(t), c / 2 + big * np.cos(t)])
        leg[-1] = [self.wale_width / 4, 0.0]  # exactly L, not L up to round-off
        return crown, shoulder, leg

    def projection(self) -> np.ndarray:
        """Dense x/y points of the quarter from A to L, shape (k, 2) (mm); read-only, and
        remembered per (w, c, r, rho) and SHOULDER_ASPECT (which an experiment may change):
        the depth does not enter, and a depth search fits a dozen depths of one shape."""
        return _projection(
            self.wale_width,
            self.course_height,
            self.yarn_radius,
            self.shoulder_radius,
            SHOULDER_ASPECT,
        )

    def height(self, y: np.ndarray) -> np.ndarray:
        """z(y) of the "band" profile: d/2 on the legs, a parabola across the band
        c - h <= |y| <= h (mm)."""
        band_start = self.course_height / 2 - self.shoulder_radius  # c - h
        t = np.clip((np.abs(y) - band_start) / (2 * self.shoulder_radius), 0.0, 1.0)
        return self.depth * (0.5 - t**2)

    def heights(self, plane: np.ndarray) -> np.ndarray:
        """z of the quarter's projected points (k, 2), from the apex to L, by `profile` (mm)."""
        if self.profile == "band":
            return self.height(plane[:, 1])
        if self.profile == "parabolic":
            return self.depth * (0.5 - (plane[:, 1] / self.head_height) ** 2)
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(plane, axis=0), axis=1))])
        return -0.5 * self.depth * np.cos(math.pi * arc / arc[-1])

    def quarter_samples(self, fractions: np.ndarray) -> "QuarterSamples":
        """Points of the 3D quarter at fractions of its arc length, and where it passes W."""
        plane = self.projection()
        points = np.column_stack([plane, self.heights(plane)])
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
        targets = fractions * arc[-1]
        samples = np.stack([np.interp(targets, arc, points[:, k]) for k in range(3)], axis=1)
        widest = int(np.argmax(plane[:, 0]))
        return QuarterSamples(samples, arc[widest] / arc[-1], points[widest])

    def curves(self) -> tuple[BSplineCurve, ...]:
        """The 4 B-spline curves of the loop: the fitted quarter, mirrored (`mirrored_loop`)."""
        return mirrored_loop(fit_quarter(self), self.wale_width)


class QuarterSamples(NamedTuple):
    """The analytic quarter sampled for the B-spline fit.

    Attributes:
        points: (m, 3) points at the requested arc-length fractions (mm).
        shoulder_fraction: arc-length fraction of the widest point W.
        shoulder: (3,) W itself, (w/4 + r, c/2, z(c/2)) (mm).
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
        shape_parameter: the shoulder radius rho (mm), chosen to minimize the loop length.
        depth: d, distance of the legs' plane from the heads' plane (mm), the smallest for
            which the loop clears its neighbours by 2r.
        curves: the 4 curves of one loop (degree 4, 12 control points each, on [0, 1]).
        loop_length: length of the B-spline loop (mm).
        min_clearance: smallest centreline distance to the periodic neighbours and to the
            non-adjacent parts of the loop itself (mm); 2r where yarns touch.
        closest: where that distance occurs.
        lattice: (2, 3) lattice vectors [(w, 0, 0), (0, c, 0)].
        profile: the out-of-plane profile (OUT_OF_PLANE_PROFILES; "band" but in the issue-14
            experiment).
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
    profile: str = "band"

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


def shoulder_radius_bounds(
    wale_width: float, course_height: float, yarn_radius: float
) -> tuple[float, float]:
    """The admissible shoulder radii (mm): from SHOULDER_ASPECT r, where the shoulder's tightest
    bend (radius rho^2 / a = rho / SHOULDER_ASPECT, at W) equals the yarn radius, to
    min(c/2, (w/4 + r) / SHOULDER_ASPECT): the overlap band c/2 - rho <= |y| starts at y >= 0
    and the crown w/4 + r - a is not negative. The second can be below the first: no loop."""
    largest = min(course_height / 2, (wale_width / 4 + yarn_radius) / SHOULDER_ASPECT)
    return SHOULDER_ASPECT * yarn_radius, largest


def adjusted_radius(minimal_radius: float, wale_width: float) -> float:
    """r = min(r0, w/8): the yarn radius the loop model can accommodate (mm)."""
    return min(float(minimal_radius), RADIUS_PER_WALE_WIDTH * float(wale_width))


def loop_geometry(knit: Knit, minimal_radius: float) -> LoopGeometry:
    """The loop of a knit (wale width, course height) with yarn radius r0 (mm)."""
    return single_jersey_loop(knit.wale_width, knit.course_height, minimal_radius)


def affine_length_gradient(
    curves: tuple[BSplineCurve, ...], points_per_span: int = 12
) -> np.ndarray:
    """(2,) (dL/dE11, dL/dE22) = (int t_x^2 ds, int t_y^2 ds) (mm): how the length L of the
    loop `curves` grows with the Green-Lagrange strains E11 and E22 at E = 0 when the loop is
    stretched affinely, its shape held (t the unit tangent; Gauss-Legendre quadrature per knot
    span). The counterpart of `loop_length_gradient`, whose loop re-shapes itself into the
    shortest one at the new w and c. A yarn of axial stiffness EA in a loop that keeps its
    shape is stretched by (a . E) / L, and its tension T, spread over the cell's area w c,
    pulls with S = T a / (w c) (the in-plane part of int T t t^T ds / (w c)): the stiffness
    k a a^T of `paper.comparison.taut_loop_split` with k = EA / (L w c) (docs/validation.md,
    "What the shape of their response says", point 6)."""
    gradient = np.zeros(2)
    for curve in curves:
        params, half, weights = curve.span_quadrature(points_per_span)
        tangent = curve(params, 1)
        speed = np.linalg.norm(tangent, axis=1, keepdims=True)
        along = (tangent[:, :2] / speed) ** 2 * speed  # t_i^2 ds/du, (s p, 2)
        gradient += half @ np.einsum("spi,p->si", along.reshape(half.size, -1, 2), weights)
    return gradient


def loop_length_gradient(
    wale_width: float,
    course_height: float,
    yarn_radius: float,
    step: float = 0.01,
    profile: str = "band",
) -> np.ndarray:
    """(2,) (w dL/dw, c dL/dc) (mm): how the minimum-length loop's length L grows with a
    course-wise and a wale-wise strain of the knit, the yarn radius r held (a finite
    difference of relative size `step`: central in c, forward in w, since a narrower loop
    could not hold r = w/8), for the loop's out-of-plane `profile` (OUT_OF_PLANE_PROFILES). A
    taut loop of inextensible yarn can only deform along the null direction of this gradient
    (docs/validation.md, "What the shape of their response says")."""
    w = check_positive("wale_width", wale_width, "mm")
    c = check_positive("course_height", course_height, "mm")
    r = check_positive("yarn_radius", yarn_radius, "mm")
    if r > RADIUS_PER_WALE_WIDTH * w * (1 + 1e-12):
        raise InputError(
            f"yarn_radius={r!r} mm is out of range: 0 < r <= w/8 = {RADIUS_PER_WALE_WIDTH * w!r} mm"
        )
    check_range("step", step, 1e-4, 0.1)

    def length(wale: float, course: float) -> float:
        return single_jersey_loop(wale, course, r, profile=profile).loop_length

    along_w = (length(w * (1 + step), c) - length(w, c)) / step
    along_c = (length(w, c * (1 + step)) - length(w, c * (1 - step))) / (2 * step)
    return np.array([along_w, along_c])


RADIUS_ADJUSTMENT_WARNING = 1.25
"""A yarn radius r0 above this times w/8 is cut to w/8 with a warning (below: an info line)."""


@lru_cache(maxsize=64)
def single_jersey_loop(
    wale_width: float,
    course_height: float,
    minimal_radius: float,
    shoulder_radius: float | None = None,
    profile: str = "band",
) -> LoopGeometry:
    """Build the minimum-length loop for wale width w, course height c, yarn radius r0 (mm).

    With `shoulder_radius` (rho, mm, within `shoulder_radius_bounds`) the shape
    parameter is given instead of optimized (the depth still follows from the clearance
    condition). `profile` (OUT_OF_PLANE_PROFILES) is the out-of-plane shape: "band", the model,
    or one of the issue-14 experiment's literature shapes. Takes about a second; results are
    remembered per process (they are immutable), since the RVE runs of one fabric all use the
    same loop. Raises InputError for
    non-positive or non-finite values and when no loop fits.
    """
    w = check_positive("wale_width", wale_width, "mm")
    c = check_positive("course_height", course_height, "mm")
    r0 = check_positive("yarn_radius", minimal_radius, "mm")
    _check_profile(profile)
    r = adjusted_radius(r0, w)
    if r < r0:  # the paper's adjustment (a few %) is routine; a large one is a surprise
        logger.log(
            logging.WARNING if r0 > RADIUS_ADJUSTMENT_WARNING * r else logging.INFO,
            "yarn_radius=%.4g mm is larger than wale_width/8: the model uses r = w/8 = %.4g mm",
            r0,
            r,
        )
    smallest, largest = shoulder_radius_bounds(w, c, r)
    if largest < smallest:
        raise _no_loop(
            w, c, r, f"course_height must be >= {2 * SHOULDER_ASPECT:g} r = {2 * smallest:.4g} mm"
        )
    search = _ShapeSearch(w, c, r, profile)
    if shoulder_radius is None:
        rho = search.shortest()
    else:
        rho = check_range("shoulder_radius", shoulder_radius, smallest, largest, "mm")
    depth = search.depth(rho)
    if not math.isfinite(depth):
        raise _no_loop(w, c, r, f"no depth up to {MAX_DEPTH_FACTOR:g} r for rho = {rho:.4g} mm")
    shape = LoopShape(w, c, r, rho, depth, profile)
    curves = shape.curves()
    closest = search.clearance(curves)
    return LoopGeometry(
        wale_width=w,
        course_height=c,
        minimal_radius=r0,
        yarn_radius=r,
        radius_adjusted=r < r0,
        shape_parameter=rho,
        depth=shape.depth,
        curves=curves,
        loop_length=4 * curves[2].arc_length(),
        min_clearance=closest.distance,
        closest=closest,
        lattice=search.lattice,
        profile=profile,
    )


class _ShapeSearch:
    """The depth each shoulder radius needs, and the shoulder radius of the shortest loop (mm).

    Remembers the depths found: the depth of the nearest shoulder radius seeds the next search.
    """

    def __init__(self, w: float, c: float, r: float, profile: str):
        self.w, self.c, self.r, self.profile = w, c, r, profile
        self.lattice = np.array([[w, 0.0, 0.0], [0.0, c, 0.0]])
        self.depths: dict[float, float] = {}

    def clearance(self, curves: tuple[BSplineCurve, ...]) -> ChainClearance:
        # the loop's symmetries map every curve onto curve 2 (docs/geometry.md)
        return chain_clearance(curves, self.lattice, ADJACENT_ARC_FACTOR * self.r, from_curve=2)

    def excess(self, rho: float, depth: float) -> float:
        """clearance / 2r - 1 of the fitted loop (>= 0: the yarns do not interpenetrate)."""
        curves = LoopShape(self.w, self.c, self.r, rho, depth, self.profile).curves()
        return self.clearance(curves).distance / (2 * self.r) - 1

    def depth(self, rho: float) -> float:
        """The smallest depth for which the loop clears its neighbours by 2r (inf if none)."""
        if rho not in self.depths:
            known = min(self.depths, key=lambda other: abs(other - rho), default=None)
            guess = 2 * self.r if known is None else self.depths[known]
            if not math.isfinite(guess):
                guess = 2 * self.r
            self.depths[rho] = _smallest_clear_depth(
                lambda depth: self.excess(rho, depth), self.r, guess
            )
        return self.depths[rho]

    def length(self, rho: float) -> float:
        """Length of the B-spline loop at its smallest clear depth (inf if none)."""
        depth = self.depth(rho)
        if not math.isfinite(depth):
            return math.inf
        shape = LoopShape(self.w, self.c, self.r, rho, depth, self.profile)
        return 4 * shape.curves()[2].arc_length()

    def shortest(self) -> float:
        """The shoulder radius of the shortest loop: a scan, then Brent's method around it."""
        r = self.r
        bounds = shoulder_radius_bounds(self.w, self.c, r)
        for scan in (_SHOULDER_SCAN, _FINE_SHOULDER_SCAN):
            grid = np.unique(np.clip(r * np.array(scan), *bounds))
            lengths = np.empty(grid.size)
            for k in np.argsort(np.abs(grid - np.median(grid))):  # the middle first: its
                lengths[k] = self.length(grid[k])  # depth is the best guess for the others
            if np.isfinite(lengths).any():
                break
        else:
            raise _no_loop(
                self.w,
                self.c,
                r,
                f"no depth up to {MAX_DEPTH_FACTOR:g} r for any shoulder radius; "
                + (
                    f"the model needs course_height >= about 4 r = {4 * r:.4g} mm"
                    if self.c < 4 * r
                    else f"course_height = {self.c / r:.3g} r and wale_width = {self.w / r:.3g} "
                    "r are too large for this yarn (loops fit up to about 70 r and 150 r)"
                ),
            )
        best = int(np.argmin(lengths))
        bracket = (grid[max(best - 1, 0)], grid[min(best + 1, grid.size - 1)])
        if bracket[0] == bracket[1]:
            return float(grid[best])
        penalty = 2 * lengths[best]  # for inf (no depth fits), which Brent's parabolas cannot use
        optimum = scipy.optimize.minimize_scalar(
            lambda rho: min(self.length(rho), penalty),
            bounds=bracket,
            method="bounded",
            options={"xatol": _SHOULDER_TOLERANCE * r},
        )
        return float(optimum.x) if optimum.fun <= lengths[best] else float(grid[best])


@lru_cache(maxsize=64)
def _projection(w: float, c: float, r: float, rho: float, aspect: float) -> np.ndarray:
    """`LoopShape.projection` of the shape (w, c, r, rho) whose shoulder aspect is `aspect`,
    SHOULDER_ASPECT's value (a key of the cache only: `sections` reads SHOULDER_ASPECT) (mm)."""
    crown, shoulder, leg = LoopShape(w, c, r, rho, 1.0).sections()  # the depth does not enter
    points = np.concatenate([crown[:-1], shoulder[:-1], leg])
    steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
    points = points[np.concatenate([[True], steps > 0])]  # no crown when a = w/4 + r
    points.flags.writeable = False
    return points


def _check_profile(profile: str) -> None:
    if profile not in OUT_OF_PLANE_PROFILES:
        raise InputError(
            f"profile={profile!r} is not an out-of-plane profile: use one of "
            + ", ".join(repr(name) for name in OUT_OF_PLANE_PROFILES)
        )


def _no_loop(w: float, c: float, r: float, reason: str) -> InputError:
    return InputError(
        f"no loop fits: with yarn_radius={r:.4g} mm no loop clears its neighbours by 2r for "
        f"wale_width={w:.4g} mm and course_height={c:.4g} mm ({reason})"
    )


def _smallest_clear_depth(excess, r: float, guess: float) -> float:
    """The smallest depth d with excess(d) >= 0, to _DEPTH_TOLERANCE r, or inf (mm).

    Below it the clearance is a smooth distance that grows with d (the crown of the course
    below passing behind the legs); above it the clearance is exactly 2r (the contacts at W,
    built into the construction), so excess is a plateau at 0 and carries no slope. The root
    is therefore predicted by the secant through the two deepest infeasible depths, and the
    next depth aimed a margin past it, so that a good prediction closes the bracket; the margin
    grows 4-fold whenever the aim falls short (where the distance meets 2r tangentially the
    secant converges only linearly). Bracketing steps grow 2-fold; bisection is the safeguard.
    """
    tolerance = _DEPTH_TOLERANCE * r
    below: list[tuple[float, float]] = []  # infeasible (depth, excess), deepest first
    clear = math.inf  # the shallowest depth found to clear
    step = 0.02 * r
    margin = 0.5 * tolerance
    aimed = False  # whether `depth` is a secant prediction
    depth = guess
    for _ in range(_DEPTH_ITERATIONS):
        value = excess(depth)
        if value >= -_ROUND_OFF:
            clear = depth
        else:
            below = [(depth, value), *below][:2]
            margin *= 4 if aimed else 1
        if not below:  # all clear so far: go shallower (staying > 0)
            depth, step = max(clear - step, 0.5 * clear), 2 * step
            aimed = False
            continue
        deepest = below[0][0]
        if clear - deepest <= tolerance:
            return clear
        root = None
        if len(below) == 2:
            (d1, v1), (d0, v0) = below
            slope = (v1 - v0) / (d1 - d0)
            root = d1 - v1 / slope + margin if slope > 0 else None
        if math.isfinite(clear):
            aimed = root is not None and deepest < root < clear
            depth = root if aimed else 0.5 * (deepest + clear)
        else:  # none clear yet: go deeper
            aimed = root is not None and deepest < root < deepest + step
            depth = root if aimed else deepest + step
            step *= 2
            if depth > MAX_DEPTH_FACTOR * r:
                return math.inf
    return clear
