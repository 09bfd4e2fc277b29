"""The face chart of a stitch pattern: stitch codes, named patterns, user charts, and the
working-side instructions of hand knitting turned into the chart.

A chart is one repeat of the pattern on a torus, as the fabric's technical face shows it:
`rows[i][j]` is the stitch of course i (row 1 of a knitting chart is `rows[0]`, the first
course knitted, at the bottom) in wale j (from the left, as seen on the face). The repeat
tiles the plane: course i + n_rows is course i, wale j + n_columns is wale j. Codes: K, a knit
loop (pulled through the loop below from the back to the front: its legs show on the face);
P, a purl loop (pulled from the front to the back: its head and sinker show); T, M and I
(tuck, miss, inlay) are recognized so that a chart can name them, but no cell models them yet.

The trap: hand instructions are written from the working side. Flat knitting turns the work
after every row, so every second row is worked from the back of the fabric, in the opposite
direction, and a stitch knitted from the back shows as a purl on the face: "knit every row" is
garter, `("K", "P")` as a chart, not jersey. `chart_from_working_side` does the turning.
"""

from collections.abc import Sequence
from dataclasses import dataclass

from rve_rod.errors import InputError

__all__ = [
    "JERSEY",
    "LOOP_CODES",
    "MAX_CHART_SIZE",
    "MODELLED_CODES",
    "NAMED_PATTERNS",
    "STITCH_CODES",
    "Chart",
    "chart_from_working_side",
    "pattern_chart",
]

STITCH_CODES = {"K": "knit", "P": "purl", "T": "tuck", "M": "miss", "I": "inlay"}
"""The stitch codes a chart may hold and what they mean."""

LOOP_CODES = "KPT"
"""The codes that catch the course's yarn on the needle (a loop, or a tuck held by one)."""

MODELLED_CODES = "KP"
"""The codes the periodic cells are built of (`rve_rod.geometry.pattern_cell`)."""

MAX_CHART_SIZE = 24
"""Largest number of rows or columns of a chart (the repeats of textbook patterns have a few)."""

JERSEY = ("K",)
"""The chart of single jersey (plain knit), the pattern of every fabric that names none."""

NAMED_PATTERNS = {
    "jersey": JERSEY,
    "reverse-jersey": ("P",),
    "rib1x1": ("KP",),
    "rib2x2": ("KKPP",),
    "garter": ("K", "P"),
    "seed": ("KP", "PK"),
    "moss": ("KP", "KP", "PK", "PK"),
}
"""The named patterns and their face charts. "seed" is the US seed stitch (knit and purl
alternating in both directions; the UK calls it moss stitch); "moss" is the US moss stitch
(also double seed or Irish moss: the seed's checkerboard with two courses per row of squares)."""

_ROW_SEPARATOR = ","


@dataclass(frozen=True)
class Chart:
    """A face chart (module docstring); the rows are checked and upper-cased on creation.

    Attributes:
        rows: the courses of one repeat, bottom (first knitted) first, each a string of stitch
            codes as the face shows them, left to right.

    Raises:
        InputError: an empty chart, an unknown code, rows of unequal length, a chart larger
            than MAX_CHART_SIZE, or a chart whose yarn has no periodic path (a course that
            catches no needle, a wale that never forms a loop); one line naming the problem.
    """

    rows: tuple[str, ...]

    def __post_init__(self):
        object.__setattr__(self, "rows", _checked_rows(self.rows))

    @property
    def n_rows(self) -> int:
        """Courses of one repeat."""
        return len(self.rows)

    @property
    def n_columns(self) -> int:
        """Wales of one repeat."""
        return len(self.rows[0])

    def code(self, row: int, column: int) -> str:
        """The stitch code of course `row`, wale `column` (any integers: the chart repeats)."""
        return self.rows[row % self.n_rows][column % self.n_columns]

    @property
    def name(self) -> str:
        """The named pattern this chart is, or "" (a shifted repeat is another chart)."""
        for name, rows in NAMED_PATTERNS.items():
            if rows == self.rows:
                return name
        return ""

    def label(self) -> str:
        """The name, else the rows joined by commas (as `pattern_chart` reads them)."""
        return self.name or _ROW_SEPARATOR.join(self.rows)

    def check_modelled(self) -> None:
        """Raise InputError unless every stitch is one the cells model (MODELLED_CODES)."""
        for i, row in enumerate(self.rows):
            for j, code in enumerate(row):
                if code not in MODELLED_CODES:
                    name = STITCH_CODES[code]
                    article = "an" if name[0] in "aeiou" else "a"
                    raise InputError(
                        f"chart row {i + 1} ({row!r}) has {article} {name} ({code!r}) in "
                        f"column {j + 1}: the cell does not model it yet; its loops are knit "
                        "(K) and purl (P)"
                    )


def pattern_chart(pattern) -> Chart:
    """The chart of `pattern`: a Chart, a name of NAMED_PATTERNS, a sequence of rows, or one
    string of rows separated by commas ("KP,PK"; bottom row first).

    Raises:
        InputError: an unknown name, or a chart `Chart` refuses (one line naming the problem).
    """
    if isinstance(pattern, Chart):
        return pattern
    if isinstance(pattern, str):
        text = pattern.strip()
        if text.lower() in NAMED_PATTERNS:
            return Chart(NAMED_PATTERNS[text.lower()])
        rows = text.split(_ROW_SEPARATOR)
        if not all(row.strip() and row.strip().isalpha() for row in rows):
            raise InputError(
                f"pattern={pattern!r} is unknown: give a named pattern "
                f"({', '.join(NAMED_PATTERNS)}) or a chart, rows of stitch codes "
                f"({', '.join(STITCH_CODES)}) separated by commas, bottom row first"
            )
        if len(rows) == 1 and not set(text.upper()) <= set(STITCH_CODES):
            raise InputError(
                f"pattern={pattern!r} is unknown: named patterns are {', '.join(NAMED_PATTERNS)}"
                f" (or give a chart of the stitch codes {', '.join(STITCH_CODES)})"
            )
        return Chart(tuple(rows))
    if isinstance(pattern, Sequence):
        return Chart(tuple(pattern))
    raise InputError(
        f"pattern={pattern!r} is neither a pattern name nor a chart (a list of rows of stitch "
        "codes)"
    )


def chart_from_working_side(rows: Sequence[str], *, flat: bool = True) -> Chart:
    """The face chart of hand instructions written from the working side.

    Args:
        rows: the rows in the order they are worked, the first one from the right side (the
            face), each in the order its stitches are worked: right to left as the face shows
            them when worked from the right side, left to right from the wrong side.
        flat: flat knitting (the work is turned after every row: rows 2, 4, ... are worked
            from the wrong side); False for knitting in the round (every row from the face).

    A right-side row reads reversed on the face; a wrong-side row keeps its order as the face
    shows it, and each of its stitches shows the other way (K worked from the back is a P on
    the face, and P a K): flat "knit every row" is garter, flat "knit a row, purl a row" is
    jersey, and in the round "knit every row" is jersey.
    """
    turned = {"K": "P", "P": "K"}
    face = []
    for index, row in enumerate(_checked_rows(rows)):
        if flat and index % 2 == 1:
            face.append("".join(turned.get(code, code) for code in row))
        else:
            face.append(row[::-1])
    return Chart(tuple(face))


def _checked_rows(rows) -> tuple[str, ...]:
    """The rows upper-cased and stripped, or InputError naming the first problem."""
    if isinstance(rows, str) or not isinstance(rows, Sequence):
        raise InputError(f"chart={rows!r} must be a list of rows (strings of stitch codes)")
    if not rows:
        raise InputError("chart=[] is empty: give at least one row of stitch codes")
    if len(rows) > MAX_CHART_SIZE:
        raise InputError(
            f"chart has {len(rows)} rows, outside the valid range [1, {MAX_CHART_SIZE}]"
        )
    checked = []
    for i, row in enumerate(rows):
        if not isinstance(row, str):
            raise InputError(f"chart row {i + 1} ({row!r}) is not a string of stitch codes")
        text = row.strip().upper()
        if not text:
            raise InputError(f"chart row {i + 1} is empty: give at least one stitch code")
        for j, code in enumerate(text):
            if code not in STITCH_CODES:
                raise InputError(
                    f"chart row {i + 1} ({row!r}) has the unknown stitch code {code!r} in "
                    f"column {j + 1}; valid codes: "
                    + ", ".join(f"{key} ({meaning})" for key, meaning in STITCH_CODES.items())
                )
        checked.append(text)
    lengths = [len(row) for row in checked]
    if len(set(lengths)) > 1:
        longer = next(i for i, length in enumerate(lengths) if length != lengths[0])
        raise InputError(
            f"chart rows have unequal lengths: row 1 has {lengths[0]} stitches, row "
            f"{longer + 1} has {lengths[longer]} (every row of a repeat has as many stitches)"
        )
    if lengths[0] > MAX_CHART_SIZE:
        raise InputError(
            f"chart rows have {lengths[0]} stitches, outside the valid range [1, {MAX_CHART_SIZE}]"
        )
    for i, row in enumerate(checked):
        if not any(code in LOOP_CODES for code in row):
            raise InputError(
                f"chart row {i + 1} ({row!r}) catches its yarn on no needle: that course's "
                "yarn has no periodic path through the loops (a row needs a K, P or T)"
            )
    for j in range(lengths[0]):
        column = "".join(row[j] for row in checked)
        if not any(code in MODELLED_CODES for code in column):
            raise InputError(
                f"chart column {j + 1} ({column!r} from the bottom) never forms a loop: no "
                "wale holds it, and the yarn has no periodic path there (a column needs a K "
                "or P)"
            )
    return tuple(checked)
