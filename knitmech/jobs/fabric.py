"""The fabric stage: a scene's part (shape or gmsh file, regions, boundary conditions) solved.

`run_fabric` meshes the part, gives each region its material (a response-surface file or
an orthotropic SVK law), follows the load path (`fabric_dolfinx.part.problem`) and writes

- `paraview/fabric.xdmf` (+ `.h5`): displacement, Green-Lagrange strain, Cauchy stress,
  principal stresses and direction, region number, stitch value, course direction per cell;
- `fabric/curves.json`: per boundary its kind, length and force (N) and mean displacement
  (mm) per step; the same as CSV, one file per boundary (`fabric/boundary_<name>.csv`) and
  per probe (`fabric/probe_<name>.csv`: strain, stress, shear angle), units in the header;
- `figures/fabric_<boundary>.png`: force against displacement of every boundary that is not
  free; `figures/fabric_stress.png`: the largest principal stress on the deformed part at
  its last converged step (plane parts). No curve figure when no step converged.

It is collective under MPI; the pipeline runs it as the `fabric` job (`knitmech.jobs`:
in-process on one rank, or under mpirun). A part in space (`[space]`) is the same problem with
3 components; it writes its own curves and figures (`knitmech.jobs.space`).
"""

import json
import logging
from pathlib import Path

import numpy as np
from mpi4py import MPI

from fabric_dolfinx.io.plot import plot_cell_field
from fabric_dolfinx.material import OrthotropicSVK, surface_material, svk_material
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.part.problem import PartProblem, PartResult, space_solver_options
from fabric_dolfinx.part.regions import Region
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.expression import FieldExpression
from knitmech.jobs.fabric_spec import FabricJob, RegionMaterial
from knitmech.jobs.space import plot_space, space_curves
from knitmech.scene.fabric import RegionSpec
from rve_rod.errors import ConvergenceError, InputError
from rve_rod.jsonable import to_jsonable
from rve_rod.surface import read_surface

__all__ = [
    "CURVES_FILE",
    "STRESS_FIGURE",
    "XDMF_FILE",
    "run_fabric",
    "run_part",
    "run_request",
    "write_csv_curves",
]

logger = logging.getLogger(__name__)

XDMF_FILE = "paraview/fabric.xdmf"
CURVES_FILE = "fabric/curves.json"
STRESS_FIGURE = "figures/fabric_stress.png"
"""The largest principal stress on the deformed part at its last converged step (plane)."""


def _region(
    spec: RegionSpec, material: RegionMaterial, index: int, coordinates: tuple[str, ...]
) -> Region:
    angle = spec.angle
    if isinstance(angle, str):
        angle = FieldExpression(angle, f"region[{index}].angle", coordinates)
    where = (
        FieldExpression(spec.where, f"region[{index}].where", coordinates) if spec.where else None
    )
    if material.family is not None:
        family = tuple(
            (stitch, surface_material(read_surface(path), name=Path(path).parent.name))
            for stitch, path in material.family
        )
        stitch = FieldExpression(material.stitch, f"region[{index}].stitch", coordinates)
        return Region(spec.name, None, angle=angle, where=where, stitch=stitch, family=family)
    if material.surface is not None:
        law = surface_material(read_surface(material.surface), name=Path(material.surface).name)
    else:
        law = svk_material(OrthotropicSVK(**material.svk))
    return Region(spec.name, law, angle=angle, where=where, stitch=material.stitch)


def run_fabric(job: FabricJob, folder: Path, comm=MPI.COMM_WORLD) -> dict:
    """Solve the part of `job`; files go into `folder`. Returns the JSON summary: per
    boundary curves, Newton iterations, cutbacks, whether strains left a surface's domain
    (per region), DOFs, cells, ranks, time, `complete` (False when the solver gave up; the
    converged steps are kept) and its `message`."""
    folder = Path(folder)
    if comm.rank == 0:
        for part in ("figures", "paraview", "fabric"):
            (folder / part).mkdir(exist_ok=True)
    comm.barrier()
    regions = [
        _region(spec, material, index, job.part.coordinates)
        for index, (spec, material) in enumerate(zip(job.part.regions, job.materials, strict=True))
    ]
    space = job.part.space
    graded = [r.name for r in regions if r.material is None]
    if space is not None and graded:
        raise InputError(f"region {graded[0]!r}: graded regions are not available in space yet")
    tagged = make_mesh(job.part.mesh, comm, space=space is not None)
    problem = PartProblem(
        tagged,
        regions,
        job.part.boundaries,
        space=space,
        element_degree=job.element_degree,
        options=SolverOptions(steps=job.steps)
        if space is None
        else space_solver_options(job.steps),
        probes=job.part.probes if space is None else None,
    )
    last = {}  # the PartFields, up to date at the last converged step

    def keep_fields(load_factor: float, fields) -> None:
        last["fields"], last["load_factor"] = fields, load_factor

    result, message = run_part(problem, folder / XDMF_FILE, "fabric", on_step=keep_fields)
    summary = _summary(result, message, tagged.mesh.topology.index_map(2).size_global)
    if space is not None:
        summary["space"] = to_jsonable(space_curves(result, space))
    if space is None and "fields" in last:  # collective: the cells are gathered to rank 0
        plot_cell_field(
            last["fields"],
            folder / STRESS_FIGURE,
            field="principal",
            title=f"deformed part at load factor {last['load_factor']:.3g}",
        )
    if comm.rank == 0:
        curves = summary["boundaries"] if space is None else summary["space"]
        (folder / CURVES_FILE).write_text(json.dumps(curves, indent=1))
        write_csv_curves(result, folder / "fabric")
        converged = len(result.load_factor) > 1  # else no curve to draw
        if converged and space is None:
            _plot_curves(result, folder / "figures")
        elif converged:
            plot_space(summary["space"], folder / "figures")
    return summary


def write_csv_curves(result: PartResult, folder: Path) -> list[Path]:
    """One CSV file per boundary (`boundary_<name>.csv`: load factor, force (N) and mean
    displacement (mm) per component) and per probe (`probe_<name>.csv`: load factor,
    Green-Lagrange strain, Cauchy stress (N/mm) and shear angle (degrees)) of `result`, one
    row per output state, the units in the header; returns the files."""
    written = []
    for name, curve in result.boundaries.items():
        axes = "xyz"[: curve.force.shape[1]]
        header = ["load factor (-)", *(f"F{a} (N)" for a in axes), *(f"u{a} (mm)" for a in axes)]
        rows = np.column_stack([result.load_factor, curve.force, curve.displacement])
        written.append(_write_csv(folder / f"boundary_{name}.csv", header, rows))
    for name, probe in result.probes.items():
        header = ["load factor (-)", "E_xx (-)", "E_yy (-)", "E_xy (-)"]
        header += ["sigma_xx (N/mm)", "sigma_yy (N/mm)", "sigma_xy (N/mm)", "shear angle (deg)"]
        rows = np.column_stack(
            [
                result.load_factor,
                probe.strain[:, 0, 0],
                probe.strain[:, 1, 1],
                probe.strain[:, 0, 1],
                probe.cauchy[:, 0, 0],
                probe.cauchy[:, 1, 1],
                probe.cauchy[:, 0, 1],
                probe.shear_angle,
            ]
        )
        written.append(_write_csv(folder / f"probe_{name}.csv", header, rows))
    return written


def _write_csv(path: Path, header: list[str], rows: np.ndarray) -> Path:
    lines = [",".join(header)] + [",".join(f"{value:.10g}" for value in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def run_part(problem: PartProblem, xdmf: Path, label: str, on_step=None) -> tuple[PartResult, str]:
    """(the part's load path, "" or why the solver gave up): when it gives up, the converged
    steps are kept (written to `xdmf` too) and a warning names `label`. `on_step(load_factor,
    fields)` is called at every converged step (PartProblem.run)."""
    try:
        return problem.run(xdmf=xdmf, on_step=on_step), ""
    except ConvergenceError as error:
        logger.warning("%s: %s; keeping the converged steps", label, error)
        return error.history, str(error)


def _summary(result: PartResult, message: str, cells: int) -> dict:
    return to_jsonable(
        {
            "complete": not message,
            "message": message,
            "load_factor": result.load_factor,
            "boundaries": {name: curve._asdict() for name, curve in result.boundaries.items()},
            "newton_iterations": result.newton_iterations,
            "cutbacks": result.cutbacks,
            "outside_domain": result.outside_domain,
            "probes": {name: probe._asdict() for name, probe in result.probes.items()},
            "dofs": result.dofs,
            "cells": cells,
            "ranks": result.ranks,
            "wall_time_s": result.wall_time_s,
        }
    )


def _plot_curves(result: PartResult, folder: Path) -> None:
    import matplotlib.pyplot as plt  # noqa: PLC0415 (matplotlib on demand)

    for name, curve in result.boundaries.items():
        if curve.kind == "free":
            continue
        figure, axes = plt.subplots(figsize=(5, 3.5))
        for axis, label in enumerate("xy"):
            if np.any(curve.force[:, axis]) or np.any(curve.displacement[:, axis]):
                axes.plot(curve.displacement[:, axis], curve.force[:, axis], "o-", label=label)
        axes.set_xlabel("mean displacement (mm)")
        axes.set_ylabel("force (N)")
        axes.set_title(f"boundary {name} ({curve.kind})")
        axes.legend(title="component")
        axes.grid(alpha=0.3)
        figure.tight_layout()
        figure.savefig(folder / f"fabric_{name}.png", dpi=120)
        plt.close(figure)


def run_request(request: dict, folder: Path, comm) -> dict:
    """The `fabric` job (`knitmech.jobs`): request a FabricJob as JSON."""
    return run_fabric(FabricJob.from_json(request), Path(folder), comm)
