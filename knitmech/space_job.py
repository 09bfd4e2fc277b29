"""The fabric stage of a part in space: the membrane in space under supports, pressure and
an indenter (`fabric_dolfinx.membrane3d_solve`), run by `knitmech.fabric_job.run_fabric`.

Boundary conditions of the plane part keep their meaning with z added: `clamp` holds x, y
and z; `displacement` moves the boundary by (dx, dy, 0); `roller` holds one in-plane
component; `traction` is the dead load (tx, ty, 0); `free` imposes nothing. It writes

- `paraview/fabric.xdmf` (+ `.h5`): displacement (3D), strain and second Piola-Kirchhoff
  stress (course/wale frame), Cauchy stress in space, principal stresses and direction, the
  slack/wrinkle indicator;
- `fabric/curves.json`: per boundary the reaction (Fx, Fy, Fz) per step; the indenter's
  force against its travel; the pressure against the largest displacement (dome height);
  the fractions of the area that are wrinkled and slack per step;
- `figures/fabric_indenter.png` and/or `figures/fabric_pressure.png`.
"""

import json
import logging
from pathlib import Path

import numpy as np
from dolfinx import fem

from fabric_dolfinx.membrane3d import PlaneIndenter, SphereIndenter
from fabric_dolfinx.membrane3d_solve import (
    EdgeLoad,
    Membrane3DProblem,
    Membrane3DResult,
    Support,
    space_solver_options,
)
from fabric_dolfinx.regions import assign_regions, cell_field
from fabric_dolfinx.shapes import make_mesh
from fabric_dolfinx.surfaces3d import axis_fields
from knitmech.fabric_job_spec import FabricJob
from rve_rod.errors import ConvergenceError, InputError
from rve_rod.jsonable import to_jsonable

__all__ = [
    "run_space",
    "space_conditions",
]

logger = logging.getLogger(__name__)


def space_conditions(boundaries) -> tuple[list[Support], list[EdgeLoad]]:
    """The supports and edge loads of the plane part's boundary conditions (module doc)."""
    supports, loads = [], []
    for condition in boundaries:
        dx, dy = condition.vector
        if condition.kind == "clamp":
            supports.append(Support(condition.name))
        elif condition.kind == "displacement":
            supports.append(Support(condition.name, "xyz", (dx, dy, 0.0)))
        elif condition.kind == "roller":
            value = [0.0, 0.0, 0.0]
            value["xy".index(condition.component)] = condition.value
            supports.append(Support(condition.name, condition.component, tuple(value)))
        elif condition.kind == "traction":
            loads.append(EdgeLoad(condition.name, (dx, dy, 0.0)))
    return supports, loads


def run_space(job: FabricJob, region, folder: Path, comm) -> dict:
    """Solve the part in space of `job` with the (single) `region` (a `Region`); files go
    into `folder`. Returns the JSON summary (see `knitmech.fabric_job.run_fabric`)."""
    part, space = job.part, job.part.space
    if region.material is None:
        raise InputError(f"region {region.name!r}: graded regions are not available in space yet")
    tagged = make_mesh(part.mesh, comm, space=True)
    frame = {}
    if tagged.mesh.geometry.dim == 3:
        course = space.course or "around"
        frame["course"], frame["side"] = axis_fields(course, space.axis, space.axis_point)
    else:
        cells = assign_regions(tagged, [region])
        scalars = fem.FunctionSpace(tagged.mesh, ("DG", 0))
        frame["angle"] = cell_field(scalars, cells, [region.angle], "angle", scale=np.pi / 180)
    supports, loads = space_conditions(part.boundaries)
    indenter = None
    if space.indenter is not None:
        spec = space.indenter
        if spec.shape == "plane":
            indenter = PlaneIndenter(spec.point, spec.normal, spec.travel, spec.penalty)
        else:
            indenter = SphereIndenter(spec.radius, spec.centre, spec.travel, spec.penalty)
    problem = Membrane3DProblem(
        tagged,
        region.material,
        supports,
        pressure=space.pressure,
        edge_loads=loads,
        indenter=indenter,
        stabilization=space.stabilization,
        element_degree=job.element_degree,
        options=space_solver_options(job.steps),
        **frame,
    )
    message = ""
    try:
        result = problem.run(xdmf=folder / "paraview" / "fabric.xdmf")
    except ConvergenceError as error:
        result, message = error.history, str(error)
        logger.warning("fabric: %s; keeping the converged steps", message)
    summary = _summary(result, job, message, tagged.mesh.topology.index_map(2).size_global)
    if comm.rank == 0:
        (folder / "fabric" / "curves.json").write_text(json.dumps(summary["space"], indent=1))
        _plot(summary["space"], folder / "figures")
    return summary


def _summary(result: Membrane3DResult, job: FabricJob, message: str, cells: int) -> dict:
    space = job.part.space
    t = result.load_factor
    kinds = {c.name: c.kind for c in job.part.boundaries}
    boundaries = {
        name: {"kind": kinds[name], "force": force, "displacement": np.zeros_like(force)}
        for name, force in result.reactions.items()
    }
    curves = {
        "load_factor": t,
        "reactions": result.reactions,
        "peak_displacement": result.peak_displacement,
        "wrinkled_area": result.wrinkled_area,
        "slack_area": result.slack_area,
        "dome_amplitude": result.dome_amplitude,
        "stabilization_force": result.stabilization_force,
    }
    if space.pressure:
        curves["pressure"] = t * space.pressure
    if result.indenter_force is not None:
        direction = np.asarray(space.indenter.travel) / np.linalg.norm(space.indenter.travel)
        curves["indenter_travel"] = result.indenter_travel
        curves["indenter_force"] = result.indenter_force
        # the force that pushes the indenter along its travel (the fabric resists: > 0)
        curves["indenter_resistance"] = -result.indenter_force @ direction
    return to_jsonable(
        {
            "complete": not message,
            "message": message,
            "load_factor": t,
            "boundaries": boundaries,
            "space": curves,
            "newton_iterations": result.newton_iterations,
            "cutbacks": result.cutbacks,
            "outside_domain": {job.part.regions[0].name: result.outside_domain},
            "probes": {},
            "dofs": result.dofs,
            "cells": cells,
            "ranks": result.ranks,
            "wall_time_s": result.wall_time_s,
        }
    )


def _plot(curves: dict, folder: Path) -> None:
    import matplotlib.pyplot as plt  # noqa: PLC0415 (matplotlib on demand)

    plots = []
    if "indenter_resistance" in curves:
        plots.append(("indenter", curves["indenter_travel"], curves["indenter_resistance"]))
    if "pressure" in curves:
        plots.append(("pressure", curves["peak_displacement"], curves["pressure"]))
    labels = {
        "indenter": ("indenter travel (mm)", "force on the indenter (N)"),
        "pressure": ("largest displacement (mm)", "pressure (N/mm^2)"),
    }
    for name, x, y in plots:
        figure, axes = plt.subplots(figsize=(5, 3.5))
        axes.plot(x, y, "o-")
        axes.set_xlabel(labels[name][0])
        axes.set_ylabel(labels[name][1])
        axes.grid(alpha=0.3)
        figure.tight_layout()
        figure.savefig(folder / f"fabric_{name}.png", dpi=120)
        plt.close(figure)
