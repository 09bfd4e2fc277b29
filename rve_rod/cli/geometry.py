"""`rve-rod geometry`: build the single-jersey loop of a fabric, or the template cell of its
stitch pattern, and report it."""

import argparse
import logging
from pathlib import Path

import numpy as np

from rve_rod.cli.common import add_fabric_arguments, fabric_from_args, print_json
from rve_rod.errors import InputError, check_positive
from rve_rod.geometry.loop import loop_geometry, loop_polylines
from rve_rod.geometry.pattern_cell import pattern_geometry
from rve_rod.imaging import knit_from_photo
from rve_rod.outputs import check_output_file, figure_formats
from rve_rod.pattern import JERSEY
from rve_rod.presets import Fabric, Knit, Yarn
from rve_rod.vtk import write_polylines

__all__ = [
    "register",
    "run",
]


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "geometry",
        help="build the loop geometry of a fabric",
        description="Build the minimum-length single-jersey loop (docs/geometry.md) for a "
        "preset or explicit wale width, course height and yarn radius.",
    )
    add_fabric_arguments(parser)
    parser.add_argument("--from-photo", type=Path, help="take w and c from a photo of the fabric")
    parser.add_argument("--pixels-per-mm", type=float, help="scale of --from-photo (px/mm)")
    parser.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    parser.add_argument("--plot", type=Path, help="write a PNG of the loop and its neighbours")
    parser.add_argument("--vtk", type=Path, help="write the loop and its neighbours as .vtu")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    if args.plot is not None:
        check_output_file("--plot", args.plot, figure_formats())
    if args.vtk is not None:
        check_output_file("--vtk", args.vtk)
    fabric = _fabric(args)
    if fabric.knit.pattern != JERSEY:
        return _pattern(args, fabric)
    geometry = loop_geometry(fabric.knit, fabric.yarn.minimal_radius)
    written = []
    if args.plot:
        from rve_rod.geometry.plot import plot_loop  # noqa: PLC0415 (matplotlib on demand)

        written.append(plot_loop(geometry, args.plot))
    if args.vtk:
        pieces = loop_polylines(geometry)
        written.append(
            write_polylines(
                args.vtk,
                [points for _, points in pieces],
                geometry.yarn_radius,
                {
                    "image_i": [np.full(len(points), i) for (i, _), points in pieces],
                    "image_j": [np.full(len(points), j) for (_, j), points in pieces],
                },
            )
        )
    report = {"preset": fabric.name or None, "stitch": fabric.knit.stitch_value}
    report |= geometry.to_dict()
    report["measured_loop_length"] = fabric.knit.measured_loop_length
    report["files"] = [str(path) for path in written]
    if args.json:
        print_json(report)
        return 0
    r = geometry.yarn_radius
    lines = [
        f"loop of w = {geometry.wale_width:.4g} mm, c = {geometry.course_height:.4g} mm, "
        f"r0 = {geometry.minimal_radius:.4g} mm",
        f"  yarn radius        {r:.4g} mm"
        + (" (adjusted to w/8)" if geometry.radius_adjusted else ""),
        f"  loop length        {geometry.loop_length:.4f} mm"
        + (
            f" (measured {fabric.knit.measured_loop_length:.3f} mm, "
            f"{100 * (geometry.loop_length / fabric.knit.measured_loop_length - 1):+.1f} %)"
            if fabric.knit.measured_loop_length
            else ""
        ),
        f"  shoulder radius    {geometry.shape_parameter:.4f} mm = "
        f"{geometry.shape_parameter / r:.3f} r (shape parameter)",
        f"  depth d            {geometry.depth:.4f} mm = {geometry.depth / r:.3f} r",
        f"  min clearance      {geometry.min_clearance:.5f} mm = "
        f"{geometry.min_clearance / (2 * r):.5f} x 2r (image {geometry.closest.image})",
        "  control points     4 curves x 12, degree 4",
    ]
    lines += [f"  wrote {path}" for path in written]
    print("\n".join(lines))
    return 0


def _pattern(args: argparse.Namespace, fabric: Fabric) -> int:
    """The template of a pattern's cell (`rve_rod.geometry.pattern_cell`): report and VTK."""
    if args.plot is not None:
        raise InputError("--plot draws single-jersey loops; use --vtk for a pattern's cell")
    knit = fabric.knit
    geometry = pattern_geometry(
        knit.pattern, knit.wale_width, knit.course_height, fabric.yarn.minimal_radius
    )
    written = []
    if args.vtk:
        u = np.linspace(0.0, 1.0, 40)
        yarns = [np.vstack([curve(u) for curve in yarn]) for yarn in geometry.yarns]
        a1, a2 = geometry.lattice
        shifts = [(i, j) for i in (-1, 0, 1) for j in (-1, 0, 1)]
        lines = [points + i * a1 + j * a2 for i, j in shifts for points in yarns]
        data = {
            "image_i": [np.full(len(p), i) for (i, _) in shifts for p in yarns],
            "image_j": [np.full(len(p), j) for (_, j) in shifts for p in yarns],
        }
        written.append(write_polylines(args.vtk, lines, geometry.yarn_radius, data))
    report = {"preset": fabric.name or None, "stitch": knit.stitch_value}
    report |= geometry.to_dict()
    report["measured_loop_length"] = knit.measured_loop_length
    report["files"] = [str(path) for path in written]
    if args.json:
        print_json(report)
        return 0
    r = geometry.yarn_radius
    (p, _), (q, s) = geometry.cell.lattice
    lines = [
        f"cell of pattern {report['pattern']} (chart {','.join(knit.pattern)}): {p * s} loops "
        f"on ({p} w, 0), ({q} w, {s} c), w = {knit.wale_width:.4g} mm, c = "
        f"{knit.course_height:.4g} mm, r0 = {geometry.minimal_radius:.4g} mm",
        f"  yarn radius        {r:.4g} mm",
        f"  loop length        {geometry.loop_length:.4f} mm per loop",
        f"  depth d            {geometry.depth:.4f} mm = {geometry.depth / r:.3f} r",
        f"  min clearance      {geometry.min_clearance / (2 * r):.5f} x 2r",
    ]
    lines += [f"  wrote {path}" for path in written]
    print("\n".join(lines))
    return 0


def _fabric(args: argparse.Namespace) -> Fabric:
    if args.from_photo is None:
        if args.pixels_per_mm is not None:
            raise InputError("--pixels-per-mm goes with --from-photo")
        return fabric_from_args(args, need_material=False)
    if args.pixels_per_mm is None:
        raise InputError("--from-photo needs --pixels-per-mm (the photo's scale)")
    if args.pattern is not None or args.relaxed:
        raise InputError("--from-photo measures single jersey: no --pattern or --relaxed")
    if args.preset is not None or args.wale_width is not None or args.course_height is not None:
        raise InputError("--from-photo replaces --preset, --wale-width and --course-height")
    if args.yarn_radius is None:
        raise InputError("--from-photo needs --yarn-radius (r0, mm)")
    check_positive("pixels_per_mm", args.pixels_per_mm, "px/mm")
    knit: Knit = knit_from_photo(args.from_photo, args.pixels_per_mm)
    logging.getLogger(__name__).info(
        "photo %s: w = %.4g mm, c = %.4g mm", args.from_photo, knit.wale_width, knit.course_height
    )
    return Fabric(yarn=Yarn(minimal_radius=args.yarn_radius, youngs_modulus=1.0), knit=knit)
