"""Built-in fabric shapes as tagged quadrilateral meshes, and the one entry point for any mesh.

Shapes (lengths in mm; `element_size` is the target edge length of the quadrilaterals):

- `rectangle` [0, width] x [0, height], structured; boundaries left, right, bottom, top.
- `patch`: the paper's 50 x 50 mm square, a rectangle.
- `cruciform` centred at the origin: a square core of side `width` and four arms of the same
  width and length `arm_length`, structured; boundaries left, right, bottom, top (the arm
  ends) and edges (every other edge, free in a biaxial test).
- `plate_with_hole` [0, width] x [0, height] with a central hole of `radius`, unstructured
  (meshes/plate_with_hole.geo); boundaries left, right, bottom, top, hole.
- `disc` of `radius` centred at the origin, an O-grid (a square core and four curved
  blocks); boundary rim.
- `tube` of `radius` and `length` along z, a curved surface in space for the membrane in
  space only (`fabric_dolfinx.mesh.surfaces`); boundaries bottom, top.

Every shape has one region, "fabric"; a scene splits it into regions by conditions on the
cell centres (`fabric_dolfinx.part.regions`), and a user's gmsh file names its own regions
(physical surfaces) and boundaries (physical curves). `make_mesh` builds either.
"""

from pathlib import Path

from mpi4py import MPI

from fabric_dolfinx.mesh.surfaces import tube_mesh
from fabric_dolfinx.mesh.tagged import mesh_gmsh_model, read_geo
from fabric_dolfinx.spec.mesh_checks import check_cells
from fabric_dolfinx.spec.part import MeshSpec, shape_cells, shape_size
from fabric_dolfinx.spec.shapes import build_shape, shape_parameters

__all__ = [
    "make_mesh",
]


def make_mesh(
    spec: MeshSpec, comm: MPI.Comm = MPI.COMM_WORLD, base: Path | None = None, *, space=False
):
    """The TaggedMesh of `spec` (collective); a relative `file` is taken relative to `base`.
    With `space`, a file keeps its z coordinates (a surface in space, gdim 3)."""
    if spec.file is not None:
        path = Path(spec.file) if base is None else Path(base) / spec.file
        return read_geo(path, comm, spec.parameters, spec.refinements, gdim=3 if space else 2)
    size = spec.element_size or shape_size(spec) / 10.0
    check_cells(
        f"shape {spec.shape} with element_size {size:.4g} mm",
        shape_cells(spec, size),
        spec.refinements,
    )
    if spec.shape == "tube":
        return tube_mesh(spec.dimension("radius"), spec.dimension("length"), size, comm=comm)
    return mesh_gmsh_model(
        lambda: build_shape(spec, size),
        comm,
        shape_parameters(spec, size),
        spec.refinements,
        source=f"shape {spec.shape}",
    )
