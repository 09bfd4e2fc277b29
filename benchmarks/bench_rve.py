"""Cost and accuracy of the knit-loop RVE: one uniaxial course-wise run and its convergence.

1. The reference run: cotton 20s/2, stitch 5.5, uniaxial course-wise 0-20 % in 21 steps,
   degree 4, 68 control points per quarter loop, friction on, one core (BLAS threads are
   pinned to 1 before numpy loads), for the default bending model and the section model
   (`--bending`). The numba kernels are compiled (or loaded from their cache) by a warm-up
   run first; then the best of `--repeats` runs is reported with its Newton iterations,
   residual evaluations and LU factorizations, and a profile of one run (cProfile) says where
   the time goes: the sparse LU, the contact search (broad phase, closest-point projection,
   region weights and their separating maxima, loads and tangents), the rod's kernels and
   assembly, the cell's coupling and macro equations, the step controller and the outputs.
   The profiler's own cost inflates the Python-heavy parts; the wall and CPU times are without
   it. On a shared machine the CPU time of the process is the better measure of one core's
   work (the wall time also counts the waits for the other jobs).
2. Speed/accuracy (without `--quick`): the force at 20 % (gf/cm), the Poisson ratio and the
   wall time for 24, 28, 36, 68, 136 control points (21 steps; at 20 and fewer the loop's
   contacts are under-resolved and the run stalls or crawls) and for 6, 11, 21, 41 steps (68
   control points), each against the finest run of its table.

    .venv/bin/python benchmarks/bench_rve.py [--repeats 3] [--quick] [--bending auto section]
"""

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import cProfile
import pstats
import time

from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import UniaxialCourse
from rve_rod.rve.simulation import RveSettings, simulate
from rve_rod.rve.yarn import BENDING_CHOICES, YarnSettings

FABRIC = load_preset("cotton-20s2", 5.5)

# Profile rows: (label, functions whose inclusive time the row adds, (callee, callers) pairs
# whose time the row subtracts: the callee's time when called directly from one of the callers,
# or from anywhere for callers None). A function is "file suffix:name"; "~:name" is a built-in.
LU_ORDER = "newton.py:node_ordering"
LU_FACTOR = "newton.py:_factorize"
LU_SOLVE = "newton.py:solve"
CONTACT = "contact/model.py:evaluate"
BROAD = (
    "broad_phase.py:group_boxes",
    "broad_phase.py:select_images",
    "broad_phase.py:find_candidates",
)
PROJECT = "contact/closest_point.py:project"
REGIONS = "contact/regions.py:region_weights"
MAXIMA = "contact/regions.py:separating_maxima"
ROD = "rod/model.py:evaluate"
KERNELS = "rod/model.py:_local_equations"
COUPLING = "rve/coupling.py:__call__"
RESULT = "rve/coupling.py:result"
CONDITIONS = ("rve/macro.py:evaluate", "rod/conditions.py:evaluate")
EVALUATE = "rve/simulation.py:evaluate"
RESIDUAL = "rve/simulation.py:residual"
RUN = "rve/simulation.py:simulate"
OUTPUTS = ("rve/simulation.py:snapshot", "rve/simulation.py:_step", "rve/cell.py:admissible")
COMMIT = "rve/coupling.py:commit"
LOGGING = ("logging/__init__.py:debug", "logging/__init__.py:info")
BUILD = "rve/simulation.py:build_cell"
IN_SEARCH = ("contact/model.py:_closest_points", "contact/model.py:_region_weights")

ROWS = (
    ("sparse LU: ordering", (LU_ORDER,), ()),
    ("sparse LU: factorization (SuperLU)", (LU_FACTOR,), ((LU_ORDER, None),)),
    ("sparse LU: solves, GMRES with old factors", (LU_SOLVE,), ((LU_FACTOR, None),)),
    ("contact: broad phase (boxes, images, candidates)", BROAD, ()),
    ("contact: closest-point projection", (PROJECT,), ()),
    ("contact: region weights without their maxima", (REGIONS,), ((MAXIMA, None),)),
    ("contact: separating maxima", (MAXIMA,), ()),
    (
        "contact: loads, friction, tangents",
        (CONTACT,),
        (*((name, IN_SEARCH) for name in BROAD), (PROJECT, IN_SEARCH), (REGIONS, IN_SEARCH)),
    ),
    ("rod: collocation kernels", (KERNELS,), ()),
    (
        "cell: contact coupling and macro equations",
        (COUPLING, *CONDITIONS),
        ((RESULT, (COUPLING, *CONDITIONS)), (KERNELS, None)),
    ),
    (
        "rod: residual and Jacobian assembly",
        (ROD,),
        ((COUPLING, None), *((c, None) for c in CONDITIONS)),
    ),
    ("outputs, admissibility, friction commit", (*OUTPUTS, COMMIT), ()),
    ("logging", LOGGING, ()),
    ("model building (geometry, cell)", (BUILD,), ()),
)


def run(control_points=68, steps=21, bending="auto"):
    settings = RveSettings(
        cell=CellSettings(control_points=control_points), yarn=YarnSettings(bending=bending)
    )
    return simulate(FABRIC, UniaxialCourse(steps=steps), settings)


def _matches(key, pattern: str) -> bool:
    filename, _, function = key
    where, name = pattern.split(":", 1)
    return function == name and (filename == where or filename.endswith(where))


def _inclusive(stats: dict, pattern: str) -> tuple[float, int]:
    """Inclusive seconds and calls of the functions matching `pattern`, counting only calls
    from outside them (no double counting of recursion or of nested matches)."""
    seconds, calls = 0.0, 0
    for key, (_, primitive, _, cumulative, callers) in stats.items():
        if not _matches(key, pattern):
            continue
        nested = [value for caller, value in callers.items() if _matches(caller, pattern)]
        seconds += cumulative - sum(value[3] for value in nested)
        calls += primitive
    return seconds, calls


def _called_from(stats: dict, callee: str, callers) -> float:
    """Inclusive seconds of `callee` in its calls from `callers` (patterns; None: all)."""
    if callers is None:
        return _inclusive(stats, callee)[0]
    seconds = 0.0
    for key, (*_, edges) in stats.items():
        if _matches(key, callee):
            seconds += sum(
                value[3]
                for caller, value in edges.items()
                if any(_matches(caller, pattern) for pattern in callers)
            )
    return seconds


def profile_parts(bending: str) -> tuple[dict[str, float], dict[str, int]]:
    """Seconds of one reference run per row of ROWS (and the rest), and the counts of
    residual evaluations (with the Jacobian and without), LU factorizations, linear solves
    and contact evaluations, from cProfile."""
    profiler = cProfile.Profile()
    profiler.enable()
    run(bending=bending)
    profiler.disable()
    stats = pstats.Stats(profiler).stats
    parts = {}
    for label, added, subtracted in ROWS:
        parts[label] = sum(_inclusive(stats, name)[0] for name in added) - sum(
            _called_from(stats, callee, callers) for callee, callers in subtracted
        )
    total = _inclusive(stats, RUN)[0]
    parts["Newton, line search and step controller (the rest)"] = total - sum(parts.values())
    parts["total"] = total
    counts = {
        "evaluations": _inclusive(stats, EVALUATE)[1] + _inclusive(stats, RESIDUAL)[1],
        "residual-only evaluations": _inclusive(stats, RESIDUAL)[1],
        "factorizations": _inclusive(stats, LU_FACTOR)[1],
        "linear solves": _inclusive(stats, LU_SOLVE)[1],
        "contact evaluations": _inclusive(stats, CONTACT)[1],
    }
    return parts, counts


def reference(repeats: int, bending: str) -> None:
    load = os.getloadavg()[0]
    started = time.perf_counter()
    run(bending=bending)
    warm_up = time.perf_counter() - started
    results, cpu = [], []
    for _ in range(repeats):
        started = time.process_time()
        results.append(run(bending=bending))
        cpu.append(time.process_time() - started)
    best = min(results, key=lambda result: result.wall_time_s)
    iterations = best.newton_iterations
    print(
        "\n## Reference run: cotton 20s/2 stitch 5.5, uniaxial course 0-20 %, 21 steps, 68 cp, "
        f"bending {bending!r}\n"
    )
    print(f"first run (compiles or loads the numba kernels): {warm_up:.2f} s")
    print(
        f"load average before the runs: {load:.1f}; CPU time of one run (one "
        f"core), best of {repeats}: {min(cpu):.3f} s"
    )
    print(
        f"wall time, best of {repeats}: {best.wall_time_s:.3f} s (all: "
        f"{', '.join(f'{result.wall_time_s:.3f}' for result in results)}), "
        f"{iterations} Newton iterations ({1e3 * best.wall_time_s / iterations:.1f} ms each), "
        f"{int(best.series('cutbacks').sum())} cutbacks, force at 20 % "
        f"{best.steps[-1].force_gf_per_cm:.10g} gf/cm, Poisson ratio {best.poisson_ratio:.10g}"
    )
    parts, counts = profile_parts(bending)
    print(
        f"\nprofile of one run (cProfile): {counts['evaluations']} residual evaluations "
        f"({counts['residual-only evaluations']} without the Jacobian), "
        f"{counts['linear solves']} linear solves, {counts['factorizations']} LU factorizations, "
        f"{counts['contact evaluations']} contact evaluations\n"
    )
    print("| part | s | ms per evaluation | share |\n|---|---:|---:|---:|")
    for name, seconds in parts.items():
        print(
            f"| {name} | {seconds:.3f} | {1e3 * seconds / counts['evaluations']:.2f} | "
            f"{100 * seconds / parts['total']:.0f} % |"
        )


def table(title: str, label: str, values, make) -> None:
    rows = []
    for value in values:
        result = make(value)
        rows.append(
            (
                value,
                result.steps[-1].force_gf_per_cm,
                result.poisson_ratio,
                result.wall_time_s,
                result.newton_iterations,
            )
        )
    finest = rows[-1]
    print(f"\n## {title}\n")
    print(
        f"| {label} | force at 20 % (gf/cm) | error | Poisson ratio | error | wall s | iterations |"
    )
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for value, force, poisson, wall, iterations in rows:
        print(
            f"| {value} | {force:.5g} | {abs(force / finest[1] - 1):.1e} | {poisson:.4g} | "
            f"{abs(poisson - finest[2]):.1e} | {wall:.2f} | {iterations} |"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="reference runs only")
    parser.add_argument(
        "--bending", nargs="+", choices=BENDING_CHOICES, default=["auto", "section"]
    )
    args = parser.parse_args()
    for bending in args.bending:
        reference(args.repeats, bending)
    if args.quick:
        return
    table(
        "Control points per quarter loop (21 steps)",
        "control points",
        (24, 28, 36, 68, 136),
        lambda n: run(control_points=n),
    )
    table("Load steps (68 control points)", "steps", (6, 11, 21, 41), lambda s: run(steps=s))


if __name__ == "__main__":
    main()
