"""Speed of the stitch patterns' cells (issue 28, item 6): a table for docs/benchmarks.md.

For jersey, 1x1 rib, 2x2 rib, garter, seed and moss (cotton 20s/2 at the jersey's measured
w = 1.33 mm, c = 1.26 mm): the uniaxial course- and wale-wise runs at the balanced level
(36 control points per quarter, 0-20 % in 21 states, friction; `fabric_settings`), wall and CPU
time of the
fastest of `--repeat` runs, per loop of the cell, and its ratio to the jersey cell's (the
issue's goal: within 4 times); then the relaxed cell of each pattern at the loop length of
stitch 5.5 (uncached: a fresh cache folder), wall time.

    .venv/bin/python benchmarks/bench_patterns.py [--repeat 2] [--patterns jersey,rib1x1,...]

About 5 minutes on a quiet core. On the shared machine the times are noisy: the minimum of
the repeats is the one reported, with the load average.
"""

import argparse
import dataclasses
import os
import tempfile
import time
from pathlib import Path

from rve_rod.errors import ConvergenceError
from rve_rod.geometry.relaxed import cached_relaxed_knit
from rve_rod.pattern import smallest_cell
from rve_rod.presets import load_preset
from rve_rod.rve.engine import fabric_settings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import simulate

PATTERNS = ("jersey", "rib1x1", "rib2x2", "garter", "seed", "moss")


def timed(function):
    """(result, wall s, CPU s) of function(); a run that stops gives its converged states."""
    wall, cpu = time.perf_counter(), time.process_time()
    try:
        result = function()
    except ConvergenceError as error:
        result = error.history
    return result, time.perf_counter() - wall, time.process_time() - cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--patterns", default=",".join(PATTERNS))
    args = parser.parse_args()
    preset = load_preset("cotton-20s2", 5.5)
    patterns = args.patterns.split(",")
    rows, per_loop = [], {}
    for pattern in patterns:
        fabric = dataclasses.replace(preset, knit=dataclasses.replace(preset.knit, pattern=pattern))
        loops = smallest_cell(pattern).n_loops
        settings = fabric_settings(fabric, 36)
        cells = []
        for name in ("uniaxial-course", "uniaxial-wale"):
            case = load_case(name, 0.2, 21)
            best = min(
                (
                    timed(
                        lambda case=case, fabric=fabric, settings=settings: simulate(
                            fabric, case, settings
                        )
                    )
                    for _ in range(args.repeat)
                ),
                key=lambda found: found[1],
            )
            result, wall, cpu = best
            per_loop[pattern, name] = wall / loops
            ratio = per_loop[pattern, name] / per_loop.get(("jersey", name), float("nan"))
            stopped = (
                "" if result.complete else f" (stopped at {100 * result.steps[-1].strain:.0f} %)"
            )
            cells.append(
                f"{wall:.1f}{stopped} | {cpu:.1f} | {result.newton_iterations} | "
                f"{wall / loops:.2f} | {ratio:.2f}"
            )
        rows.append(f"| {pattern} | {loops} | {cells[0]} | {cells[1]} |")
    print(f"load average {os.getloadavg()[0]:.2f}; minimum of {args.repeat} runs\n")
    print(
        "| pattern | loops | course wall (s) | CPU (s) | iterations | wall per loop | ratio to "
        "jersey | wale wall (s) | CPU (s) | iterations | wall per loop | ratio to jersey |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    print("\nrelaxed cells at the loop length 5.5 mm (uncached):\n")
    print("| pattern | w (mm) | c (mm) | wall (s) |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for pattern in patterns:
            knit, wall, _ = timed(
                lambda pattern=pattern: cached_relaxed_knit(
                    pattern, 5.5, preset.yarn.minimal_radius, Path(folder)
                )
            )
            print(f"| {pattern} | {knit.wale_width:.3f} | {knit.course_height:.3f} | {wall:.1f} |")


if __name__ == "__main__":
    main()
