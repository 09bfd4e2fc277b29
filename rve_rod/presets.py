"""Built-in yarns and fabrics: the reference data of single-jersey knits shipped with the package.

The data file `rve_rod/data/single_jersey.toml` is a copy of the project's reference data
(Weeger et al.; Vassiliadis et al. 2007), so nothing depends on files outside the package at
run time, with one addition: the staple fibres of the cotton yarn (`[fibre.*]`, the yarn's
`linear_density` and `fibre`; sources in the file), which only the free-fibre bending rigidity
of the yarn model reads. Preset names use dashes (`cotton-20s2`); the TOML tables use underscores.
"""

import tomllib
from dataclasses import dataclass, replace
from functools import cache
from importlib.resources import files

from rve_rod.errors import InputError, check_positive, check_range
from rve_rod.pattern.chart import JERSEY, pattern_chart

__all__ = [
    "MAX_COURSE_HEIGHT_RADII",
    "MAX_WALE_WIDTH_RADII",
    "MAX_YOUNGS_MODULUS",
    "Fabric",
    "Fibres",
    "Knit",
    "Yarn",
    "load_preset",
    "make_fabric",
    "preset_names",
    "reference_data",
    "stitch_values",
]


MAX_YOUNGS_MODULUS = 1e6
"""Largest Young's modulus of a yarn (MPa)."""
MAX_WALE_WIDTH_RADII = 150.0
"""Largest wale width of a fabric, in minimal yarn radii r0 (no loop fits beyond)."""
MAX_COURSE_HEIGHT_RADII = 70.0
"""Largest course height of a fabric, in minimal yarn radii r0 (no loop fits beyond)."""


@dataclass(frozen=True)
class Fibres:
    """The staple fibres of a spun yarn, for its free-fibre bending rigidity.

    Attributes:
        yarn_linear_density: T, the yarn's linear density (tex = g/km).
        fibre_linear_density: T_f, one fibre's (tex).
        specific_flexural_rigidity: a fibre's bending rigidity / T_f^2 (mN mm^2 / tex^2).
        specific_torsional_rigidity: a fibre's twisting rigidity / T_f^2 (mN mm^2 / tex^2).
        name: the fibre, e.g. "cotton".
    """

    yarn_linear_density: float
    fibre_linear_density: float
    specific_flexural_rigidity: float
    specific_torsional_rigidity: float
    name: str = ""

    def __post_init__(self):
        check_positive("yarn linear_density", self.yarn_linear_density, "tex")
        check_positive("fibre linear_density", self.fibre_linear_density, "tex")
        if self.fibre_linear_density > self.yarn_linear_density:
            raise InputError(
                f"fibre linear_density={self.fibre_linear_density:g} tex is outside the valid "
                f"range (0, {self.yarn_linear_density:g}] tex (at most the yarn's)"
            )
        check_positive("specific_flexural_rigidity", self.specific_flexural_rigidity)
        check_positive("specific_torsional_rigidity", self.specific_torsional_rigidity)


@dataclass(frozen=True)
class Yarn:
    """Yarn material and section.

    Attributes:
        minimal_radius: r0, the smaller semi-axis of the yarn cross-section (mm).
        youngs_modulus: E0 from yarn tensile tests (MPa).
        poissons_ratio: nu (-), in [0, 0.5).
        friction_coefficient: mu, yarn-on-yarn Coulomb friction (-), >= 0.
        name: preset name, or "" for a yarn given explicitly.
        fibres: its staple fibres, or None where they are not known.
    """

    minimal_radius: float
    youngs_modulus: float
    poissons_ratio: float = 0.3
    friction_coefficient: float = 0.15
    name: str = ""
    fibres: Fibres | None = None

    def __post_init__(self):
        check_positive("yarn_radius", self.minimal_radius, "mm")
        check_positive("youngs_modulus", self.youngs_modulus, "MPa")
        # stiffer than any fibre (diamond: 1.2e6 MPa); 1e6 converges, 1e12 has no equilibrium
        check_range("youngs_modulus", self.youngs_modulus, 0.0, MAX_YOUNGS_MODULUS, "MPa")
        check_range("poissons_ratio", self.poissons_ratio, 0.0, 0.5 - 1e-9)
        check_range("friction_coefficient", self.friction_coefficient, 0.0, 10.0)


@dataclass(frozen=True)
class Knit:
    """Knit geometry inputs: the loop and the stitch pattern.

    Attributes:
        wale_width: w, loop period across the wales, along x (mm): the width of one loop.
        course_height: c, loop period along the wales, along y (mm).
        measured_loop_length: loop length measured by unravelling (mm), or None.
        stitch_value: knitting-machine stitch setting (mm), or None.
        pattern: the stitch pattern's face chart, its rows bottom first (`rve_rod.pattern`;
            given also as a pattern name, e.g. "rib1x1", and stored as the chart's rows);
            single jersey ("K",) by default.
    """

    wale_width: float
    course_height: float
    measured_loop_length: float | None = None
    stitch_value: float | None = None
    pattern: tuple[str, ...] = JERSEY

    def __post_init__(self):
        check_positive("wale_width", self.wale_width, "mm")
        check_positive("course_height", self.course_height, "mm")
        object.__setattr__(self, "pattern", pattern_chart(self.pattern).rows)


@dataclass(frozen=True)
class Fabric:
    """A yarn knitted into a single-jersey fabric; `name` is the preset it came from, or ""."""

    yarn: Yarn
    knit: Knit
    name: str = ""

    def __post_init__(self):
        # Beyond these proportions no loop of the model fits (measured: c = 80 r0 and w = 200
        # r0 find none) and far beyond them the loop construction is singular.
        r0 = self.yarn.minimal_radius
        for name, value, most in (
            ("wale_width", self.knit.wale_width, MAX_WALE_WIDTH_RADII),
            ("course_height", self.knit.course_height, MAX_COURSE_HEIGHT_RADII),
        ):
            if value > most * r0:
                raise InputError(
                    f"{name}={value:.6g} mm is outside the valid range (0, {most:g} r0] = "
                    f"(0, {most * r0:.4g}] mm for yarn_radius r0={r0:.4g} mm"
                )


@cache
def reference_data() -> dict:
    """The parsed reference data file (a fresh dict is not made per call: do not mutate)."""
    text = files("rve_rod").joinpath("data/single_jersey.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def preset_names() -> list[str]:
    """Names of the built-in fabric presets, e.g. ['cotton-20s2', 'vassiliadis-sample2']."""
    return sorted(key.replace("_", "-") for key in reference_data()["fabric"])


def stitch_values(preset: str) -> list[float]:
    """The stitch values (mm) of a preset measured at several machine settings, else []."""
    table = _fabric_table(preset)
    values = table.get("stitch_value", [])
    return list(values) if isinstance(values, list) else [values]


def load_preset(preset: str, stitch: float | None = None) -> Fabric:
    """The yarn and knit of a built-in fabric.

    Args:
        preset: a name from `preset_names()`.
        stitch: stitch value (mm) for presets measured at several settings (cotton-20s2);
            must be None for single-setting presets.
    """
    table = _fabric_table(preset)
    yarn_key = table["yarn"]
    yarn_table = reference_data()["yarn"][yarn_key]
    yarn = Yarn(
        minimal_radius=yarn_table["minimal_radius"],
        youngs_modulus=yarn_table["youngs_modulus"],
        poissons_ratio=yarn_table["poissons_ratio"],
        friction_coefficient=yarn_table["friction_coefficient"],
        name=yarn_key.replace("_", "-"),
        fibres=_fibres(yarn_table),
    )
    stitches = stitch_values(preset)
    if isinstance(table["wale_width"], list):
        if stitch is None:
            raise InputError(f"preset {preset} needs --stitch, one of {_listing(stitches)} mm")
        index = _stitch_index(stitches, stitch)
        knit = Knit(
            wale_width=table["wale_width"][index],
            course_height=table["course_height"][index],
            measured_loop_length=table["loop_length"][index],
            stitch_value=stitches[index],
        )
    else:
        if stitch is not None:
            raise InputError(f"stitch={stitch} given, but preset {preset} has a single setting")
        knit = Knit(
            wale_width=table["wale_width"],
            course_height=table["course_height"],
            measured_loop_length=table.get("loop_length"),
        )
    return Fabric(yarn=yarn, knit=knit, name=preset)


def make_fabric(
    preset: str | None,
    stitch: float | None = None,
    *,
    wale_width: float | None = None,
    course_height: float | None = None,
    yarn_radius: float | None = None,
    youngs_modulus: float | None = None,
    poissons_ratio: float | None = None,
    friction: float | None = None,
    pattern=None,
    need_material: bool = True,
) -> Fabric:
    """A fabric from a preset and/or explicit values; explicit values override the preset's.

    The one rule behind the `rve-rod` options (`--preset`, `--wale-width`, ...) and the
    scene's `[fabric]` table.

    Args:
        preset: a name from `preset_names()`, or None for a fabric given by values alone.
        stitch: the preset's stitch value (mm), see `load_preset`; needs a preset.
        wale_width: w (mm). course_height: c (mm). yarn_radius: r0 (mm).
        youngs_modulus: E0 (MPa). poissons_ratio: nu (-). friction: mu (-).
        pattern: the stitch pattern, a name or a chart (`rve_rod.pattern.pattern_chart`);
            None: single jersey. A preset's w and c are measured on its single jersey: for
            another pattern `rve_rod.geometry.relaxed.settled_fabric` replaces them.
        need_material: without a preset, whether youngs_modulus is required (geometry alone
            does not need it; then E0 = 1 MPa stands in).

    Raises:
        InputError: an unknown preset or stitch, a stitch without a preset, a value missing
            without a preset, or a value outside its range.
    """
    if preset is not None:
        fabric = load_preset(preset, stitch)
        yarn, knit = fabric.yarn, fabric.knit
    else:
        if stitch is not None:
            raise InputError(f"stitch={stitch} needs a preset")
        required = {
            "wale_width": wale_width,
            "course_height": course_height,
            "yarn_radius": yarn_radius,
            "youngs_modulus": youngs_modulus if need_material else 1.0,
        }
        missing = [name for name, value in required.items() if value is None]
        if missing:
            raise InputError(f"give a preset, or all of {', '.join(missing)}")
        yarn = Yarn(minimal_radius=yarn_radius, youngs_modulus=youngs_modulus or 1.0)
        knit = Knit(wale_width=wale_width, course_height=course_height)
    yarn_overrides = {
        "minimal_radius": yarn_radius,
        "youngs_modulus": youngs_modulus,
        "poissons_ratio": poissons_ratio,
        "friction_coefficient": friction,
    }
    knit_overrides = {
        "wale_width": wale_width,
        "course_height": course_height,
        "pattern": pattern,
    }
    return Fabric(
        yarn=replace(yarn, **{k: v for k, v in yarn_overrides.items() if v is not None}),
        knit=replace(knit, **{k: v for k, v in knit_overrides.items() if v is not None}),
        name=preset or "",
    )


def _fibres(yarn_table: dict) -> Fibres | None:
    """The yarn's staple fibres from the data file, or None when it names none."""
    if "fibre" not in yarn_table:
        return None
    fibre = reference_data()["fibre"][yarn_table["fibre"]]
    return Fibres(
        yarn_linear_density=yarn_table["linear_density"],
        fibre_linear_density=fibre["linear_density"],
        specific_flexural_rigidity=fibre["specific_flexural_rigidity"],
        specific_torsional_rigidity=fibre["specific_torsional_rigidity"],
        name=yarn_table["fibre"],
    )


def _fabric_table(preset: str) -> dict:
    fabrics = reference_data()["fabric"]
    key = str(preset).replace("-", "_")
    if key not in fabrics:
        raise InputError(f"preset={preset!r} is unknown; valid presets: {_listing(preset_names())}")
    return fabrics[key]


def _stitch_index(stitches: list[float], stitch: float) -> int:
    for index, value in enumerate(stitches):
        if abs(value - float(stitch)) < 1e-9:
            return index
    raise InputError(
        f"stitch={stitch} mm is not measured; valid stitch values: {_listing(stitches)}"
    )


def _listing(values) -> str:
    return ", ".join(str(value) for value in values)
