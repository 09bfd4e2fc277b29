"""Tension of a single-jersey patch, course-wise and wale-wise (the paper's macro-scale test).

A 50 x 50 mm fabric patch on 10 x 10 quadrilateral membrane elements is stretched to 20 %
between clamps: course-wise the left edge is clamped and the right edge moved along x;
wale-wise the bottom edge is clamped and the top edge moved along y. The material is a
response surface (the homogenized knit): by default the cotton 20s/2, stitch 5.5 surface that
`knitmech run` makes for its default scene (shipped with the package, see docs/pipeline.md;
`knitmech run` itself also runs this test, beside the RVE). The demo prints and plots the
force per width in gf/cm against the strain, beside what the material alone gives in
homogeneous uniaxial tension (and beside an RVE curve when one is given), and it writes the
stress fields at 10 % (course) and 9 % (wale) like the paper's Figure 8, as PNG and as XDMF
for ParaView.

Run it serially or in parallel; every option has a default:

    python demos/demo_patch_tension.py [--surface results/surface.h5] [--rve-curve rve.json]
        [--elements 10] [--steps 20] [--output results/patch_tension]
    mpirun -n 2 python demos/demo_patch_tension.py
"""

import argparse
import json
from pathlib import Path

from mpi4py import MPI

from fabric_dolfinx.io.plot import plot_cell_field, plot_force_strain
from fabric_dolfinx.io.rve_curve import read_rve_curve
from fabric_dolfinx.material import surface_material
from fabric_dolfinx.part.tension import TensionSetup
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.tension import TensionTest
from knitmech.scene import default_surface_path
from rve_rod.surface import homogeneous_response, read_surface
from rve_rod.units import n_per_mm_to_gf_per_cm

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument(
    "--surface", help="response-surface file (default: cotton 20s/2, stitch 5.5, from knitmech)"
)
parser.add_argument("--rve-curve", help="JSON with the RVE's uniaxial strain, force_gf_per_cm")
parser.add_argument("--elements", type=int, default=10, help="elements per side")
parser.add_argument("--steps", type=int, default=20, help="load steps to 20 %%")
parser.add_argument("--output", default="results/patch_tension", help="output folder")
args = parser.parse_args()
comm = MPI.COMM_WORLD
output = Path(args.output)
if comm.rank == 0:
    output.mkdir(parents=True, exist_ok=True)
comm.barrier()

# The surface file is the only thing the fabric scale takes from the yarn scale; every rank
# reads it. The default one was made from rod-RVE runs of the cotton fabric by `knitmech run`.
surface_path = Path(args.surface) if args.surface else default_surface_path()
surface = read_surface(surface_path)
material = surface_material(surface, name=surface_path.name)

# The paper shows the stress fields at 10 % course-wise and 9 % wale-wise; with 20 steps to
# 20 % both are step ends, where the fields are evaluated (Cauchy stress per cell, N/mm).
FIELD_STRAIN = {"course": 0.10, "wale": 0.09}
COMPONENT = {"course": (0, 0), "wale": (1, 1)}
max_strain = 0.2
results = {}
for direction in ("course", "wale"):
    test = TensionTest(direction=direction, elements=args.elements, max_strain=max_strain)
    setup = TensionSetup(material, test, SolverOptions(steps=args.steps), comm)

    def snapshot(strain, fields, direction=direction):
        if abs(strain - FIELD_STRAIN[direction]) < 1e-9:
            plot_cell_field(
                fields,
                output / f"stress_{direction}.png",
                component=COMPONENT[direction],
                title=f"{direction}-wise tension, {100 * strain:.0f} % strain",
            )

    results[direction] = setup.run(xdmf=output / f"{direction}.xdmf", on_step=snapshot)

# What the material alone gives: homogeneous uniaxial tension (lateral stress zero), the load
# case the RVE runs. The clamps hold the patch's ends at the lateral stretch 1, so the patch
# is a little stiffer than this.
strain = results["course"].strain
uniaxial = {
    direction: n_per_mm_to_gf_per_cm(homogeneous_response(surface, strain, direction))
    for direction in ("course", "wale")
}
rve = read_rve_curve(args.rve_curve) if args.rve_curve else None
curves = {f"patch, {d}-wise": (results[d].strain, results[d].force_gf_per_cm) for d in results}
references = {f"material alone, uniaxial {d}": (strain, uniaxial[d]) for d in uniaxial}
if comm.rank == 0:
    plot_force_strain(curves, output / "force_strain.png", rve, references)
    print(f"patch tension: {args.elements} x {args.elements} elements, {comm.size} rank(s)")
    print(f"{'strain (%)':>10} {'course (gf/cm)':>15} {'wale (gf/cm)':>13} {'uniaxial c/w':>16}")
    for row in zip(
        strain,
        results["course"].force_gf_per_cm,
        results["wale"].force_gf_per_cm,
        uniaxial["course"],
        uniaxial["wale"],
        strict=True,
    ):
        print(f"{100 * row[0]:10.1f} {row[1]:15.3f} {row[2]:13.3f} {row[3]:8.3f}/{row[4]:.3f}")
    summary = {
        "ranks": comm.size,
        "elements": args.elements,
        "strain": strain.tolist(),
        **{f"{d}_force_gf_per_cm": results[d].force_gf_per_cm.tolist() for d in results},
        **{f"{d}_uniaxial_gf_per_cm": uniaxial[d].tolist() for d in uniaxial},
        "newton_iterations": {d: int(results[d].newton_iterations.sum()) for d in results},
    }
    (output / "summary.json").write_text(json.dumps(summary, indent=2))
    print(f"figures, XDMF and summary.json in {output}")
