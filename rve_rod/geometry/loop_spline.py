"""The loop's B-spline: the constrained least-squares fit of the quarter and its mirroring.

The quarter of the analytic loop (`rve_rod.geometry.loop.LoopShape`) is fitted by a degree-4
B-spline with 12 control points (least squares in arc length, with the end conditions that make
the mirrored loop C2, and the widest point W pinned) and mirrored by the loop's two symmetries,
x -> -x (about the head apex) and (x, y) -> (w/2 - x, -y) (about the leg point L), into the 4
curves of one loop from sinker to sinker (docs/geometry.md derives the conditions).
"""

from functools import cache, lru_cache
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from rve_rod.geometry.bspline import BSplineCurve, basis_functions, basis_matrix, open_knot_vector

if TYPE_CHECKING:
    from rve_rod.geometry.loop import LoopShape, QuarterSamples

__all__ = [
    "CONTROL_POINTS",
    "DEGREE",
    "SymmetryCondition",
    "assembled_loop",
    "condition_rows",
    "fit_coordinate",
    "fit_fractions",
    "fit_quarter",
    "mirrored_loop",
    "symmetry_conditions",
]

DEGREE = 4
"""Degree of the loop curves (the paper's geometry)."""
CONTROL_POINTS = 12
"""Control points of each quarter curve before refinement."""
_FIT_SAMPLES = 121


def mirrored_loop(quarter: BSplineCurve, wale_width: float) -> tuple[BSplineCurve, ...]:
    """The 4 curves of one loop from the quarter running from the head apex to L.

    Curve 2 is the quarter; curve 1 its mirror image in x = 0 (reversed, from L' to the apex);
    curve 3 its image under (x, y) -> (w/2 - x, -y) (reversed, from L to the sinker); curve 0
    the mirror image of curve 3 (from the previous sinker to L').
    """
    return assembled_loop(quarter, quarter, quarter, wale_width)


def assembled_loop(
    head: BSplineCurve, left_foot: BSplineCurve, right_foot: BSplineCurve, wale_width: float
) -> tuple[BSplineCurve, ...]:
    """The 4 curves of one loop from three quarters that share the knots and the x-y shape
    but may differ in z (a loop of a stitch pattern, `rve_rod.geometry.pattern_cell`): `head`
    gives curves 2 and 1 as in `mirrored_loop`, `right_foot` curve 3 and `left_foot` curve 0
    (each foot quarter runs from its sinker, at the quarter's apex, to L)."""
    mirror = np.array([-1.0, 1.0, 1.0])

    def turned(quarter: BSplineCurve) -> np.ndarray:
        points = quarter.control_points
        return np.column_stack([wale_width / 2 - points[:, 0], -points[:, 1], points[:, 2]])

    knots = 1.0 - head.knots[::-1]
    return (
        BSplineCurve(head.degree, knots, (turned(left_foot) * mirror)),
        BSplineCurve(head.degree, knots, (head.control_points * mirror)[::-1]),
        head,
        BSplineCurve(head.degree, knots, turned(right_foot)[::-1]),
    )


class SymmetryCondition(NamedTuple):
    """A linear condition on one coordinate of the quarter: its derivative of order `order` at
    the parameter `at` equals `value` (mm)."""

    at: float
    order: int
    value: float


def symmetry_conditions(wale_width: float) -> tuple[tuple[SymmetryCondition, ...], ...]:
    """The end conditions (x, y and z, one tuple each) that make the mirrored loop C2.

    At the apex (u = 0, mirror x -> -x) x = 0, x'' = 0, y' = 0, z' = 0; at the leg point
    (u = 1, symmetry (x, y, z) -> (w/2 - x, -y, z)) x = w/4, y = 0, x'' = y'' = 0, z' = 0
    (docs/geometry.md derives them).
    """
    return (
        (
            SymmetryCondition(0.0, 0, 0.0),
            SymmetryCondition(0.0, 2, 0.0),
            SymmetryCondition(1.0, 0, wale_width / 4),
            SymmetryCondition(1.0, 2, 0.0),
        ),
        (
            SymmetryCondition(0.0, 1, 0.0),
            SymmetryCondition(1.0, 0, 0.0),
            SymmetryCondition(1.0, 2, 0.0),
        ),
        (SymmetryCondition(0.0, 1, 0.0), SymmetryCondition(1.0, 1, 0.0)),
    )


def condition_rows(conditions: tuple[SymmetryCondition, ...]) -> np.ndarray:
    """The conditions as rows acting on one coordinate of the quarter's control points, (k, 12)."""
    return np.array([_rows_at(condition.at)[condition.order] for condition in conditions])


def fit_quarter(shape: "LoopShape", sampled: "QuarterSamples | None" = None) -> BSplineCurve:
    """Constrained least-squares fit of the quarter: 12 control points, degree 4.

    The `symmetry_conditions` make the mirrored loop C2. The curve also passes through the
    widest point W with x' = 0 there, so that the built-in contacts are exactly 2r in the
    spline as in the analytic model. `sampled`: the shape's `quarter_samples` at
    `fit_fractions()` where the caller has them already.
    """
    if sampled is None:
        sampled = shape.quarter_samples(fit_fractions())
    knots = open_knot_vector(DEGREE, CONTROL_POINTS)
    at, widest = sampled.shoulder_fraction, sampled.shoulder
    pinned = (
        (SymmetryCondition(at, 0, widest[0]), SymmetryCondition(at, 1, 0.0)),
        (SymmetryCondition(at, 0, widest[1]),),
        (SymmetryCondition(at, 0, widest[2]),),
    )
    control = np.empty((CONTROL_POINTS, 3))
    for axis, symmetric in enumerate(symmetry_conditions(shape.wale_width)):
        control[:, axis] = fit_coordinate(sampled.points[:, axis], symmetric + pinned[axis])
    return BSplineCurve(DEGREE, knots, control)


def fit_coordinate(values: np.ndarray, conditions: tuple[SymmetryCondition, ...]) -> np.ndarray:
    """The 12 control values of one coordinate of the quarter: least squares to its `values`
    (mm) at the fit samples (`fit_fractions`) subject to the linear `conditions` (KKT system)."""
    design = _design_matrix()
    n = CONTROL_POINTS
    k = len(conditions)
    kkt = np.zeros((n + k, n + k))
    rows = condition_rows(conditions)
    kkt[:n, :n] = _normal_matrix()
    kkt[:n, n:] = rows.T
    kkt[n:, :n] = rows
    rhs = np.concatenate([design.T @ values, [condition.value for condition in conditions]])
    return np.linalg.solve(kkt, rhs)[:n]


def fit_fractions() -> np.ndarray:
    """Arc-length fractions of the quarter at which it is sampled for the fit."""
    return np.linspace(0.0, 1.0, _FIT_SAMPLES)


def _basis_rows(params) -> np.ndarray:
    """Basis functions of the quarter and their first two derivatives at `params`, dense
    (3, m, control points)."""
    knots = open_knot_vector(DEGREE, CONTROL_POINTS)
    basis = basis_functions(knots, DEGREE, np.asarray(params, dtype=float), 2)
    rows = np.zeros((3, basis.spans.size, CONTROL_POINTS))
    columns = basis.spans[:, None] - DEGREE + np.arange(DEGREE + 1)
    rows[:, np.arange(basis.spans.size)[:, None], columns] = basis.values
    return rows


@lru_cache(maxsize=256)
def _rows_at(at: float) -> np.ndarray:
    """The basis functions of the quarter and their first two derivatives at the parameter
    `at`, (3, control points); remembered: the end conditions sit at 0 and 1 in every fit, and
    the three coordinates of one fit are pinned at the same W (the relaxed cell's searches fit
    thousands of quarters)."""
    rows = _basis_rows([at])[:, 0, :]
    rows.flags.writeable = False
    return rows


@cache
def _normal_matrix() -> np.ndarray:
    """design^T design of `_design_matrix` (control points, control points); read-only."""
    design = _design_matrix()
    normal = design.T @ design
    normal.flags.writeable = False
    return normal


@cache
def _design_matrix() -> np.ndarray:
    """Basis functions of the quarter at the fit samples, (samples, control points)."""
    knots = open_knot_vector(DEGREE, CONTROL_POINTS)
    return basis_matrix(knots, DEGREE, fit_fractions()).toarray()
