"""`rve-rod measure`: wale width, course height and angle of single jersey from a photo."""

import argparse

from rve_rod.cli.common import print_json
from rve_rod.imaging.image_io import read_image
from rve_rod.imaging.measure import measure_photo
from rve_rod.imaging.overlay import plot_overlay
from rve_rod.outputs import check_output_file, figure_formats

__all__ = [
    "register",
    "run",
]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the `measure` subcommand."""
    parser = subparsers.add_parser(
        "measure",
        help="measure w, c and the angle of single jersey on a photo",
        description="Estimate the wale width w and course height c (mm) with their standard "
        "uncertainties, and the in-plane angle of the courses, from a photo of single jersey "
        "(any format Pillow reads, grayscale or colour), averaged over the whole photo by its "
        "2D power spectrum. The wales must run within 45 degrees of the photo's vertical.",
    )
    parser.add_argument("photo", help="image file of the fabric")
    parser.add_argument(
        "--pixels-per-mm", type=float, required=True, help="the photo's scale (pixels per mm)"
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--plot", metavar="PNG", help="save the photo with the lattice drawn on it")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    if args.plot is not None:
        check_output_file("--plot", args.plot, figure_formats())
    image = read_image(args.photo)
    estimate = measure_photo(image, args.pixels_per_mm)
    if args.plot:
        plot_overlay(image, estimate, args.plot)
    if args.json:
        print_json({"photo": args.photo, **estimate.to_dict()})
        return 0
    height, width = image.shape
    print(f"photo {args.photo}: {width} x {height} px at {args.pixels_per_mm:g} px/mm")
    print(
        f"wale width    w = {estimate.wale_width:.4f} +- {estimate.wale_width_uncertainty:.4f} mm"
        f"  ({estimate.wales_in_image:.1f} wales across)"
    )
    print(
        f"course height c = {estimate.course_height:.4f} +- "
        f"{estimate.course_height_uncertainty:.4f} mm  ({estimate.courses_in_image:.1f} courses)"
    )
    print(
        f"angle of the courses {estimate.angle_deg:.2f} +- "
        f"{estimate.angle_uncertainty_deg:.2f} deg, skew {estimate.skew_deg:.2f} deg"
    )
    if args.plot:
        print(f"wrote {args.plot}")
    return 0
