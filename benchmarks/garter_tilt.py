"""Does garter's template want to tilt its courses, and does the tilt contract it? (issue 28)

A garter fabric is said to contract wale-wise because its knit and purl courses fold like an
accordion; the template keeps its loops in the plane (docs/patterns.md, "Garter"). Here the
garter template of `rve_rod.geometry.pattern_cell` at each ratio q = c/w gets a tilt of its
courses: z += s tau (y - y_i) on the control points of course i (s = +1 for a knit course, -1
for a purl one, y_i its centre; an affine map, so the B-splines follow it exactly and the cell
stays periodic), alternating, so that the courses fold about their interlocks. Printed for
each (q, tau): the yarn length per loop L, the scale-free bending energy E L (E the energy
per loop for EI = 1, `relaxed.bending_energy`; at r = w/8 the template scales with w, so E L
compares templates of any one loop length), its change against the flat template, and the
smallest centreline distance over 2r (`cell_clearance`; 1: no interpenetration). The relaxed
cell is the least E L: with the tilt, at the least (q, tau), l/c = (L/w) / q.

Then the other fold: each course turned rigidly by theta about its own course line (y, z
rotated; s as above) and the course spacing shortened to c cos theta, which keeps every
loop's bending energy and length and contracts the cell by cos theta; printed: the smallest
centreline distance over 2r, whether the turned courses stay clear of each other; and, at
c/w = 1, the same with the loops' depth d raised above the template's (the depth is not a
parameter of `pattern_geometry`, which takes the smallest that clears the flat cell: the
template's own search object builds the yarns at a given d here).

    .venv/bin/python benchmarks/garter_tilt.py

About a minute on the shared 2-core machine (2026-11-27).
"""

import math

import numpy as np

from rve_rod.errors import InputError
from rve_rod.geometry.bspline import BSplineCurve
from rve_rod.geometry.loop import ADJACENT_ARC_FACTOR
from rve_rod.geometry.pattern_cell import _PatternSearch, pattern_geometry
from rve_rod.geometry.proximity import cell_clearance
from rve_rod.geometry.relaxed import bending_energy
from rve_rod.pattern import pattern_chart, smallest_cell

WIDTH = 1.2
"""w (mm): below 8 r0, so that r = w/8 and the template is scale-free."""
MINIMAL_RADIUS = 0.19
"""r0 of cotton 20s/2 (mm)."""
RATIOS = (0.6, 0.8, 1.0, 1.2, 1.4, 1.7, 2.0)
TILTS = (0.0, 0.3, 0.6, 0.8, 1.0, 1.5)
TURNS = (0.0, 5.0, 10.0, 20.0, 30.0)
DEPTHS = (0.3, 0.5, 0.7, 1.0)
"""Loop depths d (mm) of the turned cell at c/w = 1 (the template's: 0.307 mm)."""


def _length(curve: BSplineCurve, samples: int = 400) -> float:
    points = curve(np.linspace(0.0, 1.0, samples + 1))
    return float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum())


def tilted(geometry, chart, tilt: float) -> list[tuple[BSplineCurve, ...]]:
    """The template's yarns with course i tilted by z += s tau (y - i c) (module docstring)."""
    yarns = []
    for course, yarn in enumerate(geometry.yarns):
        side = 1.0 if chart[course % len(chart)][0] == "K" else -1.0
        curves = []
        for curve in yarn:
            control = curve.control_points.copy()
            control[:, 2] += side * tilt * (control[:, 1] - course * geometry.course_height)
            curves.append(BSplineCurve(curve.degree, curve.knots, control))
        yarns.append(tuple(curves))
    return yarns


def turned(geometry, chart, degrees: float, yarns=None):
    """The template's yarns (or `yarns` of its cell) with course i turned by theta about its
    course line and the spacing shortened to c cos theta, and the lattice (module docstring)."""
    theta = math.radians(degrees)
    cos, sin = math.cos(theta), math.sin(theta)
    turned_yarns = []
    for course, yarn in enumerate(geometry.yarns if yarns is None else yarns):
        side = 1.0 if chart[course % len(chart)][0] == "K" else -1.0
        centre = course * geometry.course_height
        curves = []
        for curve in yarn:
            control = curve.control_points.copy()
            y, z = control[:, 1] - centre, control[:, 2].copy()
            control[:, 1] = centre * cos + y * cos - side * z * sin
            control[:, 2] = side * y * sin + z * cos
            curves.append(BSplineCurve(curve.degree, curve.knots, control))
        turned_yarns.append(tuple(curves))
    lattice = geometry.lattice.copy()
    lattice[1, 1] *= cos
    return turned_yarns, lattice


def main():
    chart = pattern_chart("garter").rows
    print("| c/w | tilt tau | L (mm) | E L | change | clearance / 2r |")
    print("|---:|---:|---:|---:|---:|---:|")
    best = (math.inf, None)
    for ratio in RATIOS:
        try:
            geometry = pattern_geometry(chart, WIDTH, ratio * WIDTH, MINIMAL_RADIUS)
        except InputError as error:  # too short a course for the interlock
            print(f"| {ratio:.1f} | | | | | no template: {error} |")
            continue
        radius, loops = geometry.yarn_radius, geometry.cell.n_loops
        flat = None
        for tilt in TILTS:
            yarns = tilted(geometry, chart, tilt)
            curves = [curve for yarn in yarns for curve in yarn]
            length = sum(_length(curve) for curve in curves) / loops
            scaled = bending_energy(curves) / loops * length
            flat = scaled if flat is None else flat
            clearance = cell_clearance(yarns, geometry.lattice, ADJACENT_ARC_FACTOR * radius)
            print(
                f"| {ratio:.1f} | {tilt:.1f} | {length:.3f} | {scaled:.2f} | "
                f"{scaled / flat - 1:+.1%} | {clearance.distance / (2 * radius):.3f} |"
            )
            if scaled < best[0]:
                best = (scaled, (ratio, tilt, length / WIDTH / ratio))
    ratio, tilt, loop_over_height = best[1]
    print(
        f"\nleast E L = {best[0]:.2f} at c/w = {ratio}, tau = {tilt}: "
        f"l/c = {loop_over_height:.2f} (the grid's least; no refinement between its points)"
    )
    print("\n| c/w | turn (degrees) | clearance / 2r |\n|---:|---:|---:|")
    for ratio in (0.8, 1.0, 1.2):
        geometry = pattern_geometry(chart, WIDTH, ratio * WIDTH, MINIMAL_RADIUS)
        for degrees in TURNS:
            yarns, lattice = turned(geometry, chart, degrees)
            radius = geometry.yarn_radius
            clearance = cell_clearance(yarns, lattice, ADJACENT_ARC_FACTOR * radius)
            print(f"| {ratio:.1f} | {degrees:g} | {clearance.distance / (2 * radius):.3f} |")
    geometry = pattern_geometry(chart, WIDTH, WIDTH, MINIMAL_RADIUS)
    search = _PatternSearch(
        smallest_cell(chart),
        geometry.wale_width,
        geometry.course_height,
        geometry.yarn_radius,
        geometry.shape_parameter,
    )
    print("\n| turn (degrees) | depth d (mm) | clearance / 2r |\n|---:|---:|---:|")
    for degrees in (10.0, 20.0):
        for depth in DEPTHS:
            yarns, lattice = turned(geometry, chart, degrees, search.yarns(depth))
            radius = geometry.yarn_radius
            clearance = cell_clearance(yarns, lattice, ADJACENT_ARC_FACTOR * radius)
            print(f"| {degrees:g} | {depth:.1f} | {clearance.distance / (2 * radius):.3f} |")


if __name__ == "__main__":
    main()
