"""Scene files: one TOML file that describes a whole study, checked before anything runs.

A scene names the fabric (a preset or explicit yarn and knit), the meso-scale RVE runs wanted,
the response-surface sampling and the fabric-scale problem. Every problem found while reading
is collected, and `SceneError` reports all of them at once, one line each, naming the key.
Settings left out of a scene come from its fidelity level (`knitmech.fidelity`); docs/pipeline.md
describes the format.
"""

import math
from dataclasses import asdict, dataclass, field, fields, replace
from importlib.resources import files
from pathlib import Path
from typing import Any

from knitmech.fidelity import DEFAULT, LEVELS, Fidelity
from knitmech.scene.fabric import (
    PartSpec,
    knit_fabric,
    part_toml,
    pattern_problems,
    read_part,
)
from knitmech.scene.fabric import toml_value as _toml_value
from knitmech.scene.keys import describe, read_toml, unknown_key
from knitmech.scene.space import SPACE_TABLES
from rve_rod import limits
from rve_rod.errors import InputError
from rve_rod.presets import Fabric, load_preset
from rve_rod.rve.yarn import BENDING_CHOICES

__all__ = [
    "DEFAULT_SURFACE",
    "DIRECTIONS",
    "FIDELITY_NAMES",
    "MESO_CASES",
    "SURFACE_KINDS",
    "FabricSpec",
    "MacroSpec",
    "MesoSpec",
    "Scene",
    "SceneError",
    "SurfaceSpec",
    "default_scene_path",
    "default_surface_path",
    "load_scene",
    "scene_from_dict",
    "starter_scene_path",
]

MESO_CASES = (
    "uniaxial-course",
    "uniaxial-wale",
    "strip-biaxial-course",
    "strip-biaxial-wale",
    "shear",
)
"""Meso-scale load cases a scene may ask for by name (design.md); biaxial rays come from
the surface sampling."""

DEFAULT_SURFACE = "cotton-20s2_stitch-5.5.h5"
"""File name of the default scene's surface in knitmech/data."""

DIRECTIONS = ("course", "wale")
SURFACE_KINDS = ("stress", "energy")
FIDELITY_NAMES = tuple(LEVELS)


class SceneError(InputError):
    """A scene has problems; `problems` lists them, one message per problem."""

    def __init__(self, source: str, problems: list[str]):
        self.problems = list(problems)
        lines = "\n".join(f"  - {problem}" for problem in self.problems)
        super().__init__(f"scene {source} has {len(self.problems)} problem(s):\n{lines}")


@dataclass(frozen=True)
class FabricSpec:
    """The knitted fabric: a preset (with stitch value) and/or explicit values (mm, MPa).

    Explicit values override the preset's; without a preset, wale_width, course_height,
    yarn_radius and youngs_modulus are required. `bending` is the RVE's model of the yarn's
    bending and twisting rigidity (`rve_rod.rve.yarn.BENDING_CHOICES`: "auto", the default, is
    "free-fibres" where the yarn's fibres are known and "section" where not; "free-fibres"
    needs a preset with fibre data). The stitch pattern is `pattern` (a name, e.g. "rib1x1",
    or a chart as one string, "KP,PK") or `chart` (its rows, bottom first), single jersey by
    default (docs/patterns.md); a preset's w and c are measured on its jersey, so another
    pattern takes those of its relaxed cell unless wale_width and course_height are given;
    `relaxed = true` takes them for jersey too.
    """

    preset: str | None = None
    stitch: float | None = None
    wale_width: float | None = None
    course_height: float | None = None
    yarn_radius: float | None = None
    youngs_modulus: float | None = None
    poissons_ratio: float | None = None
    friction: float | None = None
    bending: str = "auto"
    pattern: str | None = None
    chart: tuple[str, ...] | None = None
    relaxed: bool | None = None


@dataclass(frozen=True)
class MesoSpec:
    """Meso-scale RVE runs reported beside the fabric results (uniaxial curves, Poisson ratios).

    Attributes:
        cases: load-case names from MESO_CASES.
        max_strain: largest prescribed engineering strain (-).
        steps: load steps including the zero step; None takes the fidelity level's.
        control_points: control points per loop curve; None takes the fidelity level's.
    """

    cases: tuple[str, ...] = ("uniaxial-course", "uniaxial-wale")
    max_strain: float = 0.20
    steps: int | None = None
    control_points: int | None = None


@dataclass(frozen=True)
class SurfaceSpec:
    """Response-surface sampling and fit, or an existing surface file to use as it is.

    Attributes:
        kind: "stress" (the paper's stress surfaces) or "energy" (hyperelastic potential).
        path: an existing surface file; when given nothing is sampled.
        rays: number of biaxial rays; None takes the fidelity level's.
        max_strain: largest engineering strain along the rays, in tension (-).
        max_compression: largest engineering strain along the rays, in compression (-); None
            (the default): follow the fabric's contraction in uniaxial tension
            (`rve_rod.homogenize.sampling.compression_box`).
        shear_max_strain: largest shear strain of the pure-shear run (-).
    """

    kind: str = "stress"
    path: str | None = None
    rays: int | None = None
    max_strain: float = 0.20
    max_compression: float | None = None
    shear_max_strain: float = 0.30


@dataclass(frozen=True)
class MacroSpec:
    """The fabric-scale problem: a square patch pulled in tension (design.md, paper Fig. 8).

    Attributes:
        size: patch edge length (mm).
        elements: elements per side; None takes the fidelity level's.
        directions: "course" (clamp left, pull right) and/or "wale" (clamp bottom, pull top).
        max_strain: largest nominal strain of the patch (-).
        steps: load steps; None takes the fidelity level's.
        angle: orientation of the course direction against the x axis (degrees).
        ranks: MPI ranks for the fabric runs (1 runs in-process).
    """

    size: float = 50.0
    elements: int | None = None
    directions: tuple[str, ...] = DIRECTIONS
    max_strain: float = 0.20
    steps: int | None = None
    angle: float = 0.0
    ranks: int = 1


@dataclass(frozen=True)
class Scene:
    """A whole study; see the module docstring and docs/pipeline.md."""

    name: str = "scene"
    fidelity: str = DEFAULT
    fabric: FabricSpec = field(default_factory=FabricSpec)
    meso: MesoSpec = field(default_factory=MesoSpec)
    surface: SurfaceSpec = field(default_factory=SurfaceSpec)
    macro: MacroSpec = field(default_factory=MacroSpec)
    part: PartSpec | None = None
    """The fabric part ([fabric.shape] or [fabric.mesh], [[region]], [[boundary]];
    `knitmech.scene.fabric`); None: the patch tension tests of [macro]."""

    def to_dict(self) -> dict[str, Any]:
        """The scene as plain data (lists for tuples, no None), for TOML/JSON records."""
        return _to_plain(self)

    def to_toml(self) -> str:
        """The scene as TOML text that `load_scene` reads back to an equal scene."""
        data = self.to_dict()
        lines = [f"{key} = {_toml_value(data[key])}" for key in ("name", "fidelity")]
        for section in ("fabric", "meso", "surface", "macro"):
            lines += ["", f"[{section}]"]
            lines += [f"{key} = {_toml_value(value)}" for key, value in data[section].items()]
        if self.part is not None:
            lines += ["", part_toml(self.part).rstrip()]
        return "\n".join(lines) + "\n"

    def resolved(self, level: Fidelity) -> "Scene":
        """The scene with every setting it leaves to the fidelity level taken from `level`."""

        def fill(spec, **defaults):
            return replace(spec, **{k: v for k, v in defaults.items() if getattr(spec, k) is None})

        return replace(
            self,
            fidelity=level.name,
            meso=fill(self.meso, steps=level.meso_steps, control_points=level.control_points),
            surface=fill(self.surface, rays=level.rays),
            macro=fill(self.macro, elements=level.elements, steps=level.macro_steps),
            part=self.part.resolved(level.elements) if self.part is not None else None,
        )

    def fabric_model(self) -> Fabric:
        """The yarn and knit of the scene: the preset's values with the explicit ones on top."""
        values = asdict(self.fabric)
        del values["bending"]  # a model choice of the RVE, not fabric data
        return knit_fabric(values)


def default_scene_path() -> Path:
    """Path of the built-in default scene (cotton 20s/2, stitch 5.5, 50 mm patch)."""
    return Path(str(files("knitmech").joinpath("data/default_scene.toml")))


def starter_scene_path() -> Path:
    """Path of the commented scene `knitmech init` writes (a strip tensile test)."""
    return Path(str(files("knitmech").joinpath("data/starter_scene.toml")))


def default_surface_path() -> Path:
    """The response surface of the default scene as `knitmech run` made it at the default
    fidelity (shipped for the demos; docs/pipeline.md says how it is remade)."""
    return Path(str(files("knitmech").joinpath(f"data/{DEFAULT_SURFACE}")))


def load_scene(path: str | Path | None = None) -> Scene:
    """Read and check a scene file (the built-in default scene when `path` is None)."""
    path = default_scene_path() if path is None else Path(path)
    return scene_from_dict(read_toml(path, "scene file"), source=str(path), base=path.parent)


def scene_from_dict(data: dict, source: str = "<dict>", base: Path | None = None) -> Scene:
    """Build a Scene from parsed TOML, collecting every problem into one SceneError.

    Relative paths (surface.path) are taken relative to `base`.
    """
    problems: list[str] = []
    sections = {"fabric": FabricSpec, "meso": MesoSpec, "surface": SurfaceSpec, "macro": MacroSpec}
    top: dict[str, Any] = {}
    fabric_table = data.get("fabric", {})
    if isinstance(fabric_table, dict):
        fabric_table = dict(fabric_table)
        data = {**data, "fabric": fabric_table}
        part = read_part(data, fabric_table, problems, base)
    else:
        part = None
    for key, value in data.items():
        if key in sections or key in ("region", "boundary", "probe", *SPACE_TABLES):
            continue
        if key not in ("name", "fidelity"):
            valid = ("name", "fidelity", *sections, "region", "boundary", "probe", *SPACE_TABLES)
            problems.append(unknown_key(key, valid))
            continue
        top[key] = value
    if not isinstance(top.get("name", ""), str):
        problems.append(f"name: expected a string, got {describe(top['name'])}")
    fidelity = top.get("fidelity", "balanced")
    if fidelity not in FIDELITY_NAMES:
        problems.append(f"fidelity: {fidelity!r} is not one of {', '.join(FIDELITY_NAMES)}")
    parts = {}
    for name, cls in sections.items():
        table = data.get(name, {})
        if not isinstance(table, dict):
            problems.append(f"{name}: expected a table, got {describe(table)}")
            table = {}
        parts[name] = _read_section(name, cls, table, problems)
    _check_values(parts, problems, base, part)
    if problems:
        raise SceneError(source, problems)
    surface = parts["surface"]
    if surface.path is not None and base is not None:
        resolved = (base / surface.path).resolve()
        surface = SurfaceSpec(**{**surface.__dict__, "path": str(resolved)})
    return Scene(
        name=top.get("name", "scene"),
        fidelity=fidelity,
        fabric=parts["fabric"],
        meso=parts["meso"],
        surface=surface,
        macro=parts["macro"],
        part=part,
    )


# Expected Python types of every section key (TOML integers are accepted for floats).
_TYPES: dict[str, dict[str, tuple[type, ...]]] = {
    "fabric": {
        "preset": (str,),
        "stitch": (float,),
        "wale_width": (float,),
        "course_height": (float,),
        "yarn_radius": (float,),
        "youngs_modulus": (float,),
        "poissons_ratio": (float,),
        "friction": (float,),
        "bending": (str,),
        "pattern": (str,),
        "chart": (list,),
        "relaxed": (bool,),
    },
    "meso": {"cases": (list,), "max_strain": (float,), "steps": (int,), "control_points": (int,)},
    "surface": {
        "kind": (str,),
        "path": (str,),
        "rays": (int,),
        "max_strain": (float,),
        "max_compression": (float,),
        "shear_max_strain": (float,),
    },
    "macro": {
        "size": (float,),
        "elements": (int,),
        "directions": (list,),
        "max_strain": (float,),
        "steps": (int,),
        "angle": (float,),
        "ranks": (int,),
    },
}


def _read_section(name: str, cls: type, table: dict, problems: list[str]):
    valid = [f.name for f in fields(cls)]
    values = {}
    for key, raw in table.items():
        if key not in valid:
            problems.append(unknown_key(f"{name}.{key}", valid))
            continue
        expected = _TYPES[name][key]
        value = raw
        if float in expected and isinstance(raw, int) and not isinstance(raw, bool):
            value = float(raw)
        if (isinstance(value, bool) and bool not in expected) or not isinstance(value, expected):
            wanted = " or ".join(t.__name__ for t in expected)
            problems.append(f"{name}.{key}: expected {wanted}, got {describe(value)}")
            continue
        if isinstance(value, float) and not math.isfinite(value):
            problems.append(f"{name}.{key}: {value} is not a finite number")
            continue
        values[key] = tuple(value) if isinstance(value, list) else value
    return cls(**values)


def _check_values(
    parts: dict, problems: list[str], base: Path | None, part: PartSpec | None = None
) -> None:
    fabric, meso, surface, macro = (parts[k] for k in ("fabric", "meso", "surface", "macro"))
    for key in ("stitch", "wale_width", "course_height", "yarn_radius", "youngs_modulus"):
        value = getattr(fabric, key)
        if value is not None and value <= 0:
            problems.append(f"fabric.{key}: {value} must be > 0")
    if fabric.poissons_ratio is not None and not 0 <= fabric.poissons_ratio < 0.5:
        problems.append(f"fabric.poissons_ratio: {fabric.poissons_ratio} is outside [0, 0.5)")
    if fabric.friction is not None and fabric.friction < 0:
        problems.append(f"fabric.friction: {fabric.friction} must be >= 0")
    problems += pattern_problems("fabric", asdict(fabric))
    if fabric.bending not in BENDING_CHOICES:
        problems.append(
            f"fabric.bending: {fabric.bending!r} is unknown (valid: {', '.join(BENDING_CHOICES)})"
        )
    # a preset or stitch of the wrong type is reported once, not again as unknown or missing
    reported = {
        key for key in ("preset", "stitch") if any(p.startswith(f"fabric.{key}:") for p in problems)
    }
    if fabric.preset is not None:
        if "stitch" not in reported:
            try:
                load_preset(fabric.preset, fabric.stitch)
            except InputError as error:
                key = "fabric.stitch" if "stitch" in str(error) else "fabric.preset"
                problems.append(f"{key}: {error}")
    elif "preset" not in reported:
        keys = ("wale_width", "course_height", "yarn_radius", "youngs_modulus")
        missing = [key for key in keys if getattr(fabric, key) is None]
        if missing and part is not None:
            problems.append(_no_knit(part))
        else:
            for key in missing:
                problems.append(f"fabric.{key}: required when fabric.preset is not given")
    for case in meso.cases:
        if case not in MESO_CASES:
            problems.append(f"meso.cases: {case!r} is not one of {', '.join(MESO_CASES)}")
    for direction in macro.directions:
        if direction not in DIRECTIONS:
            problems.append(f"macro.directions: {direction!r} is not one of course, wale")
    if surface.kind not in SURFACE_KINDS:
        problems.append(f"surface.kind: {surface.kind!r} is not one of stress, energy")
    if surface.path is not None:
        path = Path(surface.path) if base is None else base / surface.path
        if not path.is_file():
            problems.append(f"surface.path: no such file {path}")
    ranges = (  # key, value, low, high: low < value <= high
        ("meso.max_strain", meso.max_strain, 0.0, 1.0),
        ("surface.max_strain", surface.max_strain, 0.0, 0.8),
        ("surface.shear_max_strain", surface.shear_max_strain, 0.0, 0.8),
        ("macro.max_strain", macro.max_strain, 0.0, 1.0),
        ("macro.size", macro.size, 0.0, math.inf),
        ("macro.angle", macro.angle, -360.0, 360.0),
    )
    for key, value, low, high in ranges:
        if not low < value <= high:
            problems.append(f"{key}: {value} is outside the valid range ({low}, {high}]")
    if surface.max_compression is not None and not 0.0 <= surface.max_compression <= 0.5:
        problems.append(
            f"surface.max_compression: {surface.max_compression} is outside the valid range "
            "[0.0, 0.5]"
        )
    counts = (  # the ranges of rve_rod.limits; macro.ranks' upper bound: pipeline.check_plan
        ("meso.steps", meso.steps, limits.RVE_STEPS),
        ("meso.control_points", meso.control_points, limits.CONTROL_POINTS),
        ("surface.rays", surface.rays, limits.RAYS),
        ("macro.elements", macro.elements, limits.ELEMENTS),
        ("macro.steps", macro.steps, limits.MACRO_STEPS),
        ("macro.ranks", macro.ranks, (1, math.inf)),
    )
    for key, value, (low, high) in counts:
        if value is not None and not low <= value <= high:
            problems.append(f"{key}: {value} is outside the valid range [{low}, {high}]")


def _no_knit(part: PartSpec) -> str:
    """The one problem of a part scene whose [fabric] table gives no knit: the regions that
    would take theirs from it (those without a preset, surface or svk of their own)."""
    bare = [
        f"region[{index}] {region.name!r}"
        for index, region in enumerate(part.regions)
        if "preset" not in region.knit and region.surface is None and region.svk is None
    ]
    if not bare:
        return (
            "fabric: no knit (the scene's own, for its geometry and meso stages): give [fabric] "
            "preset and stitch, or wale_width, course_height, yarn_radius and youngs_modulus"
        )
    return (
        f"fabric: no knit for {', '.join(bare)}: give [fabric] preset and stitch, or "
        "wale_width, course_height, yarn_radius and youngs_modulus, or the region a preset, "
        "surface or svk"
    )


def _to_plain(value: Any) -> Any:
    if hasattr(value, "__dataclass_fields__"):
        return {
            f.name: _to_plain(getattr(value, f.name))
            for f in fields(value)
            if getattr(value, f.name) is not None
        }
    if isinstance(value, tuple):
        return [_to_plain(v) for v in value]
    return value
