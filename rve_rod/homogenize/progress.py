"""The progress display of long batches of runs (surfaces, sweeps): a tqdm bar with runs done,
elapsed time and an estimate of the time left, on a terminal only.

API (the one progress helper of the project):

    bar = Progress(stream, total, cached=0, label="RVE runs")
    bar.draw()                 # show the bar (the cached runs already counted)
    bar.advance()              # one more run computed
    bar.advance(failed=True)   # one more run ended with an error (counted as done)
    bar.close()                # finish the line (done by the last advance)

`stream` is where to draw (the tools pass sys.stderr). When it is not a terminal (a log
file, a pipe, a test) nothing is drawn: progress bars redrawn in place are noise there, and
the tools log what finished. The time left is tqdm's estimate from the runs computed since
the start (cached runs are counted as done at once and do not speed it up).
"""

from typing import TextIO

from tqdm import tqdm

__all__ = [
    "Progress",
]


class Progress:
    """Progress of `total` runs of which `cached` were already done, drawn on `stream`.

    Attributes:
        total: number of runs.
        cached: runs taken from the cache (done without computing).
        computed: runs computed so far.
        failed: runs that ended with an error so far.
    """

    def __init__(self, stream: TextIO, total: int, cached: int = 0, label: str = "RVE runs"):
        self.total = total
        self.cached = cached
        self.computed = 0
        self.failed = 0
        self._bar = tqdm(
            total=total,
            initial=cached,
            desc=label,
            unit="run",
            file=stream,
            disable=not stream.isatty(),
            dynamic_ncols=True,
            postfix={"cached": cached},
        )

    @property
    def done(self) -> int:
        """Runs done: cached, computed and failed."""
        return self.cached + self.computed + self.failed

    def draw(self) -> None:
        """Draw the current state (and end the line when every run is done)."""
        self._bar.refresh()
        if self.done >= self.total:
            self.close()

    def advance(self, failed: bool = False) -> None:
        """Count one more computed (or `failed`) run and redraw; the last one closes the bar."""
        if failed:
            self.failed += 1
            self._bar.set_postfix(cached=self.cached, failed=self.failed, refresh=False)
        else:
            self.computed += 1
        self._bar.update(1)
        if self.done >= self.total:
            self.close()

    def close(self) -> None:
        """End the bar's line."""
        self._bar.close()
