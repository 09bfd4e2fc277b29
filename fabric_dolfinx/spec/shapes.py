"""The built-in shapes' gmsh geometry and mesh, without DOLFINx (the scene check meshes them in
a child process, `fabric_dolfinx.spec.part.part_contents`; `fabric_dolfinx.mesh.shapes` makes
the DOLFINx mesh of the same model).

`build_shape(spec, size)` builds and meshes a plane built-in shape in the initialized gmsh,
its boundaries and its one region "fabric" named as physical groups; `shape_parameters` are
the gmsh parameters it needs (the plate with a hole is the `.geo` file
`meshes/plate_with_hole.geo`, set by `-setnumber`). Lengths are mm.
"""

import math
from collections.abc import Callable
from pathlib import Path

from fabric_dolfinx.gmsh_api import gmsh
from fabric_dolfinx.spec.part import MeshSpec, mesh_gmsh_file
from rve_rod.errors import InputError

__all__ = [
    "MESH_DIRECTORY",
    "build_shape",
    "shape_parameters",
]

MESH_DIRECTORY = Path(__file__).resolve().parents[2] / "meshes"
"""The repository's folder of gmsh geometry files."""


def shape_parameters(spec: MeshSpec, size: float) -> dict[str, float]:
    """The gmsh parameters `build_shape` needs for `spec` at element size `size` (mm): the
    plate with a hole's (InputError when its hole does not fit), none for the others."""
    if spec.shape != "plate_with_hole":
        return {}
    width, height = spec.dimension("width"), spec.dimension("height")
    radius = spec.dimension("radius")
    if not radius < 0.5 * min(width, height):
        raise InputError(
            f"radius={radius:.6g} mm must be below half the plate's smaller side "
            f"({0.5 * min(width, height):.6g} mm)"
        )
    return {"width": width, "height": height, "radius": radius, "size": size}


def build_shape(spec: MeshSpec, size: float) -> None:
    """Build and mesh the plane built-in shape `spec` at element size `size` (mm) in the
    initialized gmsh (its `shape_parameters` set); not the tube (a surface in space,
    `fabric_dolfinx.mesh.surfaces`)."""
    if spec.shape == "plate_with_hole":
        mesh_gmsh_file(MESH_DIRECTORY / "plate_with_hole.geo")
        return
    builders: dict[str, Callable[[MeshSpec, float], None]] = {
        "rectangle": _rectangle,
        "patch": _rectangle,
        "cruciform": _cruciform,
        "disc": _disc,
    }
    builders[spec.shape](spec, size)


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
