"""The fabric part of a scene: shape or gmsh file, regions and boundary conditions (TOML).

    [fabric.shape]              # or [fabric.mesh] file = "part.geo"
    kind = "rectangle"
    width = 50.0
    height = 200.0

    [[region]]                  # optional; default one region "fabric" of the [fabric] knit
    name = "fabric"
    angle = 45.0                # or an expression of x, y (mm; and z in space), in degrees

    [[boundary]]
    name = "bottom"
    kind = "clamp"

    [[boundary]]
    name = "top"
    kind = "displacement"
    displacement = [0.0, 20.0]  # mm at the end of the load path

A scene with a shape or mesh runs the fabric stage (`knitmech.jobs.fabric`) instead of the
patch tension tests of `[macro]` (whose `steps` and `ranks` it uses). Reading collects every
problem into the caller's list, naming the key (`fabric.shape.width`, `region[2].angle`,
`boundary[1].kind`); no DOLFINx here. docs/scenes.md describes every key.
"""

import json
import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from fabric_dolfinx.spec.contents import GmshContents, part_contents
from fabric_dolfinx.spec.expression import FieldExpression, expression_coordinates
from fabric_dolfinx.spec.mesh_checks import check_geo_parameters
from fabric_dolfinx.spec.part import (
    BOUNDARY_KINDS,
    SHAPE_DIMENSIONS,
    SHAPES,
    BoundaryCondition,
    MeshSpec,
    shape_points,
    shape_size,
)
from fabric_dolfinx.spec.space import SpaceSpec
from knitmech.scene.keys import check_keys, describe, number
from knitmech.scene.space import read_space, space_toml
from rve_rod.errors import InputError
from rve_rod.geometry.relaxed import settled_fabric
from rve_rod.pattern import pattern_chart
from rve_rod.presets import Fabric, load_preset, make_fabric, stitch_values

__all__ = [
    "KNIT_KEYS",
    "PATTERN_KEYS",
    "PartSpec",
    "RegionSpec",
    "fabric_arguments",
    "knit_fabric",
    "part_problems",
    "part_toml",
    "pattern_problems",
    "read_part",
    "region_knit",
]

KNIT_KEYS = (
    "preset",
    "stitch",
    "wale_width",
    "course_height",
    "yarn_radius",
    "youngs_modulus",
    "poissons_ratio",
    "friction",
    "pattern",
    "chart",
    "relaxed",
)
"""Keys of a region that change its knit (as in [fabric]; a region's preset replaces the
[fabric] knit, its other values override; its pattern or chart replaces the [fabric]'s)."""

PATTERN_KEYS = ("pattern", "chart", "relaxed")
"""The knit keys that are not numbers: the stitch pattern (`knit_fabric`)."""

SVK_KEYS = ("course_stiffness", "wale_stiffness", "poissons_ratio", "shear_stiffness")


@dataclass(frozen=True)
class RegionSpec:
    """A region of the scene: where it is, its knit (or material) and course direction.

    Attributes:
        name: a physical surface of the mesh, or any name with `where`.
        where: a condition on x, y (mm; and z for a part in space) selecting cells by their
            centres, or None.
        angle: course direction (degrees from x): a number or an expression of x, y (and z).
        knit: knit values overriding the [fabric] knit (KNIT_KEYS).
        surface: a response-surface file to use as it is (absolute path), or None.
        svk: orthotropic SVK constants (N/mm) instead of a knit (verification), or None.
        graded_stitch: a stitch value varying over the region (an expression of x, y, mm), or
            None; its law interpolates the surfaces at `members` (`fabric_dolfinx.graded`).
        members: the preset's stitch values a graded region needs (those bracketing its
            range), increasing.
    """

    name: str
    where: str | None = None
    angle: float | str = 0.0
    knit: dict[str, Any] = field(default_factory=dict)
    surface: str | None = None
    svk: dict[str, float] | None = None
    graded_stitch: str | None = None
    members: tuple[float, ...] = ()


@dataclass(frozen=True)
class PartSpec:
    """The fabric part of a scene.

    Attributes:
        mesh: the shape or gmsh file (a relative file resolved against the scene's folder).
        regions: the regions, in order (later ones take cells from earlier ones).
        boundaries: the boundary conditions.
        probes: name -> (x, y) mm, points whose cell's strain, stress and shear angle are
            recorded every step.
        space: the membrane in space and its loads (`knitmech.scene.space`), or None for
            the plane-stress membrane.
    """

    mesh: MeshSpec
    regions: tuple[RegionSpec, ...]
    boundaries: tuple[BoundaryCondition, ...]
    probes: dict[str, tuple[float, float]] = field(default_factory=dict)
    space: SpaceSpec | None = None

    @property
    def coordinates(self) -> tuple[str, ...]:
        """The coordinates the part's expressions may use: x, y, and z in space."""
        return expression_coordinates(self.space is not None)

    def resolved(self, elements: int) -> "PartSpec":
        """With the element size of a built-in shape filled in: its characteristic length
        (the patch side, the strip width, ...) over the fidelity level's `elements`."""
        if self.mesh.shape is None or self.mesh.element_size is not None:
            return self
        size = shape_size(self.mesh) / elements
        return replace(self, mesh=replace(self.mesh, element_size=size))


def read_part(
    data: dict, fabric_table: dict, problems: list[str], base: Path | None
) -> PartSpec | None:
    """The PartSpec of parsed scene TOML, or None when the scene has no shape and no mesh.

    `fabric_table` is the [fabric] table, from which "shape" and "mesh" are removed (the
    knit keys stay for `knitmech.scene`). Problems go to `problems`, one per key.
    """
    shape = fabric_table.pop("shape", None)
    mesh = fabric_table.pop("mesh", None)
    regions = data.get("region")
    boundaries = data.get("boundary")
    if shape is None and mesh is None:
        for key, value in (
            ("region", regions),
            ("boundary", boundaries),
            ("probe", data.get("probe")),
        ):
            if value is not None:
                problems.append(f"{key}: needs [fabric.shape] or [fabric.mesh]")
        read_space(data, None, problems)
        return None
    if shape is not None and mesh is not None:
        problems.append("fabric.shape, fabric.mesh: give one of them, not both")
        return None
    count = len(problems)
    if shape is not None:
        spec = _read_shape(shape, problems)
    else:
        spec = _read_mesh(mesh, problems, base)
    contents = None  # a gmsh file's physical groups and element centres
    if spec is not None and spec.file is not None and Path(spec.file).is_file():
        refused = check_geo_parameters(spec.file, spec.parameters)
        problems.extend(f"fabric.mesh.parameters.{problem}" for problem in refused)
        try:
            if not refused:
                contents = part_contents(spec, plane="space" not in data)
        except InputError as error:
            problems.append(f"fabric.mesh.file: {error}")
    axes = expression_coordinates("space" in data)
    region_specs = tuple(
        _read_region(i, table, problems, base, axes)
        for i, table in enumerate(_tables("region", regions, problems))
    ) or (RegionSpec(name="fabric"),)
    names = [r.name for r in region_specs]
    for name in sorted({n for n in names if names.count(n) > 1}):
        problems.append(f"region: the name {name!r} is given twice")
    region_specs = tuple(
        _graded_members(
            index, region, fabric_table, _points(spec, contents, region, axes), problems, axes
        )
        if region.graded_stitch is not None
        else region
        for index, region in enumerate(region_specs)
    )
    for index, region in enumerate(region_specs):
        # a region whose preset or stitch was refused already is not reported twice
        reported = any(problem.startswith(f"region[{index}]") for problem in problems)
        if (
            not reported
            and region.graded_stitch is None
            and region.knit
            and None not in region.knit.values()
        ):
            try:
                make_fabric(**fabric_arguments(region_knit(fabric_table, region))[0])
            except (InputError, TypeError) as error:
                problems.append(f"region[{index}]: {error}")
    boundary_specs = tuple(
        _read_boundary(i, table, problems, "".join(axes))
        for i, table in enumerate(_tables("boundary", boundaries, problems))
    )
    if boundaries is None or not boundary_specs:
        problems.append("boundary: at least one [[boundary]] is needed (what holds the part)")
    names = [b.name for b in boundary_specs if b is not None]
    for name in sorted({n for n in names if names.count(n) > 1}):
        problems.append(f"boundary: conditions overlap, {name!r} is given twice")
    valid = [b for b in boundary_specs if b is not None]
    if valid and len(valid) == len(boundary_specs) and not any(b.dirichlet for b in valid):
        problems.append(
            "boundary: no clamp, displacement or roller: nothing holds the part in place"
        )
    if spec is not None and spec.shape is not None:
        names = (_SHAPE_BOUNDARIES[spec.shape], ("fabric",))
        _check_names(spec.shape, names, region_specs, boundary_specs, problems)
    elif contents is not None:
        if regions is None:  # every physical surface, with the [fabric] knit
            region_specs = tuple(RegionSpec(name=n) for n in contents.surfaces) or region_specs
        names = (contents.curves, contents.surfaces)
        _check_names(Path(spec.file).name, names, region_specs, boundary_specs, problems)
    probes = _read_probes(data.get("probe"), problems)
    space = read_space(data, spec, problems) if spec is not None else None
    if space is not None and probes:
        problems.append("probe: not available for the membrane in space yet")
    for index, region in enumerate(region_specs):
        if space is not None and region.graded_stitch is not None:
            problems.append(
                f"region[{index}].stitch: a graded stitch is not available for the membrane in "
                "space yet (a graded sleeve: knitmech design, docs/design.md)"
            )
    if len(problems) > count or spec is None:
        return None
    return PartSpec(spec, region_specs, boundary_specs, probes, space)


def part_problems(part: PartSpec) -> list[str]:
    """What only the part's mesh shows, found on the mesh gmsh makes of the resolved part (in
    a child process, `fabric_dolfinx.spec.contents.part_contents`) before any stage runs: a
    region that holds no cell, cells in no region (a physical surface not listed), a course
    direction or graded stitch not finite at a cell centre or a stitch leaving its family,
    a probe outside the part; and the mesh checks for a built-in shape. One problem per key.
    A tube (a surface in space, no probes) is not meshed here: its cell centres are stood in
    for by a grid of points on its surface (`shape_points`)."""
    coordinates = part.coordinates
    contents = None
    if part.mesh.shape == "tube":
        names = ["fabric"]
        centres = shape_points(part.mesh)
    else:
        key = "fabric.mesh.file" if part.mesh.file is not None else "fabric.shape"
        try:
            contents = part_contents(part.mesh, plane=part.space is None)
        except InputError as error:
            return [f"{key}: {error}"]
        names = list(contents.centres)
        centres = np.concatenate([np.zeros((0, 2)), *(contents.centres[n] for n in names)])
    counts = [len(centres)] if contents is None else [len(contents.centres[n]) for n in names]
    surface = np.repeat(np.arange(len(names)), counts)
    index = np.full(len(centres), -1)
    for position, region in enumerate(part.regions):
        if region.where is not None:
            where = FieldExpression(region.where, f"region[{position}].where", coordinates)
            index[where(*centres.T) != 0.0] = position
        elif region.name in names:
            index[surface == names.index(region.name)] = position
    problems = []
    for position, region in enumerate(part.regions):
        cells = centres[index == position]
        if not len(cells):
            problems.append(
                f"region[{position}]: {region.name!r} holds no cell of the mesh ({len(centres)} "
                "cells; a later region may have taken them, or its where selects no cell centre)"
            )
            continue
        expressions = [("angle", region.angle), ("stitch", region.graded_stitch)]
        for name, text in expressions:
            if not isinstance(text, str):
                continue
            try:
                values = FieldExpression(text, f"region[{position}].{name}", coordinates)(*cells.T)
            except InputError as error:
                problems.append(f"{error} (the centres of its cells)")
                continue
            members = region.members
            if (
                name == "stitch"
                and members
                and not (members[0] - 1e-9 <= values.min() and values.max() <= members[-1] + 1e-9)
            ):
                problems.append(
                    f"region[{position}].stitch: {values.min():.4g} ... {values.max():.4g} mm at "
                    f"its cells leaves the members [{members[0]:g}, {members[-1]:g}] mm"
                )
    missing = np.flatnonzero(index < 0)
    if len(missing) and not problems:
        listed = {region.name for region in part.regions}
        others = sorted({names[i] for i in surface[missing]} - listed)
        problems.append(
            f"region: {len(missing)} cells belong to no region (physical surfaces not listed: "
            f"{', '.join(others) or 'none'}); add a region for them"
        )
    if contents is None:  # a tube: no probes (a part in space has none)
        return problems
    points = np.array(list(part.probes.values())).reshape(-1, 2)
    for position, (name, inside) in enumerate(
        zip(part.probes, contents.contains(points), strict=True)
    ):
        if not inside:
            x, y = part.probes[name]
            problems.append(f"probe[{position}] {name!r}: ({x:g}, {y:g}) mm is not in the part")
    return problems


def _read_probes(value, problems: list[str]) -> dict[str, tuple[float, float]]:
    probes = {}
    for index, table in enumerate(_tables("probe", value, problems)):
        prefix = f"probe[{index}]"
        check_keys(prefix, table, ("name", "x", "y"), problems)
        name = table.get("name")
        if not isinstance(name, str) or not name or name in probes:
            problems.append(f"{prefix}.name: required, a name of its own, got {name!r}")
            continue
        point = []
        for key in ("x", "y"):
            value = table.get(key)
            if isinstance(value, bool) or not isinstance(value, int | float):
                problems.append(f"{prefix}.{key}: required, a coordinate in mm, got {value!r}")
            else:
                point.append(float(value))
        if len(point) == 2:
            probes[name] = (point[0], point[1])
    return probes


def _points(
    spec: MeshSpec | None,
    contents: GmshContents | None,
    region: RegionSpec,
    coordinates: tuple[str, ...],
) -> np.ndarray | None:
    """(n, 2 or 3) points (mm) where a region's graded stitch is checked before meshing: a
    grid over a built-in shape, the element centres of a gmsh file's physical surface (of
    every surface for a region with `where`), within `where`; None when they are not known."""
    if spec is not None and spec.shape is not None:
        points = shape_points(spec)
    elif contents is not None and region.where is None:
        points = contents.centres.get(region.name, np.zeros((0, 2)))
    elif contents is not None:
        points = np.concatenate([np.zeros((0, 2)), *contents.centres.values()])
    else:
        return None
    if region.where is not None:
        points = points[FieldExpression(region.where, coordinates=coordinates)(*points.T) != 0.0]
    return points


def _graded_members(
    index: int,
    region: RegionSpec,
    fabric: dict,
    points: np.ndarray | None,
    problems: list[str],
    axes: tuple[str, ...],
) -> RegionSpec:
    """The region with the preset stitch values its graded stitch (an expression of `axes`)
    needs at `points` (all of them when None or empty); problems when the preset has no family
    or the stitch leaves it."""
    key = f"region[{index}].stitch"
    preset = region.knit.get("preset", fabric.get("preset"))
    values = stitch_values(preset) if isinstance(preset, str) else []
    if len(values) < 2:
        problems.append(f"{key}: a graded stitch needs a preset measured at several stitch values")
        return region
    values = sorted(float(v) for v in values)
    if points is None or len(points) == 0:
        return replace(region, members=tuple(values))
    stitch = FieldExpression(region.graded_stitch, key, axes)(*points.T)
    low, high = float(stitch.min()), float(stitch.max())
    if low < values[0] - 1e-9 or high > values[-1] + 1e-9:
        problems.append(
            f"{key}: {low:.4g} ... {high:.4g} mm over the region leaves the family's range "
            f"[{values[0]:g}, {values[-1]:g}] mm of {preset}"
        )
        return region
    first = max(i for i, v in enumerate(values) if v <= low + 1e-9)
    last = min(i for i, v in enumerate(values) if v >= high - 1e-9)
    return replace(region, members=tuple(values[first : last + 1]))


def knit_fabric(values: dict) -> Fabric:
    """The Fabric of knit values (a [fabric] table's or a region's: the `make_fabric`
    arguments, with `chart` for the pattern's rows and `relaxed`), its w and c settled for
    its pattern (`rve_rod.geometry.relaxed.settled_fabric`: a preset's are its jersey's,
    another pattern takes its relaxed cell's unless w and c are given)."""
    arguments, relaxed = fabric_arguments(values)
    fabric = make_fabric(**arguments)
    measured = any(arguments.get(key) is not None for key in ("wale_width", "course_height"))
    return settled_fabric(fabric, relaxed=relaxed, measured=measured)


def fabric_arguments(values: dict) -> tuple[dict[str, Any], bool | None]:
    """The `make_fabric` arguments of knit values (`chart` made the pattern) and `relaxed`."""
    arguments = dict(values)
    relaxed = arguments.pop("relaxed", None)
    chart = arguments.pop("chart", None)
    if chart is not None:
        arguments["pattern"] = tuple(chart)
    return arguments, relaxed


def pattern_problems(prefix: str, knit: dict) -> list[str]:
    """The problems of the pattern keys of a knit table (one line each)."""
    problems = []
    pattern, chart, relaxed = (knit.get(key) for key in PATTERN_KEYS)
    if pattern is not None and chart is not None:
        problems.append(f"{prefix}: give pattern or chart, not both")
    for key, value in (("pattern", pattern), ("chart", chart)):
        if value is None:
            continue
        try:
            pattern_chart(list(value) if key == "chart" else value).check_modelled()
        except InputError as error:
            problems.append(f"{prefix}.{key}: {error}")
    if relaxed is not None and not isinstance(relaxed, bool):
        problems.append(f"{prefix}.relaxed: expected true or false, got {describe(relaxed)}")
    elif relaxed and any(knit.get(key) is not None for key in ("wale_width", "course_height")):
        problems.append(
            f"{prefix}.relaxed: finds wale_width and course_height from the loop length; "
            "give relaxed or wale_width and course_height, not both"
        )
    return problems


def region_knit(fabric: dict, region: RegionSpec) -> dict[str, Any]:
    """The knit values of a region (`knit_fabric` makes its Fabric): the [fabric] knit values
    (`fabric`, a mapping of KNIT_KEYS) with the region's on top; a region's preset replaces
    them all, its pattern or chart the [fabric]'s pattern and chart."""
    if "preset" in region.knit:
        return dict(region.knit)
    if any(key in region.knit for key in ("pattern", "chart")):
        fabric = {k: v for k, v in fabric.items() if k not in ("pattern", "chart")}
    base = {key: fabric[key] for key in KNIT_KEYS if fabric.get(key) is not None}
    return {**base, **region.knit}


def _tables(key: str, value, problems: list[str]) -> list[dict]:
    if value is None:
        return []
    if not isinstance(value, list) or not all(isinstance(t, dict) for t in value):
        problems.append(f"{key}: expected [[{key}]] tables")
        return []
    return value


def _read_shape(table, problems: list[str]) -> MeshSpec | None:
    if not isinstance(table, dict):
        problems.append("fabric.shape: expected a table ([fabric.shape])")
        return None
    kind = table.get("kind")
    if kind not in SHAPES:
        problems.append(f"fabric.shape.kind: {kind!r} is not one of {', '.join(SHAPES)}")
        return None
    valid = ("kind", *SHAPE_DIMENSIONS[kind], "element_size", "refinements")
    check_keys("fabric.shape", table, valid, problems)
    dimensions = {}
    for key in SHAPE_DIMENSIONS[kind]:
        if key in table:
            value = number(f"fabric.shape.{key}", table[key], problems, low=0.0, high=1e5)
            if value is not None:
                dimensions[key] = value
    size = None
    if "element_size" in table:
        size = number("fabric.shape.element_size", table["element_size"], problems, 0.0, 1e4)
    refinements = _refinements("fabric.shape", table, problems)
    try:
        spec = MeshSpec(kind, dimensions, element_size=size, refinements=refinements)
    except InputError as error:
        problems.append(f"fabric.shape: {error}")
        return None
    if kind == "plate_with_hole":
        half = 0.5 * min(spec.dimension("width"), spec.dimension("height"))
        if spec.dimension("radius") >= half:
            problems.append(
                f"fabric.shape.radius: {spec.dimension('radius')} mm must be below half the "
                f"plate's smaller side ({half} mm)"
            )
    return spec


def _refinements(prefix: str, table: dict, problems: list[str]) -> int:
    value = table.get("refinements", 0)
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 6:
        problems.append(f"{prefix}.refinements: {value!r} is not an integer in [0, 6]")
        return 0
    return value


def _read_mesh(table, problems: list[str], base: Path | None) -> MeshSpec | None:
    if not isinstance(table, dict):
        problems.append("fabric.mesh: expected a table ([fabric.mesh] file = ...)")
        return None
    check_keys("fabric.mesh", table, ("file", "parameters", "refinements"), problems)
    file = table.get("file")
    if not isinstance(file, str):
        problems.append(f"fabric.mesh.file: expected a .geo or .msh file name, got {file!r}")
        return None
    path = Path(file) if base is None else (base / file).resolve()
    if path.suffix not in (".geo", ".msh"):
        problems.append(f"fabric.mesh.file: {file} must end in .geo or .msh")
    elif not path.is_file():
        problems.append(f"fabric.mesh.file: no such file {path}")
    parameters = table.get("parameters", {})
    if not isinstance(parameters, dict) or not all(
        isinstance(v, int | float) and not isinstance(v, bool) for v in parameters.values()
    ):
        problems.append("fabric.mesh.parameters: expected a table of numbers")
        parameters = {}
    refinements = _refinements("fabric.mesh", table, problems)
    return MeshSpec(
        shape=None,
        file=str(path),
        parameters={k: float(v) for k, v in parameters.items()},
        refinements=refinements,
    )


def _read_region(
    index: int, table: dict, problems: list[str], base: Path | None, coordinates: tuple[str, ...]
) -> RegionSpec:
    """One [[region]] table; its expressions may use `coordinates` (x, y, and z in space)."""
    prefix = f"region[{index}]"
    valid = ("name", "where", "angle", "surface", "svk", *KNIT_KEYS)
    check_keys(prefix, table, valid, problems)
    name = table.get("name")
    if not isinstance(name, str) or not name:
        problems.append(f"{prefix}.name: required, a physical surface or a new name with where")
        name = f"region-{index}"
    where = table.get("where")
    if where is not None:
        where = _expression(f"{prefix}.where", where, problems, "condition", coordinates)
    angle = table.get("angle", 0.0)
    if isinstance(angle, str):
        angle = (
            _expression(f"{prefix}.angle", angle, problems, "a course direction", coordinates)
            or 0.0
        )
    elif isinstance(angle, bool) or not isinstance(angle, int | float) or not -360 <= angle <= 360:
        problems.append(f"{prefix}.angle: {angle!r} is not a number in [-360, 360] degrees")
        angle = 0.0
    knit = {key: table[key] for key in KNIT_KEYS if key in table}
    graded = None
    if isinstance(knit.get("stitch"), str):
        graded = _expression(
            f"{prefix}.stitch", knit.pop("stitch"), problems, "a stitch value", coordinates
        )
    surface, svk = table.get("surface"), table.get("svk")
    given = [key for key, value in (("surface", surface), ("svk", svk)) if value is not None]
    if knit or graded is not None:
        given.append("knit values")
    if len(given) > 1:
        problems.append(f"{prefix}: give one of {', '.join(given)}, not several")
    if surface is not None:
        path = Path(surface) if base is None else (base / surface).resolve()
        if not isinstance(surface, str) or not path.is_file():
            problems.append(f"{prefix}.surface: no such file {surface!r}")
        surface = str(path)
    if svk is not None:
        svk = _read_svk(prefix, svk, problems)
    if "preset" in knit and graded is None:
        try:
            load_preset(knit["preset"], knit.get("stitch"))
        except InputError as error:
            problems.append(f"{prefix}.{'stitch' if 'stitch' in str(error) else 'preset'}: {error}")
    problems += pattern_problems(prefix, knit)
    for key in KNIT_KEYS[1:]:
        if key in knit and key not in PATTERN_KEYS:
            value = number(
                f"{prefix}.{key}", knit[key], problems, low=-1.0 if key == "poissons_ratio" else 0.0
            )
            knit[key] = value
    angle = float(angle) if not isinstance(angle, str) else angle
    return RegionSpec(name, where, angle, knit, surface, svk, graded)


def _read_svk(prefix: str, table, problems: list[str]) -> dict[str, float] | None:
    if not isinstance(table, dict):
        problems.append(f"{prefix}.svk: expected a table {{{', '.join(SVK_KEYS)}}}")
        return None
    from fabric_dolfinx.material import OrthotropicSVK  # noqa: PLC0415 (ufl only for SVK)

    check_keys(f"{prefix}.svk", table, SVK_KEYS, problems)
    values = {k: table[k] for k in SVK_KEYS if k in table}
    try:
        OrthotropicSVK(**values)
    except (InputError, TypeError) as error:
        problems.append(f"{prefix}.svk: {error}")
        return None
    return {k: float(v) for k, v in values.items()}


def _expression(
    key: str, text, problems: list[str], kind: str, coordinates: tuple[str, ...]
) -> str | None:
    """`text` when it is an expression of `coordinates` of `kind` ("condition", or what a
    value expression gives, e.g. "a stitch value"), else None and a problem."""
    if not isinstance(text, str):
        problems.append(
            f"{key}: expected an expression of {', '.join(coordinates)} (a string), got {text!r}"
        )
        return None
    try:
        expression = FieldExpression(text, key, coordinates)
        if kind == "condition":
            expression.as_condition()
        else:
            expression.as_value(kind)
    except InputError as error:
        problems.append(str(error))
        return None
    return text


def _read_boundary(
    index: int, table: dict, problems: list[str], axes: str
) -> BoundaryCondition | None:
    """One [[boundary]] table; `axes` "xy", or "xyz" for a part in space (a third number of
    a displacement or traction, a roller holding z or several components)."""
    prefix = f"boundary[{index}]"
    valid = ("name", "kind", "displacement", "traction", "component", "value")
    check_keys(prefix, table, valid, problems)
    name = table.get("name")
    if not isinstance(name, str) or not name:
        problems.append(f"{prefix}.name: required, a physical curve of the mesh")
        return None
    kind = table.get("kind")
    if kind not in BOUNDARY_KINDS:
        problems.append(f"{prefix}.kind: {kind!r} is not one of {', '.join(BOUNDARY_KINDS)}")
        return None
    needed = {"displacement": "displacement", "traction": "traction"}.get(kind)
    vector = (0.0, 0.0)
    for key in ("displacement", "traction"):
        if key in table and key != needed:
            problems.append(f"{prefix}.{key}: not used by kind {kind!r}")
    if needed is not None:
        value = table.get(needed)
        if (
            not isinstance(value, list)
            or not 2 <= len(value) <= len(axes)
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
            or not all(math.isfinite(v) for v in value)
        ):
            unit = "mm" if needed == "displacement" else "N/mm"
            numbers = "two numbers [x, y]" if axes == "xy" else "two or three numbers [x, y, z]"
            problems.append(f"{prefix}.{needed}: required, {numbers} in {unit}")
            return None
        vector = tuple(float(v) for v in value)
    component = table.get("component", "x")
    if kind != "roller" and ("component" in table or "value" in table):
        problems.append(f"{prefix}: component and value belong to kind 'roller'")
    if (
        not isinstance(component, str)
        or not component
        or any(c not in axes for c in component)
        or len(set(component)) != len(component)
    ):
        valid = "x or y" if axes == "xy" else "x, y or z (or several once, e.g. 'yz')"
        problems.append(f"{prefix}.component: {component!r} is not {valid}")
        component = "x"
    value = table.get("value", 0.0)
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        problems.append(f"{prefix}.value: expected a number (mm), got {value!r}")
        value = 0.0
    return BoundaryCondition(name, kind, vector, component, float(value))


_SHAPE_BOUNDARIES = {
    "rectangle": ("left", "right", "bottom", "top"),
    "patch": ("left", "right", "bottom", "top"),
    "cruciform": ("left", "right", "bottom", "top", "edges"),
    "plate_with_hole": ("left", "right", "bottom", "top", "hole"),
    "disc": ("rim",),
    "tube": ("bottom", "top"),
}


def _check_names(source: str, names, regions, boundaries, problems: list[str]) -> None:
    """Boundary and region names the mesh does not have, naming those it has."""
    curves, surfaces = names
    for index, boundary in enumerate(boundaries):
        if boundary is not None and boundary.name not in curves:
            problems.append(
                f"boundary[{index}].name: {source} has no boundary {boundary.name!r}; "
                f"its boundaries: {', '.join(curves) or 'none'}"
            )
    for index, region in enumerate(regions):
        refused = any(p.startswith(f"region[{index}].where:") for p in problems)
        if region.where is None and region.name not in surfaces and not refused:
            problems.append(
                f"region[{index}].name: {source} has no region {region.name!r} (its regions: "
                f"{', '.join(surfaces) or 'none'}); a new region needs a where condition"
            )


def toml_value(value: Any) -> str:
    """A number, string or list as TOML text."""
    if isinstance(value, list | tuple):
        return "[" + ", ".join(toml_value(item) for item in value) + "]"
    if isinstance(value, str):
        return json.dumps(value)  # a TOML basic string uses the same escapes
    return repr(value)


def part_toml(part: PartSpec) -> str:
    """TOML text of `part` (the [fabric.shape]/[fabric.mesh] table, [[region]], [[boundary]])
    that `read_part` reads back to an equal PartSpec."""
    mesh = part.mesh
    if mesh.shape is not None:
        lines = ["[fabric.shape]", f"kind = {toml_value(mesh.shape)}"]
        lines += [f"{k} = {toml_value(v)}" for k, v in mesh.dimensions.items()]
        if mesh.element_size is not None:
            lines.append(f"element_size = {mesh.element_size!r}")
    else:
        lines = ["[fabric.mesh]", f"file = {toml_value(mesh.file)}"]
        if mesh.parameters:
            items = ", ".join(f"{k} = {v!r}" for k, v in mesh.parameters.items())
            lines.append(f"parameters = {{{items}}}")
    lines.append(f"refinements = {mesh.refinements}")
    for region in part.regions:
        lines += ["", "[[region]]", f"name = {toml_value(region.name)}"]
        for key in ("where", "angle", "surface"):
            value = getattr(region, key)
            if value is not None:
                lines.append(f"{key} = {toml_value(value)}")
        lines += [f"{k} = {toml_value(v)}" for k, v in region.knit.items()]
        if region.graded_stitch is not None:
            lines.append(f"stitch = {toml_value(region.graded_stitch)}")
        if region.svk is not None:
            items = ", ".join(f"{k} = {v!r}" for k, v in region.svk.items())
            lines.append(f"svk = {{{items}}}")
    for boundary in part.boundaries:
        lines += ["", "[[boundary]]", f"name = {toml_value(boundary.name)}"]
        lines.append(f"kind = {toml_value(boundary.kind)}")
        if boundary.kind in ("displacement", "traction"):
            lines.append(f"{boundary.kind} = {toml_value(list(boundary.vector))}")
        if boundary.kind == "roller":
            lines.append(f"component = {toml_value(boundary.component)}")
            lines.append(f"value = {boundary.value!r}")
    for name, (x, y) in part.probes.items():
        lines += ["", "[[probe]]", f"name = {toml_value(name)}", f"x = {x!r}", f"y = {y!r}"]
    if part.space is not None:
        lines += ["", space_toml(part.space).rstrip()]
    return "\n".join(lines) + "\n"
