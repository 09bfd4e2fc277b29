"""Arguments and output helpers shared by the `rve-rod` subcommands."""

import argparse
import json
import sys

from rve_rod import limits
from rve_rod.geometry.relaxed import settled_fabric
from rve_rod.jsonable import to_jsonable
from rve_rod.outputs import ignore_broken_pipe
from rve_rod.pattern import NAMED_PATTERNS
from rve_rod.presets import Fabric, make_fabric, preset_names, stitch_values
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.yarn import BENDING_CHOICES, YarnSettings

__all__ = [
    "add_bending_argument",
    "add_control_points_argument",
    "add_fabric_arguments",
    "fabric_from_args",
    "print_json",
]


def add_fabric_arguments(parser: argparse.ArgumentParser) -> None:
    """Add `--preset/--stitch` or explicit `--wale-width/--course-height/--yarn-radius/...`."""
    group = parser.add_argument_group("fabric (a preset, or explicit knit and yarn parameters)")
    group.add_argument("--preset", help=f"built-in fabric: {', '.join(preset_names())}")
    stitches = "; ".join(
        f"{name}: {', '.join(f'{v:g}' for v in stitch_values(name))}"
        for name in preset_names()
        if stitch_values(name)
    )
    group.add_argument(
        "--stitch", type=float, help=f"stitch value of the preset (mm; measured: {stitches})"
    )
    group.add_argument("--wale-width", type=float, help="w, wale width (mm)")
    group.add_argument("--course-height", type=float, help="c, course height (mm)")
    group.add_argument("--yarn-radius", type=float, help="r0, minimal yarn radius (mm)")
    group.add_argument("--youngs-modulus", type=float, help="E0 of the yarn (MPa)")
    group.add_argument("--poissons-ratio", type=float, help="nu of the yarn (-)")
    group.add_argument("--friction", type=float, help="mu, yarn-on-yarn friction (-)")
    group.add_argument(
        "--pattern",
        help=f"stitch pattern: {', '.join(NAMED_PATTERNS)}, or a face chart, rows of K and P "
        "bottom row first, separated by commas (e.g. KP,PK); default jersey. A preset's w and "
        "c are its jersey's: another pattern takes those of its relaxed cell (docs/patterns.md)",
    )
    group.add_argument(
        "--relaxed",
        action="store_true",
        help="w and c of the relaxed cell from the preset's loop length, for jersey too "
        "(not with --wale-width/--course-height)",
    )


def add_control_points_argument(parser: argparse.ArgumentParser) -> None:
    """`--control-points`: control points per quarter loop of the RVE (rve_rod.limits range)."""
    low, high = limits.CONTROL_POINTS
    parser.add_argument(
        "--control-points",
        type=int,
        default=CellSettings().control_points,
        help=f"control points per quarter loop of every RVE run, {low} to {high} (the periodic "
        "yarn curve has about 4 times as many)",
    )


def add_bending_argument(parser: argparse.ArgumentParser) -> None:
    """`--bending`: how the rods' bending and twisting rigidity is found (YarnSettings.bending)."""
    parser.add_argument(
        "--bending",
        choices=BENDING_CHOICES,
        default=YarnSettings().bending,
        help="the rods' bending and twisting rigidity: the sum of the yarn's staple fibres' "
        "(free-fibres; needs fibre data: cotton-20s2), of its solid section (section, the "
        "paper's model), or auto (default): free-fibres where the fibres are known",
    )


def fabric_from_args(args: argparse.Namespace, *, need_material: bool = True) -> Fabric:
    """The fabric named by `add_fabric_arguments` options (`rve_rod.presets.make_fabric`),
    its w and c settled for its pattern (`rve_rod.geometry.relaxed.settled_fabric`)."""
    fabric = make_fabric(
        args.preset,
        args.stitch,
        wale_width=args.wale_width,
        course_height=args.course_height,
        yarn_radius=args.yarn_radius,
        youngs_modulus=args.youngs_modulus,
        poissons_ratio=args.poissons_ratio,
        friction=args.friction,
        pattern=args.pattern,
        need_material=need_material,
    )
    measured = args.wale_width is not None or args.course_height is not None
    return settled_fabric(fabric, relaxed=args.relaxed or None, measured=measured)


def print_json(payload: dict) -> None:
    """Write one JSON object to stdout (the whole of stdout for `--json` runs)."""
    ignore_broken_pipe()
    json.dump(to_jsonable(payload), sys.stdout, indent=2)
    sys.stdout.write("\n")
