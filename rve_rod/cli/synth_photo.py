"""`rve-rod synth-photo`: a synthetic photo of single jersey with known w, c and angle."""

import argparse

from rve_rod.cli.common import add_fabric_arguments, fabric_from_args
from rve_rod.imaging.image_io import write_image
from rve_rod.imaging.synthetic import SyntheticPhoto, render_photo
from rve_rod.outputs import check_output_file, image_formats

__all__ = [
    "register",
    "run",
]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the `synth-photo` subcommand."""
    parser = subparsers.add_parser(
        "synth-photo",
        help="render a synthetic photo of single jersey (test data for `measure`)",
        description="Render the yarns of the loop model as seen from above, for a preset or "
        "explicit w, c and yarn radius (drawn with the adjusted radius min(r0, w/8)), rotated, "
        "blurred, unevenly lit and noisy, and save it as an 8-bit image.",
    )
    add_fabric_arguments(parser)
    parser.add_argument("-o", "--output", required=True, help="image file to write (.png)")
    parser.add_argument("--pixels-per-mm", type=float, default=25.0, help="resolution (25)")
    parser.add_argument(
        "--size",
        type=int,
        nargs=2,
        default=(512, 512),
        metavar=("WIDTH", "HEIGHT"),
        help="image size in pixels (512 512)",
    )
    parser.add_argument("--angle-deg", type=float, default=0.0, help="fabric rotation (0)")
    parser.add_argument("--blur-mm", type=float, default=0.0, help="Gaussian blur sigma (0)")
    parser.add_argument("--noise", type=float, default=0.0, help="noise sigma, full scale 1 (0)")
    parser.add_argument("--lighting", type=float, default=0.0, help="uneven lighting, 0-0.9 (0)")
    parser.add_argument("--side", choices=("face", "back"), default="face", help="fabric side")
    parser.add_argument("--seed", type=int, default=0, help="seed of the noise (0)")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    check_output_file("--output", args.output, image_formats())
    fabric = fabric_from_args(args, need_material=False)
    knit = fabric.knit
    photo = SyntheticPhoto(
        wale_width=knit.wale_width,
        course_height=knit.course_height,
        minimal_radius=fabric.yarn.minimal_radius,
        angle_deg=args.angle_deg,
        pixels_per_mm=args.pixels_per_mm,
        width_px=args.size[0],
        height_px=args.size[1],
        blur_mm=args.blur_mm,
        noise=args.noise,
        lighting=args.lighting,
        seed=args.seed,
        side=args.side,
    )
    write_image(args.output, render_photo(photo))
    radius = photo.loop().yarn_radius
    print(
        f"wrote {args.output}: {photo.width_px} x {photo.height_px} px at "
        f"{photo.pixels_per_mm:g} px/mm; w = {photo.wale_width:g} mm, c = "
        f"{photo.course_height:g} mm, yarn radius {radius:.4g} mm, angle {photo.angle_deg:g} deg"
    )
    return 0
