"""The specification of a fabric part, without DOLFINx (the pipeline plans and checks with it).

`MeshSpec`: a built-in shape with its dimensions or a gmsh file (`fabric_dolfinx.mesh.shapes`
meshes it); `BoundaryCondition`: what holds or loads one named boundary
(`fabric_dolfinx.part.boundary` applies it).
"""

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fabric_dolfinx.spec.mesh_checks import check_cells, estimated_geo_cells
from rve_rod.errors import InputError, check_integer, check_positive

__all__ = [
    "AXES",
    "BOUNDARY_KINDS",
    "QUADRILATERAL_TYPES",
    "SHAPES",
    "SHAPE_DIMENSIONS",
    "BoundaryCondition",
    "MeshSpec",
    "mesh_gmsh_file",
    "physical_groups",
    "shape_cells",
    "shape_points",
    "shape_size",
]

QUADRILATERAL_TYPES = {3: "4-node quadrilateral"}
"""gmsh element types accepted for the fabric's cells."""


SHAPES = ("rectangle", "patch", "cruciform", "plate_with_hole", "disc", "tube")
"""Names of the built-in shapes."""

SHAPE_DIMENSIONS = {
    "rectangle": {"width": 50.0, "height": 50.0},
    "patch": {},
    "cruciform": {"width": 50.0, "arm_length": 50.0},
    "plate_with_hole": {"width": 50.0, "height": 50.0, "radius": 10.0},
    "disc": {"radius": 25.0},
    "tube": {"radius": 10.0, "length": 50.0},
}
"""Shape -> its dimensions (mm) with their defaults."""


@dataclass(frozen=True)
class MeshSpec:
    """A fabric mesh: a built-in shape with its dimensions, or a gmsh file.

    Attributes:
        shape: one of SHAPES, or None when `file` is given.
        dimensions: the shape's dimensions (mm), see SHAPE_DIMENSIONS; missing ones take
            the defaults.
        file: a gmsh `.geo` (meshed here) or `.msh` file (used as it is).
        parameters: values of the `.geo` file's DefineConstant parameters.
        element_size: target quadrilateral edge (mm) of a built-in shape (and the `size`
            parameter of plate_with_hole); None: shape_size / 10.
        refinements: uniform refinements after meshing (each quad split into four).
    """

    shape: str | None = "patch"
    dimensions: dict[str, float] = field(default_factory=dict)
    file: str | None = None
    parameters: dict[str, float] = field(default_factory=dict)
    element_size: float | None = None
    refinements: int = 0

    def __post_init__(self):
        if (self.shape is None) == (self.file is None):
            raise InputError("a mesh needs exactly one of shape and file")
        if self.shape is not None:
            if self.shape not in SHAPES:
                raise InputError(f"shape={self.shape!r} is not one of {', '.join(SHAPES)}")
            valid = SHAPE_DIMENSIONS[self.shape]
            for key, value in self.dimensions.items():
                if key not in valid:
                    names = ", ".join(valid) or "none"
                    raise InputError(f"{key!r} is not a dimension of {self.shape} ({names})")
                check_positive(key, value, "mm")
        if self.element_size is not None:
            check_positive("element_size", self.element_size, "mm")
        check_integer("refinements", self.refinements, 0, 6)

    def dimension(self, key: str) -> float:
        """The dimension `key` (mm), given or default."""
        if self.shape == "patch":
            return 50.0
        return float(self.dimensions.get(key, SHAPE_DIMENSIONS[self.shape][key]))


def shape_size(spec: MeshSpec) -> float:
    """The characteristic length of a built-in shape (mm): the smallest of its width, height
    or diameter; the default element size is a tenth of it."""
    if spec.shape in ("rectangle", "plate_with_hole"):
        return min(spec.dimension("width"), spec.dimension("height"))
    if spec.shape == "disc":
        return 2.0 * spec.dimension("radius")
    if spec.shape == "tube":
        return min(2.0 * spec.dimension("radius"), spec.dimension("length"))
    return spec.dimension("width") if spec.shape == "cruciform" else 50.0


def shape_cells(spec: MeshSpec, element_size: float | None = None) -> float:
    """At least how many cells a built-in shape's mesh has before refinement: its area over
    the square of its element size (`element_size`, else the spec's, else shape_size / 10);
    the structured shapes' edges are at most that size, the disc's O-grid and the plate's
    recombined cells smaller (up to twice as many cells)."""
    size = element_size or spec.element_size or shape_size(spec) / 10.0
    dimension = spec.dimension
    areas = {
        "rectangle": lambda: dimension("width") * dimension("height"),
        "patch": lambda: 2500.0,
        "cruciform": lambda: (
            dimension("width") * (dimension("width") + 4 * dimension("arm_length"))
        ),
        "plate_with_hole": lambda: (
            dimension("width") * dimension("height") - math.pi * dimension("radius") ** 2
        ),
        "disc": lambda: math.pi * dimension("radius") ** 2,
        "tube": lambda: 2 * math.pi * dimension("radius") * dimension("length"),
    }
    return areas[spec.shape]() / size**2


BOUNDARY_KINDS = ("clamp", "displacement", "roller", "traction", "free")
AXES = "xyz"
"""The displacement's components by name: x, y, and z for a part in space."""


@dataclass(frozen=True)
class BoundaryCondition:
    """A condition on one named boundary (see the module docstring for the kinds).

    Attributes:
        name: a physical curve of the mesh.
        kind: one of BOUNDARY_KINDS.
        vector: (ux, uy) mm for `displacement`, (tx, ty) N/mm for `traction`, at t = 1; a
            part in space takes a third number (uz, tz), 0 when only two are given.
        component: the components a `roller` holds, letters of AXES: "x", "y", or for a part
            in space also "z" or several, e.g. "yz".
        value: the roller's displacement at t = 1 (mm), of every held component.
    """

    name: str
    kind: str = "clamp"
    vector: tuple[float, ...] = (0.0, 0.0)
    component: str = "x"
    value: float = 0.0

    def __post_init__(self):
        if self.kind not in BOUNDARY_KINDS:
            raise InputError(
                f"boundary {self.name!r}: kind={self.kind!r} is not one of "
                f"{', '.join(BOUNDARY_KINDS)}"
            )
        if len(self.vector) not in (2, 3) or not all(np.isfinite(self.vector)):
            raise InputError(
                f"boundary {self.name!r}: vector={self.vector!r} needs 2 numbers (3 in space)"
            )
        held = self.component
        if not held or any(c not in AXES for c in held) or len(set(held)) != len(held):
            raise InputError(
                f"boundary {self.name!r}: component={held!r} is not x, y or z (or several once)"
            )

    @property
    def dirichlet(self) -> bool:
        return self.kind in ("clamp", "displacement", "roller")


def mesh_gmsh_file(path, refinements: int = 0) -> None:
    """Open a `.geo` or `.msh` file in the initialized gmsh (its parameters set) and leave
    its 2D mesh in the current model: a `.geo` file is meshed after its estimated size
    passed the budget with `refinements` (`fabric_dolfinx.spec.mesh_checks`). InputError when
    gmsh cannot read or mesh it."""
    from fabric_dolfinx.gmsh_api import gmsh  # noqa: PLC0415 (gmsh only for meshes)

    name = Path(path).name
    try:
        gmsh.open(str(path))
    except Exception as error:  # gmsh raises plain Exceptions
        raise InputError(f"gmsh cannot read {path}: {error}") from None
    if str(path).endswith(".geo"):
        size_min = gmsh.option.getNumber("Mesh.MeshSizeMin")  # the estimate raises it
        try:
            estimate = estimated_geo_cells()
            check_cells(f"{name} (estimated from its boundary, at least)", estimate, refinements)
            gmsh.model.mesh.generate(2)
        except InputError:
            raise
        except Exception as error:  # gmsh raises plain Exceptions
            raise InputError(f"gmsh cannot mesh {path}: {error}") from None
        finally:  # gmsh keeps its options from one initialization to the next
            gmsh.option.setNumber("Mesh.MeshSizeMin", size_min)


def physical_groups(source: str) -> tuple[dict[str, int], dict[str, int]]:
    """(curve name -> tag, surface name -> tag) of the current gmsh model (meshed), after
    checking that its 2D elements are 4-node quadrilaterals, that it has a physical surface,
    that no curve (surface) is in two physical curves (surfaces) and that every group has a
    name (InputError naming `source` otherwise)."""
    from fabric_dolfinx.gmsh_api import gmsh  # noqa: PLC0415 (gmsh only for meshes)

    types = set(gmsh.model.mesh.getElementTypes(2))
    if not types:
        raise InputError(f"{source}: the mesh has no 2D elements")
    others = sorted(int(t) for t in types - set(QUADRILATERAL_TYPES))
    if others:
        names = ", ".join(gmsh.model.mesh.getElementProperties(t)[0] for t in others)
        raise InputError(
            f"{source}: the mesh has {names} elements; only 4-node quadrilaterals are "
            "supported (recombine the mesh: Recombine Surface, Mesh.RecombineAll = 1)"
        )
    boundaries = {
        gmsh.model.getPhysicalName(1, tag): tag for _, tag in gmsh.model.getPhysicalGroups(1)
    }
    regions = {
        gmsh.model.getPhysicalName(2, tag): tag for _, tag in gmsh.model.getPhysicalGroups(2)
    }
    if not regions:
        raise InputError(f"{source}: no physical surface (a region) is defined")
    # a DOLFINx mesh tag holds one value per entity: overlapping groups would lose names
    for dim, groups, kind in ((1, boundaries, "curves"), (2, regions, "surfaces")):
        owner: dict[int, str] = {}
        for name, tag in groups.items():
            for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                if entity in owner:
                    raise InputError(
                        f"{source}: {kind[:-1]} {entity} belongs to the physical {kind} "
                        f"{owner[entity]!r} and {name!r}; they must not overlap"
                    )
                owner[entity] = name
    unnamed = [n for n in (*boundaries, *regions) if not n]
    if unnamed:
        raise InputError(f"{source}: every physical group needs a name")
    return boundaries, regions


def shape_points(spec: MeshSpec, count: int = 101) -> np.ndarray:
    """(n, 3) points (mm) in a built-in shape, for checking expressions of x, y (and z) over
    the part before it is meshed: a count x count grid over a plane shape's bounding box that
    lies in the shape (z = 0; the hole of plate_with_hole included), or over a tube's surface
    (count around the circumference times count along its axis z, at the centres of count
    equal rings from 0 to its length)."""
    if spec.shape == "tube":
        radius = spec.dimension("radius")
        angle, z = np.meshgrid(
            np.linspace(0.0, 2.0 * np.pi, count, endpoint=False),
            (np.arange(count) + 0.5) * spec.dimension("length") / count,
        )
        angle, z = angle.ravel(), z.ravel()
        return np.column_stack([radius * np.cos(angle), radius * np.sin(angle), z])
    if spec.shape == "cruciform":
        half = spec.dimension("width") / 2
        end = half + spec.dimension("arm_length")
        box = (-end, end, -end, end)
    elif spec.shape == "disc":
        radius = spec.dimension("radius")
        box = (-radius, radius, -radius, radius)
    elif spec.shape == "patch":
        box = (0.0, 50.0, 0.0, 50.0)
    else:
        box = (0.0, spec.dimension("width"), 0.0, spec.dimension("height"))
    x, y = np.meshgrid(np.linspace(*box[:2], count), np.linspace(*box[2:], count))
    x, y = x.ravel(), y.ravel()
    if spec.shape == "cruciform":
        inside = (np.abs(x) <= half + 1e-9) | (np.abs(y) <= half + 1e-9)
    elif spec.shape == "disc":
        inside = x**2 + y**2 <= radius**2 * (1 + 1e-12)
    else:
        inside = np.ones(x.size, dtype=bool)
    return np.column_stack([x[inside], y[inside], np.zeros(np.count_nonzero(inside))])
