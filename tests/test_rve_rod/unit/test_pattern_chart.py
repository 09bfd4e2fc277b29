"""Stitch patterns, topology: the face chart, the working-side trap, the knit graph, the
smallest periodic cell and its lattice, and the one-line refusal of bad charts."""

import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.pattern import (
    NAMED_PATTERNS,
    Chart,
    chart_from_working_side,
    knit_graph,
    pattern_chart,
    periodic_cell,
    smallest_cell,
)
from rve_rod.pattern.graph import CROSSING, SAME_FACE
from rve_rod.pattern.lattice import translations

# the lattices (wales, courses) the issue and the textbooks give for the named patterns
LATTICES = {
    "jersey": ((1, 0), (0, 1)),
    "reverse-jersey": ((1, 0), (0, 1)),
    "rib1x1": ((2, 0), (0, 1)),
    "rib2x2": ((4, 0), (0, 1)),
    "garter": ((1, 0), (0, 2)),
    "seed": ((2, 0), (1, 1)),
    "moss": ((2, 0), (1, 2)),
}


def test_every_named_pattern_has_a_lattice_here():
    assert set(LATTICES) == set(NAMED_PATTERNS)


@pytest.mark.parametrize("name", sorted(LATTICES))
def test_named_patterns_have_their_smallest_cells(name):
    cell = smallest_cell(name)
    assert cell.lattice == LATTICES[name]
    assert cell.chart.name == name


@pytest.mark.parametrize(
    "rows",
    [*NAMED_PATTERNS.values(), ("KPP", "PKP", "PPK"), ("KKP", "KPP"), ("KPPP", "PPKP"), ("KK",)],
)
def test_the_cell_repeats_the_chart_and_no_smaller_cell_does(rows):
    """Independent of how the basis is found: the cell's loops are the chart's up to its
    lattice (every chart position lies on a cell loop of the same stitch), and the cell holds
    as many loops as the torus divided by its symmetries (the index of the translations)."""
    chart = Chart(rows)
    cell = smallest_cell(chart)
    codes = [cell.code(index) for index in range(cell.n_loops)]
    for row in range(-5, 9):
        for column in range(-7, 11):
            index, (a, b) = cell.locate(row, column)
            loop_row, loop_column = cell.loops()[index]
            (p, _), (q, s) = cell.lattice
            assert (loop_column + a * p + b * q, loop_row + b * s) == (column, row)
            assert codes[index] == chart.code(row, column)
    assert cell.n_loops * len(translations(chart)) == chart.n_rows * chart.n_columns
    (p, _), (q, s) = cell.lattice
    assert -p / 2 < q <= p / 2


def test_an_oblique_diagonal_chart():
    assert smallest_cell(["KPP", "PKP", "PPK"]).lattice == ((3, 0), (1, 1))
    assert smallest_cell(["KPP", "PPK", "PKP"]).lattice == ((3, 0), (-1, 1))


def test_lattice_vectors_in_millimetres():
    np.testing.assert_array_equal(
        smallest_cell("seed").vectors(1.3, 1.2), [[2.6, 0.0, 0.0], [1.3, 1.2, 0.0]]
    )
    np.testing.assert_array_equal(
        smallest_cell("garter").vectors(1.3, 1.2), [[1.3, 0.0, 0.0], [0.0, 2.4, 0.0]]
    )


def test_a_supercell_on_a_given_lattice_and_lattices_that_do_not_repeat_the_chart():
    assert periodic_cell("jersey", ((2, 0), (0, 1))).n_loops == 2
    assert periodic_cell("seed", ((2, 0), (-1, 1))).lattice == ((2, 0), (-1, 1))
    assert periodic_cell("seed", ((2, 0), (0, 2))).n_loops == 4
    for lattice in (((1, 0), (0, 1)), ((2, 0), (0, 1)), ((2, 1), (0, 1)), ((0, 0), (1, 1))):
        with pytest.raises(InputError, match="lattice"):
            periodic_cell("seed", lattice)


# -- the working-side trap ------------------------------------------------------------------


@pytest.mark.parametrize(
    ("worked", "flat", "face"),
    [
        (["K", "K"], True, ("K", "P")),  # flat "knit every row": garter
        (["K", "P"], True, ("K", "K")),  # flat "knit a row, purl a row": jersey
        (["K"], False, ("K",)),  # in the round "knit every row": jersey
        (["KP", "KP"], True, ("PK", "PK")),  # flat K1 P1 on an even count: 1x1 rib
        (["KP", "PK"], True, ("PK", "KP")),  # flat K1 P1, P1 K1: seed
        (["KKP", "KKP"], True, ("PKK", "PPK")),  # a wrong-side row keeps the face's order
    ],
)
def test_working_side_instructions_become_the_face_chart(worked, flat, face):
    assert chart_from_working_side(worked, flat=flat).rows == face


def test_garter_written_as_knitted_is_not_jersey():
    """The trap: 'knit every row' read as a chart would be jersey; turned, it is garter."""
    assert smallest_cell(Chart(("K", "K"))).lattice == LATTICES["jersey"]
    assert smallest_cell(chart_from_working_side(["K", "K"])).lattice == LATTICES["garter"]
    assert smallest_cell(chart_from_working_side(["KP", "KP"])).lattice == LATTICES["rib1x1"]
    assert smallest_cell(chart_from_working_side(["KP", "PK"])).lattice == LATTICES["seed"]


# -- the knit graph -------------------------------------------------------------------------


def test_loops_are_pulled_through_the_loop_below_from_the_side_of_their_code():
    graph = knit_graph("seed")
    assert graph.loops() == ((0, 0), (0, 1), (1, 0), (1, 1))
    assert graph.pulled_through(0, 1) == ((-1, 1),)
    assert [graph.side(i, j) for i, j in graph.loops()] == [1, -1, -1, 1]


def test_a_tuck_is_held_with_the_loop_below_it():
    graph = knit_graph(["K", "T", "K"])
    assert graph.pulled_through(2, 0) == ((1, 0), (0, 0))
    assert graph.loops() == ((0, 0), (2, 0))
    assert graph.caught(1) == (0,)


@pytest.mark.parametrize(
    ("pattern", "kinds"),
    [
        ("jersey", [SAME_FACE]),
        ("rib1x1", [CROSSING, CROSSING]),
        ("rib2x2", [SAME_FACE, CROSSING, SAME_FACE, CROSSING]),
        ("garter", [SAME_FACE]),
    ],
)
def test_the_yarn_between_consecutive_loops_stays_on_a_face_or_crosses(pattern, kinds):
    connections = knit_graph(pattern).connections(0)
    assert [connection.kind for connection in connections] == kinds
    assert [connection.second - connection.first for connection in connections] == [1] * len(kinds)


def test_a_float_over_a_missed_stitch():
    (connection,) = knit_graph(["KM", "KK"]).connections(0)
    assert (connection.first, connection.second, connection.floats) == (0, 2, (1,))
    assert connection.kind == SAME_FACE


# -- bad input: one line naming the problem -------------------------------------------------


@pytest.mark.parametrize(
    ("pattern", "message"),
    [
        ("ribb", "pattern='ribb' is unknown: named patterns are jersey, reverse-jersey"),
        (["KX"], "chart row 1 \\('KX'\\) has the unknown stitch code 'X' in column 2"),
        (["KP", "KPP"], "unequal lengths: row 1 has 2 stitches, row 2 has 3"),
        ([], "chart=\\[\\] is empty"),
        (["KP", ""], "chart row 2 is empty"),
        (["KK", "MI"], "chart row 2 \\('MI'\\) catches its yarn on no needle"),
        (["KM"], "chart column 2 \\('M' from the bottom\\) never forms a loop"),
        (["KT", "KT"], "chart column 2 \\('TT' from the bottom\\) never forms a loop"),
        (["K" * 25], "outside the valid range \\[1, 24\\]"),
        ("KP,P1", "pattern='KP,P1' is unknown: give a named pattern"),
        (42, "neither a pattern name nor a chart"),
        ("KP", None),
    ],
)
def test_bad_charts_are_refused_with_one_line_naming_the_problem(pattern, message):
    if message is None:
        assert pattern_chart(pattern).rows == ("KP",)
        return
    with pytest.raises(InputError, match=message) as error:
        pattern_chart(pattern)
    assert "\n" not in str(error.value)


def test_tucks_and_misses_are_charted_but_not_modelled():
    chart = Chart(("KT", "KK"))
    assert chart.label() == "KT,KK"
    with pytest.raises(InputError, match="row 1 \\('KT'\\) has a tuck \\('T'\\) in column 2"):
        chart.check_modelled()
    with pytest.raises(InputError, match="row 2 \\('KM'\\) has a miss \\('M'\\) in column 2"):
        Chart(("KK", "KM")).check_modelled()
    with pytest.raises(InputError, match="row 1 \\('IK'\\) has an inlay \\('I'\\) in column 1"):
        Chart(("IK", "KK")).check_modelled()
    Chart(("KP",)).check_modelled()


def test_names_labels_and_case():
    assert pattern_chart("Rib1x1") == Chart(("KP",))
    assert pattern_chart("kp,pk").name == "seed"
    assert pattern_chart(["pk"]).label() == "PK"
    assert pattern_chart("garter").label() == "garter"
