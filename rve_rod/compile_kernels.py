"""Compile the numba kernels of `rve_rod` into numba's cache, once per environment.

numba compiles a kernel at its first call and keeps the machine code in `__pycache__` beside
its module (`@njit(cache=True)`), so a new installation pays for the compilation in its first
run: about 20 s of CPU for the 40 kernels (the clearance search's 5 about 6 s, the rod's and
the contact's about 14 s; docs/benchmarks.md), in the first geometry and meso stages of
`knitmech run`. `make bootstrap` (scripts/bootstrap.sh) runs this module from the source tree
beside pip's install of the project, as a package with C extensions compiles them when it is
installed, so that the first run starts with every kernel compiled; numba recompiles a kernel
by itself when its source changes.

The compilation is driven by what the package does with the kernels, not by hand-written
signatures: the loop of cotton 20s/2 at stitch 5.5 (the clearance search) and a three-step
uniaxial RVE run of it at 28 control points (the rod and the contact, with friction). The
kernels are typed by their arguments' dtypes, dimensions and layouts, not by their sizes, so
the short run compiles what the full runs use (measured: `knitmech run` on the default scene
compiles no kernel after it). `uncached_kernels` lists the kernels with no entry in numba's
cache; `main` names them (a kernel that only another path reaches would be compiled at its
first call, as before).

    .venv/bin/python -m rve_rod.compile_kernels
"""

import importlib
import time
from pathlib import Path

from numba.core.registry import CPUDispatcher

__all__ = ["compile_kernels", "kernels", "uncached_kernels"]

WARM_UP_CONTROL_POINTS = 28
"""Control points per quarter loop of the warm-up run (the fast fidelity level's)."""

WARM_UP_STEPS = 3
"""Load steps of the warm-up run (0, 10 and 20 % course-wise)."""


def kernels() -> dict[str, CPUDispatcher]:
    """Every numba kernel of the package: the dispatchers of its `_kernels` modules, by
    qualified name ("rve_rod.rod._kernels.collocation_equations")."""
    package = Path(__file__).parent
    found = {}
    for path in sorted(package.glob("*/_kernels.py")):
        name = f"rve_rod.{path.parent.name}._kernels"
        module = importlib.import_module(name)
        for attribute, value in vars(module).items():
            if isinstance(value, CPUDispatcher) and value.py_func.__module__ == name:
                found[f"{name}.{attribute}"] = value
    return found


def uncached_kernels() -> list[str]:
    """The kernels with no index file in numba's cache (a kernel compiled once has one, also
    when it was compiled as the callee of another)."""
    # numba 0.56 (Debian 12) names no public path for a dispatcher's cache index
    return [
        name
        for name, kernel in kernels().items()
        if not Path(kernel._cache._cache_file._index_path).is_file()
    ]


def compile_kernels() -> None:
    """Run the clearance search and a short RVE run (module docstring): compiles every kernel
    they reach, or loads it from numba's cache."""
    from rve_rod.geometry.loop import loop_geometry  # noqa: PLC0415 (numba on demand)
    from rve_rod.presets import load_preset  # noqa: PLC0415
    from rve_rod.rve.cell import CellSettings  # noqa: PLC0415
    from rve_rod.rve.load_cases import UniaxialCourse  # noqa: PLC0415
    from rve_rod.rve.simulation import RveSettings, simulate  # noqa: PLC0415

    fabric = load_preset("cotton-20s2", 5.5)
    loop_geometry(fabric.knit, fabric.yarn.minimal_radius)
    settings = RveSettings(cell=CellSettings(control_points=WARM_UP_CONTROL_POINTS))
    simulate(fabric, UniaxialCourse(steps=WARM_UP_STEPS), settings)


def main() -> int:
    start = time.perf_counter()
    compile_kernels()
    left = uncached_kernels()
    total = len(kernels())
    print(
        f"{total - len(left)} of {total} numba kernels compiled or in the cache "
        f"({time.perf_counter() - start:.1f} s)"
    )
    if left:
        print("not reached (compiled at their first call instead): " + ", ".join(left))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
