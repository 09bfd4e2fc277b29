"""The smallest periodic cell of a chart and its lattice vectors.

The chart repeats on the torus n_columns x n_rows, but the pattern may repeat sooner, and
along an oblique direction: the translations (dx wales, dy courses) that map the chart onto
itself form a lattice T that contains (n_columns, 0) and (0, n_rows). Its basis is taken with
the first vector along the courses, a1 = (p, 0), p the shortest repeat of a course (so that
each course's yarn is periodic in a1, as the cell's rods are), and a2 = (q, s), s the fewest
courses after which the pattern repeats and q its shift along the course, reduced to
-p/2 < q <= p/2 (the least oblique cell). The cell holds p s loops: s courses (yarn patches)
of p loops each, at wales 0..p-1 and courses 0..s-1 of the chart. In millimetres, with loop
width w and course height c, the lattice vectors are (p w, 0) and (q w, s c): jersey one loop
on (w, 0), (0, c); 1x1 rib 2 loops on (2w, 0), (0, c); seed 2 loops on (2w, 0), (w, c);
garter 2 courses of 1 loop on (w, 0), (0, 2c).
"""

import math
from dataclasses import dataclass

import numpy as np

from rve_rod.errors import InputError
from rve_rod.pattern.chart import Chart, pattern_chart

__all__ = [
    "ChartCell",
    "periodic_cell",
    "smallest_cell",
    "translations",
]


@dataclass(frozen=True)
class ChartCell:
    """A periodic cell of a chart (module docstring).

    Attributes:
        chart: the face chart.
        lattice: ((p, 0), (q, s)), the lattice vectors in wales and courses.
    """

    chart: Chart
    lattice: tuple[tuple[int, int], tuple[int, int]]

    @property
    def loops_per_course(self) -> int:
        """p: the loops of each course (yarn patch) of the cell."""
        return self.lattice[0][0]

    @property
    def courses(self) -> int:
        """s: the courses (yarn patches) of the cell."""
        return self.lattice[1][1]

    @property
    def n_loops(self) -> int:
        """p s, the loops of the cell."""
        return self.loops_per_course * self.courses

    def loops(self) -> tuple[tuple[int, int], ...]:
        """The (row, column) of the cell's loops on the chart, course by course."""
        return tuple(
            (row, column) for row in range(self.courses) for column in range(self.loops_per_course)
        )

    def code(self, index: int) -> str:
        """The stitch code of the cell's loop `index` (in the order of `loops`)."""
        return self.chart.code(*self.loops()[index])

    def vectors(self, wale_width: float, course_height: float) -> np.ndarray:
        """The lattice vectors a1 = (p w, 0, 0), a2 = (q w, s c, 0) in mm, shape (2, 3)."""
        (p, _), (q, s) = self.lattice
        return np.array([[p * wale_width, 0.0, 0.0], [q * wale_width, s * course_height, 0.0]])

    def locate(self, row: int, column: int) -> tuple[int, tuple[int, int]]:
        """The cell loop at chart position (row, column) and the lattice image it lies in:
        (index into `loops`, (a, b)) with (column, row) = loop + a a1 + b a2."""
        (p, _), (q, s) = self.lattice
        b = math.floor(row / s)
        along = column - b * q
        a = math.floor(along / p)
        return (row - b * s) * p + (along - a * p), (a, b)


def translations(chart: Chart) -> np.ndarray:
    """(k, 2) every translation (dx, dy), 0 <= dx < n_columns, 0 <= dy < n_rows, that maps
    the chart onto itself (the lattice T modulo the chart's torus)."""
    codes = np.array([list(row) for row in chart.rows])
    return np.array(
        [
            (dx, dy)
            for dy in range(chart.n_rows)
            for dx in range(chart.n_columns)
            if np.array_equal(np.roll(codes, (-dy, -dx), axis=(0, 1)), codes)
        ]
    )


def smallest_cell(pattern) -> ChartCell:
    """The smallest periodic cell of a chart (or of anything `pattern_chart` reads), with
    a1 along the courses (module docstring)."""
    chart = pattern_chart(pattern)
    found = translations(chart)
    along = found[(found[:, 1] == 0) & (found[:, 0] > 0), 0]
    p = int(along.min()) if along.size else chart.n_columns
    upward = found[found[:, 1] > 0]
    if upward.size:
        s = int(upward[:, 1].min())
        q = int(upward[upward[:, 1] == s, 0].min()) % p
    else:
        s, q = chart.n_rows, 0
    if q > p / 2:
        q -= p
    return ChartCell(chart, ((p, 0), (q, s)))


def periodic_cell(pattern, lattice) -> ChartCell:
    """The cell of a chart on a given lattice ((p, 0), (q, s)) of wales and courses: any
    lattice of translations that map the chart onto itself (a multiple of the smallest cell,
    e.g. two jersey loops side by side, ((2, 0), (0, 1))), for tests and supercells.

    Raises:
        InputError: a lattice whose first vector is not along the courses, whose p or s is
            not positive, or that is not a translation of the pattern.
    """
    chart = pattern_chart(pattern)
    try:
        (p, zero), (q, s) = ((int(a), int(b)) for a, b in lattice)
    except (TypeError, ValueError) as error:
        raise InputError(f"lattice={lattice!r} must be ((p, 0), (q, s)), integers") from error
    if zero != 0 or p < 1 or s < 1:
        raise InputError(
            f"lattice={lattice!r} must be ((p, 0), (q, s)) with p >= 1 and s >= 1: the first "
            "vector along the courses (the yarn's period)"
        )
    smallest = smallest_cell(chart)
    (p0, _), (q0, s0) = smallest.lattice
    # (p, 0) and (q, s) lie in T = span{(p0, 0), (q0, s0)} exactly when these divide
    if p % p0 or s % s0 or (q - (s // s0) * q0) % p0:
        raise InputError(
            f"lattice={lattice!r} does not repeat the chart {chart.label()!r}: its vectors "
            f"must be translations of the pattern, whose smallest cell is {smallest.lattice}"
        )
    return ChartCell(chart, ((p, 0), (q, s)))
