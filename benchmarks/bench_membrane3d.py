"""Speed and accuracy of the membrane in space: prints tables (record them in
docs/benchmarks.md).

Two cases on the shipped cotton 20s/2 stitch 5.5 surface, at the mesh of each fidelity level
(`knitmech.fidelity`: 6, 10, 20, 40 elements across the part) and finer:

  ball   the ball burst of examples/ball_burst.toml (ASTM D3787: ball 25.4 mm, ring 44.45
         mm, 12 mm travel in 12 steps, the example's penalty and stabilization): force on the
         ball, its convergence with the mesh and the penalty, and how many steps kept the
         stabilization (could not be released).
  tube   the tube of examples/tube_inflation.toml (radius 20 mm, length 80 mm, ends
         clamped, the example's pressure and steps): the largest displacement.

Both with the solver settings of `knitmech` (`part.problem.space_solver_options`). For
each: DOFs, wall time (s, forms compiled beforehand), Newton iterations per step
(mean/max) and cutbacks; each on 1 and on 2 MPI ranks (the 2-rank runs start this script
under mpirun with --case and --elements).

  hencky the full-resolution variant of
         tests/test_fabric_dolfinx/verification/test_membrane3d_hencky.py:
         central deflection error against Hencky's series down to 1.25 mm quads, with the
         observed convergence rate.

    python benchmarks/bench_membrane3d.py [--case ball|tube|hencky] [--quick] [--sizes 40,80]
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
from mpi4py import MPI

from fabric_dolfinx.material import surface_material
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.part.problem import PartProblem, space_solver_options
from fabric_dolfinx.part.regions import Region
from fabric_dolfinx.spec.part import BoundaryCondition, MeshSpec
from fabric_dolfinx.spec.space import IndenterSpec, SpaceSpec
from rve_rod.errors import ConvergenceError
from rve_rod.surface import read_surface

ROOT = Path(__file__).resolve().parents[1]
SURFACE = ROOT / "knitmech" / "data" / "cotton-20s2_stitch-5.5.h5"
BALL_BURST = tomllib.loads((ROOT / "examples" / "ball_burst.toml").read_text())
TUBE = tomllib.loads((ROOT / "examples" / "tube_inflation.toml").read_text())
PENALTY = BALL_BURST["indenter"]["penalty"]
STABILIZATION = BALL_BURST["space"]["stabilization"]
LEVELS = {6: "fast", 10: "balanced", 20: "accurate", 40: "(finer)", 80: "(finer)"}
MPI_ENV = {
    **os.environ,
    "OMPI_ALLOW_RUN_AS_ROOT": "1",
    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1",
}


def ball(elements: int, penalty: float = PENALTY, stabilization: float = STABILIZATION) -> dict:
    material = surface_material(read_surface(SURFACE))
    radius = 22.225
    tagged = make_mesh(MeshSpec("disc", {"radius": radius}, element_size=2 * radius / elements))
    sphere = IndenterSpec((0.0, 0.0, 12.0), radius=12.7, centre=(0.0, 0.0, -12.7), penalty=penalty)
    problem = PartProblem(
        tagged,
        [Region("fabric", material)],
        [BoundaryCondition("rim")],
        space=SpaceSpec(indenter=sphere, stabilization=stabilization),
        options=space_solver_options(12),
    )
    start = time.perf_counter()
    result, reached = _run(problem)
    force = -result.space.indenter_force[-1, 2]
    return _record(problem, result, time.perf_counter() - start, force, reached)


def tube(elements: int) -> dict:
    material = surface_material(read_surface(SURFACE))
    spec = MeshSpec("tube", {"radius": 20.0, "length": 80.0}, element_size=40.0 / elements)
    tagged = make_mesh(spec)
    problem = PartProblem(
        tagged,
        [Region("fabric", material)],
        [BoundaryCondition("bottom"), BoundaryCondition("top")],
        space=SpaceSpec(pressure=TUBE["pressure"]["value"], course="around"),
        options=space_solver_options(TUBE["macro"]["steps"]),
    )
    start = time.perf_counter()
    result, reached = _run(problem)
    displacement = result.space.peak_displacement[-1]
    return _record(problem, result, time.perf_counter() - start, displacement, reached)


def _run(problem):
    """(result, load factor reached): the converged steps when the solver gives up."""
    try:
        result = problem.run()
    except ConvergenceError as error:
        result = error.history
    return result, float(result.load_factor[-1])


def _record(problem, result, seconds: float, value: float, reached: float) -> dict:
    iterations = result.newton_iterations
    return {
        "reached": reached,
        "dofs": problem.dofs,
        "ranks": MPI.COMM_WORLD.size,
        "seconds": seconds,
        "steps": int(iterations.size),
        "mean_iterations": float(iterations.mean()),
        "max_iterations": int(iterations.max()),
        "cutbacks": result.cutbacks,
        "value": float(value),
        "stabilized": int(np.count_nonzero(result.space.stabilization_force[1:])),
    }


CASES = {"ball": (ball, "force on the ball (N)"), "tube": (tube, "largest displacement (mm)")}


def on_two_ranks(case: str, elements: int, settings: dict) -> dict:
    command = ["mpirun", "-n", "2", sys.executable, __file__, "--case", case]
    command += ["--elements", str(elements), "--json"]
    for key, value in settings.items():
        command += [f"--{key}", str(value)]
    process = subprocess.run(
        command, capture_output=True, text=True, env=MPI_ENV, check=True, timeout=3600
    )
    return json.loads(process.stdout.strip().splitlines()[-1])


def table(case: str, sizes, settings: dict) -> None:
    """One row per mesh and rank count; `settings` go to the case (e.g. stabilization)."""
    run, label = CASES[case]
    print(f"\n{case}: {label} {settings or ''}")
    print(
        "| elements | level | DOFs | ranks | time (s) | Newton per step (mean / max) |"
        f" cutbacks | stabilized steps | {label} |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for elements in sizes:
        run(elements, **settings)  # compile the forms (cached for the timed runs)
        for record in (run(elements, **settings), on_two_ranks(case, elements, settings)):
            reached = record["reached"]
            note = "" if reached == 1.0 else f" (gave up at t = {reached:.3g})"
            print(
                f"| {elements} | {LEVELS[elements]} | {record['dofs']} | {record['ranks']} | "
                f"{record['seconds']:.2f} | {record['mean_iterations']:.1f} / "
                f"{record['max_iterations']} | {record['cutbacks']} | {record['stabilized']} | "
                f"{record['value']:.6g}{note} |"
            )


def penalty_table() -> None:
    print("\nball: force on the ball (N) against the penalty (balanced mesh)")
    print("| penalty (N/mm^3) | force (N) | change from the previous |")
    print("|---|---|---|")
    previous = None
    for penalty in (1.0, 3.0, 10.0, 30.0):
        force = ball(10, penalty)["value"]
        change = "" if previous is None else f"{(force - previous) / force:+.3%}"
        print(f"| {penalty:g} | {force:.6g} | {change} |")
        previous = force


def hencky_table() -> None:
    sys.path.insert(0, str(ROOT / "tests" / "test_fabric_dolfinx" / "verification"))
    import test_membrane3d_hencky as hencky  # noqa: PLC0415 (the test's series and setup)

    expected = hencky.hencky_deflection()
    print(f"\nHencky: central deflection against the series ({expected:.6f} mm)")
    print("| quad size (mm) | DOFs | deflection (mm) | relative error | rate | time (s) |")
    print("|---|---|---|---|---|---|")
    previous = None
    for size in (10.0, 5.0, 2.5, 1.25):
        start = time.perf_counter()
        problem, result = hencky.solve(size)
        seconds = time.perf_counter() - start
        error = abs(result.space.peak_displacement[-1] - expected) / expected
        rate = "" if previous is None else f"{math.log2(previous / error):.2f}"
        print(
            f"| {size:g} | {problem.dofs} | {result.space.peak_displacement[-1]:.6f} | "
            f"{error:.2e} | {rate} | {seconds:.2f} |"
        )
        previous = error


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", choices=[*sorted(CASES), "hencky"])
    parser.add_argument("--elements", type=int)
    parser.add_argument("--json", action="store_true", help="one run as JSON (for mpirun)")
    parser.add_argument("--quick", action="store_true", help="fast and balanced meshes only")
    parser.add_argument("--sizes", help="elements across, comma-separated (default 6,10,20,40)")
    parser.add_argument(
        "--stabilization", type=float, help="ball: instead of the example's (N/mm^3)"
    )
    args = parser.parse_args()
    settings = {} if args.stabilization is None else {"stabilization": args.stabilization}
    if args.json:
        record = CASES[args.case][0](args.elements, **settings)
        if MPI.COMM_WORLD.rank == 0:
            print(json.dumps(record))
        return
    sizes = (6, 10) if args.quick else (6, 10, 20, 40)
    if args.sizes:
        sizes = tuple(int(size) for size in args.sizes.split(","))
    if args.case in (None, "hencky"):
        hencky_table()
    for case in [args.case] if args.case in CASES else [] if args.case else sorted(CASES):
        table(case, sizes, settings if case == "ball" else {})
    if args.case in (None, "ball"):
        penalty_table()


if __name__ == "__main__":
    main()
