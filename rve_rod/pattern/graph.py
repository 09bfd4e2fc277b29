"""The periodic knit graph of a face chart: loops, the loops each is pulled through and from
which side, the yarn's path along a course and how it connects consecutive loops.

Every course is one yarn running left to right (+x) through the wales of the repeat and on
into the next repeat. The stitch in course i, wale j (`Chart.code(i, j)`) is:

* K or P, a loop pulled through the loops the needle held: the loop of the last course below
  that knitted in this wale, with the tucks above it. K pulls it from the back to the front
  (its side is +1, the face), P from the front to the back (-1): a purl loop is a knit loop
  mirrored through the fabric's mid-plane;
* T, a tuck: the yarn is caught on the needle without being pulled through, and is held with
  the loop below by the next loop of the wale;
* M and I (miss, inlay): the yarn passes the wale without being caught.

Between two consecutive loops of a course the yarn (the sinker loop) stays on one face when
the two are alike (K-K, P-P) and crosses the mid-plane when they differ (K-P, P-K): that
connecting yarn is what tells the patterns apart. Positions are (row, column) on the chart's
torus; any integers are accepted (the chart repeats).
"""

from dataclasses import dataclass
from typing import NamedTuple

from rve_rod.errors import InputError
from rve_rod.pattern.chart import LOOP_CODES, MODELLED_CODES, Chart, pattern_chart

__all__ = [
    "CROSSING",
    "SAME_FACE",
    "Connection",
    "KnitGraph",
    "knit_graph",
    "loop_side",
]

SAME_FACE = "same face"
"""The yarn between two alike loops (K-K, P-P) stays on one face of the fabric."""
CROSSING = "crossing"
"""The yarn between a knit and a purl loop crosses the fabric's mid-plane."""


def loop_side(code: str) -> int:
    """The side a loop of `code` is pulled through to: +1 (the face) for K, -1 for P."""
    if code == "K":
        return 1
    if code == "P":
        return -1
    raise InputError(f"code={code!r} is not a loop (K or P)")


class Connection(NamedTuple):
    """The yarn between two consecutive loops of a course.

    Attributes:
        row: the course.
        first, second: the columns of the two loops (second > first; second may lie in the
            next repeat, its column is then first + the distance along the yarn).
        kind: SAME_FACE or CROSSING.
        floats: columns passed between them without a loop (misses, inlays, tucks).
    """

    row: int
    first: int
    second: int
    kind: str
    floats: tuple[int, ...]


@dataclass(frozen=True)
class KnitGraph:
    """The knit graph of a chart (module docstring).

    Attributes:
        chart: the face chart.
    """

    chart: Chart

    def loops(self) -> tuple[tuple[int, int], ...]:
        """The (row, column) of every K or P loop of one repeat, course by course."""
        chart = self.chart
        return tuple(
            (i, j)
            for i in range(chart.n_rows)
            for j in range(chart.n_columns)
            if chart.code(i, j) in MODELLED_CODES
        )

    def side(self, row: int, column: int) -> int:
        """+1 if the loop at (row, column) is pulled from the back to the front (K), -1 from
        the front to the back (P)."""
        return loop_side(self.chart.code(row, column))

    def pulled_through(self, row: int, column: int) -> tuple[tuple[int, int], ...]:
        """What the loop at (row, column) is pulled through, nearest first: the tucks held
        on the needle and the last loop below them in the same wale."""
        chart = self.chart
        if chart.code(row, column) not in MODELLED_CODES:
            raise InputError(f"({row}, {column}) holds a {chart.code(row, column)}, not a loop")
        held = []
        below = row - 1
        while True:  # terminates: every column has a loop (Chart's check)
            code = chart.code(below, column)
            if code == "T":
                held.append((below, column))
            elif code in MODELLED_CODES:
                held.append((below, column))
                return tuple(held)
            below -= 1

    def course(self, row: int) -> tuple[tuple[int, str], ...]:
        """The yarn's path along course `row` through one repeat: (column, code) left to
        right; it continues into the next repeat at column n_columns."""
        return tuple((j, self.chart.code(row, j)) for j in range(self.chart.n_columns))

    def connections(self, row: int) -> tuple[Connection, ...]:
        """The yarn between each loop of course `row` and the next loop along the yarn
        (one per loop of the repeat; the last one reaches into the next repeat)."""
        chart = self.chart
        columns = [j for j, code in self.course(row) if code in MODELLED_CODES]
        found = []
        for index, first in enumerate(columns):
            second = (
                columns[index + 1] if index + 1 < len(columns) else columns[0] + chart.n_columns
            )
            kind = SAME_FACE if chart.code(row, first) == chart.code(row, second) else CROSSING
            floats = tuple(range(first + 1, second))
            found.append(Connection(row, first, second, kind, floats))
        return tuple(found)

    def caught(self, row: int) -> tuple[int, ...]:
        """The columns of course `row` where its yarn is caught on a needle (K, P or T)."""
        return tuple(j for j, code in self.course(row) if code in LOOP_CODES)


def knit_graph(pattern) -> KnitGraph:
    """The knit graph of a Chart (or anything `pattern_chart` reads)."""
    return KnitGraph(pattern_chart(pattern))
