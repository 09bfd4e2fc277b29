"""The sleeve's contact model: the knitted tube drawn over the limb, a membrane in space in
frictionless contact with a rigid body of revolution (DOLFINx).

The reference surface is the sleeve at rest (`knitmech.design.sleeve.relaxed_tube`): a tube
about the z axis whose radius N(z) w(s(z)) / 2 pi and stitch field s(z) follow the bands, one
graded region (`fabric_dolfinx.graded`) with the course around the tube. A quarter is
modelled (symmetry rollers on its straight edges). The limb is an expanding mandrel
(`membrane.loads.RevolutionIndenter`): it starts at `start_scale` r(z), inside the tube, and
grows to r(z) over the load path while the tube's top end is carried axially to the limb's
end (rollers holding z at both ends; the ends are free radially); the contact is
frictionless, so the tube slides along the limb to its own axial equilibrium.

At the end of the path every band is measured on a ring about its centre on the limb (the
cells whose deformed centre lies within a quarter of a band length of it), deformed-area
averages: the interface pressure (the contact force over the deformed area), the hoop and
axial membrane forces N_theta, N_phi (Cauchy, per deformed length), the hoop and axial
stretches against the sleeve at rest, the stitch value, the deformed radius, and
the membrane-of-revolution pressure N_theta cos(alpha) / rho + N_phi kappa (alpha the limb's
slope angle, kappa its meridian's curvature), which the contact pressure must equal where the
fabric lies on the limb (the normal equilibrium of a membrane of revolution; Laplace's law
p = T / r is its first term with cos(alpha) = 1).

Writes `paraview/sleeve.xdmf` (the fields of every step) and `sleeve/bands.json`.
"""

import json
import logging
from pathlib import Path

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from fabric_dolfinx.material import surface_material
from fabric_dolfinx.membrane.forms import membrane_state
from fabric_dolfinx.membrane.loads import contact_pressure
from fabric_dolfinx.mesh.surfaces import tube_mesh
from fabric_dolfinx.part.problem import PartProblem, space_solver_options
from fabric_dolfinx.part.regions import Region
from fabric_dolfinx.spec.expression import FieldExpression
from fabric_dolfinx.spec.part import BoundaryCondition
from fabric_dolfinx.spec.revolution import RadiusProfile
from fabric_dolfinx.spec.space import IndenterSpec, SpaceSpec
from knitmech.design.family import SurfaceFamily
from knitmech.design.sleeve import relaxed_tube
from knitmech.jobs.fabric import run_part
from knitmech.jobs.sleeve_spec import SleeveJob
from rve_rod.jsonable import to_jsonable
from rve_rod.surface import read_surface

__all__ = [
    "BANDS_FILE",
    "START_GAP",
    "run_request",
    "run_sleeve",
]

logger = logging.getLogger(__name__)

BANDS_FILE = "sleeve/bands.json"
XDMF_FILE = "paraview/sleeve.xdmf"
START_GAP = 0.9
"""The mandrel starts at this fraction of the largest scale that keeps it inside the tube."""


def _tube(job: SleeveJob, family: SurfaceFamily, limb: RadiusProfile, comm):
    """The quarter tube at rest (mesh mapped onto the relaxed radius) and its RelaxedTube."""
    start = limb.extent[0]
    tube = relaxed_tube(family, start, (job.stitches, job.needles, job.courses))
    length = tube.edges[-1] - tube.edges[0]
    reference = float(np.mean(tube.radius(tube.centres)))
    tagged = tube_mesh(reference, length, job.element_size, quarter=True, comm=comm)
    x = tagged.mesh.geometry.x
    z = x[:, 2] + start
    scale = tube.radius(z) / np.hypot(x[:, 0], x[:, 1])
    x[:, 0] *= scale
    x[:, 1] *= scale
    x[:, 2] = z
    return tagged, tube


def run_sleeve(job: SleeveJob, folder: Path, comm=MPI.COMM_WORLD) -> dict:
    """Draw the sleeve of `job` over its limb; files into `folder`. Returns the JSON summary
    (module docstring): per band its ring's measures, Newton iterations, cutbacks, DOFs,
    cells, time, `complete` (False when the solver gave up: the converged steps are kept)."""
    folder = Path(folder)
    if comm.rank == 0:
        for part in ("sleeve", "paraview"):
            (folder / part).mkdir(exist_ok=True)
    comm.barrier()
    family = SurfaceFamily(job.members)
    limb = RadiusProfile(*zip(*job.limb, strict=True))
    tagged, tube = _tube(job, family, limb, comm)
    nodes = tagged.mesh.geometry.x
    inside = np.hypot(nodes[:, 0], nodes[:, 1]) / limb.radius(nodes[:, 2])
    start_scale = START_GAP * comm.allreduce(float(inside.min()), op=MPI.MIN)
    start, end = limb.extent
    conditions = [
        BoundaryCondition("bottom", "roller", component="z"),
        BoundaryCondition("top", "roller", component="z", value=end - tube.edges[-1]),
        BoundaryCondition("x0", "roller", component="x"),
        BoundaryCondition("y0", "roller", component="y"),
    ]
    mandrel = IndenterSpec(
        shape="revolution", profile=job.limb, start_scale=start_scale, penalty=job.penalty
    )
    members = tuple(
        (m.stitch, surface_material(read_surface(m.path), name=f"stitch {m.stitch:g}"))
        for m in family.members
    )
    stitch = FieldExpression(tube.stitch, "sleeve stitch", ("x", "y", "z"))
    region = Region("fabric", None, stitch=stitch, family=members)
    problem = PartProblem(
        tagged,
        [region],
        conditions,
        space=SpaceSpec(indenter=mandrel, stabilization=job.stabilization),
        element_degree=job.element_degree,
        options=space_solver_options(job.steps),
    )
    result, message = run_part(problem, folder / XDMF_FILE, "sleeve")
    edges = np.linspace(start, end, len(job.stitches) + 1)
    bands = band_rings(problem, limb, 0.5 * (edges[:-1] + edges[1:]), 0.25 * (edges[1] - edges[0]))
    summary = to_jsonable(
        {
            "complete": not message,
            "message": message,
            "load_factor": result.load_factor,
            "bands": bands,
            "start_scale": start_scale,
            "relaxed_edges": tube.edges,
            "newton_iterations": result.newton_iterations,
            "cutbacks": result.cutbacks,
            "dofs": result.dofs,
            "cells": tagged.mesh.topology.index_map(2).size_global,
            "ranks": result.ranks,
            "wall_time_s": result.wall_time_s,
        }
    )
    if comm.rank == 0:
        (folder / BANDS_FILE).write_text(json.dumps(summary["bands"], indent=1))
    return summary


def band_rings(
    problem: PartProblem, limb: RadiusProfile, centres: np.ndarray, half_width: float
) -> list[dict]:
    """Per band centre z_k on the limb (mm), the deformed-area averages over the cells whose
    deformed centre lies within `half_width` of it (module docstring). Collective."""
    mesh = problem.tagged.mesh
    problem.material.update()
    state = membrane_state(problem.u, problem.material.stress, problem.frame)
    pressure, _ = contact_pressure(
        problem.u, problem.indenter, problem.indenter_state, problem.frame
    )
    F, sigma, J = state.deformation_gradient, state.cauchy, state.area_ratio
    hoop, axial = (F[:, i] / ufl.sqrt(ufl.dot(F[:, i], F[:, i])) for i in (0, 1))
    position = problem.frame.position + problem.u
    cells = fem.FunctionSpace(mesh, ("DG", 0))
    cell = ufl.TestFunction(cells)
    dx = problem.material.measure()
    measures = {
        "area": J,
        "contact": pressure,
        "z": position[2] * J,
        "radius": ufl.sqrt(position[0] ** 2 + position[1] ** 2) * J,
        "hoop_tension": ufl.dot(hoop, sigma * hoop) * J,
        "axial_tension": ufl.dot(axial, sigma * axial) * J,
        "hoop_stretch": ufl.sqrt(ufl.dot(F[:, 0], F[:, 0])) * J,
        "axial_stretch": ufl.sqrt(ufl.dot(F[:, 1], F[:, 1])) * J,
        "stitch": problem.stitch * J,
    }
    owned = cells.dofmap.index_map.size_local  # one value per owned cell
    values = {
        name: fem.assemble_vector(fem.form(integrand * cell * dx)).array[:owned].copy()
        for name, integrand in measures.items()
    }
    z = values["z"] / values["area"]
    rings = []
    for centre in centres:
        ring = np.abs(z - centre) <= half_width
        sums = {k: mesh.comm.allreduce(float(v[ring].sum()), op=MPI.SUM) for k, v in values.items()}
        area = sums["area"]
        radius = sums["radius"] / area
        hoop_tension, axial_tension = sums["hoop_tension"] / area, sums["axial_tension"] / area
        slope, curvature = float(limb.slope(centre)), float(limb.curvature(centre))
        rings.append(
            {
                "z": centre,
                "pressure": sums["contact"] / area,
                "hoop_tension": hoop_tension,
                "axial_tension": axial_tension,
                "radius": radius,
                "limb_radius": float(limb.radius(centre)),
                "membrane_pressure": hoop_tension / (radius * np.sqrt(1.0 + slope**2))
                + axial_tension * curvature,
                "laplace_term": hoop_tension / radius,
                "hoop_stretch": sums["hoop_stretch"] / area,
                "axial_stretch": sums["axial_stretch"] / area,
                "stitch": sums["stitch"] / area,
            }
        )
    return rings


def run_request(request: dict, folder: Path, comm) -> dict:
    """The `sleeve` job (`knitmech.jobs`): request a SleeveJob as JSON."""
    return run_sleeve(SleeveJob.from_json(request), Path(folder), comm)
