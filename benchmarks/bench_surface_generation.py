"""Wall time of a response-surface generation: cold and cached, with 1 and 2 worker processes.

Uses the rod RVE (`rve_rod.rve.surface_engine()`) on cotton 20s/2 at stitch 5.5, the default
surface of the main job. Each configuration starts from an empty cache ("cold") and is then
repeated on the filled cache ("cached"); "fit+write s" is what the orchestration adds to the
runs (process pool, cache, fit, file).

Run: .venv/bin/python benchmarks/bench_surface_generation.py [--rays 16]
"""

import argparse
import tempfile
import time
from pathlib import Path

from rve_rod.cache import ResultCache
from rve_rod.homogenize.generate import generate_surface
from rve_rod.homogenize.sampling import SamplingPlan
from rve_rod.presets import load_preset
from rve_rod.rve.engine import surface_engine
from rve_rod.surface import write_surface


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rays", type=int, default=SamplingPlan().rays)
    args = parser.parse_args()
    engine = surface_engine()
    plan = SamplingPlan(rays=args.rays)
    fabric = load_preset("cotton-20s2", 5.5)
    print(f"rod RVE: {len(plan.load_paths())} runs (cotton-20s2, stitch 5.5)")
    print(f"{'jobs':>4} {'cache':>6} {'wall s':>8} {'computed':>8} {'fit+write s':>11}")
    for jobs in (1, 2):
        with tempfile.TemporaryDirectory() as folder:
            cache = ResultCache(Path(folder) / "cache")
            for state in ("cold", "cached"):
                started = time.perf_counter()
                generated = generate_surface(fabric, engine, plan, cache=cache, jobs=jobs)
                write_surface(Path(folder) / "surface.h5", generated.surface)
                wall = time.perf_counter() - started
                overhead = wall - generated.runs.wall_time_s
                print(
                    f"{jobs:>4} {state:>6} {wall:>8.2f} {generated.runs.computed:>8} "
                    f"{overhead:>11.3f}"
                )


if __name__ == "__main__":
    main()
