"""Speed/accuracy trade of the fidelity levels on the default scene, against the finest settings.

Each level runs the default scene (cotton 20s/2, stitch 5.5, 50 mm patch course- and
wale-wise) twice in a fresh process: cold (empty stage and RVE-run caches; the FFCx kernel
cache of DOLFINx is left as it is) and again on the filled cache, as a user would. The table
gives wall times (per stage and total), the patch (macro) and RVE (meso) forces at 10 and 20 %
in both directions with their errors against `reference` (knitmech.fidelity.REFERENCE), and
the Poisson ratios nu12, nu21 at 20 %.

Run: .venv/bin/python benchmarks/bench_pipeline.py [--levels fast,balanced,accurate,reference]
         [--jobs 2] [--keep DIR]

`--keep DIR` keeps every level's results folder and cache under DIR, and a level whose
results DIR already holds is not run again (the reference takes the longest): its numbers are
read back, with the times measured when it ran.
"""

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

LEVELS = ("fast", "balanced", "accurate", "reference")
STRAINS = (0.10, 0.20)


def run_level(level: str, folder: Path, jobs: int) -> dict:
    """Run the default scene at `level` cold, then cached; returns both summaries."""
    runs = {}
    for state in ("cold", "cached"):
        command = [
            sys.executable,
            "-c",
            "import sys, json; from knitmech.pipeline import run_scene; "
            "from knitmech.scene import load_scene; "
            f"r = run_scene(load_scene(), fidelity={level!r}, output={str(folder / 'results')!r},"
            f" cache_dir={str(folder / 'cache')!r}, jobs={jobs}); "
            "json.dump(r.summary, sys.stdout)",
        ]
        started = time.perf_counter()
        process = subprocess.run(command, check=True, capture_output=True, text=True)
        runs[state] = json.loads(process.stdout)
        runs[state]["process_wall_time_s"] = time.perf_counter() - started
    (folder / "bench.json").write_text(json.dumps(runs))
    return runs


def _at(record: dict, key: str, strain: float) -> float:
    index = min(range(len(record["strain"])), key=lambda i: abs(record["strain"][i] - strain))
    if abs(record["strain"][index] - strain) > 1e-9:
        return float("nan")
    return record[key][index] if record[key][index] is not None else float("nan")


def numbers(summary: dict) -> dict[str, float]:
    """Forces at 10 and 20 % (macro and meso, both directions) and Poisson ratios at 20 %."""
    values = {}
    for direction, case in (("course", "uniaxial-course"), ("wale", "uniaxial-wale")):
        for strain in STRAINS:
            label = f"{direction[0]}{round(100 * strain)}"
            values[f"macro {label}"] = _at(summary["macro"][direction], "force_gf_per_cm", strain)
            values[f"meso {label}"] = _at(summary["meso"][case], "force_gf_per_cm", strain)
    for name in ("nu12", "nu21"):
        entry = summary["poisson_ratios"][name]
        for scale in ("meso", "macro"):
            value = entry[scale][-1]  # None: a run that stopped before 20 %
            values[f"{scale} {name}"] = float("nan") if value is None else value
    return values


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", default=",".join(LEVELS))
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--keep", type=Path, help="keep (and reuse) results under this folder")
    args = parser.parse_args()
    levels = args.levels.split(",")
    with tempfile.TemporaryDirectory() as scratch:
        root = args.keep or Path(scratch)
        runs = {}
        for level in levels:
            folder = root / level
            if (folder / "bench.json").is_file():
                runs[level] = json.loads((folder / "bench.json").read_text())
            else:
                folder.mkdir(parents=True, exist_ok=True)
                runs[level] = run_level(level, folder, args.jobs)
            print(f"{level}: done", file=sys.stderr)
    reference = numbers(runs["reference"]["cold"]) if "reference" in runs else None

    print(f"default scene, jobs {args.jobs}; wall times in s (cold: empty caches)")
    stages = ("geometry", "meso", "surface", "macro")
    print(
        f"{'level':<10}{'cp':>4}{'rays':>5}{'elem':>5}"
        + "".join(f"{s:>9}" for s in stages)
        + f"{'cold':>8}{'cached':>8}"
    )
    for level, run in runs.items():
        cold, fidelity = run["cold"], run["cold"]["fidelity"]
        timings = cold["timings_s"]
        print(
            f"{level:<10}{fidelity['control_points']:>4}{fidelity['rays']:>5}"
            f"{fidelity['elements']:>5}"
            + "".join(f"{timings.get(s, 0.0):>9.1f}" for s in stages)
            + f"{run['cold']['process_wall_time_s']:>8.1f}"
            + f"{run['cached']['process_wall_time_s']:>8.1f}"
        )
    keys = list(numbers(next(iter(runs.values()))["cold"]))
    print()
    print("forces (gf/cm) at 10/20 % course (c) and wale (w), Poisson ratios at 20 %;")
    print("in brackets: relative difference to the reference (%)")
    print(f"{'quantity':<12}" + "".join(f"{level:>18}" for level in runs))
    for key in keys:
        cells = ""
        for run in runs.values():
            value = numbers(run["cold"])[key]
            if reference is None or reference[key] in (0.0, None):
                cells += f"{value:>18.3f}"
            else:
                error = 100 * (value - reference[key]) / abs(reference[key])
                cells += f"{value:>10.3f} ({error:+5.1f})"
        print(f"{key:<12}{cells}")


if __name__ == "__main__":
    main()
