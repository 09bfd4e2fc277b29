"""The relaxed cell: the loop width w and course height c a knit takes, unloaded, from its loop
length and stitch pattern alone (docs/patterns.md, "The relaxed cell").

A yarn has no set: straight is its stress-free shape, and a knit relaxes towards the loops that
bend it least. Among the cell templates of the pattern (`rve_rod.geometry.pattern_cell`: every
template free of interpenetration, its yarns 2r apart where they touch, with the crossing order
of the pattern), the relaxed cell is the one of the given loop length l whose bending energy

    U(w, c) = (EI / 2) int kappa^2 ds   (per loop; EI of the yarn, uniform)

is least. Its lattice is the macro deformation of the template family, so the stationary
point is the cell's unloaded equilibrium within the family: dU/dF = 0, zero macro stress,
with the contacts hard (the templates' clearance) and the yarn inextensible (the length held).
At fixed l the family has one free parameter, the ratio q = c/w; w follows from l. Where the
yarn is wider than w/8 the model's radius is r = w/8 and the template scales with w, so the
relaxed ratios l/w, l/c are constants of the pattern, as Munden's are.

Why not the rod cell itself (a naturally straight rod bent into the template, relaxed at zero
macro stress): with the paper's contact law the contacts cannot hold a straight yarn's bending
prestress: the cotton jersey cell collapses (w shrinks by 36 % at a tenth of the straightening,
its centrelines come closer than one radius at 82 % of it; benchmarks/relaxed_rod_cell.py,
docs/patterns.md), so the contacts are taken as hard here.
"""

import logging
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from rve_rod.cache import ResultCache, default_cache_root
from rve_rod.errors import InputError, check_positive
from rve_rod.geometry.pattern_cell import pattern_geometry
from rve_rod.pattern import JERSEY, pattern_chart
from rve_rod.presets import Fabric

__all__ = [
    "RATIO_SCAN",
    "RelaxedKnit",
    "bending_energy",
    "cached_relaxed_knit",
    "relaxed_knit",
    "settled_fabric",
]

logger = logging.getLogger(__name__)

RATIO_SCAN = tuple(np.round(np.arange(0.5, 1.31, 0.1), 2))
"""The ratios q = c/w scanned for the least energy (relaxed knits of the literature have
q = 0.7-0.85; the measured cotton fabrics 0.7-1.26)."""

RELAXED_VERSION = 1
"""Version of the relaxed cell's computation in its cache keys (raise it when it changes)."""

_LENGTH_TOLERANCE = 1e-6
"""Relative tolerance of the loop length of the relaxed template."""
_LENGTH_ITERATIONS = 12
_GAUSS_POINTS = 8


@dataclass(frozen=True)
class RelaxedKnit:
    """The relaxed cell of a pattern (module docstring).

    Attributes:
        pattern: the chart's rows.
        loop_length: l, the yarn length per loop (mm).
        wale_width: w, relaxed (mm). course_height: c, relaxed (mm).
        yarn_radius: r = min(r0, w/8) of the relaxed template (mm).
        energy: the relaxed cell's bending energy per loop for EI = 1, int kappa^2 ds / 2 (1/mm).
        scan: ((q, energy per loop times l), ...) over RATIO_SCAN (inf where no template of
            that ratio fits): the scale-free energy whose least value is the relaxed ratio.
    """

    pattern: tuple[str, ...]
    loop_length: float
    wale_width: float
    course_height: float
    yarn_radius: float
    energy: float
    scan: tuple[tuple[float, float], ...]

    @property
    def ratios(self) -> tuple[float, float]:
        """(l/w, l/c), to compare with Munden's constants."""
        return self.loop_length / self.wale_width, self.loop_length / self.course_height


def bending_energy(curves) -> float:
    """int kappa^2 ds / 2 over B-spline curves (1/mm: the bending energy for EI = 1), by Gauss
    quadrature on every knot span."""
    nodes, weights = np.polynomial.legendre.leggauss(_GAUSS_POINTS)
    total = 0.0
    for curve in curves:
        edges = curve.breakpoints()
        half = 0.5 * np.diff(edges)
        u = (edges[:-1, None] + half[:, None] * (nodes[None, :] + 1.0)).ravel()
        derivatives = curve.derivatives(u, 2)
        first, second = derivatives[1], derivatives[2]
        speed = np.linalg.norm(first, axis=1)
        squared = np.sum(np.cross(first, second) ** 2, axis=1) / speed**6
        total += float(
            np.sum(squared * speed * np.repeat(half, nodes.size) * np.tile(weights, half.size))
        )
    return 0.5 * total


class _Template:
    """The template of ratio q whose yarn length per loop is l, and its energy."""

    def __init__(self, pattern: tuple[str, ...], loop_length: float, minimal_radius: float):
        self.pattern, self.length, self.radius = pattern, loop_length, minimal_radius

    def at(self, ratio: float, width: float):
        """(geometry, energy per loop) of the template of width `width` and c = ratio w."""
        geometry = pattern_geometry(self.pattern, width, ratio * width, self.radius)
        curves = [curve for yarn in geometry.yarns for curve in yarn]
        return geometry, bending_energy(curves) / geometry.cell.n_loops

    def of_length(self, ratio: float, width: float):
        """The template of ratio q whose loop length is l. While r = w/8 the template scales
        with w, so w l / L(w) is exact in one step (the length scales with w, the energy per
        loop with 1/w); else the secant on L(w) = l. Returns (width, geometry or None where
        scaled, energy per loop)."""
        tight = 8 * self.radius
        previous = None
        for _ in range(_LENGTH_ITERATIONS):
            geometry, energy = self.at(ratio, width)
            error = geometry.loop_length - self.length
            if abs(error) <= _LENGTH_TOLERANCE * self.length:
                return width, geometry, energy
            scale = self.length / geometry.loop_length
            if width <= tight and width * scale <= tight:
                return width * scale, None, energy / scale
            if previous is None or previous[1] == error:
                step = width * (scale - 1.0)
            else:
                step = -error * (width - previous[0]) / (error - previous[1])
            previous = (width, error)
            width += step
        raise InputError(
            f"no template of ratio c/w={ratio:g} has the loop length {self.length:g} mm"
        )


def relaxed_knit(pattern, loop_length: float, minimal_radius: float) -> RelaxedKnit:
    """The relaxed w and c of `pattern` (a name or a chart) at the yarn length per loop
    `loop_length` (mm) for a yarn of radius r0 = `minimal_radius` (mm) (module docstring).

    The scan over RATIO_SCAN and a parabola through the least value and its neighbours give
    the relaxed ratio (the scan's least where the parabola's vertex is not lower); a template
    of that ratio and length gives w and c.

    Raises:
        InputError: a bad chart or length, or no template of the loop length fits.
    """
    chart = pattern_chart(pattern)
    chart.check_modelled()
    length = check_positive("loop_length", loop_length, "mm")
    radius = check_positive("yarn_radius", minimal_radius, "mm")
    template = _Template(chart.rows, length, radius)
    width = length / 4.0  # Munden's l/w for jersey
    scan, widths = [], []
    for ratio in RATIO_SCAN:
        try:
            width, _, energy = template.of_length(ratio, width)
        except InputError as error:
            logger.debug("relaxed cell: ratio %g skipped: %s", ratio, error)
            scan.append((float(ratio), math.inf))
            widths.append(math.nan)
            width = length / 4.0
            continue
        scan.append((float(ratio), energy * length))
        widths.append(width)
    values = np.array([value for _, value in scan])
    if not np.isfinite(values).any():
        raise InputError(
            f"no template of pattern {chart.label()!r} has the loop length {length:g} mm with "
            f"yarn_radius={radius:g} mm (c/w scanned over {RATIO_SCAN[0]}-{RATIO_SCAN[-1]})"
        )
    least = int(np.argmin(values))
    best = _least_ratio(np.array(RATIO_SCAN), values)
    try:
        width, geometry, energy = template.of_length(best, widths[least])
    except InputError:
        energy = math.inf
    if energy * length > values[least]:  # the energy is not smooth in q (the shoulder's
        best = float(RATIO_SCAN[least])  # optimum jumps): the scan's least, unless lower
        width, geometry, energy = template.of_length(best, widths[least])
    if geometry is None:
        geometry, energy = template.at(best, width)
    return RelaxedKnit(
        pattern=chart.rows,
        loop_length=length,
        wale_width=geometry.wale_width,
        course_height=geometry.course_height,
        yarn_radius=geometry.yarn_radius,
        energy=energy,
        scan=tuple(scan),
    )


def cached_relaxed_knit(
    pattern, loop_length: float, minimal_radius: float, folder: Path | None = None
) -> RelaxedKnit:
    """`relaxed_knit`, remembered on disk (default: `default_cache_root()/relaxed`): a scene
    planned again does not relax its knits again."""
    chart = pattern_chart(pattern)
    cache = ResultCache(default_cache_root() / "relaxed" if folder is None else folder)
    inputs = {
        "version": RELAXED_VERSION,
        "pattern": list(chart.rows),
        "loop_length": float(loop_length),
        "minimal_radius": float(minimal_radius),
    }
    stored = cache.load(inputs)
    if stored is None:
        knit = relaxed_knit(chart, loop_length, minimal_radius)
        cache.store(
            inputs,
            {
                "values": np.array(
                    [knit.wale_width, knit.course_height, knit.yarn_radius, knit.energy]
                ),
                "scan": np.array(knit.scan),
            },
        )
        return knit
    width, height, radius, energy = stored["values"]
    return RelaxedKnit(
        pattern=chart.rows,
        loop_length=float(loop_length),
        wale_width=float(width),
        course_height=float(height),
        yarn_radius=float(radius),
        energy=float(energy),
        scan=tuple((float(q), float(e)) for q, e in stored["scan"]),
    )


def settled_fabric(
    fabric: Fabric, *, relaxed: bool | None = None, measured: bool = False
) -> Fabric:
    """The fabric with the loop width and course height its RVE uses.

    Args:
        fabric: the fabric (`rve_rod.presets.make_fabric`).
        relaxed: True: w and c of the relaxed cell (`relaxed_knit`) from the knit's measured
            loop length; False: the knit's as they are; None (the default): relaxed for a
            pattern other than jersey whose w and c are not the user's own (a preset's are
            measured on its single jersey), as they are otherwise.
        measured: whether w and c were given by the user (they are kept: measured values
            override the relaxed ones).

    Raises:
        InputError: relaxed asked for together with measured w and c, or without a loop
            length to relax (a fabric given by values: give w and c).
    """
    if relaxed and measured:
        raise InputError(
            "relaxed=true finds wale_width and course_height from the loop length: give "
            "either relaxed or wale_width and course_height, not both"
        )
    if relaxed is None:
        relaxed = fabric.knit.pattern != JERSEY and not measured
    if not relaxed:
        return fabric
    length = fabric.knit.measured_loop_length
    if length is None:
        raise InputError(
            f"pattern {pattern_chart(fabric.knit.pattern).label()!r} needs wale_width and "
            "course_height, or a preset with a measured loop length to find them from (the "
            "relaxed cell)"
        )
    knit = cached_relaxed_knit(fabric.knit.pattern, length, fabric.yarn.minimal_radius)
    logger.info(
        "relaxed cell of %s at loop length %.4g mm: w = %.4g mm, c = %.4g mm",
        pattern_chart(fabric.knit.pattern).label(),
        length,
        knit.wale_width,
        knit.course_height,
    )
    return replace(
        fabric,
        knit=replace(fabric.knit, wale_width=knit.wale_width, course_height=knit.course_height),
    )


def _least_ratio(ratios: np.ndarray, values: np.ndarray) -> float:
    """The ratio of least energy: the vertex of the parabola fitted (least squares) to the
    least scanned value and up to two neighbours on each side, within the scanned interval
    around it (the scan itself where the parabola opens downwards)."""
    best = int(np.argmin(values))
    window = np.arange(max(best - 2, 0), min(best + 3, ratios.size))
    window = window[np.isfinite(values[window])]
    if window.size < 3:
        return float(ratios[best])
    a, b, _ = np.polyfit(ratios[window], values[window], 2)
    if a <= 0.0:
        return float(ratios[best])
    step = ratios[1] - ratios[0]
    return float(np.clip(-b / (2 * a), ratios[best] - step, ratios[best] + step))
