"""Arguments and output helpers shared by the `rve-rod` subcommands."""

import argparse
import json
import math
import sys

import numpy as np

from rve_rod.errors import InputError
from rve_rod.presets import Fabric, Knit, Yarn, load_preset, preset_names


def add_fabric_arguments(parser: argparse.ArgumentParser) -> None:
    """Add `--preset/--stitch` or explicit `--wale-width/--course-height/--yarn-radius/...`."""
    group = parser.add_argument_group("fabric (a preset, or explicit knit and yarn parameters)")
    group.add_argument("--preset", help=f"built-in fabric: {', '.join(preset_names())}")
    group.add_argument("--stitch", type=float, help="stitch value of the preset (mm)")
    group.add_argument("--wale-width", type=float, help="w, wale width (mm)")
    group.add_argument("--course-height", type=float, help="c, course height (mm)")
    group.add_argument("--yarn-radius", type=float, help="r0, minimal yarn radius (mm)")
    group.add_argument("--youngs-modulus", type=float, help="E0 of the yarn (MPa)")
    group.add_argument("--poissons-ratio", type=float, help="nu of the yarn (-)")
    group.add_argument("--friction", type=float, help="mu, yarn-on-yarn friction (-)")


def fabric_from_args(args: argparse.Namespace, *, need_material: bool = True) -> Fabric:
    """The fabric named by `add_fabric_arguments` options; explicit values override a preset.

    Without a preset, wale width, course height and yarn radius are required, and so is the
    Young's modulus when `need_material` is true (geometry alone does not need it).
    """
    if args.preset is not None:
        fabric = load_preset(args.preset, args.stitch)
        yarn, knit = fabric.yarn, fabric.knit
    else:
        if args.stitch is not None:
            raise InputError("--stitch needs --preset")
        missing = [
            flag
            for flag, value in (
                ("--wale-width", args.wale_width),
                ("--course-height", args.course_height),
                ("--yarn-radius", args.yarn_radius),
                ("--youngs-modulus", args.youngs_modulus if need_material else 1.0),
            )
            if value is None
        ]
        if missing:
            raise InputError(f"give --preset, or all of {', '.join(missing)}")
        yarn = Yarn(minimal_radius=args.yarn_radius, youngs_modulus=args.youngs_modulus or 1.0)
        knit = Knit(wale_width=args.wale_width, course_height=args.course_height)
    overrides = {
        "minimal_radius": args.yarn_radius,
        "youngs_modulus": args.youngs_modulus,
        "poissons_ratio": args.poissons_ratio,
        "friction_coefficient": args.friction,
    }
    yarn_fields = {**yarn.__dict__, **{k: v for k, v in overrides.items() if v is not None}}
    knit_fields = dict(knit.__dict__)
    for key in ("wale_width", "course_height"):
        if getattr(args, key) is not None:
            knit_fields[key] = getattr(args, key)
    return Fabric(yarn=Yarn(**yarn_fields), knit=Knit(**knit_fields), name=args.preset or "")


def to_jsonable(value):
    """Convert numpy scalars/arrays, dataclass-like dicts and non-finite floats for JSON."""
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [to_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, np.generic):
        return to_jsonable(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def print_json(payload: dict) -> None:
    """Write one JSON object to stdout (the whole of stdout for `--json` runs)."""
    json.dump(to_jsonable(payload), sys.stdout, indent=2)
    sys.stdout.write("\n")
