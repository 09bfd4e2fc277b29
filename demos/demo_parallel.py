"""A large fabric patch in parallel: course-wise tension on a fine mesh under MPI.

The 50 x 50 mm patch of the tension demo, now with 200 x 200 elements (80 802 degrees of
freedom) by default, stretched to 10 % in 5 steps. Run it with several ranks; DOLFINx
partitions the gmsh mesh, PETSc assembles and solves in parallel (MUMPS by default, or
GMRES with hypre BoomerAMG for large meshes), and the reaction force is reduced over ranks,
so the force equals the serial one to round-off:

    mpirun -n 2 python demos/demo_parallel.py [--elements 200] [--steps 5]
        [--linear-solver lu|gmres] [--surface surface.h5]

The material is, by default, the cotton 20s/2, stitch 5.5 response surface that `knitmech run`
makes for its default scene (shipped with the package).
"""

import argparse
import time

from mpi4py import MPI

from fabric_dolfinx.material import surface_material
from fabric_dolfinx.part.tension import TensionSetup
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.tension import TensionTest
from knitmech.scene import default_surface_path
from rve_rod.surface import read_surface

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--elements", type=int, default=200, help="elements per side")
parser.add_argument("--steps", type=int, default=5, help="load steps to 10 %%")
parser.add_argument("--linear-solver", default="lu", help="lu (MUMPS), gmres or cg")
parser.add_argument("--surface", help="response-surface file (default: cotton, from knitmech)")
args = parser.parse_args()
comm = MPI.COMM_WORLD

# Every rank reads the surface file (small).
surface = read_surface(args.surface or default_surface_path())
material = surface_material(surface)

# Mesh generation (gmsh on rank 0, then partitioning) and form compilation are timed apart
# from the solve: the JIT compiles once and caches the kernels on disk.
start = time.perf_counter()
test = TensionTest(direction="course", elements=args.elements, max_strain=0.1)
setup = TensionSetup(
    material, test, SolverOptions(steps=args.steps, linear_solver=args.linear_solver), comm
)
setup_time = time.perf_counter() - start
result = setup.run()

if comm.rank == 0:
    print(f"ranks: {result.ranks}")
    print(f"dofs: {result.dofs}")
    print(f"linear solver: {args.linear_solver}")
    print(f"Newton iterations: {int(result.newton_iterations.sum())} in {args.steps} steps")
    print(f"force at 10 %: {result.force_gf_per_cm[-1]:.12g} gf/cm")
    print(f"setup (mesh, forms): {setup_time:.2f} s, solve: {result.wall_time_s:.2f} s")
