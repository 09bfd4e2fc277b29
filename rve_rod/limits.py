"""The ranges of the run-size settings: the smallest value that gives an answer worth having and
the largest that runs on a workstation in hours, not days or out of memory.

One home for the command-line tools, the scene checks and the settings' own checks: a value
outside its range is refused before any work (`rve_rod.errors.check_integer` names the
parameter, the value and the range). The library's settings accept smaller values than the
tools (a test may run 5 control points); the tools and scenes hold the minimums here.

Minimums (docs/benchmarks.md, docs/reliability.md):

- control points per quarter loop: 20. The RVE's forces converge fast above it (20 is within
  0.3 % of 132); 12, the geometry's own count, gave 21.9 instead of 27.1 gf/cm (-19 %).
- rays of a surface: 16. The fit's error between the rays is 7 % at 8 rays (the patch 13 % off
  at 20 % strain, tension rays turned into compression at 3 rays), 2 % at 16.

Maximums (memory and time grow with them; a run of the largest value shows progress). 300
control points run (cotton 20s/2 at stitch 5.5, 0-5 % in 3 states: 51 s, 370 MB); at 400 the
unloaded cell found no equilibrium (docs/reliability.md has the reason for every bound):
control points 300, rays 128, steps per ray and shear steps 100, RVE output states 1000, patch
elements per side 200 (80 000 triangles), cells of a part 40 000 (refinements counted),
patch load steps 1000.
"""

import os

from rve_rod.errors import check_integer

__all__ = [
    "CONTROL_POINTS",
    "ELEMENTS",
    "MACRO_STEPS",
    "PART_CELLS",
    "RAYS",
    "RVE_STEPS",
    "STEPS_PER_RAY",
    "available_cores",
    "check_count",
]

CONTROL_POINTS = (20, 300)
"""Control points per quarter loop curve of an RVE run (meso and surface), (min, max)."""
RAYS = (16, 128)
"""Biaxial rays of a response surface, (min, max)."""
STEPS_PER_RAY = (1, 100)
"""Output steps along one ray or the shear path, (min, max)."""
RVE_STEPS = (2, 1000)
"""Output states of one RVE load case, the unloaded one included, (min, max)."""
ELEMENTS = (1, 200)
"""Elements per side of the fabric patch, (min, max)."""
PART_CELLS = ELEMENTS[1] ** 2
"""Cells of a scene's fabric part, refinements counted (the patch's largest mesh, 200 x 200:
80 802 unknowns, 358 MB and 0.95 s per Newton iteration with MUMPS on one rank)."""
MACRO_STEPS = (1, 1000)
"""Load steps of the fabric patch, (min, max)."""


def available_cores() -> int:
    """CPU cores this process may use (the bound of MPI ranks without oversubscribing)."""
    return len(os.sched_getaffinity(0))


def check_count(name: str, value: int, limits: tuple[int, int]) -> int:
    """`value` as int, or InputError naming `name`, the value and the range `limits`."""
    return check_integer(name, value, *limits)
