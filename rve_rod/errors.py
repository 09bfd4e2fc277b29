"""Typed errors shared by both scales, the checks that raise them for bad input, and the exit
statuses the command-line tools give them.

`InputError` is what a user can fix (a parameter outside its valid range); the command-line
tools print its one-line message and exit with status 2. `ConvergenceError` is what a solver
raises when it cannot go on; it carries everything that converged before it stopped (exit
status 3). `cli_exit_status` is the one mapping of the three tools (`rve-rod`,
`fabric-dolfinx`, `knitmech`), and `CommandLineParser` their argument parser, whose usage errors
are InputErrors; `terminate_as_interrupt` makes SIGTERM unwind a tool like Ctrl-C (children
stopped, temporary folders removed) and exit with 143, and remembers each signal until it is
handled, so that `raise_pending_interrupt` can raise one that Python lost (its exception
raised in a callback whose exceptions are ignored, such as logging's lock release after a fork).
"""

import argparse
import math
import numbers
import os
import signal
import sys
from typing import Any

__all__ = [
    "EXIT_BROKEN_PIPE",
    "EXIT_INPUT",
    "EXIT_INTERRUPTED",
    "EXIT_NOT_CONVERGED",
    "EXIT_STOPPED",
    "EXIT_TERMINATED",
    "CommandLineParser",
    "ConvergenceError",
    "InputError",
    "Terminated",
    "check_finite",
    "check_integer",
    "check_positive",
    "check_range",
    "cli_exit_status",
    "raise_pending_interrupt",
    "terminate_as_interrupt",
]

EXIT_STOPPED = 1
"""Exit status of a run that stopped on an error it can resume from (run it again)."""
EXIT_INPUT = 2
"""Exit status for bad input (`InputError`)."""
EXIT_NOT_CONVERGED = 3
"""Exit status of a solver that gave up (`ConvergenceError`) after saving what converged."""
EXIT_INTERRUPTED = 130
"""Exit status after Ctrl-C (128 + SIGINT, as shells report it)."""
EXIT_TERMINATED = 128 + signal.SIGTERM
"""Exit status after SIGTERM (143)."""
EXIT_BROKEN_PIPE = 128 + signal.SIGPIPE
"""Exit status when stdout was closed by its reader (141, as `yes | head` reports it)."""


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


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived (raised by the handler of `terminate_as_interrupt`): a subclass of
    KeyboardInterrupt, so that everything that cleans up after Ctrl-C does so after it too."""


_pending: list[type[KeyboardInterrupt]] = []
"""The interruption that arrived and has not been handled yet (at most one kind)."""


def _raise_terminated(signum, frame):
    _pending[:] = [Terminated]
    raise Terminated()


def _raise_interrupt(signum, frame):
    _pending[:] = _pending or [KeyboardInterrupt]
    raise KeyboardInterrupt


def terminate_as_interrupt() -> None:
    """Make SIGTERM raise `Terminated` in the main thread, and remember SIGTERM and SIGINT until
    `cli_exit_status` handles them (call it from a tool's main). SIGINT keeps its meaning
    (KeyboardInterrupt) where Python's own handler has it; an ignored SIGINT (a background job)
    stays ignored."""
    signal.signal(signal.SIGTERM, _raise_terminated)
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, _raise_interrupt)


def raise_pending_interrupt() -> None:
    """Raise the KeyboardInterrupt (or `Terminated`) of a signal that arrived but was lost.

    Python ignores an exception raised in some callbacks (it prints "Exception ignored in"): an
    at-fork hook, a finalizer, a weakref callback. A Ctrl-C that lands in one, e.g. in logging's
    lock release while a process pool forks a worker, would be lost and the run go on; a loop
    that waits on long work calls this between its steps (`rve_rod.homogenize.generate`), so
    the interruption takes effect there. Does nothing when no signal is pending.
    """
    if _pending:
        raise _pending.pop()()


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


class CommandLineParser(argparse.ArgumentParser):
    """argparse that reports usage errors as InputError (one line, exit status 2), its
    subcommands' parsers too."""

    def error(self, message):
        raise InputError(message)


def cli_exit_status(
    program: str,
    error: BaseException,
    *,
    resumable: tuple[type[Exception], ...] = (),
    quiet: bool = False,
) -> int:
    """The exit status of a command-line tool that stopped on `error`, after printing why on
    stderr as one line prefixed by `program` (e.g. "rve-rod simulate"):

    InputError -> EXIT_INPUT ("error: ..."), ConvergenceError -> EXIT_NOT_CONVERGED
    ("not converged: ..."), an error of a `resumable` type -> EXIT_STOPPED ("stopped: ...;
    run again to resume"), Terminated (SIGTERM) -> EXIT_TERMINATED ("terminated"),
    KeyboardInterrupt -> EXIT_INTERRUPTED ("interrupted"), BrokenPipeError (the reader of
    stdout, e.g. `head`, closed it) -> EXIT_BROKEN_PIPE with nothing printed and stdout sent
    to /dev/null (so that the interpreter's final flush does not fail again). Any other error
    (SystemExit of --help included) is raised again. `quiet` prints nothing (MPI ranks other
    than 0).
    """
    resume = "; run again to resume" if resumable else ""
    if isinstance(error, KeyboardInterrupt):
        _pending.clear()  # handled here
    if isinstance(error, BrokenPipeError):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
        return EXIT_BROKEN_PIPE
    if isinstance(error, InputError):
        status, line = EXIT_INPUT, f"error: {error}"
    elif isinstance(error, ConvergenceError):
        status, line = EXIT_NOT_CONVERGED, f"not converged: {error}"
    elif isinstance(error, resumable):
        status, line = EXIT_STOPPED, f"stopped: {error}{resume}"
    elif isinstance(error, Terminated):
        status, line = EXIT_TERMINATED, f"terminated{resume}"
    elif isinstance(error, KeyboardInterrupt):
        status, line = EXIT_INTERRUPTED, f"interrupted{resume}"
    else:
        raise error
    if not quiet:
        print(f"{program.strip()}: {line}", file=sys.stderr)
    return status
