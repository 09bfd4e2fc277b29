"""Typed errors shared by both scales, and the checks that raise them for bad input.

`InputError` is what a user can fix (a parameter outside its valid range); the command-line
tools print its one-line message and exit with status 2. `ConvergenceError` is what a solver
raises when it cannot go on; it carries everything that converged before it stopped.
"""

import math
import numbers
from typing import Any


class InputError(ValueError):
    """A parameter is outside its valid range; the message names parameter, value and range."""


class ConvergenceError(RuntimeError):
    """A nonlinear solve failed even after cutting the load step back.

    Attributes:
        last_converged: the solver's last converged state (solver-specific object) or None.
        history: the results of all converged steps (solver-specific object) or None.
    """

    def __init__(self, message: str, last_converged: Any = None, history: Any = None):
        super().__init__(message)
        self.last_converged = last_converged
        self.history = history


def _format(value: float) -> str:
    return f"{value:.6g}"


def check_finite(name: str, value: float, unit: str = "") -> float:
    """Return `value` as float, or raise InputError if it is not a finite number."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}={value!r} is not a number") from None
    if not math.isfinite(number):
        raise InputError(f"{name}={value} {unit}".rstrip() + " must be a finite number")
    return number


def check_positive(name: str, value: float, unit: str = "") -> float:
    """Return `value` as float, or raise InputError if it is not finite and > 0."""
    number = check_finite(name, value, unit)
    if number <= 0.0:
        suffix = f" {unit}" if unit else ""
        raise InputError(f"{name}={_format(number)}{suffix} must be > 0")
    return number


def check_range(
    name: str, value: float, low: float, high: float, unit: str = "", *, closed: bool = True
) -> float:
    """Return `value` as float, or raise InputError unless low <= value <= high.

    With `closed=False` the bounds themselves are excluded.
    """
    number = check_finite(name, value, unit)
    inside = low <= number <= high if closed else low < number < high
    if not inside:
        suffix = f" {unit}" if unit else ""
        brackets = "[]" if closed else "()"
        raise InputError(
            f"{name}={_format(number)}{suffix} is outside the valid range "
            f"{brackets[0]}{_format(low)}, {_format(high)}{brackets[1]}{suffix}"
        )
    return number


def check_integer(name: str, value: int, low: int, high: int | None = None) -> int:
    """Return `value` as int, or raise InputError unless it is an integer in [low, high]."""
    is_number = isinstance(value, numbers.Real) and not isinstance(value, bool)
    if not is_number or not math.isfinite(value) or value != int(value):
        raise InputError(f"{name}={value!r} must be an integer")
    number = int(value)
    if number < low or (high is not None and number > high):
        upper = "inf" if high is None else str(high)
        raise InputError(f"{name}={number} is outside the valid range [{low}, {upper}]")
    return number
