"""Adaptive load stepping: the one step controller of both scales' Newton solvers.

A load path runs from a start load factor t0 through increasing targets t1 < t2 < ... (the
requested output states). `StepController` proposes the next load factor to try; the solver
runs Newton there and reports the outcome:

* accepted (converged, and the state is admissible): the path moves on; after an easy step
  (at most `easy_iterations` Newton iterations) the increment grows by `growth_factor`, up
  to `max_increment`. Every target is reached exactly.
* rejected (Newton failed, or the converged state was refused): the increment is cut to half
  of the one that failed, and the solver retries from the last accepted state. The path
  stops when the increment falls below `min_increment` or more than `max_cutbacks` attempts
  in a row failed; what was accepted up to there is kept by the solver.

The controller knows nothing of states or equations, so both solvers share it and this
vocabulary (docs/rod.md, docs/fabric.md):

    SteppingOptions  initial_increment, max_increment, min_increment, max_cutbacks,
                     growth_factor, easy_iterations, extrapolate
    NewtonResult     converged, iterations, residual_norms, reason (one solve at fixed t)
    StepRecord       load_factor, iterations, residual_norms, substeps, cutbacks
    PathResult       steps, newton_iterations (failed attempts included), cutbacks

`rve_rod.newton` (SuperLU, the rod RVE) and `fabric_dolfinx.solve` (PETSc, the membrane) each
define their NewtonResult, StepRecord and PathResult with these fields plus their own.
"""

import logging
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rve_rod.errors import InputError, check_integer, check_positive

__all__ = ["StepController", "StepCount", "SteppingOptions"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class SteppingOptions:
    """Options of the load stepping.

    Attributes:
        initial_increment: first load-factor increment (default 1: try the whole way).
        max_increment: largest increment (1).
        min_increment: smallest increment before giving up (1e-6).
        max_cutbacks: consecutive failed attempts allowed before giving up (16).
        growth_factor: increment growth after an easy step (2).
        easy_iterations: a step with at most this many Newton iterations is easy (5).
        extrapolate: start each Newton solve from the linear extrapolation of the last two
            accepted states instead of the last one (True; the membrane's default
            `SolverOptions.stepping_options()` turns it off).
    """

    initial_increment: float = 1.0
    max_increment: float = 1.0
    min_increment: float = 1e-6
    max_cutbacks: int = 16
    growth_factor: float = 2.0
    easy_iterations: int = 5
    extrapolate: bool = True

    def __post_init__(self):
        check_positive("initial_increment", self.initial_increment)
        check_positive("max_increment", self.max_increment)
        check_positive("min_increment", self.min_increment)
        check_integer("max_cutbacks", self.max_cutbacks, 0)
        if self.growth_factor < 1.0:
            raise InputError(f"growth_factor={self.growth_factor} must be >= 1")
        check_integer("easy_iterations", self.easy_iterations, 1)


class StepCount(NamedTuple):
    """What an accepted step completed.

    Attributes:
        reached: whether it reached the current target.
        substeps: accepted steps since the previous target, this one included.
        cutbacks: failed attempts since the previous target.
    """

    reached: bool
    substeps: int
    cutbacks: int


class StepController:
    """The adaptive load factor of one path (module docstring).

    Use: while not `finished`: t = `trial()`; solve at t; then `accept(t, iterations)` or
    `reject(t)`, which returns True when the path must stop.

    Attributes:
        options: the SteppingOptions.
        targets: the requested load factors, increasing from `start`.
        load_factor: the last accepted load factor (`start` before the first step).
        previous: the accepted load factor before `load_factor`, or None.
        increment: the increment of the next trial.
        substeps: accepted steps since the previous target.
        cutbacks: failed attempts since the previous target.
        consecutive: failed attempts since the last accepted step.
        total_cutbacks: all failed attempts of the path.
    """

    def __init__(
        self, targets: Sequence[float], options: SteppingOptions, start: float = 0.0
    ) -> None:
        values = np.asarray(targets, dtype=float)
        if values.ndim != 1 or values.size == 0 or np.any(np.diff(np.r_[start, values]) <= 0):
            raise InputError(
                f"load_factors must increase strictly from start={start}: {values.tolist()}"
            )
        self.options = options
        self.targets = tuple(float(value) for value in values)
        self.load_factor = float(start)
        self.previous: float | None = None
        self.increment = min(options.initial_increment, options.max_increment)
        self.consecutive = 0
        self.total_cutbacks = 0
        self.substeps = 0
        self.cutbacks = 0
        self._index = 0

    @property
    def finished(self) -> bool:
        """Whether every target was reached."""
        return self._index == len(self.targets)

    @property
    def target(self) -> float:
        """The target the path is heading for."""
        return self.targets[self._index]

    def trial(self) -> float:
        """The next load factor to try: the last accepted one plus the increment, never past
        the target (a gap below 1e-12 relative to it is closed)."""
        target = self.target
        trial = min(self.load_factor + self.increment, target)
        if target - trial < 1e-12 * max(1.0, abs(target)):
            trial = target
        return trial

    def accept(self, trial: float, iterations: int) -> StepCount:
        """Record an accepted state at `trial` reached in `iterations` Newton iterations."""
        options = self.options
        self.previous, self.load_factor = self.load_factor, trial
        self.substeps += 1
        self.consecutive = 0
        if iterations <= options.easy_iterations:
            self.increment = min(self.increment * options.growth_factor, options.max_increment)
        reached = trial == self.target
        count = StepCount(reached, self.substeps, self.cutbacks)
        if reached:
            self._index += 1
            self.substeps = self.cutbacks = 0
        return count

    def reject(self, trial: float) -> bool:
        """Cut the increment back after a failed attempt at `trial`; True when the path must
        stop (increment below min_increment, or more than max_cutbacks failures in a row)."""
        self.cutbacks += 1
        self.consecutive += 1
        self.total_cutbacks += 1
        self.increment = 0.5 * (trial - self.load_factor)
        return (
            self.increment < self.options.min_increment
            or self.consecutive > self.options.max_cutbacks
        )
