"""Speed and accuracy of the fabric membrane: prints tables (record them in docs/benchmarks.md).

Sections (all by default, or pick with --section):

  material  response-surface material against orthotropic SVK, same mesh and load path:
            assembly times and whole solve (the forms' cold compilation:
            benchmarks/bench_quadrature_material.py).
  scaling   time and peak memory against DOFs, 10 x 10 ... 400 x 400 elements (each size in
            a fresh process); then 1 against 2 MPI ranks on the largest.
  accuracy  element degree (1, 2) and quadrature degree against the reaction-force error and
            time, on the plate with a hole (smooth solution, reference by Richardson
            extrapolation of Q2 results).

    python benchmarks/bench_membrane.py [--section material|scaling|accuracy] [--quick]

Timings on a shared machine are noisy: each number is the best of a few repetitions where
cheap, and every table says what it timed.
"""

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import dolfinx.fem.petsc
from mpi4py import MPI

from fabric_dolfinx.material import OrthotropicSVK, surface_material, svk_material
from fabric_dolfinx.part.tension import TensionSetup
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.tension import TensionTest

# the synthetic surface is a test fixture (tests/support/surface_cases.py)
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from support.plate_cases import stretched_plate
from support.surface_cases import synthetic_surface

MPI_ENV = {
    **os.environ,
    "OMPI_ALLOW_RUN_AS_ROOT": "1",
    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1",
}
# The SVK law with the synthetic surface's stiffness at E = 0 (a1 b1, a2 b2, c, g).
SVK = OrthotropicSVK(
    course_stiffness=0.12 - 0.02**2 / 0.2,
    wale_stiffness=0.2 - 0.02**2 / 0.12,
    poissons_ratio=0.02 / 0.2,
    shear_stiffness=0.025,
)


def best_time(function, repeat=3):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def material_section(quick):
    """Surface against SVK on one mesh and load path; kernel sizes and compile times."""
    elements = 60 if quick else 150
    surface = synthetic_surface()
    test = TensionTest(elements=elements, max_strain=0.2)
    options = SolverOptions(steps=10)
    print(f"\n## material: surface vs SVK, {elements} x {elements} Q1, course to 20 % in 10 steps")
    print(
        "| material | J assembly (s) | R assembly (s) | solve (s) | Newton | force 20 % (gf/cm) |"
    )
    print("|---|---|---|---|---|---|")
    rows = {}
    for name, material in (("surface", surface_material(surface)), ("SVK", svk_material(SVK))):
        setup = TensionSetup(material, test, options)
        setup.run()  # warm: compiled kernels, factorization structures
        result = setup.run()
        stepper = setup.stepper
        matrix = stepper._matrix

        def assemble_jacobian(stepper=stepper, matrix=matrix):
            matrix.zeroEntries()
            dolfinx.fem.petsc.assemble_matrix(matrix, stepper._jacobian_form, bcs=stepper.bcs)
            matrix.assemble()

        jacobian = best_time(assemble_jacobian, 5)
        residual = best_time(stepper._assemble_residual, 5)
        solve = min(result.wall_time_s, setup.run().wall_time_s)
        rows[name] = (jacobian, residual, solve)
        iterations = int(result.newton_iterations.sum())
        print(
            f"| {name} | {jacobian:.4f} | {residual:.4f} | {solve:.2f} | {iterations} | "
            f"{result.force_gf_per_cm[-1]:.2f} |"
        )
    ratios = [rows["surface"][i] / rows["SVK"][i] for i in range(3)]
    print(f"| ratio surface/SVK | {ratios[0]:.2f} | {ratios[1]:.2f} | {ratios[2]:.2f} | | |")


def peak_memory_mb():
    """Peak resident memory of this process (MB): VmHWM, which, unlike ru_maxrss, does not
    inherit the peak of the process that forked it."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return float(line.split()[1]) / 1024.0
    return float("nan")


def one_size(elements, steps, linear_solver):
    """Run one tension test; rank 0 prints a JSON line (times, Newton, memory)."""
    comm = MPI.COMM_WORLD
    start = time.perf_counter()
    test = TensionTest(elements=elements, max_strain=0.1)
    setup = TensionSetup(
        surface_material(synthetic_surface()),
        test,
        SolverOptions(steps=steps, linear_solver=linear_solver),
        comm,
    )
    setup_time = time.perf_counter() - start
    result = setup.run()
    memory = comm.allreduce(peak_memory_mb())
    if comm.rank == 0:
        record = {
            "elements": elements,
            "dofs": result.dofs,
            "ranks": comm.size,
            "setup_s": setup_time,
            "solve_s": result.wall_time_s,
            "newton": int(result.newton_iterations.sum()),
            "linear": sum(step.linear_iterations for step in result.path.steps),
            "memory_mb": memory,
            "force": float(result.force_gf_per_cm[-1]),
        }
        print(json.dumps(record))


def run_size(elements, steps, linear_solver, ranks=1):
    command = [sys.executable, __file__, "--one-size", str(elements), str(steps), linear_solver]
    if ranks > 1:
        command = ["mpirun", "-n", str(ranks), *command]
    output = subprocess.run(command, check=True, capture_output=True, text=True, env=MPI_ENV).stdout
    return json.loads(output.strip().splitlines()[-1])


def scaling_section(quick):
    sizes = [10, 25, 50, 100] if quick else [10, 25, 50, 100, 200, 400]
    steps = 5
    print(f"\n## scaling: course tension to 10 % in {steps} steps, surface material, Q1")
    print("| elements | dofs | solver | ranks | setup (s) | solve (s) | Newton | linear its "
          "| s/Newton | peak memory (MB, all ranks) | force (gf/cm) |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    runs = [(n, "lu", 1) for n in sizes]
    runs += [(sizes[-1], "gmres", 1), (sizes[-1], "lu", 2), (sizes[-1], "gmres", 2)]
    for elements, solver, ranks in runs:
        r = run_size(elements, steps, solver, ranks)
        print(
            f"| {elements} | {r['dofs']} | {solver} | {ranks} | {r['setup_s']:.2f} | "
            f"{r['solve_s']:.2f} | {r['newton']} | {r['linear']} | "
            f"{r['solve_s'] / r['newton']:.3f} | "
            f"{r['memory_mb']:.0f} | {r['force']:.6f} |"
        )


def hole_reaction(degree, quadrature_degree, refinements):
    """(reaction (N), solve (s), dofs) of the plate with a hole on rollers stretched by 10 %
    (tests/support/plate_cases.py, the mesh-convergence test's problem)."""
    result = stretched_plate(refinements, degree, quadrature_degree)
    return result.reaction[0], result.seconds, result.dofs


def accuracy_section(quick):
    levels = [0, 1, 2] if quick else [0, 1, 2, 3]
    reference_levels = levels[-2:]
    q2 = [hole_reaction(2, 4, level)[0] for level in reference_levels]
    # Q2 on the polygonal hole converges as h^2 (the geometry error): Richardson with rate 2.
    reference = q2[1] + (q2[1] - q2[0]) / 3.0
    print(f"\n## accuracy: plate with hole, 10 % stretch, reference {reference:.8f} N")
    print("(Richardson extrapolation of Q2 on the two finest levels)")
    print("| element | Gauss points | level | dofs | reaction (N) | rel. error | solve (s) |")
    print("|---|---|---|---|---|---|---|")
    # Gauss rules exact to degree q have ceil((q + 1) / 2) points per direction.
    for degree, quadratures in ((1, (1, 2, 4)), (2, (2, 4, 6))):
        for quadrature in quadratures:
            points = f"{(quadrature + 2) // 2}x{(quadrature + 2) // 2}"
            for level in levels:
                reaction, seconds, dofs = hole_reaction(degree, quadrature, level)
                error = abs(reaction - reference) / reference
                print(
                    f"| Q{degree} | {points} | {level} | {dofs} | {reaction:.8f} | "
                    f"{error:.2e} | {seconds:.2f} |"
                )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--section", choices=["material", "scaling", "accuracy"])
    parser.add_argument("--quick", action="store_true", help="smaller sizes")
    parser.add_argument("--one-size", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one_size:
        one_size(int(args.one_size[0]), int(args.one_size[1]), args.one_size[2])
        return
    print(f"# bench_membrane ({'quick' if args.quick else 'full'}), load: {os.getloadavg()}")
    sections = {"material": material_section, "scaling": scaling_section}
    sections["accuracy"] = accuracy_section
    for name, section in sections.items():
        if args.section in (None, name):
            section(args.quick)


if __name__ == "__main__":
    main()
