"""The material-level inverse: the stitch value whose uniaxial curves fit target curves.

Given target forces per width at a few engineering strains, course-wise and/or wale-wise (typed
into the design table, or a measured curve as CSV), find the stitch value s of the family
(`knitmech.design.family`) whose homogeneous uniaxial response F(eps; s) (lateral stress 0,
the RVE's uniaxial load case) fits them best in the least-squares sense:

    minimize  sum_targets sum_i [ w_t (F(eps_i; s) - F_i) / max_i |F_i| ]^2
    over s in [s_0, s_n] (the family's range, or the bounds given).

Each target curve is scaled by its largest force, so a course-wise and a wale-wise curve
weigh alike however different their forces. Between two neighbouring members the law is
linear in s and F smooth; at a member value it has a kink. The search therefore runs one
bounded least-squares solve per member interval (`knitmech.design.solve`) and keeps the best:
a target that a member reproduces is met exactly at that member's value.
"""

from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np

from fabric_dolfinx.spec.table import read_table
from knitmech.design.family import SurfaceFamily
from knitmech.design.solve import Solution, SolverSettings, Variable, solve_least_squares
from rve_rod.errors import InputError
from rve_rod.units import GRAM_FORCE

__all__ = [
    "CURVE_COLUMNS",
    "DIRECTIONS",
    "FORCE_UNITS",
    "MaterialFit",
    "UniaxialTarget",
    "fit_stitch",
    "read_curve",
    "uniaxial_residuals",
]

DIRECTIONS = ("course", "wale")

FORCE_UNITS = {"N/mm": 1.0, "gf/cm": GRAM_FORCE / 10.0}
"""Units of a target's force per width -> the factor to N/mm."""

CURVE_COLUMNS = {"force_n_per_mm": "N/mm", "force_gf_per_cm": "gf/cm"}
"""A curve file's force column -> its unit (the other column is `strain`)."""


class UniaxialTarget(NamedTuple):
    """A target uniaxial curve.

    Attributes:
        direction: "course" or "wale".
        strain: (m,) engineering strains (-), increasing, > 0.
        force: (m,) force per width (N/mm) at those strains.
        weight: the curve's weight in the least-squares sum.
        tolerance: met when every |F - F_i| <= tolerance * max |F_i|.
        source: where it came from (a file, or "values").
    """

    direction: str
    strain: np.ndarray
    force: np.ndarray
    weight: float = 1.0
    tolerance: float = 0.05
    source: str = "values"

    def check(self, name: str) -> "UniaxialTarget":
        """The target with arrays, or InputError naming `name` and what is wrong."""
        if self.direction not in DIRECTIONS:
            raise InputError(f"{name}.direction: {self.direction!r} is not course or wale")
        strain = np.asarray(self.strain, dtype=float)
        force = np.asarray(self.force, dtype=float)
        if strain.ndim != 1 or strain.shape != force.shape or strain.size < 1:
            raise InputError(
                f"{name}: strain and force need the same number (>= 1) of values, got "
                f"{strain.size} and {force.size}"
            )
        if not (np.all(np.isfinite(strain)) and np.all(np.isfinite(force))):
            raise InputError(f"{name}: strain and force must be finite numbers")
        if np.any(strain <= 0.0) or np.any(strain > 1.0) or np.any(np.diff(strain) <= 0.0):
            raise InputError(
                f"{name}.strain: {strain.tolist()} must increase within (0, 1] (engineering)"
            )
        if np.all(force == 0.0):
            raise InputError(f"{name}.force: all forces are 0; nothing to fit")
        return self._replace(strain=strain, force=force)

    def predicted(self, family: SurfaceFamily, stitch: float) -> np.ndarray:
        """(m,) the family's uniaxial force per width (N/mm) at `stitch` and these strains."""
        return family.uniaxial(stitch, self.strain, self.direction)

    def miss(self, predicted: np.ndarray) -> float:
        """The largest |F - F_i| over the curve relative to its largest |F_i|."""
        return float(np.max(np.abs(predicted - self.force)) / np.max(np.abs(self.force)))


def uniaxial_residuals(
    family: SurfaceFamily, targets: Sequence[UniaxialTarget], stitch: float
) -> np.ndarray:
    """The scaled residuals w_t (F(eps_i; s) - F_i) / max |F_i| of every target, stacked."""
    return np.concatenate(
        [
            target.weight
            * (target.predicted(family, stitch) - target.force)
            / np.max(np.abs(target.force))
            for target in targets
        ]
    )


class MaterialFit(NamedTuple):
    """The stitch value that fits target curves best.

    Attributes:
        stitch: the best stitch value (mm).
        predicted: per target, (m,) the family's uniaxial force per width there (N/mm).
        misses: per target, its largest deviation relative to its largest force.
        met: whether every target is within its tolerance.
        solution: the search's record (evaluations, time, message).
    """

    stitch: float
    predicted: tuple[np.ndarray, ...]
    misses: tuple[float, ...]
    met: bool
    solution: Solution


def fit_stitch(
    family: SurfaceFamily,
    targets: Sequence[UniaxialTarget],
    settings: SolverSettings | None = None,
    bounds: tuple[float, float] | None = None,
) -> MaterialFit:
    """The stitch value within `bounds` (default: the family's range, mm) whose uniaxial
    curves fit `targets` best (module docstring): one bounded search per member interval."""
    if not targets:
        raise InputError("design: no target curves to fit")
    low, high = bounds if bounds is not None else family.stitch_range
    low = family.check_stitch("stitch lower bound", low)
    high = family.check_stitch("stitch upper bound", high)
    knots = np.unique(np.clip([low, *family.stitch_values, high], low, high))
    boxes = [(knots[i : i + 1], knots[i + 1 : i + 2]) for i in range(knots.size - 1)]
    variable = Variable("stitch", low, high, 0.5 * (low + high))
    solution = solve_least_squares(
        lambda x: uniaxial_residuals(family, targets, x[0]),
        [variable],
        settings or SolverSettings(),
        boxes=boxes,
    )
    stitch = float(solution.x[0])
    predicted = tuple(target.predicted(family, stitch) for target in targets)
    misses = tuple(t.miss(p) for t, p in zip(targets, predicted, strict=True))
    met = all(m <= t.tolerance for t, m in zip(targets, misses, strict=True))
    return MaterialFit(stitch, predicted, misses, met, solution)


def read_curve(path: str | Path, name: str = "curve") -> tuple[np.ndarray, np.ndarray]:
    """(strain (m,), force per width (m,) N/mm) of a CSV file with a header naming the
    columns `strain` (engineering, -) and one of CURVE_COLUMNS; InputError naming `name`,
    the file and the problem otherwise (`fabric_dolfinx.spec.table`)."""
    table = read_table(path, name, (("strain",), tuple(CURVE_COLUMNS)))
    column = next(c for c in CURVE_COLUMNS if c in table)
    return table["strain"], table[column] * FORCE_UNITS[CURVE_COLUMNS[column]]
