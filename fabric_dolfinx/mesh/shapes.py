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

import math
from collections.abc import Callable
from pathlib import Path

import gmsh
from mpi4py import MPI

from fabric_dolfinx.mesh.surfaces import tube_mesh
from fabric_dolfinx.mesh.tagged import MESH_DIRECTORY, mesh_gmsh_model, read_geo
from fabric_dolfinx.spec.mesh_checks import check_cells
from fabric_dolfinx.spec.part import MeshSpec, shape_cells, shape_size
from rve_rod.errors import InputError

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
    if spec.shape == "plate_with_hole":
        width, height = spec.dimension("width"), spec.dimension("height")
        radius = spec.dimension("radius")
        if not radius < 0.5 * min(width, height):
            raise InputError(
                f"radius={radius:.6g} mm must be below half the plate's smaller side "
                f"({0.5 * min(width, height):.6g} mm)"
            )
        parameters = {"width": width, "height": height, "radius": radius, "size": size}
        return read_geo(MESH_DIRECTORY / "plate_with_hole.geo", comm, parameters, spec.refinements)
    if spec.shape == "tube":
        return tube_mesh(spec.dimension("radius"), spec.dimension("length"), size, comm=comm)
    builders: dict[str, Callable[[MeshSpec, float], None]] = {
        "rectangle": _rectangle,
        "patch": _rectangle,
        "cruciform": _cruciform,
        "disc": _disc,
    }
    return mesh_gmsh_model(
        lambda: builders[spec.shape](spec, size),
        comm,
        refinements=spec.refinements,
        source=f"shape {spec.shape}",
    )


def _divisions(length: float, size: float) -> int:
    return max(1, math.ceil(length / size - 1e-9))


class _Blocks:
    """Structured quadrilateral blocks on shared points and lines (gmsh built-in kernel)."""

    def __init__(self, size: float):
        self.size = size
        self.points: dict[tuple[float, float], int] = {}
        self.lines: dict[tuple[int, int], int] = {}
        self.named: dict[str, list[int]] = {}
        self.surfaces: list[int] = []

    def point(self, x: float, y: float) -> int:
        key = (round(x, 9), round(y, 9))
        if key not in self.points:
            self.points[key] = gmsh.model.geo.addPoint(x, y, 0.0)
        return self.points[key]

    def line(self, a: int, b: int, centre: int | None = None, divisions: int = 1) -> int:
        """Line a -> b (a circle arc about `centre` if given); returns a signed tag."""
        if (b, a) in self.lines:
            return -self.lines[(b, a)]
        if (a, b) not in self.lines:
            if centre is None:
                tag = gmsh.model.geo.addLine(a, b)
            else:
                tag = gmsh.model.geo.addCircleArc(a, centre, b)
            gmsh.model.geo.mesh.setTransfiniteCurve(tag, divisions + 1)
            self.lines[(a, b)] = tag
        return self.lines[(a, b)]

    def block(self, corners, counts, arcs=(None,) * 4, names=(None,) * 4):
        """A transfinite quad block from 4 corner points (counter-clockwise) with counts[0]
        elements along edges 0 and 2, counts[1] along edges 1 and 3; `arcs[i]` is the centre
        point of edge i if it is a circle arc, `names[i]` the boundary name of edge i."""
        tags = []
        for i in range(4):
            tag = self.line(corners[i], corners[(i + 1) % 4], arcs[i], counts[i % 2])
            tags.append(tag)
            if names[i] is not None:
                self.named.setdefault(names[i], []).append(abs(tag))
        loop = gmsh.model.geo.addCurveLoop(tags)
        surface = gmsh.model.geo.addPlaneSurface([loop])
        gmsh.model.geo.mesh.setTransfiniteSurface(surface)
        gmsh.model.geo.mesh.setRecombine(2, surface)
        self.surfaces.append(surface)

    def finish(self) -> None:
        gmsh.model.geo.synchronize()
        for name, tags in self.named.items():
            gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, tags), name)
        gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, self.surfaces), "fabric")
        gmsh.model.mesh.generate(2)


def _rectangle(spec: MeshSpec, size: float) -> None:
    width, height = spec.dimension("width"), spec.dimension("height")
    blocks = _Blocks(size)
    corners = [blocks.point(x, y) for x, y in ((0, 0), (width, 0), (width, height), (0, height))]
    counts = (_divisions(width, size), _divisions(height, size))
    blocks.block(corners, counts, names=("bottom", "right", "top", "left"))
    blocks.finish()


def _cruciform(spec: MeshSpec, size: float) -> None:
    half = spec.dimension("width") / 2
    end = half + spec.dimension("arm_length")
    blocks = _Blocks(size)

    def square(x0, y0, x1, y1, names):
        corners = [blocks.point(x, y) for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]
        blocks.block(corners, (_divisions(x1 - x0, size), _divisions(y1 - y0, size)), names=names)

    square(-half, -half, half, half, (None, None, None, None))
    square(half, -half, end, half, ("edges", "right", "edges", None))
    square(-end, -half, -half, half, ("edges", None, "edges", "left"))
    square(-half, half, half, end, (None, "edges", "top", "edges"))
    square(-half, -end, half, -half, ("bottom", "edges", None, "edges"))
    blocks.finish()


def _disc(spec: MeshSpec, size: float) -> None:
    radius = spec.dimension("radius")
    core = 0.45 * radius  # half side of the core square
    rim = radius / math.sqrt(2.0)
    blocks = _Blocks(size)
    centre = blocks.point(0.0, 0.0)
    inner = [
        blocks.point(x, y) for x, y in ((-core, -core), (core, -core), (core, core), (-core, core))
    ]
    outer = [blocks.point(x, y) for x, y in ((-rim, -rim), (rim, -rim), (rim, rim), (-rim, rim))]
    around = _divisions(0.5 * math.pi * radius, size)
    across = _divisions(radius - core * math.sqrt(2.0), size)
    blocks.block(inner, (around, around))
    for i in range(4):
        j = (i + 1) % 4
        blocks.block(
            [inner[i], outer[i], outer[j], inner[j]],
            (across, around),
            arcs=(None, centre, None, None),
            names=(None, "rim", None, None),
        )
    blocks.finish()
