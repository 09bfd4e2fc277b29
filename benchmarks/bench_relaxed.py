"""Speed of the relaxed cell (issue 28, item 6: "the relaxed cell in seconds"): a table for
docs/benchmarks.md.

For each pattern, `relaxed_knit` at cotton 20s/2's loop length of stitch 5.5 (l = 5.5 mm,
r0 = 0.19 mm), uncached (the per-process memos of the jersey loop and of the pattern
templates cleared before every run):
w, c and the bending energy (to compare versions: a speed-up must give the same cell), and the
wall and CPU time of the fastest of `--repeat` runs (on a loaded machine the CPU time is the
steadier measure: the search runs on one core). The first run of a process also loads the
clearance search's numba kernels from their cache (about 0.5 s; compiling them, with an empty
cache, about 9 s of CPU): keep `--repeat` at 2 or more.

    .venv/bin/python benchmarks/bench_relaxed.py [--repeat 2] [--patterns jersey,rib1x1,...]

About a minute (4 before the kernels). On the shared machine the times are noisy: the minimum
of the repeats is the one reported, with the load average.
"""

import argparse
import os
import time

from rve_rod.geometry.loop import single_jersey_loop
from rve_rod.geometry.pattern_cell import pattern_geometry
from rve_rod.geometry.relaxed import relaxed_knit

PATTERNS = ("jersey", "rib1x1", "rib2x2", "garter", "seed", "moss")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--patterns", default=",".join(PATTERNS))
    args = parser.parse_args()
    rows = []
    for pattern in args.patterns.split(","):
        best = (float("inf"), float("inf"))
        for _ in range(args.repeat):
            single_jersey_loop.cache_clear()
            pattern_geometry.cache_clear()
            wall, cpu = time.perf_counter(), time.process_time()
            knit = relaxed_knit(pattern, 5.5, 0.19)
            best = min(best, (time.perf_counter() - wall, time.process_time() - cpu))
        rows.append(
            f"| {pattern} | {knit.wale_width:.6f} | {knit.course_height:.6f} | "
            f"{knit.energy:.6f} | {best[0]:.1f} | {best[1]:.1f} |"
        )
    print(f"load average {os.getloadavg()[0]:.2f}; minimum of {args.repeat} runs\n")
    print("| pattern | w (mm) | c (mm) | energy (1/mm) | wall (s) | CPU (s) |")
    print("|---|---|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
