"""Cost and accuracy of the knit-loop RVE: one uniaxial course-wise run and its convergence.

1. The reference run: cotton 20s/2, stitch 5.5, uniaxial course-wise 0-20 % in 21 steps,
   degree 4, 68 control points per quarter loop, friction on, one core (BLAS threads are
   pinned to 1 before numpy loads). The numba kernels are compiled (or loaded from their
   cache) by a warm-up run first; then the best of `--repeats` runs is reported with its
   Newton iterations and where the time goes (contact search and loads, rod residual and
   Jacobian, sparse LU), from a profile of one run.
2. Speed/accuracy: the force at 20 % (gf/cm), the Poisson ratio and the wall time for 12, 24,
   36, 68, 136 control points (21 steps) and for 6, 11, 21, 41 steps (68 control points), each
   against the finest run of its table.

    .venv/bin/python benchmarks/bench_rve.py [--repeats 3] [--quick]
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

FABRIC = load_preset("cotton-20s2", 5.5)
PARTS = {
    "contact (search, loads, tangents)": "contact/model.py:evaluate",
    "rod residual + Jacobian": "rod/model.py:evaluate",
    "sparse LU (SuperLU)": "gstrf",
}


def run(control_points=68, steps=21):
    settings = RveSettings(cell=CellSettings(control_points=control_points))
    return simulate(FABRIC, UniaxialCourse(steps=steps), settings)


def profile_parts() -> dict[str, float]:
    """Seconds spent in the main parts of one reference run (cumulative, from cProfile)."""
    profiler = cProfile.Profile()
    profiler.enable()
    run()
    profiler.disable()
    stats = pstats.Stats(profiler).stats
    parts = {}
    for name, pattern in PARTS.items():
        parts[name] = sum(
            values[3]
            for (filename, _, function), values in stats.items()
            if pattern in f"{filename}:{function}" or pattern == function
        )
    parts["total"] = max(values[3] for values in stats.values())
    return parts


def reference(repeats: int) -> None:
    started = time.perf_counter()
    run()
    warm_up = time.perf_counter() - started
    results = [run() for _ in range(repeats)]
    best = min(results, key=lambda result: result.wall_time_s)
    iterations = best.newton_iterations
    print("## Reference run: cotton 20s/2 stitch 5.5, uniaxial course 0-20 %, 21 steps, 68 cp")
    print(f"first run (compiles or loads the numba kernels): {warm_up:.2f} s")
    print(
        f"best of {repeats}: {best.wall_time_s:.2f} s, {iterations} Newton iterations "
        f"({1e3 * best.wall_time_s / iterations:.1f} ms each), "
        f"{int(best.series('cutbacks').sum())} cutbacks, force at 20 % "
        f"{best.steps[-1].force_gf_per_cm:.4g} gf/cm, Poisson ratio {best.poisson_ratio:.4g}"
    )
    print("\n| part | s | share |\n|---|---:|---:|")
    parts = profile_parts()
    for name, seconds in parts.items():
        print(f"| {name} | {seconds:.2f} | {100 * seconds / parts['total']:.0f} % |")


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
    parser.add_argument("--quick", action="store_true", help="reference run only")
    args = parser.parse_args()
    reference(args.repeats)
    if args.quick:
        return
    table(
        "Control points per quarter loop (21 steps)",
        "control points",
        (12, 24, 36, 68, 136),
        lambda n: run(control_points=n),
    )
    table("Load steps (68 control points)", "steps", (6, 11, 21, 41), lambda s: run(steps=s))


if __name__ == "__main__":
    main()
