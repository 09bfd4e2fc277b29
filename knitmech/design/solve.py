"""The design's optimizer: bounded least squares over the design variables (scipy).

    minimize 1/2 sum_i r_i(x)^2  subject to lower <= x <= upper

by `scipy.optimize.least_squares` (trust-region reflective), its Jacobian by forward finite
differences (`SolverSettings.difference_step`, relative to max(1, |x|)); where the caller knows
which residuals a variable moves (`sparsity`, e.g. a sleeve's band pressure depends on its own
band's variables only) the differences are grouped, so a Jacobian costs as many evaluations as
the widest group, not one per variable. Every evaluation is counted and remembered (an x met
again is not evaluated again); the caller caches what is expensive on disk (a part's fabric
stage). `boxes` restarts the search in sub-boxes of the bounds and keeps the best: the graded
law has a kink at every member's stitch value, so a one-variable fit searches each member
interval.
"""

import logging
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.optimize

from rve_rod.errors import InputError, check_integer, check_positive

__all__ = [
    "Solution",
    "SolverSettings",
    "Variable",
    "solve_least_squares",
]

logger = logging.getLogger(__name__)


class Variable(NamedTuple):
    """A design variable.

    Attributes:
        name: what it sets (e.g. "band 3 stitch").
        lower, upper: its bounds.
        initial: where the search starts.
        unit: its unit ("mm" for a stitch value, "" for a needle count).
    """

    name: str
    lower: float
    upper: float
    initial: float
    unit: str = "mm"


@dataclass(frozen=True)
class SolverSettings:
    """Options of the least-squares search.

    Attributes:
        max_evaluations: evaluations of the residuals allowed per search (finite
            differences included).
        difference_step: forward-difference step relative to max(1, |x|).
        tolerance: the relative change of the cost, of x and the gradient's norm at which
            the search stops (scipy's ftol, xtol, gtol).
    """

    max_evaluations: int = 400
    difference_step: float = 1e-4
    tolerance: float = 1e-10

    def __post_init__(self):
        check_integer("design.max_evaluations", self.max_evaluations, 2, 100_000)
        check_positive("design.difference_step", self.difference_step)
        check_positive("design.tolerance", self.tolerance)


class Solution(NamedTuple):
    """The outcome of a search.

    Attributes:
        x: (n,) the best design found.
        residuals: (m,) the residuals there.
        cost: 1/2 sum r^2 there.
        evaluations: residual evaluations made (finite differences included; x met again
            is not counted again).
        message: why the search stopped.
        wall_time_s: time of the search (s).
    """

    x: np.ndarray
    residuals: np.ndarray
    cost: float
    evaluations: int
    message: str
    wall_time_s: float


class _Counted:
    """The residual function, counted and remembered by x, reporting progress."""

    def __init__(self, residuals, settings: SolverSettings, bounds: tuple[np.ndarray, np.ndarray]):
        self.residuals, self.settings, self.bounds = residuals, settings, bounds
        self.seen: dict[bytes, np.ndarray] = {}
        self.best = np.inf

    def __call__(self, x: np.ndarray) -> np.ndarray:
        x = np.clip(np.asarray(x, dtype=float), *self.bounds)  # round-off beyond a bound
        key = x.tobytes()
        if key not in self.seen:
            if len(self.seen) >= self.settings.max_evaluations:
                raise _EvaluationsSpentError
            values = np.asarray(self.residuals(np.array(x, dtype=float)), dtype=float)
            if not np.all(np.isfinite(values)):
                raise InputError(
                    f"the design's residuals at x={np.round(x, 6).tolist()} are not finite"
                )
            self.seen[key] = values
            cost = 0.5 * float(values @ values)
            if cost < self.best:
                self.best = cost
                shown = ", ".join(f"{value:.5g}" for value in x[:6])
                logger.info(
                    "design: evaluation %d, cost %.4g at (%s%s)",
                    len(self.seen),
                    cost,
                    shown,
                    ", ..." if x.size > 6 else "",
                )
        return self.seen[key]


class _EvaluationsSpentError(Exception):
    """The evaluations allowed are spent."""


def solve_least_squares(
    residuals: Callable[[np.ndarray], np.ndarray],
    variables: Sequence[Variable],
    settings: SolverSettings,
    *,
    sparsity: np.ndarray | None = None,
    boxes: Sequence[tuple[np.ndarray, np.ndarray]] | None = None,
) -> Solution:
    """Minimize 1/2 |residuals(x)|^2 within the variables' bounds (see the module docstring).

    Args:
        residuals: x (n,) -> r (m,), finite.
        variables: the n variables (bounds, start).
        settings: the search's options.
        sparsity: (m, n) True where residual i depends on variable j, or None (dense).
        boxes: sub-boxes (lower (n,), upper (n,)) of the bounds to search one by one (each
            from its centre, the start clipped into it); None: the bounds, from the start.

    Returns the best Solution over the boxes; when the evaluations run out, the best point
    evaluated so far.
    """
    if not variables:
        raise InputError("design: no variables to design")
    started = time.perf_counter()
    lower = np.array([v.lower for v in variables], dtype=float)
    upper = np.array([v.upper for v in variables], dtype=float)
    initial = np.array([v.initial for v in variables], dtype=float)
    for variable in variables:
        if not variable.lower < variable.upper:
            raise InputError(
                f"design variable {variable.name!r}: bounds [{variable.lower:g}, "
                f"{variable.upper:g}] {variable.unit} are empty"
            )
    counted = _Counted(residuals, settings, (lower, upper))
    messages = []
    for box_lower, box_upper in boxes or [(lower, upper)]:
        start = initial if boxes is None else 0.5 * (box_lower + box_upper)
        try:
            if boxes is not None:  # the box's ends: the search approaches them only
                counted(box_lower)
                counted(box_upper)
            result = scipy.optimize.least_squares(
                counted,
                start,
                jac="2-point",
                bounds=(box_lower, box_upper),
                method="trf",
                x_scale=upper - lower,
                diff_step=settings.difference_step,
                jac_sparsity=sparsity,
                ftol=settings.tolerance,
                xtol=settings.tolerance,
                gtol=settings.tolerance,
                max_nfev=settings.max_evaluations,
            )
            messages.append(result.message)
        except _EvaluationsSpentError:
            messages.append(f"the {settings.max_evaluations} evaluations allowed are spent")
            break
    keys = list(counted.seen)
    costs = [0.5 * float(counted.seen[key] @ counted.seen[key]) for key in keys]
    best = keys[int(np.argmin(costs))]
    x = np.frombuffer(best, dtype=float).copy()
    return Solution(
        x=x,
        residuals=counted.seen[best],
        cost=min(costs),
        evaluations=len(keys),
        message="; ".join(dict.fromkeys(messages)),
        wall_time_s=time.perf_counter() - started,
    )
