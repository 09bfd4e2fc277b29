"""Built-in yarns and fabrics: the reference data of single-jersey knits shipped with the package.

The data file `rve_rod/data/single_jersey.toml` is a copy of the project's reference data
(Weeger et al.; Vassiliadis et al. 2007), so nothing depends on files outside the package at
run time. Preset names use dashes (`cotton-20s2`); the TOML tables use underscores.
"""

import tomllib
from dataclasses import dataclass
from functools import cache
from importlib.resources import files

from rve_rod.errors import InputError, check_positive, check_range


@dataclass(frozen=True)
class Yarn:
    """Yarn material and section.

    Attributes:
        minimal_radius: r0, the smaller semi-axis of the yarn cross-section (mm).
        youngs_modulus: E0 from yarn tensile tests (MPa).
        poissons_ratio: nu (-), in [0, 0.5).
        friction_coefficient: mu, yarn-on-yarn Coulomb friction (-), >= 0.
        name: preset name, or "" for a yarn given explicitly.
    """

    minimal_radius: float
    youngs_modulus: float
    poissons_ratio: float = 0.3
    friction_coefficient: float = 0.15
    name: str = ""

    def __post_init__(self):
        check_positive("yarn_radius", self.minimal_radius, "mm")
        check_positive("youngs_modulus", self.youngs_modulus, "MPa")
        check_range("poissons_ratio", self.poissons_ratio, 0.0, 0.5 - 1e-9)
        check_range("friction_coefficient", self.friction_coefficient, 0.0, 10.0)


@dataclass(frozen=True)
class Knit:
    """Knit geometry inputs of one single-jersey loop.

    Attributes:
        wale_width: w, loop period across the wales, along x (mm).
        course_height: c, loop period along the wales, along y (mm).
        measured_loop_length: loop length measured by unravelling (mm), or None.
        stitch_value: knitting-machine stitch setting (mm), or None.
    """

    wale_width: float
    course_height: float
    measured_loop_length: float | None = None
    stitch_value: float | None = None

    def __post_init__(self):
        check_positive("wale_width", self.wale_width, "mm")
        check_positive("course_height", self.course_height, "mm")


@dataclass(frozen=True)
class Fabric:
    """A yarn knitted into a single-jersey fabric; `name` is the preset it came from, or ""."""

    yarn: Yarn
    knit: Knit
    name: str = ""


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


def model_settings() -> dict:
    """The paper's model settings: the [model], [macro] and [performance] tables."""
    data = reference_data()
    return {key: dict(data[key]) for key in ("model", "macro", "performance")}


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
