"""Speed and accuracy of the design (issue 30, docs/design.md): evaluations, wall times, the
recovered stitch values, and the sleeve's Laplace model against its contact model.

1. Material-level inverse on the cotton 20s/2 family (level --level): each member's own
   uniaxial curves (5, 10, 15, 20 %, both directions) as the target, the family with the
   member (it must come back exactly) and without it (the graded law between its neighbours:
   how far a measured knit's stitch value is found from the interpolated family); the mean of
   two neighbours' curves.
2. The leg sleeve of examples/design/leg_sleeve.toml (8 bands, 4.5 -> 3.0 mmHg, needles
   designed): evaluations and time of the Laplace design, then the contact model at element
   sizes --sizes (mm): per band the contact pressure against the Laplace model, and the
   explanation of the difference (docs/design.md).
3. The part design of examples/design/graded_strip.toml through `knitmech design`, twice: cold
   (its evaluations computed) and warm (every evaluation from the stage cache).

Timings are wall times on the shared machine: noisy, repeat and take the minimum.

Run: .venv/bin/python benchmarks/bench_design.py [--level fast] [--sizes 5,2.5] [--jobs 2]
         [--cache DIR] [--skip-part]
"""

import argparse
import shutil
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from knitmech.design.family import SurfaceFamily
from knitmech.design.material import UniaxialTarget, fit_stitch
from knitmech.design.run import contact_job, run_design
from knitmech.design.sleeve import PressureTarget, design_sleeve, stretched_band
from knitmech.design.solve import SolverSettings
from knitmech.design.spec import load_design
from knitmech.fidelity import fidelity_level
from knitmech.jobs.sleeve import run_sleeve
from knitmech.scene import scene_from_dict
from knitmech.stages import SurfaceRuns, plan_run
from knitmech.stages.cache import StageCache
from knitmech.stages.family import family_members, family_stitches
from rve_rod.cache import ResultCache, default_cache_root
from rve_rod.homogenize.executors import ExecutorChoice
from rve_rod.units import MMHG

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "design"
STRAINS = np.array([0.05, 0.10, 0.15, 0.20])


def cotton_family(level: str, cache: Path, jobs: int, folder: Path) -> SurfaceFamily:
    scene = scene_from_dict({"fabric": {"preset": "cotton-20s2", "stitch": 5.5}})
    plan = plan_run(scene, fidelity_level(level))
    stages = StageCache(cache / "stages")
    runs = SurfaceRuns(ResultCache(cache / "rve-runs"), ExecutorChoice("local", jobs), None)
    members = family_members(
        plan, family_stitches(plan), lambda s: stages.run(s, folder).summary, runs, folder
    )
    return SurfaceFamily(members)


def curves(family: SurfaceFamily, stitch: float) -> list[UniaxialTarget]:
    return [
        UniaxialTarget(d, STRAINS, family.uniaxial(stitch, STRAINS, d)) for d in ("course", "wale")
    ]


def material(family: SurfaceFamily) -> None:
    print("\n1. material-level inverse (targets: 5, 10, 15, 20 %, course and wale)")
    print(f"{'target':<30}{'family':<22}{'found (mm)':>11}{'error':>9}{'evals':>7}{'time (s)':>10}")
    for stitch in family.stitch_values[1:-1]:
        for left_out in (False, True):
            members = family
            if left_out:
                kept = [i for i, s in enumerate(family.stitch_values) if s != stitch]
                members = SurfaceFamily(
                    tuple(family.members[i] for i in kept), tuple(family.surfaces[i] for i in kept)
                )
            fit = fit_stitch(members, curves(family, stitch))
            label = "without it" if left_out else "all members"
            print(
                f"{f'member {stitch:g}':<30}{label:<22}{fit.stitch:>11.4f}"
                f"{fit.stitch - stitch:>+9.4f}{fit.solution.evaluations:>7d}"
                f"{fit.solution.wall_time_s:>10.2f}"
            )
    for low, high in zip(family.stitch_values[:-1], family.stitch_values[1:], strict=True):
        targets = [
            UniaxialTarget(t.direction, STRAINS, 0.5 * (t.force + u.force))
            for t, u in zip(curves(family, low), curves(family, high), strict=True)
        ]
        fit = fit_stitch(family, targets)
        print(
            f"{f'mean of {low:g} and {high:g}':<30}{'all members':<22}{fit.stitch:>11.4f}"
            f"{'':>9}{fit.solution.evaluations:>7d}{fit.solution.wall_time_s:>10.2f}"
        )


def sleeve(family: SurfaceFamily, sizes: list[float], folder: Path) -> None:
    _, spec = load_design(EXAMPLES / "leg_sleeve.toml")
    target_spec = spec.targets[0]
    sleeve_spec = spec.sleeve
    target = PressureTarget(target_spec.pressure_at(sleeve_spec.centres), tolerance=0.05)
    design = design_sleeve(family, sleeve_spec, target, spec.bounds, SolverSettings())
    print(
        f"\n2. leg sleeve, 8 bands, 4.5 -> 3.0 mmHg: {design.evaluations} evaluations, "
        f"search {design.search_time_s:.2f} s, "
        f"largest miss {100 * np.abs(design.misses).max():.2f} %"
    )
    print(
        "stitch", np.round(design.stitches, 3), "needles", design.needles, "courses", design.courses
    )
    bands = [
        {
            "stitch": s,
            "needles": n,
            "courses": c,
        }
        for s, n, c in zip(design.stitches, design.needles, design.courses, strict=True)
    ]
    laplace = np.array([state.pressure for state in design.states])
    for size in sizes:
        job = replace(contact_job(family, spec, bands, size), steps=10)
        started = time.perf_counter()
        output = folder / f"contact-{size:g}"
        output.mkdir()
        summary = run_sleeve(job, output)
        wall = time.perf_counter() - started
        print(
            f"\ncontact model, {size:g} mm quads: {summary['dofs']} DOFs, "
            f"{len(summary['newton_iterations'])} steps, {sum(summary['newton_iterations'])} "
            f"Newton iterations, {summary['cutbacks']} cutbacks, "
            f"solve {summary['wall_time_s']:.1f} s, "
            f"wall {wall:.1f} s (FFCx included)"
        )
        print(
            f"{'band':>4}{'z':>6}{'Laplace':>9}{'contact':>9}{'diff':>8}{'hoop L':>8}{'hoop c':>8}"
            f"{'axial c':>9}{'L at c':>9}{'N_phi k':>9}{'identity':>10}  (mmHg)"
        )
        for k, ring in enumerate(summary["bands"]):
            own = stretched_band(
                family,
                ring["stitch"],
                (ring["hoop_stretch"], ring["axial_stretch"]),
                ring["limb_radius"],
            )
            print(
                f"{k + 1:>4}{ring['z']:>6.0f}{laplace[k] / MMHG:>9.3f}"
                f"{ring['pressure'] / MMHG:>9.3f}"
                f"{100 * (ring['pressure'] / laplace[k] - 1):>+7.1f}%"
                f"{design.states[k].hoop_stretch:>8.4f}{ring['hoop_stretch']:>8.4f}"
                f"{ring['axial_stretch']:>9.4f}{own.pressure / MMHG:>9.3f}"
                f"{(ring['membrane_pressure'] - ring['laplace_term']) / MMHG:>+9.3f}"
                f"{100 * (ring['membrane_pressure'] / ring['pressure'] - 1):>+9.2f}%"
            )


def part(cache: Path, jobs: int, folder: Path) -> None:
    scene, spec = load_design(EXAMPLES / "graded_strip.toml")
    print("\n3. part design, examples/design/graded_strip.toml")
    for run in ("cold", "warm"):
        started = time.perf_counter()
        result = run_design(scene, spec, output=folder / "strip", cache_dir=cache, jobs=jobs)
        summary = result.summary
        values = ", ".join(f"{v['name']} {v['value']:.4f}" for v in summary["variables"])
        misses = ", ".join(f"{100 * t['miss']:.3f} %" for t in summary["targets"])
        print(
            f"{run}: {summary['evaluations']} evaluations, {time.perf_counter() - started:.1f} s; "
            f"{values}; misses {misses}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", default="fast")
    parser.add_argument("--sizes", default="5,2.5")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--cache", type=Path, default=default_cache_root())
    parser.add_argument("--skip-part", action="store_true")
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="bench-design-"))
    try:
        family = cotton_family(args.level, args.cache, args.jobs, work)
        material(family)
        sleeve(family, [float(s) for s in args.sizes.split(",")], work)
        if not args.skip_part:
            part(args.cache, args.jobs, work)
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
