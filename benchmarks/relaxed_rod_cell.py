"""The rod cell relaxed as a naturally straight yarn: the relaxed jersey cell by mechanics,
against the one found among the templates (issue 28, docs/patterns.md "The relaxed cell").

The cotton 20s/2 jersey cell at stitch 5.5 (its measured w, c; with --start relaxed the
geometric relaxed cell's, `rve_rod.geometry.relaxed.settled_fabric`, whose yarn per loop is the
measured loop length and whose yarn radius r = min(r0, w/8) is that cell's own) with the rods'
natural curvature taken from the loop's (scale 1, the model as it is) down to a straight yarn (0),
frictionless, the macro F11, F22 free (zero macro stress; with --shear F12 too;
`rve_rod.rve.relaxation`): a table of the natural curvature's scale, F11, F22 (F12), w, c and
the largest penetration, until the penetration limit (one radius) stops the path.

    .venv/bin/python benchmarks/relaxed_rod_cell.py [--control-points 132] [--shear]
        [--stitch 5.5] [--start measured|relaxed]

The bent yarn's rest state resolves slowly: at 20 and 36 control points the cell collapses in
width, from 68 on it opens to the relaxed jersey cell (docs/patterns.md, "The relaxed cell").
About 20 s at 100 control points, 90 s at 132, 4 min at 200 on the shared machine.
"""

import argparse

from rve_rod.errors import ConvergenceError
from rve_rod.geometry.relaxed import settled_fabric
from rve_rod.presets import load_preset
from rve_rod.rve.relaxation import relax_cell


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--control-points", type=int, default=132)
    parser.add_argument("--shear", action="store_true", help="F12 free as well")
    parser.add_argument("--stitch", type=float, default=5.5)
    parser.add_argument(
        "--start",
        choices=("measured", "relaxed"),
        default="measured",
        help="start from the measured w, c or from the geometric relaxed cell",
    )
    args = parser.parse_args()
    fabric = settled_fabric(
        load_preset("cotton-20s2", args.stitch), relaxed=args.start == "relaxed"
    )
    try:
        states, stopped = relax_cell(fabric, args.control_points, shear=args.shear), ""
    except ConvergenceError as error:
        states, stopped = error.history, str(error)
    print("| natural curvature | F11 | F22 | F12 | w (mm) | c (mm) | penetration / r |")
    print("|---|---|---|---|---|---|---|")
    for state in states:
        F = state.deformation
        print(
            f"| {state.natural_curvature:.2f} | {F[0, 0]:.4f} | {F[1, 1]:.4f} | {F[0, 1]:.4f} "
            f"| {state.wale_width:.4f} | {state.course_height:.4f} | {state.penetration:.3f} |"
        )
    if stopped:
        print(f"\nstopped: {stopped}")


if __name__ == "__main__":
    main()
