"""Wall time of a response-surface generation: cold and cached, with 1 and 2 worker processes.

Uses the rod RVE (`rve_rod.rve.surface_engine()`) when it is installed; otherwise the analytic
stand-in with a CPU-bound busy loop of `--run-seconds` per run, which measures what the
orchestration adds (process pool, cache, fit, file) and the speed-up of `--jobs 2` for runs of
a given cost. Each configuration starts from an empty cache ("cold") and is then repeated on
the filled cache ("cached").

Run: .venv/bin/python benchmarks/bench_surface_generation.py [--run-seconds 1.0] [--rays 16]
"""

import argparse
import dataclasses
import tempfile
import time
from pathlib import Path

from rve_rod.cache import ResultCache
from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.homogenize.generate import EngineUnavailableError, default_engine, generate_surface
from rve_rod.homogenize.sampling import SamplingPlan
from rve_rod.presets import load_preset
from rve_rod.surface import write_surface


@dataclasses.dataclass(frozen=True)
class BusyAnalyticRve(AnalyticRve):
    """The analytic RVE plus `seconds` of busy CPU per run (a stand-in for the rod RVE's cost)."""

    seconds: float = 1.0

    def __call__(self, case):
        end = time.process_time() + self.seconds
        while time.process_time() < end:
            pass
        return super().__call__(case)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run-seconds", type=float, default=1.0)
    parser.add_argument("--rays", type=int, default=SamplingPlan().rays)
    args = parser.parse_args()
    try:
        engine, label = default_engine(), "rod RVE"
    except EngineUnavailableError:
        engine = BusyAnalyticRve(seconds=args.run_seconds)
        label = f"analytic RVE + {args.run_seconds:g} s CPU per run"
    plan = SamplingPlan(rays=args.rays)
    fabric = load_preset("cotton-20s2", 5.5)
    print(f"engine: {label}; {len(plan.load_paths())} runs (cotton-20s2, stitch 5.5)")
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
