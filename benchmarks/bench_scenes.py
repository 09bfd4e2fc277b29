"""The example scenes graded strip and bias extension at each fidelity level, cold and cached.

Each (scene, level) runs `knitmech run examples/<scene>.toml --fidelity <level>` in a fresh
process twice: cold (empty stage and RVE-run caches; the FFCx kernel and numba caches are
left as they are) and again on the filled cache, as a user would. The table gives the wall
time of the whole process, the time of each stage of the cold run (summed over a stage's
items: `knits` are the graded strip's family members besides the scene's own surface), the
part's cells, Newton iterations and one result per scene with its difference to the finest
level run:

* graded strip: the force on the top clamp at 20 mm (N) and the wale-wise Green-Lagrange
  strain E22 at the probes `middle` (stitch 7.0) and `end` (stitch 4.5);
* bias extension: the force on the top clamp at 20 mm (N) and the shear angle of the central
  zone (probe `centre`, degrees).

Run: .venv/bin/python benchmarks/bench_scenes.py [--levels fast,balanced,accurate]
         [--scenes graded_strip,bias_extension] [--jobs 2] [--keep DIR]
"""

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
STAGES = ("geometry", "meso", "surface", "knits", "fabric", "report")


def run(scene: str, level: str, folder: Path, jobs: int) -> dict:
    """Cold and cached runs of examples/<scene>.toml at `level`: their summaries."""
    folder.mkdir(parents=True, exist_ok=True)
    runs = {}
    for state in ("cold", "cached"):
        command = [
            sys.executable,
            "-m",
            "knitmech",
            "run",
            str(EXAMPLES / f"{scene}.toml"),
            "--fidelity",
            level,
            "--output",
            str(folder / "results"),
            "--cache-dir",
            str(folder / "cache"),
            "--jobs",
            str(jobs),
        ]
        started = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True, text=True)
        runs[state] = json.loads((folder / "results" / "summary.json").read_text())
        runs[state]["process_wall_time_s"] = time.perf_counter() - started
    return runs


def stage_times(summary: dict) -> dict[str, float]:
    """Seconds per stage of a run (the knit surfaces besides the scene's under `knits`)."""
    times = dict.fromkeys(STAGES, 0.0)
    for record in summary["stages"]:
        name = "knits" if record["stage"] == "surface" and record["item"] else record["stage"]
        times[name] = times.get(name, 0.0) + record["wall_time_s"]
    times["report"] = summary["timings_s"]["report"]
    return times


def results(scene: str, part: dict) -> dict[str, float]:
    """The scene's physical numbers at the end of its load path."""
    values = {"force (N)": part["boundaries"]["top"]["force"][-1][1]}
    if scene == "graded_strip":
        for probe in ("middle", "end"):
            values[f"E22 {probe}"] = part["probes"][probe]["strain"][-1][1][1]
    else:
        values["shear angle"] = part["probes"]["centre"]["shear_angle"][-1]
    return values


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", default="fast,balanced,accurate")
    parser.add_argument("--scenes", default="graded_strip,bias_extension")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--keep", type=Path, help="keep results and caches under this folder")
    args = parser.parse_args()
    levels = args.levels.split(",")
    root = args.keep or Path(tempfile.mkdtemp(prefix="bench-scenes-"))
    for scene in args.scenes.split(","):
        print(f"\n{scene}")
        header = "".join(f"{name:>9}" for name in STAGES)
        print(f"{'level':>9}{'cells':>7}{'newton':>7}{'cold':>8}{'cached':>8}{header}")
        table = {}
        for level in levels:
            runs = run(scene, level, root / scene / level, args.jobs)
            cold, cached = runs["cold"], runs["cached"]
            part = cold["part"]
            times = stage_times(cold)
            cells = "".join(f"{times[name]:>9.1f}" for name in STAGES)
            print(
                f"{level:>9}{part['cells']:>7}{sum(part['newton_iterations']):>7}"
                f"{cold['process_wall_time_s']:>8.1f}{cached['process_wall_time_s']:>8.1f}{cells}"
            )
            assert all(r["status"] in ("cached", "given") for r in cached["stages"])
            table[level] = results(scene, part)
        finest = table[levels[-1]]
        print(f"{'level':>9}" + "".join(f"{key:>24}" for key in finest))
        for level, values in table.items():
            cells = "".join(
                f"{values[k]:>14.5g} ({100 * (values[k] / finest[k] - 1):+5.1f} %)" for k in finest
            )
            print(f"{level:>9}{cells}")
    print(f"\nresults and caches: {root}")


if __name__ == "__main__":
    main()
