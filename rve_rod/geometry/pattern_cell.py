"""The loops of a stitch pattern's periodic cell: the template the pattern's RVE starts from.

Every loop keeps the single-jersey loop's projection (`rve_rod.geometry.loop`: the same x-y
shape, the shoulder radius of the shortest jersey loop of the knit); what differs between the
patterns is how the yarn runs through the thickness. Seen from the face (+z), a knit loop is
the jersey loop: legs in front, head and sinkers behind the loops they interlock with; a purl
loop is its mirror image through the mid-plane (z -> -z). Along a loop of course i, wale j,
with s its side (+1 knit, -1 purl; `rve_rod.pattern.graph.loop_side`) and u the side of the
loop above it:

* the head, where the loop above is pulled through it, has the jersey profile of that
  junction, times u: z = u d (1/2 - t^2) across the overlap band (t from 0 where the band
  starts to 1 at the head apex), so the loop above passes in front of its head (knit above)
  or behind it (purl above);
* the feet, where the loop is pulled through the loop below, have the profile times s;
* the legs, between the two bands, go from s d/2 to u d/2 (a quintic step, C2; flat when the
  loop and the one above are alike);
* a sinker between a knit and a purl loop (1x1 rib, seed) crosses the mid-plane at the
  sinker point: its z is the jersey sinker's plus s (d/2) (1 - phi(x/x_b)), phi(xi) =
  (15 xi - 10 xi^3 + 3 xi^5)/8, from the sinker to the widest point (x_b = w/4 + r from the
  sinker), so that it passes the loops below on the same side as the jersey's sinker.

Each quarter is fitted by the loop's B-spline (`rve_rod.geometry.loop_spline`): x and y as the
jersey's, z with conditions that make every join C2 (its value, slope and zero curvature at
both ends, and its value at the widest point W). For charts of one stitch (jersey, reverse
jersey) the loops are the jersey loop (mirrored for purl) and the cell is exactly the jersey
cell; otherwise the depth d is the smallest for which every yarn clears every other and their
images by 2r (`cell_clearance`), the template free of interpenetration with the crossing
order of the pattern (docs/patterns.md).
"""

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from rve_rod.errors import InputError
from rve_rod.geometry.bspline import BSplineCurve
from rve_rod.geometry.loop import (
    ADJACENT_ARC_FACTOR,
    LoopShape,
    QuarterSamples,
    _smallest_clear_depth,
    single_jersey_loop,
)
from rve_rod.geometry.loop_spline import (
    DEGREE,
    SymmetryCondition,
    assembled_loop,
    fit_coordinate,
    fit_fractions,
    fit_quarter,
)
from rve_rod.geometry.proximity import CellClearance, cell_clearance
from rve_rod.pattern import ChartCell, smallest_cell
from rve_rod.pattern.graph import loop_side

__all__ = [
    "PatternGeometry",
    "PeriodicYarns",
    "QuarterSides",
    "pattern_geometry",
    "pattern_heights",
]

_LEG_STEP_SLOPE = 15.0 / 8.0
"""phi5'(1/2) of the legs' quintic step phi5(xi) = 6 xi^5 - 15 xi^4 + 10 xi^3."""
_SINKER_SLOPE = 15.0 / 8.0
"""phi'(0) of the crossing sinker's phi(xi) = (15 xi - 10 xi^3 + 3 xi^5) / 8."""


class QuarterSides(NamedTuple):
    """How z runs along one quarter of a pattern loop, from its crown (the head apex, or for
    a foot quarter the sinker) to the leg point L.

    Attributes:
        crown: the side (+1, -1) of the band at the crown: for a head quarter the side of the
            loop above, for a foot quarter the loop's own.
        leg: the side at the far end of the leg: for a head quarter the loop's own, for a
            foot quarter the side of the loop above.
        crossing: the crown is a sinker between a knit and a purl loop.
    """

    crown: int
    leg: int
    crossing: bool = False


class PeriodicYarns(NamedTuple):
    """The yarns of a periodic cell, what `rve_rod.rve.cell.LoopCell` is built from.

    Attributes:
        yarns: one tuple of curves per course of the cell: 4 quarter curves per loop, one
            period along a1 (C2 throughout; the last curve ends where the first starts + a1).
        lattice: (2, 3) lattice vectors a1 (along the courses) and a2 (mm).
    """

    yarns: tuple[tuple[BSplineCurve, ...], ...]
    lattice: np.ndarray


@dataclass(frozen=True, eq=False)
class PatternGeometry:
    """The template loops of a pattern's periodic cell (lengths in mm).

    Attributes:
        cell: the chart's periodic cell (its loops and lattice in wales and courses).
        wale_width: w, the width of one loop. course_height: c.
        minimal_radius: r0 as given; yarn_radius: r = min(r0, w/8), the model's.
        shape_parameter: the shoulder radius rho (the shortest jersey loop's).
        depth: d, the loops' depth: the jersey loop's for a chart of one stitch, else the
            smallest that clears every yarn by 2r.
        yarns: the curves of each course of the cell (`PeriodicYarns`).
        lattice: (2, 3) the cell's lattice vectors a1 = (p w, 0, 0), a2 = (q w, s c, 0).
        loop_length: the yarn length per loop (mm), the mean over the cell's loops.
        min_clearance: the smallest centreline distance between the yarns and their images.
    """

    cell: ChartCell
    wale_width: float
    course_height: float
    minimal_radius: float
    yarn_radius: float
    shape_parameter: float
    depth: float
    yarns: tuple[tuple[BSplineCurve, ...], ...]
    lattice: np.ndarray
    loop_length: float
    min_clearance: float

    def periodic_yarns(self) -> PeriodicYarns:
        """The yarns and the lattice, as the RVE's cell takes them."""
        return PeriodicYarns(self.yarns, self.lattice)

    def to_dict(self) -> dict:
        """Scalars for JSON reports."""
        (p, _), (q, s) = self.cell.lattice
        return {
            "pattern": self.cell.chart.label(),
            "chart": list(self.cell.chart.rows),
            "lattice_loops": [[p, 0], [q, s]],
            "loops_per_cell": self.cell.n_loops,
            "lattice": self.lattice.tolist(),
            "wale_width": self.wale_width,
            "course_height": self.course_height,
            "minimal_radius": self.minimal_radius,
            "adjusted_radius": self.yarn_radius,
            "shape_parameter": self.shape_parameter,
            "depth": self.depth,
            "loop_length": self.loop_length,
            "min_clearance": self.min_clearance,
            "clearance_over_diameter": self.min_clearance / (2 * self.yarn_radius),
        }


def pattern_heights(shape: LoopShape, sides: QuarterSides, plane: np.ndarray) -> np.ndarray:
    """z of a pattern quarter at its projected points (k, 2) (module docstring) (mm).

    `plane` holds the quarter's own coordinates: x from the crown (0) to L (w/4), y from the
    crown (h) to L (0). The jersey quarter is QuarterSides(1, 1).
    """
    c, rho, d = shape.course_height, shape.shoulder_radius, shape.depth
    band_start = c / 2 - rho
    y = plane[:, 1]
    t = np.clip((y - band_start) / (2 * rho), 0.0, 1.0)
    band = sides.crown * d * (0.5 - t**2)
    xi = (y + band_start) / (2 * band_start)
    step = xi**3 * (10 - 15 * xi + 6 * xi**2)
    leg = 0.5 * d * (sides.leg + (sides.crown - sides.leg) * step)
    z = np.where(y >= band_start, band, leg)
    if sides.crossing:  # from the sinker to W (x rising, y >= c/2), and none beyond
        xi = np.where(y >= c / 2, np.clip(plane[:, 0] / _crossing_length(shape), 0.0, 1.0), 1.0)
        z += sides.crown * 0.5 * d * (1 - (15 * xi - 10 * xi**3 + 3 * xi**5) / 8)
    return z


def _crossing_length(shape: LoopShape) -> float:
    """x_b, the length over which a crossing sinker goes through the mid-plane: from the
    sinker to the quarter's widest point W (mm). Where w = 8r the sinker passes 1.6 r from the
    shoulders of both loops below it; a shorter crossing would bring it to their faces there."""
    return shape.widest_x


def _pattern_quarter(
    shape: LoopShape, sampled: QuarterSamples, sides: QuarterSides, jersey: BSplineCurve
) -> BSplineCurve:
    """The quarter of `sides`: the jersey quarter's x and y, z fitted to `pattern_heights` at
    the same samples (`sampled`, the shape's `quarter_samples` at `fit_fractions()`) with the
    conditions that make every join of pattern quarters C2."""
    z = pattern_heights(shape, sides, sampled.points[:, :2])
    d, band_start = shape.depth, shape.course_height / 2 - shape.shoulder_radius
    # slopes of the fitted x at the crown and y at L (the same for every quarter)
    slopes = jersey.derivatives(np.array([0.0, 1.0]), 1)[1]
    crown_value, crown_slope = -0.5 * d * sides.crown, 0.0
    if sides.crossing:
        crown_value = 0.0
        crown_slope = -sides.crown * 0.5 * d * _SINKER_SLOPE / _crossing_length(shape)
        crown_slope *= slopes[0, 0]
    leg_value = 0.25 * d * (sides.crown + sides.leg)
    leg_slope = 0.5 * d * (sides.crown - sides.leg) * _LEG_STEP_SLOPE / (2 * band_start)
    widest = pattern_heights(shape, sides, sampled.shoulder[None, :2])[0]
    conditions = (
        SymmetryCondition(0.0, 0, crown_value),
        SymmetryCondition(0.0, 1, crown_slope),
        SymmetryCondition(0.0, 2, 0.0),
        SymmetryCondition(1.0, 0, leg_value),
        SymmetryCondition(1.0, 1, leg_slope * slopes[1, 1]),
        SymmetryCondition(1.0, 2, 0.0),
        SymmetryCondition(sampled.shoulder_fraction, 0, widest),
    )
    control = jersey.control_points.copy()
    control[:, 2] = fit_coordinate(z, conditions)
    return BSplineCurve(DEGREE, jersey.knots, control)


def _loop_sides(cell: ChartCell, row: int, column: int) -> tuple[QuarterSides, ...]:
    """The sides of the head, left foot and right foot quarters of the loop at (row, column)."""
    code = cell.chart.code
    own, above = loop_side(code(row, column)), loop_side(code(row + 1, column))
    left, right = (loop_side(code(row, column + k)) for k in (-1, 1))
    return (
        QuarterSides(above, own),
        QuarterSides(own, above, left != own),
        QuarterSides(own, above, right != own),
    )


def _cell_yarns(cell: ChartCell, loops: dict, w: float, c: float) -> tuple:
    """The yarns of the cell: course by course, its loops' curves translated to their
    wales, from `loops[(row, column)]` (4 curves each, centred on the origin)."""
    yarns = []
    for row in range(cell.courses):
        curves = []
        for column in range(cell.loops_per_course):
            shift = np.array([column * w, row * c, 0.0])
            for curve in loops[row, column]:
                curves.append(
                    curve
                    if not shift.any()
                    else BSplineCurve(curve.degree, curve.knots, curve.control_points + shift)
                )
        yarns.append(tuple(curves))
    return tuple(yarns)


def _plain_loops(cell: ChartCell, curves: tuple[BSplineCurve, ...]) -> dict:
    """The loops of a chart of one stitch: the jersey loop, mirrored through the mid-plane
    for purl."""
    if cell.code(0) == "K":
        return dict.fromkeys(cell.loops(), curves)
    mirror = np.array([1.0, 1.0, -1.0])
    purl = tuple(
        BSplineCurve(curve.degree, curve.knots, curve.control_points * mirror) for curve in curves
    )
    return dict.fromkeys(cell.loops(), purl)


class _PatternSearch:
    """The loops of a mixed chart for each depth, and their clearance."""

    def __init__(self, cell: ChartCell, w: float, c: float, r: float, rho: float):
        self.cell, self.w, self.c, self.r, self.rho = cell, w, c, r, rho
        self.lattice = cell.vectors(w, c)
        self.sides = {loop: _loop_sides(cell, *loop) for loop in cell.loops()}

    def loops(self, depth: float) -> dict:
        shape = LoopShape(self.w, self.c, self.r, self.rho, depth)
        sampled = shape.quarter_samples(fit_fractions())
        jersey = fit_quarter(shape, sampled)
        quarters = {
            sides: _pattern_quarter(shape, sampled, sides, jersey)
            for sides in set().union(*self.sides.values())
        }
        return {
            loop: assembled_loop(*(quarters[sides] for sides in self.sides[loop]), self.w)
            for loop in self.cell.loops()
        }

    def yarns(self, depth: float) -> tuple:
        return _cell_yarns(self.cell, self.loops(depth), self.w, self.c)

    def clearance(self, yarns) -> CellClearance:
        return cell_clearance(list(yarns), self.lattice, ADJACENT_ARC_FACTOR * self.r)

    def excess(self, depth: float) -> float:
        return self.clearance(self.yarns(depth)).distance / (2 * self.r) - 1


def pattern_geometry(
    pattern, wale_width: float, course_height: float, minimal_radius: float
) -> PatternGeometry:
    """The template loops of the periodic cell of `pattern` (a chart's rows as a list or
    tuple, a name, or a ChartCell for a given lattice) for loop width w, course height c and
    yarn radius r0 (mm); built once per pattern and sizes (a cache of 32).

    Raises:
        InputError: a chart with stitches the cell does not model, or no loop fits (as
            `single_jersey_loop`).
    """
    if isinstance(pattern, list):
        pattern = tuple(pattern)
    return _pattern_geometry(pattern, wale_width, course_height, minimal_radius)


@lru_cache(maxsize=32)
def _pattern_geometry(
    pattern, wale_width: float, course_height: float, minimal_radius: float
) -> PatternGeometry:
    cell = pattern if isinstance(pattern, ChartCell) else smallest_cell(pattern)
    cell.chart.check_modelled()
    jersey = single_jersey_loop(wale_width, course_height, minimal_radius)
    w, c, r = jersey.wale_width, jersey.course_height, jersey.yarn_radius
    codes = {cell.code(index) for index in range(cell.n_loops)}
    if len(codes) == 1:
        depth = jersey.depth
        yarns = _cell_yarns(cell, _plain_loops(cell, jersey.curves), w, c)
        clearance = jersey.min_clearance
    else:
        rho = jersey.shape_parameter
        if c / 2 - rho <= 0.0:
            raise InputError(
                f"course_height={c:.4g} mm leaves the loops of pattern "
                f"{cell.chart.label()!r} no legs between their bands (c/2 <= rho = {rho:.4g} "
                "mm): no pattern loop fits"
            )
        search = _PatternSearch(cell, w, c, r, rho)
        depth = _smallest_clear_depth(search.excess, r, jersey.depth)
        if not math.isfinite(depth):
            raise InputError(
                f"no loop of pattern {cell.chart.label()!r} fits: with yarn_radius={r:.4g} mm "
                f"no depth clears the yarns by 2r for wale_width={w:.4g} mm and "
                f"course_height={c:.4g} mm"
            )
        yarns = search.yarns(depth)
        clearance = search.clearance(yarns).distance
    length = sum(curve.arc_length() for yarn in yarns for curve in yarn)
    return PatternGeometry(
        cell=cell,
        wale_width=w,
        course_height=c,
        minimal_radius=jersey.minimal_radius,
        yarn_radius=r,
        shape_parameter=jersey.shape_parameter,
        depth=depth,
        yarns=yarns,
        lattice=cell.vectors(w, c),
        loop_length=length / cell.n_loops,
        min_clearance=clearance,
    )


pattern_geometry.cache_clear = _pattern_geometry.cache_clear
