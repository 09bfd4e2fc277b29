"""Quadrilateral fabric meshes from gmsh, distributed over MPI ranks, with tagged boundaries.

The geometries live as gmsh `.geo` files in the repository's `meshes/` folder (open them in
the gmsh GUI to look at them): `rectangle.geo`, a structured patch of any size and element
count, and `plate_with_hole.geo`, an unstructured recombined all-quad plate with a central
hole. Their `DefineConstant` parameters are set through gmsh's `-setnumber`. Gmsh runs on
rank 0 only; `dolfinx.io.gmshio.model_to_mesh` partitions the mesh over the communicator.
Lengths are mm.
"""

from collections.abc import Mapping
from pathlib import Path
from typing import NamedTuple

import dolfinx.io.gmshio
import dolfinx.mesh
import gmsh
import numpy as np
from mpi4py import MPI

from rve_rod.errors import InputError, check_integer, check_positive

__all__ = [
    "MESH_DIRECTORY",
    "TaggedMesh",
    "plate_with_hole",
    "read_geo",
    "rectangle_patch",
]

MESH_DIRECTORY = Path(__file__).resolve().parents[1] / "meshes"
"""The repository's folder of gmsh geometry files."""


class TaggedMesh(NamedTuple):
    """A distributed mesh with its boundary facets tagged by gmsh physical groups.

    Attributes:
        mesh: the DOLFINx mesh (gdim 2, quadrilaterals, mm).
        facet_tags: facet markers (the physical-group numbers of the .geo file).
        boundaries: physical-group name -> facet marker, e.g. {"left": 4, "right": 2}.
    """

    mesh: dolfinx.mesh.Mesh
    facet_tags: dolfinx.mesh.MeshTagsMetaClass
    boundaries: dict[str, int]

    def facets(self, name: str) -> np.ndarray:
        """Local indices of the facets on boundary `name` (InputError if there is none)."""
        if name not in self.boundaries:
            raise InputError(f"boundary {name!r} is not tagged; tagged: {sorted(self.boundaries)}")
        return self.facet_tags.find(self.boundaries[name])


def read_geo(
    path: Path | str,
    comm: MPI.Comm = MPI.COMM_WORLD,
    parameters: Mapping[str, float] | None = None,
    refinements: int = 0,
) -> TaggedMesh:
    """Mesh a gmsh `.geo` file on rank 0 and distribute it over `comm`.

    Args:
        path: the geometry; its physical curves become the facet tags, named as in the file.
        parameters: values for the file's `DefineConstant` parameters (gmsh `-setnumber`).
        refinements: uniform refinements after meshing (each quad split into four; new
            boundary nodes are placed on the geometry, so curved boundaries converge).
    """
    path = Path(path)
    check_integer("refinements", refinements, 0, 6)
    if not path.is_file():
        raise InputError(f"gmsh geometry file {path} does not exist")
    boundaries = None
    if comm.rank == 0:
        arguments = ["fabric_dolfinx"]
        for name, value in (parameters or {}).items():
            arguments += ["-setnumber", name, repr(float(value))]
        gmsh.initialize(arguments)
    try:
        if comm.rank == 0:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.open(str(path))
            gmsh.model.mesh.generate(2)
            for _ in range(refinements):
                gmsh.model.mesh.refine()
            boundaries = {
                gmsh.model.getPhysicalName(1, tag): tag
                for _, tag in gmsh.model.getPhysicalGroups(1)
            }
        boundaries = comm.bcast(boundaries, root=0)
        mesh, _, facet_tags = dolfinx.io.gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=2)
    finally:
        if comm.rank == 0:
            gmsh.finalize()
    if mesh.topology.cell_type != dolfinx.mesh.CellType.quadrilateral:
        raise InputError(f"{path} did not give a quadrilateral mesh")
    return TaggedMesh(mesh=mesh, facet_tags=facet_tags, boundaries=boundaries)


def rectangle_patch(
    comm: MPI.Comm = MPI.COMM_WORLD,
    *,
    width: float = 50.0,
    height: float = 50.0,
    elements_x: int = 10,
    elements_y: int = 10,
) -> TaggedMesh:
    """Structured patch [0, width] x [0, height] mm with elements_x x elements_y quads.

    Boundaries: "left", "right", "bottom", "top".
    """
    check_positive("width", width, "mm")
    check_positive("height", height, "mm")
    check_integer("elements_x", elements_x, 1)
    check_integer("elements_y", elements_y, 1)
    parameters = {"width": width, "height": height, "nx": elements_x, "ny": elements_y}
    return read_geo(MESH_DIRECTORY / "rectangle.geo", comm, parameters)


def plate_with_hole(
    comm: MPI.Comm = MPI.COMM_WORLD,
    *,
    width: float = 50.0,
    height: float = 50.0,
    radius: float = 10.0,
    element_size: float = 5.0,
    refinements: int = 0,
) -> TaggedMesh:
    """Unstructured all-quad plate [0, width] x [0, height] mm with a central hole.

    Boundaries: "left", "right", "bottom", "top", "hole". The element size halves with every
    uniform refinement.
    """
    check_positive("width", width, "mm")
    check_positive("height", height, "mm")
    check_positive("element_size", element_size, "mm")
    limit = 0.5 * min(width, height)
    if not 0.0 < radius < limit:
        raise InputError(f"radius={radius:.6g} mm is outside the valid range (0, {limit:.6g}) mm")
    parameters = {"width": width, "height": height, "radius": radius, "size": element_size}
    return read_geo(MESH_DIRECTORY / "plate_with_hole.geo", comm, parameters, refinements)
