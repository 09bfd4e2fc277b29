"""A plain-text progress bar for long batches of runs (runs done, elapsed time, time left)."""

import time
from dataclasses import dataclass, field
from typing import TextIO


def _clock(seconds: float) -> str:
    minutes, seconds = divmod(round(seconds), 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours}:{minutes:02d}:{seconds:02d}" if hours else f"{minutes}:{seconds:02d}"


@dataclass
class Progress:
    """Progress of `total` runs of which `cached` were already done, drawn on `stream`.

    On a terminal the bar is redrawn in place; otherwise (a log file) one line per update.
    The time left is extrapolated from the runs computed since the start.

    Attributes:
        stream: where to draw (the CLI passes sys.stderr).
        total: number of runs.
        cached: runs taken from the cache (done without computing).
        failed: runs that ended with an error (counted as done).
        label: text in front of the bar.
        width: characters of the bar.
    """

    stream: TextIO
    total: int
    cached: int = 0
    label: str = "RVE runs"
    width: int = 24
    computed: int = 0
    failed: int = 0
    started: float = field(default_factory=time.monotonic)

    def line(self) -> str:
        """The current progress line (without line end)."""
        done = self.cached + self.computed + self.failed
        filled = round(self.width * done / self.total) if self.total else self.width
        elapsed = time.monotonic() - self.started
        remaining = self.total - done
        if remaining == 0:
            left = "done"
        elif self.computed:
            left = f"~{_clock(elapsed / self.computed * remaining)} left"
        else:
            left = "time left unknown"
        failed = f", {self.failed} failed" if self.failed else ""
        return (
            f"{self.label} [{'#' * filled}{'.' * (self.width - filled)}] {done}/{self.total} "
            f"({self.cached} cached{failed}), {_clock(elapsed)} elapsed, {left}"
        )

    def draw(self) -> None:
        """Draw the current state."""
        if self.stream.isatty():
            end = "\n" if self.cached + self.computed + self.failed == self.total else ""
            self.stream.write("\r" + self.line() + end)
        else:
            self.stream.write(self.line() + "\n")
        self.stream.flush()

    def advance(self, failed: bool = False) -> None:
        """Count one more computed (or `failed`) run and redraw."""
        if failed:
            self.failed += 1
        else:
            self.computed += 1
        self.draw()
