"""`rve-rod simulate`: one load case on the knit-loop RVE (strain-force curve, Poisson ratio).

Progress goes to stderr, one line per converged state. A run that cannot reach the end of its
load path still writes its JSON, plot and VTK files for the converged states, then exits with
status 3 (the error line names where it stopped).
"""

import argparse
import sys

from rve_rod import limits
from rve_rod.cli.common import (
    add_bending_argument,
    add_control_points_argument,
    add_fabric_arguments,
    fabric_from_args,
    print_json,
)
from rve_rod.errors import ConvergenceError, check_range
from rve_rod.limits import check_count
from rve_rod.outputs import check_output_file, check_output_folder, figure_formats
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import CASES, load_case
from rve_rod.rve.simulation import (
    RveResult,
    RveSettings,
    RveStep,
    simulate,
)
from rve_rod.rve.yarn import YarnSettings, bending_model, check_bending

__all__ = [
    "register",
    "run_simulate",
]


def register(subparsers) -> None:
    """Add the `simulate` subcommand."""
    parser = subparsers.add_parser(
        "simulate",
        help="run a load case on the knit-loop RVE",
        description="Load one periodic knit cell (the single-jersey loop, or the loops of a "
        "stitch pattern; Cosserat rods, frictional contact with their periodic neighbours) "
        "along a macro load case and report the strain-force curve, lateral strain, Poisson "
        "ratio and bending moments (docs/rve.md).",
    )
    add_fabric_arguments(parser)
    parser.add_argument("--case", choices=list(CASES), default="uniaxial-course", help="load case")
    parser.add_argument(
        "--max-strain",
        type=float,
        default=None,
        help="final engineering strain (ray length for biaxial, g for shear; default 0.2, "
        "shear 0.3; negative: compression)",
    )
    parser.add_argument("--angle", type=float, default=0.0, help="ray angle (deg) of biaxial")
    parser.add_argument("--steps", type=int, default=21, help="output states including zero")
    add_control_points_argument(parser)
    add_bending_argument(parser)
    parser.add_argument(
        "--penetration-limit",
        type=float,
        default=CellSettings().penetration_limit,
        help="largest contact penetration 2r - d accepted, in yarn radii; the "
        "run stops where the yarns would be squeezed further",
    )
    parser.add_argument(
        "--second-moment",
        choices=("solid", "paper"),
        default="solid",
        help="I = pi r^4/4 (solid) or the paper's pi r^4/12",
    )
    parser.add_argument(
        "--natural-curvature",
        type=float,
        default=YarnSettings().natural_curvature,
        help="the share s of its bending set the yarn keeps, in [0, 1]: its stress-free "
        "curvature s times the loop's (1: the loop is stress-free; below 1 the unloaded cell "
        "carries the moment of the curl at rest, docs/patterns.md)",
    )
    parser.add_argument("--frictionless", action="store_true", help="switch friction off")
    parser.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    parser.add_argument("--plot", help="PNG of the strain-force curve")
    parser.add_argument("--vtk", help="folder for the deformed yarns (one .vtu per state)")
    parser.set_defaults(run=run_simulate)


def run_simulate(args: argparse.Namespace) -> int:
    if args.plot is not None:
        check_output_file("--plot", args.plot, figure_formats())
    if args.vtk is not None:
        check_output_folder("--vtk", args.vtk)
    check_count("--control-points", args.control_points, limits.CONTROL_POINTS)
    check_range("--natural-curvature", args.natural_curvature, 0.0, 1.0)
    fabric = fabric_from_args(args)
    strain = args.max_strain
    case = load_case(args.case, strain, args.steps, args.angle)
    limit = args.penetration_limit
    cell = CellSettings(control_points=args.control_points, penetration_limit=limit)
    bending = bending_model(fabric, args.bending, report=True)
    check_bending(fabric, bending)
    settings = RveSettings(
        cell=cell,
        yarn=YarnSettings(
            second_moment=args.second_moment,
            friction=not args.frictionless,
            bending=bending,
            natural_curvature=args.natural_curvature,
        ),
    )
    try:
        result = simulate(fabric, case, settings, on_step=_progress, moments=True)
    except ConvergenceError as error:
        if isinstance(error.history, RveResult):
            _write(error.history, args)
        raise
    _write(result, args)
    return 0


def _progress(step: RveStep) -> None:
    print(
        f"  strain {100 * step.strain:7.3f} %  force {step.force_gf_per_cm:10.4g} gf/cm  "
        f"{step.newton_iterations:3d} iterations  {step.active_contacts:4d} contacts  "
        f"{step.wall_time_s:6.2f} s",
        file=sys.stderr,
        flush=True,
    )


def _write(result: RveResult, args: argparse.Namespace) -> None:
    """The JSON (or the report), plot and VTK files of a (possibly partial) result."""
    written = []
    if args.plot:
        from rve_rod.rve.plot import plot_curve  # noqa: PLC0415 (matplotlib on demand)

        written.append(str(plot_curve(result, args.plot)))
    if args.vtk:
        from rve_rod.vtk import write_vtk  # noqa: PLC0415

        written.extend(str(path) for path in write_vtk(result, args.vtk))
    if args.json:
        payload = result.to_dict()
        payload["files"] = written
        print_json(payload)
        return
    _report(result)
    for path in written:
        print(f"wrote {path}")


def _report(result: RveResult) -> None:
    yarn = result.yarn
    adjusted = f" (adjusted from r0 = {yarn.minimal_radius:.4g})" if yarn.adjusted else ""
    print(
        f"{result.case.name}: yarn radius {yarn.radius:.4g} mm{adjusted}, contact exponent "
        f"{yarn.law.exponent:.3g}, {result.settings.cell.control_points} control points per "
        f"quarter loop ({result.curve.n_control_points} on the periodic curve)"
    )
    print(
        f"  {'strain %':>9}{'force gf/cm':>13}{'force N':>11}{'lateral %':>11}"
        f"{'M11 gf cm/cm':>14}{'M22 gf cm/cm':>14}{'iter':>6}"
    )
    for step in result.steps:
        lateral = "" if step.lateral_strain is None else f"{100 * step.lateral_strain:.3f}"
        moment = step.bending_moment_gf_cm_per_cm
        print(
            f"  {100 * step.strain:9.3f}{step.force_gf_per_cm:13.5g}{step.force_n:11.4g}"
            f"{lateral:>11}{moment[0]:14.4g}{moment[1]:14.4g}{step.newton_iterations:6d}"
        )
    if result.poisson_ratio is not None:
        print(f"  Poisson ratio {result.poisson_ratio:.4g} at the last state")
    print(
        f"  {result.newton_iterations} Newton iterations, {result.wall_time_s:.2f} s"
        + ("" if result.complete else f"; stopped early: {result.message}")
    )
