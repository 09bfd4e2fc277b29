"""The design file: a scene with a [design] table (and a [sleeve] table for a sleeve), checked
before anything runs.

    [design]                    # the optimizer's options (all optional)
    max_evaluations = 400
    difference_step = 1e-4      # forward differences, relative to max(1, |x|)
    tolerance = 1e-10
    bounds = [4.5, 7.0]         # the stitch values searched (material, sleeve); mm

    [[design.variable]]         # a part's region's stitch value ...
    region = "band"
    bounds = [5.0, 6.5]         # mm; default the family's range
    initial = 5.5               # default the middle of the bounds
    # axis = "y"                # ... or a stitch field: its values at stations along x or y,
    # stations = [0.0, 100.0, 200.0]  # linear between them, constant beyond

    [[design.target]]
    kind = "uniaxial"           # the knit's curve; or "force", "probe", "pressure"
    direction = "course"
    strain = [0.05, 0.1, 0.2]
    force = [2.0, 4.5, 10.0]    # in `unit` (N/mm or gf/cm); or file = "course.csv"
    unit = "gf/cm"
    weight = 1.0
    tolerance = 0.05            # relative

    [[design.member]]           # optional: the family from given surface files
    stitch = 5.0
    surface = "s5.h5"
    wale_width = 1.31
    course_height = 1.08

What is designed follows from the scene: with [sleeve] the stitch value (and, with
`needles = "design"`, the needle count) of every course band of a compression sleeve
(`knitmech.design.sleeve`); with a part ([fabric.shape] or [fabric.mesh]) the
[[design.variable]]s, stitch values of its regions; otherwise the knit's stitch value alone
(the material-level inverse, `knitmech.design.material`). Each kind takes its targets:
uniaxial curves (material), boundary forces and probe values (part), an interface pressure
profile (sleeve). Every problem is reported at once, one line each naming its key, as for a
scene (`SceneError`). docs/design.md describes every key.
"""

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fabric_dolfinx.spec.revolution import RadiusProfile, read_profile
from knitmech.design.material import CURVE_COLUMNS, FORCE_UNITS, UniaxialTarget, read_curve
from knitmech.design.sleeve import SleeveSpec
from knitmech.design.solve import SolverSettings
from knitmech.scene import Scene, SceneError, scene_from_dict
from knitmech.scene.keys import check_keys, number, read_toml
from rve_rod.errors import InputError
from rve_rod.presets import stitch_values
from rve_rod.units import KPA, MMHG

__all__ = [
    "DESIGN_KINDS",
    "PRESSURE_UNITS",
    "PROBE_QUANTITIES",
    "TARGET_KINDS",
    "DesignSpec",
    "MemberSpec",
    "TargetSpec",
    "VariableSpec",
    "load_design",
]

DESIGN_KINDS = ("material", "part", "sleeve")
TARGET_KINDS = {"uniaxial": "material", "force": "part", "probe": "part", "pressure": "sleeve"}
"""A target kind -> the kind of design it belongs to."""

PROBE_QUANTITIES = {
    "strain_xx": ("strain", (0, 0)),
    "strain_yy": ("strain", (1, 1)),
    "strain_xy": ("strain", (0, 1)),
    "stress_xx": ("cauchy", (0, 0)),
    "stress_yy": ("cauchy", (1, 1)),
    "stress_xy": ("cauchy", (0, 1)),
    "shear_angle": ("shear_angle", ()),
}
"""A probe target's quantity -> (the ProbeRecord field, its index): Green-Lagrange strain
(-), Cauchy stress (N/mm), global frame; the shear angle (degrees)."""

PRESSURE_UNITS = {"mmHg": MMHG, "kPa": KPA, "N/mm^2": 1.0}
"""A pressure target's unit -> the factor to N/mm^2."""

FORCE_COMPONENTS = {"x": 0, "y": 1}


@dataclass(frozen=True)
class VariableSpec:
    """A part's design variable: the stitch value of a region, or of a stitch field.

    Attributes:
        region: the region whose stitch value it sets.
        bounds: (lower, upper) mm, or None for the family's range.
        initial: the start (mm), or None for the middle of the bounds.
        axis: "x" or "y" for a stitch field given at `stations`, None for one value.
        stations: the field's stations along the axis (mm), increasing; one variable each.
    """

    region: str
    bounds: tuple[float, float] | None = None
    initial: float | None = None
    axis: str | None = None
    stations: tuple[float, ...] = ()


@dataclass(frozen=True)
class TargetSpec:
    """A design target (its kind's fields; the others stay at their defaults).

    Attributes:
        kind: one of TARGET_KINDS.
        weight: its weight in the least-squares sum.
        tolerance: met when its relative deviation is at most this.
        value: "force": the force (N); "probe": the quantity's value.
        boundary, component, step: "force": the boundary, "x" or "y", the load step
            (-1: the last).
        probe, quantity: "probe": the probe and one of PROBE_QUANTITIES (and `step`).
        curve: "uniaxial": the target curve (forces in N/mm).
        profile: "pressure": ((z mm, pressure N/mm^2), ...), linear between the points.
        unit: the unit the target was given in (pressure, uniaxial force), for reports.
    """

    kind: str
    weight: float = 1.0
    tolerance: float = 0.05
    value: float | None = None
    boundary: str | None = None
    component: str = "y"
    step: int = -1
    probe: str | None = None
    quantity: str | None = None
    curve: UniaxialTarget | None = None
    profile: tuple[tuple[float, float], ...] = ()
    unit: str = ""

    def pressure_at(self, z: np.ndarray) -> np.ndarray:
        """A pressure target's pressure (N/mm^2) at z (mm), linear between its points."""
        points = np.array(self.profile)
        return np.interp(z, points[:, 0], points[:, 1])


@dataclass(frozen=True)
class MemberSpec:
    """A family member given by its surface file and knit geometry (mm)."""

    stitch: float
    surface: str
    wale_width: float
    course_height: float


@dataclass(frozen=True)
class DesignSpec:
    """What `knitmech design` designs (module docstring).

    Attributes:
        kind: one of DESIGN_KINDS.
        settings: the optimizer's options.
        bounds: the stitch values searched (mm): the family's range, or the [design]
            bounds (material and sleeve designs).
        variables: a part's design variables.
        targets: the targets.
        members: the family's members given as files (else the preset's, computed).
        sleeve: the sleeve of a sleeve design.
        scene_data: the scene's parsed TOML (without the design's tables): a part design
            runs the scene with its regions' stitch values replaced.
        base: the folder relative file names of the scene are taken against.
    """

    kind: str
    settings: SolverSettings
    bounds: tuple[float, float]
    variables: tuple[VariableSpec, ...] = ()
    targets: tuple[TargetSpec, ...] = ()
    members: tuple[MemberSpec, ...] = ()
    sleeve: SleeveSpec | None = None
    scene_data: dict = field(default_factory=dict)
    base: str | None = None


DESIGN_TABLES = ("design", "sleeve")
"""The top-level tables of a design file beside a scene's."""


def load_design(path: str | Path) -> tuple[Scene, DesignSpec]:
    """Read and check a design file: its scene and its design (SceneError listing every
    problem of both)."""
    path = Path(path)
    return design_from_dict(read_toml(path, "design file"), source=str(path), base=path.parent)


def design_from_dict(
    data: dict, source: str = "<dict>", base: Path | None = None
) -> tuple[Scene, DesignSpec]:
    """The scene and design of parsed TOML (`load_design`); relative files against `base`."""
    problems: list[str] = []
    tables = {key: data.get(key) for key in DESIGN_TABLES}
    scene = None
    try:
        scene = scene_from_dict(
            {k: v for k, v in data.items() if k not in DESIGN_TABLES}, source, base
        )
    except SceneError as error:
        problems += error.problems
    design = None
    if not isinstance(tables["design"], dict):
        problems.append("design: a design file needs a [design] table (with its targets)")
    elif tables["sleeve"] is not None and not isinstance(tables["sleeve"], dict):
        problems.append("sleeve: expected a table ([sleeve])")
    else:
        design = _read_design(tables["design"], tables["sleeve"], data, scene, base, problems)
    if problems:
        raise SceneError(source, problems)
    return scene, design


def _read_design(
    table: dict, sleeve_table: dict | None, data: dict, scene: Scene | None, base, problems
) -> DesignSpec | None:
    count = len(problems)
    valid = ("max_evaluations", "difference_step", "tolerance", "bounds", "variable", "target")
    check_keys("design", table, (*valid, "member"), problems)
    part = scene.part if scene is not None else None
    has_part = part is not None or any(k in data.get("fabric", {}) for k in ("shape", "mesh"))
    kind = "sleeve" if sleeve_table is not None else "part" if has_part else "material"
    if kind == "sleeve" and has_part:
        problems.append("sleeve: a sleeve design has no [fabric.shape] or [fabric.mesh]")
    settings = _settings(table, problems)
    members = tuple(
        _member(i, t, base, problems)
        for i, t in enumerate(_tables("design.member", table, problems))
    )
    family = _family_range(data.get("fabric", {}), members, problems)
    bounds = _bounds("design.bounds", table.get("bounds"), family, problems) or family
    if "bounds" in table and kind == "part":
        problems.append("design.bounds: a part's bounds belong to its [[design.variable]]s")
    variables = tuple(
        _variable(i, t, family, part, problems)
        for i, t in enumerate(_tables("design.variable", table, problems))
    )
    named = [v.region for v in variables if v is not None]
    for region in sorted({name for name in named if named.count(name) > 1}):
        problems.append(f"design.variable: the region {region!r} is designed twice")
    if kind == "part" and not variables:
        problems.append(
            "design.variable: no variables to design; add [[design.variable]] with the "
            "region whose stitch value is designed"
        )
    if kind != "part" and variables:
        problems.append(
            f"design.variable: a {kind} design has its variables implied (the "
            f"{'bands' if kind == 'sleeve' else 'knit'}' stitch values); remove them"
        )
    targets = tuple(
        _target(i, t, kind, part, base, problems)
        for i, t in enumerate(_tables("design.target", table, problems))
    )
    if not targets:
        problems.append("design.target: no targets; add [[design.target]] tables")
    sleeve = _sleeve(sleeve_table, base, problems) if kind == "sleeve" else None
    if len(problems) > count or family is None:
        return None
    scene_data = {k: v for k, v in data.items() if k not in DESIGN_TABLES}
    return DesignSpec(
        kind,
        settings,
        bounds,
        variables,
        targets,
        members,
        sleeve,
        scene_data,
        None if base is None else str(base),
    )


def _tables(key: str, table: dict, problems: list[str]) -> list[dict]:
    value = table.get(key.rsplit(".", maxsplit=1)[-1], [])
    if not isinstance(value, list) or not all(isinstance(t, dict) for t in value):
        problems.append(f"{key}: expected [[{key}]] tables")
        return []
    return value


def _settings(table: dict, problems: list[str]) -> SolverSettings:
    values = {}
    ranges = (("max_evaluations", 1.0, 1e5), ("difference_step", 0.0, 0.1), ("tolerance", 0.0, 0.1))
    for key, low, high in ranges:
        if key in table:
            value = number(f"design.{key}", table[key], problems, low, high)
            if key == "max_evaluations" and value is not None and value != int(value):
                problems.append(f"design.{key}: expected an integer, got {value!r}")
            elif value is not None:
                values[key] = int(value) if key == "max_evaluations" else value
    return SolverSettings(**values)


def _member(index: int, table: dict, base, problems: list[str]) -> MemberSpec | None:
    prefix = f"design.member[{index}]"
    keys = ("stitch", "surface", "wale_width", "course_height")
    check_keys(prefix, table, keys, problems)
    values = {
        k: number(f"{prefix}.{k}", table.get(k), problems, 0.0) for k in keys if k != "surface"
    }
    surface = table.get("surface")
    path = None
    if not isinstance(surface, str):
        problems.append(f"{prefix}.surface: required, a response-surface file")
    else:
        path = Path(surface) if base is None else (base / surface).resolve()
        if not path.is_file():
            problems.append(f"{prefix}.surface: no such file {path}")
    if path is None or None in values.values():
        return None
    return MemberSpec(surface=str(path), **values)


def _family_range(fabric: dict, members, problems: list[str]) -> tuple[float, float] | None:
    """(smallest, largest) stitch value of the family: the given members' or the preset's."""
    if members:
        if None in members:
            return None
        stitches = sorted(m.stitch for m in members)
        if len(stitches) < 2 or len(set(stitches)) < len(stitches):
            problems.append(
                f"design.member: {stitches} mm; a family needs >= 2 different stitch values"
            )
            return None
        return stitches[0], stitches[-1]
    preset = fabric.get("preset") if isinstance(fabric, dict) else None
    values = sorted(stitch_values(preset)) if isinstance(preset, str) else []
    if len(values) < 2:
        problems.append(
            f"fabric.preset: {preset!r} is not measured at several stitch values; a design "
            "needs a family: a preset such as cotton-20s2, or [[design.member]] files"
        )
        return None
    return float(values[0]), float(values[-1])


def _bounds(key: str, value, family, problems: list[str]) -> tuple[float, float] | None:
    if value is None:
        return None
    if (
        not isinstance(value, list)
        or len(value) != 2
        or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        or not value[0] < value[1]
    ):
        problems.append(f"{key}: expected [lower, upper] mm with lower < upper, got {value!r}")
        return None
    if family is not None and (value[0] < family[0] - 1e-9 or value[1] > family[1] + 1e-9):
        problems.append(
            f"{key}: {value} mm leaves the family's range [{family[0]:g}, {family[1]:g}] mm"
        )
        return None
    return float(value[0]), float(value[1])


def _variable(index: int, table: dict, family, part, problems: list[str]) -> VariableSpec | None:
    prefix = f"design.variable[{index}]"
    check_keys(prefix, table, ("region", "bounds", "initial", "axis", "stations"), problems)
    region = table.get("region")
    regions = {r.name: r for r in part.regions} if part is not None else {}
    if not isinstance(region, str):
        problems.append(f"{prefix}.region: required, the region whose stitch value is designed")
        return None
    names = list(regions) if part is not None else None
    _known(f"{prefix}.region", region, names, ("region", "regions"), problems)
    if region in regions and (regions[region].surface or regions[region].svk):
        problems.append(f"{prefix}.region: {region!r} has a surface file or SVK constants, no knit")
    bounds = _bounds(f"{prefix}.bounds", table.get("bounds"), family, problems)
    initial = None
    if "initial" in table:
        initial = number(f"{prefix}.initial", table["initial"], problems)
        low, high = bounds or family or (-math.inf, math.inf)
        if initial is not None and not low <= initial <= high:
            problems.append(f"{prefix}.initial: {initial} mm is outside [{low:g}, {high:g}] mm")
    axis, stations = table.get("axis"), table.get("stations")
    if (axis is None) != (stations is None):
        problems.append(f"{prefix}: a stitch field needs both axis and stations")
        return None
    if axis is not None:
        if axis not in FORCE_COMPONENTS:
            problems.append(f"{prefix}.axis: {axis!r} is not x or y")
        if (
            not isinstance(stations, list)
            or len(stations) < 2
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in stations)
            or np.any(np.diff(stations) <= 0)
        ):
            problems.append(f"{prefix}.stations: expected >= 2 increasing numbers (mm)")
            return None
        stations = tuple(float(v) for v in stations)
    return VariableSpec(region, bounds, initial, axis, stations or ())


def _common(prefix: str, table: dict, problems: list[str]) -> dict:
    values = {}
    if "weight" in table:
        values["weight"] = number(f"{prefix}.weight", table["weight"], problems, 0.0)
    if "tolerance" in table:
        values["tolerance"] = number(f"{prefix}.tolerance", table["tolerance"], problems, 0.0, 1.0)
    return {k: v for k, v in values.items() if v is not None}


def _target(index: int, table: dict, kind: str, part, base, problems) -> TargetSpec | None:
    prefix = f"design.target[{index}]"
    target = table.get("kind")
    if target not in TARGET_KINDS:
        problems.append(f"{prefix}.kind: {target!r} is not one of {', '.join(TARGET_KINDS)}")
        return None
    if TARGET_KINDS[target] != kind:
        problems.append(
            f"{prefix}.kind: a {target} target belongs to a {TARGET_KINDS[target]} design; "
            f"this is a {kind} design"
        )
        return None
    common = _common(prefix, table, problems)
    reader = {"uniaxial": _uniaxial, "force": _force, "probe": _probe, "pressure": _pressure}
    return reader[target](prefix, table, common, (part, base), problems)


def _uniaxial(prefix, table, common, context, problems) -> TargetSpec | None:
    keys = ("kind", "direction", "strain", "force", "unit", "file", "weight", "tolerance")
    check_keys(prefix, table, keys, problems)
    base = context[1]
    file = table.get("file")
    given = [key for key in ("strain", "force") if key in table]
    if (file is not None) == bool(given):
        problems.append(f"{prefix}: give strain and force, or a file, not both or neither")
        return None
    unit = table.get("unit", "N/mm")
    if file is not None:
        if "unit" in table:
            problems.append(
                f"{prefix}.unit: a file's header names its unit ({', '.join(CURVE_COLUMNS)})"
            )
        path = Path(file) if base is None else (base / file).resolve()
        try:
            strain, force = read_curve(path, f"{prefix}.file")
        except InputError as error:
            problems.append(str(error))
            return None
        source = str(path)
    else:
        if unit not in FORCE_UNITS:
            problems.append(f"{prefix}.unit: {unit!r} is not one of {', '.join(FORCE_UNITS)}")
            return None
        strain, force = table.get("strain"), table.get("force")
        if not all(
            isinstance(v, list)
            and all(isinstance(x, int | float) and not isinstance(x, bool) for x in v)
            for v in (strain, force)
        ):
            problems.append(f"{prefix}: strain and force must be lists of numbers")
            return None
        force = np.asarray(force, dtype=float) * FORCE_UNITS[unit]
        source = "values"
    curve = UniaxialTarget(table.get("direction"), strain, force, source=source, **common)
    try:
        curve = curve.check(prefix)
    except InputError as error:
        problems.append(str(error))
        return None
    return TargetSpec("uniaxial", curve=curve, unit=unit, **common)


def _value_and_step(prefix: str, table: dict, what: str, problems: list[str]):
    """A force or probe target's nonzero `value` and load `step` (-1: the last)."""
    value = number(f"{prefix}.value", table.get("value"), problems)
    if value == 0.0:
        problems.append(f"{prefix}.value: 0; a target {what} must be nonzero (relative misses)")
    step = table.get("step", -1)
    if isinstance(step, bool) or not isinstance(step, int):
        problems.append(f"{prefix}.step: expected a load step number (-1: the last), got {step!r}")
        step = -1
    return value, step


def _known(key: str, value, names: list[str] | None, what: tuple[str, str], problems) -> None:
    """A problem naming `key` when `value` is not one of the part's `names` (None: no part
    read), `what` = (singular, plural) of what they name."""
    if names is not None and value not in names:
        problems.append(
            f"{key}: the part has no {what[0]} {value!r}; its {what[1]}: "
            f"{', '.join(names) or 'none'}"
        )


def _force(prefix, table, common, context, problems) -> TargetSpec | None:
    keys = ("kind", "boundary", "component", "step", "value", "weight", "tolerance")
    check_keys(prefix, table, keys, problems)
    part = context[0]
    boundary = table.get("boundary")
    names = [b.name for b in part.boundaries] if part is not None else None
    _known(f"{prefix}.boundary", boundary, names, ("boundary condition on", "boundaries"), problems)
    component = table.get("component", "y")
    if component not in FORCE_COMPONENTS:
        problems.append(f"{prefix}.component: {component!r} is not x or y")
    value, step = _value_and_step(prefix, table, "force", problems)
    return TargetSpec(
        "force", value=value, boundary=boundary, component=component, step=step, **common
    )


def _probe(prefix, table, common, context, problems) -> TargetSpec | None:
    keys = ("kind", "probe", "quantity", "step", "value", "weight", "tolerance")
    check_keys(prefix, table, keys, problems)
    part = context[0]
    probe = table.get("probe")
    names = list(part.probes) if part is not None else None
    _known(f"{prefix}.probe", probe, names, ("probe", "probes"), problems)
    quantity = table.get("quantity")
    if quantity not in PROBE_QUANTITIES:
        problems.append(
            f"{prefix}.quantity: {quantity!r} is not one of {', '.join(PROBE_QUANTITIES)}"
        )
    value, step = _value_and_step(prefix, table, "value", problems)
    return TargetSpec("probe", value=value, probe=probe, quantity=quantity, step=step, **common)


def _pressure(prefix, table, common, context, problems) -> TargetSpec | None:
    check_keys(prefix, table, ("kind", "profile", "unit", "weight", "tolerance"), problems)
    unit = table.get("unit", "mmHg")
    if unit not in PRESSURE_UNITS:
        problems.append(f"{prefix}.unit: {unit!r} is not one of {', '.join(PRESSURE_UNITS)}")
        return None
    profile = table.get("profile")
    if (
        not isinstance(profile, list)
        or not profile
        or not all(
            isinstance(p, list)
            and len(p) == 2
            and all(isinstance(v, int | float) and not isinstance(v, bool) for v in p)
            for p in profile
        )
        or np.any(np.diff([p[0] for p in profile]) <= 0)
        or any(p[1] <= 0 for p in profile)
    ):
        problems.append(
            f"{prefix}.profile: expected [[z mm, pressure], ...] with z increasing and "
            "pressures > 0"
        )
        return None
    points = tuple((float(z), float(p) * PRESSURE_UNITS[unit]) for z, p in profile)
    return TargetSpec("pressure", profile=points, unit=unit, **common)


def _sleeve(table: dict, base, problems: list[str]) -> SleeveSpec | None:
    keys = ("limb", "bands", "needles", "axial_stretch", "hoop_strain", "contact", "element_size")
    check_keys("sleeve", table, keys, problems)
    count = len(problems)
    limb = table.get("limb")
    profile = None
    try:
        if isinstance(limb, str):
            path = Path(limb) if base is None else (base / limb).resolve()
            profile = read_profile(path, "sleeve.limb")
        elif isinstance(limb, list) and all(isinstance(p, list) and len(p) == 2 for p in limb):
            profile = RadiusProfile(tuple(p[0] for p in limb), tuple(p[1] for p in limb))
        else:
            problems.append(
                "sleeve.limb: required, a CSV file (z_mm, radius_mm) or [[z, r], ...] in mm"
            )
    except InputError as error:
        problems.append(str(error) if str(error).startswith("sleeve") else f"sleeve.limb: {error}")
    bands = table.get("bands", 8)
    if isinstance(bands, bool) or not isinstance(bands, int) or not 1 <= bands <= 200:
        problems.append(f"sleeve.bands: {bands!r} is not an integer in [1, 200]")
    needles = table.get("needles", "design")
    if needles == "design":
        needles = None
    elif isinstance(needles, int | float) and not isinstance(needles, bool) and needles > 0:
        needles = (float(needles),) * (bands if isinstance(bands, int) else 1)
    elif isinstance(needles, list) and all(
        isinstance(n, int | float) and not isinstance(n, bool) and n > 0 for n in needles
    ):
        needles = tuple(float(n) for n in needles)
    else:
        problems.append(f'sleeve.needles: {needles!r} is not "design", a count > 0 or one per band')
    values = {}
    for key in ("axial_stretch", "hoop_strain", "element_size"):
        if key in table:
            values[key] = number(f"sleeve.{key}", table[key], problems, 0.0, 100.0)
    if "contact" in table:
        if not isinstance(table["contact"], bool):
            problems.append(f"sleeve.contact: expected true or false, got {table['contact']!r}")
        values["contact"] = table["contact"]
    if len(problems) > count:
        return None
    try:
        return SleeveSpec(profile, bands, needles, **values)
    except InputError as error:
        problems.append(str(error))
        return None
