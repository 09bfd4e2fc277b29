"""The membrane in space in a scene: the [space] table and its loads [pressure], [indenter].

    [space]                     # the fabric moves in 3D (fabric_dolfinx.membrane.loads)
    stabilization = 0.0         # N/mm^3, optional normal stabilization
    course = "around"           # gmsh surfaces in space only: course around/along the axis
    axis = [0.0, 0.0, 1.0]
    axis_point = [0.0, 0.0, 0.0]

    [pressure]                  # follower pressure, needs [space]
    value = 0.02                # N/mm^2 at the end of the load path

    [indenter]                  # a rigid indenter, needs [space]
    shape = "sphere"            # or "plane" (with point and normal instead of radius, centre),
                                # or "revolution" (profile = [[z, r], ...], start_scale)
    radius = 12.7               # mm
    centre = [0.0, 0.0, -12.7]  # mm, at the start (outside the fabric)
    travel = [0.0, 0.0, 30.0]   # mm, the indenter's displacement at the end
    penalty = 100.0             # N/mm^3

Problems go to the caller's list, one per key; no DOLFINx here. docs/scenes.md.
"""

from fabric_dolfinx.spec.part import MeshSpec
from fabric_dolfinx.spec.space import COURSE_KINDS, INDENTER_SHAPES, IndenterSpec, SpaceSpec
from knitmech.scene.keys import check_keys, number, triple
from rve_rod.errors import InputError

__all__ = [
    "SPACE_TABLES",
    "read_space",
]

SPACE_TABLES = ("space", "pressure", "indenter")
"""Top-level scene tables of the membrane in space."""


def read_space(data: dict, mesh: MeshSpec | None, problems: list[str]) -> SpaceSpec | None:
    """The SpaceSpec of parsed scene TOML, or None for a plane-stress scene.

    `mesh` is the part's mesh (None when the scene has none): a tube needs [space]; a gmsh
    file in space needs the course field.
    """
    space, pressure, indenter = (data.get(key) for key in SPACE_TABLES)
    for key, value in (("space", space), ("pressure", pressure), ("indenter", indenter)):
        if value is not None and not isinstance(value, dict):
            problems.append(f"{key}: expected a table ([{key}])")
            return None
    if space is None:
        for key, value in (("pressure", pressure), ("indenter", indenter)):
            if value is not None:
                problems.append(
                    f"{key}: needs the membrane in space (add a [space] table); the "
                    "plane-stress membrane carries in-plane loads only"
                )
        if mesh is not None and mesh.shape == "tube":
            problems.append("fabric.shape.kind: a tube needs the membrane in space ([space])")
        return None
    if mesh is None:
        problems.append("space: needs [fabric.shape] or [fabric.mesh]")
        return None
    count = len(problems)
    valid = ("stabilization", "course", "axis", "axis_point")
    check_keys("space", space, valid, problems)
    values = {}
    if "stabilization" in space:
        values["stabilization"] = number("space.stabilization", space["stabilization"], problems)
    for key in ("axis", "axis_point"):
        if key in space:
            values[key] = triple(f"space.{key}", space[key], problems)
    course = space.get("course")
    if course is not None and course not in COURSE_KINDS:
        problems.append(f"space.course: {course!r} is not one of {', '.join(COURSE_KINDS)}")
    if mesh.file is not None and course is None:
        problems.append(
            "space.course: a gmsh surface in space needs its course direction field: "
            f"course = one of {', '.join(map(repr, COURSE_KINDS))} the axis (space.axis)"
        )
    if mesh.file is None and course is not None:
        problems.append("space.course: only for a gmsh surface ([fabric.mesh])")
    values["course"] = course
    if pressure is not None:
        check_keys("pressure", pressure, ("value",), problems)
        values["pressure"] = number("pressure.value", pressure.get("value"), problems)
    if indenter is not None:
        shape = indenter.get("shape", "sphere")
        placing = INDENTER_SHAPES.get(shape, ()) if isinstance(shape, str) else ()
        valid = ("shape", *placing, "travel", "penalty")
        check_keys("indenter", indenter, valid, problems)
        values["indenter"] = _indenter(indenter, problems, count)
    if len(problems) > count:
        return None
    try:
        return SpaceSpec(**values)
    except InputError as error:
        problems.append(f"space: {error}")
        return None


def _indenter(table: dict, problems: list[str], count: int) -> IndenterSpec | None:
    """The IndenterSpec of an [indenter] table, or None with its problems added."""
    spec = {key: value for key, value in table.items() if key == "shape"}
    revolution = table.get("shape") == "revolution"
    for key in ("centre", "point", "normal", "travel"):
        if key in table or (key == "travel" and not revolution):
            spec[key] = triple(f"indenter.{key}", table.get(key), problems)
    for key in ("radius", "penalty", "start_scale"):
        if key in table:
            spec[key] = number(f"indenter.{key}", table[key], problems)
    if "profile" in table:
        profile = table["profile"]
        if not isinstance(profile, list) or not all(
            isinstance(p, list) and len(p) == 2 and all(isinstance(v, int | float) for v in p)
            for p in profile
        ):
            problems.append(f"indenter.profile: expected [[z, r], ...] in mm, got {profile!r}")
        else:
            spec["profile"] = tuple((float(z), float(r)) for z, r in profile)
    if len(problems) > count:
        return None
    try:
        return IndenterSpec(**spec)
    except InputError as error:
        problems.append(f"indenter: {error}")
        return None


def space_toml(space: SpaceSpec) -> str:
    """TOML text of `space` ([space], [pressure], [indenter]) that `read_space` reads back."""
    lines = ["[space]", f"stabilization = {space.stabilization!r}"]
    if space.course is not None:
        lines.append(f'course = "{space.course}"')
    lines += [f"axis = {list(space.axis)!r}", f"axis_point = {list(space.axis_point)!r}"]
    if space.pressure:
        lines += ["", "[pressure]", f"value = {space.pressure!r}"]
    if space.indenter is not None:
        indenter = space.indenter
        lines += ["", "[indenter]", f'shape = "{indenter.shape}"']
        for key in (*INDENTER_SHAPES[indenter.shape], "travel"):
            value = getattr(indenter, key)
            if key == "profile":
                value = [list(point) for point in value]
            lines.append(f"{key} = {value if key in ('radius', 'start_scale') else list(value)!r}")
        lines.append(f"penalty = {indenter.penalty!r}")
    return "\n".join(lines) + "\n"
