"""Sweep speed-up: the six cotton stitch values at the fast level, local and mpi executors.

Runs `knitmech sweep` on the six stitch values of cotton 20s/2 (examples/sweeps/cotton_stitch.toml,
25 RVE runs each, 150 in all), every time from an empty cache, with the local executor on 1 and
2 jobs and the mpi executor on 2 and 3 ranks (`mpirun -n N python -m mpi4py.futures`: one rank
drives, N-1 compute). It prints the wall time (the whole command: start-up, runs, fits, files)
and the speed-up against 1 job, and checks that every configuration wrote the same surfaces.

From the run times measured with 1 job (W = their sum, t_max = the longest; F = the fits,
serial in the driver; T0 = the rest of the 1-job wall time: start-up, JIT compilation, cache)
it predicts the wall time on P workers,

    T(P) = T0 + max(W / P, t_max) + F,        efficiency = T(1) / (P T(P)),

and checks it against a simulation of the schedule: the runs, in the order the sweep submits
them, each go to the first free worker (list scheduling, what both executors do).

Run: .venv/bin/python benchmarks/bench_sweep.py [--rays 24] [--keep DIR]
(mpirun must be on PATH; as root set OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1,
and OMPI_MCA_rmaps_base_oversubscribe=1 for more ranks than cores)
"""

import argparse
import heapq
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from rve_rod.surface import read_surface

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "sweeps" / "cotton_stitch.toml"
CONFIGURATIONS = (("local", 1), ("local", 2), ("mpi", 2), ("mpi", 3))
"""(executor, jobs or ranks) measured; mpi ranks include the driver."""
PREDICTED_WORKERS = (8, 64, 256)


def sweep_file(folder: Path, rays: int | None) -> Path:
    """The example sweep, with `rays` biaxial rays if given (fewer: a quicker benchmark)."""
    text = EXAMPLE.read_text()
    if rays is not None:
        text = text.replace("\n[surface]", f"\n[surface]\nrays = {rays}", 1)
    path = folder / "sweep.toml"
    path.write_text(text)
    return path


def run_configuration(folder: Path, sweep: Path, executor: str, workers: int) -> dict:
    """One cold sweep; returns its summary.json and the wall time of the command."""
    name = f"{executor}-{workers}"
    command = [sys.executable, "-m", "knitmech", "sweep", str(sweep), "-q"]
    command += ["-o", str(folder / name), "--cache-dir", str(folder / f"cache-{name}")]
    if executor == "mpi":
        command = [
            "mpirun",
            "-n",
            str(workers),
            sys.executable,
            "-m",
            "mpi4py.futures",
            *command[1:],
        ]
        command += ["--executor", "mpi"]
    else:
        command += ["--jobs", str(workers)]
    started = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - started
    summary = json.loads((folder / name / "summary.json").read_text())
    return {"name": name, "wall_s": wall, "summary": summary, "folder": folder / name}


def list_schedule(run_times: list[float], workers: int) -> float:
    """Makespan (s) of the runs, in order, each started on the first free of `workers`."""
    free = [0.0] * workers
    for duration in run_times:
        heapq.heappush(free, heapq.heappop(free) + duration)
    return max(free)


def largest_difference(first: Path, second: Path) -> float:
    """Largest |coefficient difference| / max |coefficient| over the surface files of two runs."""
    worst = 0.0
    for path in sorted(first.glob("*.h5")):
        a, b = read_surface(path).groups(), read_surface(second / path.name).groups()
        for name, spline in a.items():
            scale = np.abs(spline.coefficients).max()
            worst = max(worst, np.abs(b[name].coefficients - spline.coefficients).max() / scale)
    return worst


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rays", type=int, help="biaxial rays (default: the fast level's 24)")
    parser.add_argument("--keep", help="folder to keep the sweeps in (default: a temporary one)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(args.keep or temporary)
        folder.mkdir(parents=True, exist_ok=True)
        sweep = sweep_file(folder, args.rays)
        results = []
        for executor, workers in CONFIGURATIONS:
            results.append(run_configuration(folder, sweep, executor, workers))
            print(f"  {results[-1]['name']}: {results[-1]['wall_s']:.1f} s", file=sys.stderr)
        report(results)


def report(results: list[dict]) -> None:
    serial = results[0]
    runs = serial["summary"]["run_times_s"]
    fits = sum(knit["fit_s"] for knit in serial["summary"]["knits"])
    work, longest = sum(runs), max(runs)
    start_up = serial["wall_s"] - work - fits
    print(f"sweep: {len(runs)} RVE runs of {len(serial['summary']['knits'])} knits, cold cache")
    print(f"{'configuration':<16}{'workers':>8}{'wall s':>9}{'speed-up':>10}{'sim s':>9}")
    for result in results:
        name = result["name"]
        workers = int(name.split("-")[1]) - (1 if name.startswith("mpi") else 0)
        simulated = start_up + list_schedule(runs, workers) + fits
        print(
            f"{name:<16}{workers:>8}{result['wall_s']:>9.1f}"
            f"{serial['wall_s'] / result['wall_s']:>10.2f}{simulated:>9.1f}"
        )
    same = max(largest_difference(serial["folder"], r["folder"]) for r in results[1:])
    print(f"largest relative coefficient difference to local-1 over all surfaces: {same:.1e}")
    print(
        f"run times (1 job): sum W = {work:.1f} s, mean {np.mean(runs):.2f} s, median "
        f"{np.median(runs):.2f} s, longest t_max = {longest:.2f} s; fits F = {fits:.1f} s; "
        f"start-up etc. T0 = {start_up:.1f} s"
    )
    print(f"{'workers P':>9}{'T(P) s':>9}{'simulated s':>13}{'speed-up':>10}{'efficiency':>11}")
    for workers in PREDICTED_WORKERS:
        predicted = start_up + max(work / workers, longest) + fits
        simulated = start_up + list_schedule(runs, workers) + fits
        print(
            f"{workers:>9}{predicted:>9.1f}{simulated:>13.1f}{serial['wall_s'] / predicted:>10.1f}"
            f"{serial['wall_s'] / (workers * predicted):>11.2f}"
        )


if __name__ == "__main__":
    main()
