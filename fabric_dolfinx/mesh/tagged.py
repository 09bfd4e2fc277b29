"""Quadrilateral fabric meshes from gmsh, distributed over MPI ranks, with tagged boundaries.

The geometries live as gmsh `.geo` files in the repository's `meshes/` folder (open them in
the gmsh GUI to look at them): `plate_with_hole.geo`, an unstructured recombined all-quad
plate with a central hole (the structured shapes are built in `fabric_dolfinx.mesh.shapes`).
Their `DefineConstant` parameters are set through gmsh's `-setnumber`. Gmsh runs on rank 0
only; `dolfinx.io.gmshio.model_to_mesh` partitions the mesh over the communicator. Lengths
are mm.
"""

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import NamedTuple

import dolfinx.io.gmshio
import dolfinx.mesh
import numpy as np
from mpi4py import MPI

import fabric_dolfinx.jit  # noqa: F401 (FFCx's compilation safe to interrupt, and quiet)
from fabric_dolfinx.gmsh_api import gmsh
from fabric_dolfinx.spec.mesh_checks import check_geo_parameters, check_gmsh_mesh
from fabric_dolfinx.spec.part import mesh_gmsh_file, physical_groups
from fabric_dolfinx.spec.shapes import MESH_DIRECTORY
from rve_rod.errors import InputError, check_integer

__all__ = [
    "MESH_DIRECTORY",
    "TaggedMesh",
    "mesh_gmsh_model",
    "read_geo",
]


class TaggedMesh(NamedTuple):
    """A distributed mesh with its boundary facets and its cells tagged by gmsh physical groups.

    Attributes:
        mesh: the DOLFINx mesh (gdim 2, quadrilaterals, mm).
        facet_tags: facet markers (the physical-group numbers of the .geo file).
        boundaries: physical-curve name -> facet marker, e.g. {"left": 4, "right": 2}.
        cell_tags: cell markers (the physical-surface numbers).
        regions: physical-surface name -> cell marker, e.g. {"fabric": 10}.
    """

    mesh: dolfinx.mesh.Mesh
    facet_tags: dolfinx.mesh.MeshTagsMetaClass
    boundaries: dict[str, int]
    cell_tags: dolfinx.mesh.MeshTagsMetaClass | None = None
    regions: dict[str, int] | None = None

    def facets(self, name: str) -> np.ndarray:
        """Local indices of the facets on boundary `name` (InputError if there is none)."""
        if name not in self.boundaries:
            raise InputError(f"boundary {name!r} is not tagged; tagged: {sorted(self.boundaries)}")
        return self.facet_tags.find(self.boundaries[name])

    def cells(self, name: str) -> np.ndarray:
        """Local indices (owned and ghost) of the cells of region `name` (InputError if none)."""
        if name not in (self.regions or {}):
            raise InputError(f"region {name!r} is not tagged; tagged: {sorted(self.regions or {})}")
        return self.cell_tags.find(self.regions[name])


def read_geo(
    path: Path | str,
    comm: MPI.Comm = MPI.COMM_WORLD,
    parameters: Mapping[str, float] | None = None,
    refinements: int = 0,
    *,
    gdim: int = 2,
) -> TaggedMesh:
    """Mesh a gmsh `.geo` file (or read a `.msh` file) on rank 0 and distribute it over `comm`
    (`gdim` 3: a surface in space, see `mesh_gmsh_model`).

    Args:
        path: the geometry; its physical curves become the facet tags and its physical
            surfaces the cell tags, named as in the file.
        parameters: values for the file's `DefineConstant` parameters (gmsh `-setnumber`).
        refinements: uniform refinements after meshing (each quad split into four; new
            boundary nodes are placed on the geometry, so curved boundaries converge).
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"gmsh geometry file {path} does not exist")
    if path.suffix not in (".geo", ".msh"):
        raise InputError(f"gmsh file {path}: the name must end in .geo or .msh")

    problems = check_geo_parameters(path, dict(parameters or {}))
    if problems:
        raise InputError(f"{path.name}: parameters " + "; ".join(problems))

    def build() -> None:
        mesh_gmsh_file(path, refinements)

    return mesh_gmsh_model(build, comm, parameters, refinements, source=str(path), gdim=gdim)


def mesh_gmsh_model(
    build: Callable[[], None],
    comm: MPI.Comm = MPI.COMM_WORLD,
    parameters: Mapping[str, float] | None = None,
    refinements: int = 0,
    source: str = "gmsh model",
    *,
    gdim: int = 2,
) -> TaggedMesh:
    """Run `build` on rank 0 inside an initialized gmsh (it must leave a 2D mesh in the
    current model), refine, check and distribute the mesh over `comm`. `gdim` 3 keeps the
    z coordinate: a curved surface in space (`fabric_dolfinx.membrane.loads`).

    Raises InputError (on every rank) when the mesh has cells other than 4-node
    quadrilaterals, no physical surface, or a curve (surface) in two physical curves
    (surfaces), more cells than the budget, or fails `fabric_dolfinx.spec.mesh_checks`
    (not conforming, in pieces, degenerate cells, a plane part not in the x-y plane).
    """
    check_integer("refinements", refinements, 0, 6)
    groups = None
    if comm.rank == 0:
        arguments = ["fabric_dolfinx"]
        for name, value in (parameters or {}).items():
            arguments += ["-setnumber", name, repr(float(value))]
        gmsh.initialize(arguments)
    try:
        if comm.rank == 0:
            gmsh.option.setNumber("General.Terminal", 0)
            try:
                build()
                check_gmsh_mesh(source, refinements, plane=gdim == 2)
                for _ in range(refinements):
                    gmsh.model.mesh.refine()
                groups = physical_groups(source)
            except Exception as error:  # gmsh raises plain Exceptions
                groups = (
                    error
                    if isinstance(error, InputError)
                    else InputError(f"{source}: gmsh failed ({error})")
                )
        groups = comm.bcast(groups, root=0)
        if isinstance(groups, InputError):
            raise groups
        mesh, cell_tags, facet_tags = dolfinx.io.gmshio.model_to_mesh(
            gmsh.model, comm, 0, gdim=gdim
        )
    finally:
        if comm.rank == 0:
            gmsh.finalize()
    if mesh.topology.cell_type != dolfinx.mesh.CellType.quadrilateral:
        raise InputError(f"{source} did not give a quadrilateral mesh")
    boundaries, regions = groups
    return TaggedMesh(mesh, facet_tags, boundaries, cell_tags, regions)
