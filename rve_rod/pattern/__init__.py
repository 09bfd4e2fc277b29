"""Stitch patterns: the face chart, the knit graph it means and the smallest periodic cell.

Modules: `chart` (stitch codes, named patterns, user charts, the working-side instructions of
hand knitting turned into the face chart, and the checks that refuse a bad chart), `graph`
(the periodic knit graph: loops, the loop each is pulled through and from which side, the
yarn's path along a course and its connections), `lattice` (the smallest periodic cell of a
chart and its lattice vectors). Pure topology: no geometry, no mechanics (docs/patterns.md).
"""

from rve_rod.pattern.chart import (
    JERSEY,
    NAMED_PATTERNS,
    STITCH_CODES,
    Chart,
    chart_from_working_side,
    pattern_chart,
)
from rve_rod.pattern.graph import KnitGraph, knit_graph
from rve_rod.pattern.lattice import ChartCell, periodic_cell, smallest_cell

__all__ = [
    "JERSEY",
    "NAMED_PATTERNS",
    "STITCH_CODES",
    "Chart",
    "ChartCell",
    "KnitGraph",
    "chart_from_working_side",
    "knit_graph",
    "pattern_chart",
    "periodic_cell",
    "smallest_cell",
]
