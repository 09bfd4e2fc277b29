"""Regions of a fabric: which cells carry which material, course direction and stitch value.

A region is either a physical surface of the mesh (named in the gmsh file; every built-in shape
has one, "fabric") or, when it gives a condition `where` on x, y (mm; and z on a surface in
space, e.g. along a tube's axis), the cells whose centres satisfy it. Regions are assigned in
the order given, a later one taking cells from an earlier one, so a scene can say "the fabric,
and a stiffer band where 80 < y < 120". Every cell must end in exactly one region. The course
direction (degrees from the x axis to the course) and the stitch value are constants or
expressions of x, y (and z on a surface in space), evaluated at the cell centres (one value per
cell, DG0).
"""

from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import dolfinx.mesh
import numpy as np
from dolfinx import fem
from mpi4py import MPI

from fabric_dolfinx.material import Material
from fabric_dolfinx.mesh.tagged import TaggedMesh
from fabric_dolfinx.spec.expression import FieldExpression
from rve_rod.errors import InputError

__all__ = [
    "Region",
    "RegionCells",
    "assign_regions",
    "cell_centres",
    "cell_field",
]


@dataclass(frozen=True)
class Region:
    """A part of the fabric with one material.

    Attributes:
        name: a physical surface of the mesh, or any name when `where` is given.
        material: the membrane material (its law sees the strain in the course/wale frame);
            None for a graded region.
        angle: course direction, degrees from the x axis: a number or an expression of x, y.
        where: a condition of x, y (and z in space; mm) selecting cells by their centres, or
            None.
        stitch: the stitch value (mm; a number, an expression, or None): written to the
            output, and for a graded region the value its law is interpolated at.
        family: a graded region's laws at a few stitch values, ((stitch, Material), ...)
            (`fabric_dolfinx.graded`), or None.
    """

    name: str
    material: Material | None
    angle: float | FieldExpression = 0.0
    where: FieldExpression | None = None
    stitch: float | FieldExpression | None = None
    family: tuple[tuple[float, Material], ...] | None = None

    def __post_init__(self):
        if (self.material is None) == (self.family is None):
            raise InputError(f"region {self.name!r} needs exactly one of material and family")
        if self.family is not None and self.stitch is None:
            raise InputError(f"region {self.name!r}: a graded region needs its stitch value")
        if isinstance(self.angle, FieldExpression):
            self.angle.as_value("a course direction in degrees")
        if isinstance(self.stitch, FieldExpression):
            self.stitch.as_value("a stitch value in mm")
        if self.where is not None:
            self.where.as_condition()


class RegionCells(NamedTuple):
    """The cells of every region.

    Attributes:
        tags: DOLFINx cell tags, value = region index (order of the regions given).
        index: (local cells incl. ghosts,) region index of each cell, -1 where unknown
            (ghost cells of physical surfaces not held on this rank).
        centres: (local cells, gdim) cell centres (mm).
    """

    tags: dolfinx.mesh.MeshTagsMetaClass
    index: np.ndarray
    centres: np.ndarray

    def cells(self, region: int) -> np.ndarray:
        """Local cells of region number `region`."""
        return np.flatnonzero(self.index == region).astype(np.int32)


def cell_centres(mesh: dolfinx.mesh.Mesh) -> np.ndarray:
    """(local cells incl. ghosts, gdim) mean of each cell's geometry nodes (mm): (x, y), or
    (x, y, z) for a surface in space."""
    count = mesh.topology.index_map(2).size_local + mesh.topology.index_map(2).num_ghosts
    nodes = mesh.geometry.dofmap.array.reshape(count, -1)
    return mesh.geometry.x[nodes, : mesh.geometry.dim].mean(axis=1)


def assign_regions(tagged: TaggedMesh, regions: Sequence[Region]) -> RegionCells:
    """Cell -> region, checked: names exist, no region is empty, every cell has a region
    (InputError naming the names the mesh has). Collective."""
    mesh = tagged.mesh
    comm = mesh.comm
    names = [region.name for region in regions]
    repeated = sorted({name for name in names if names.count(name) > 1})
    if repeated:
        raise InputError(f"region names must differ: {', '.join(repeated)} given twice")
    centres = cell_centres(mesh)
    owned = mesh.topology.index_map(2).size_local
    index = np.full(centres.shape[0], -1, dtype=np.int32)
    tagged_surfaces = tagged.regions or {}
    for number, region in enumerate(regions):
        if region.where is not None:
            inside = region.where(*centres.T) != 0.0
            index[inside] = number
        elif region.name in tagged_surfaces:
            index[tagged.cells(region.name)] = number
        else:
            raise InputError(
                f"region {region.name!r} is not a physical surface of the mesh and has no "
                f"'where' condition; the mesh's regions: {', '.join(sorted(tagged_surfaces))}"
            )
    counts = comm.allreduce(np.bincount(index[:owned][index[:owned] >= 0], minlength=len(regions)))
    empty = [regions[i].name for i in range(len(regions)) if counts[i] == 0]
    if empty:
        raise InputError(f"region(s) {', '.join(empty)} hold no cell of the mesh")
    missing = comm.allreduce(int(np.count_nonzero(index[:owned] < 0)), op=MPI.SUM)
    if missing:
        listed = set(names)
        others = sorted(set(tagged_surfaces) - listed)
        raise InputError(
            f"{missing} cells belong to no region (physical surfaces not listed: "
            f"{', '.join(others) or 'none'}); add a region for them"
        )
    known = np.flatnonzero(index >= 0).astype(np.int32)
    tags = dolfinx.mesh.meshtags(mesh, 2, known, index[known])
    return RegionCells(tags=tags, index=index, centres=centres)


def cell_field(
    space: fem.FunctionSpace,
    cells: RegionCells,
    values: Sequence[float | FieldExpression | None],
    name: str,
    *,
    scale: float = 1.0,
    missing: float = 0.0,
) -> fem.Function:
    """A DG0 scalar function with, on the cells of region i, `values[i]` (a number or an
    expression of the cell centre) times `scale`; `missing` where values[i] is None."""
    function = fem.Function(space, name=name)
    dofs = space.dofmap.list.array.reshape(cells.index.size, -1)[:, 0]
    for number, value in enumerate(values):
        local = cells.cells(number)
        if value is None:
            result = np.full(local.size, missing)
        elif isinstance(value, FieldExpression):
            result = value(*cells.centres[local].T) * scale
        else:
            result = np.full(local.size, float(value) * scale)
        function.x.array[dofs[local]] = result
    function.x.scatter_forward()
    return function
