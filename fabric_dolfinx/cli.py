"""The `fabric-dolfinx` command: membrane simulations of knitted fabric patches (MPI-ready).

    fabric-dolfinx tension --surface surface.h5 --direction course|wale [--size 50]
        [--elements 10] [--max-strain 0.2] [--steps 20] [--angle DEG] [--json]
        [--xdmf out.xdmf] [--plot curve.png] [--rve-curve rve.json]

Run it under `mpirun -n N` as it is; rank 0 prints. Bad input (`InputError`, including
unusable arguments) prints one line and exits with status 2; a solve that cannot converge
(`ConvergenceError`) prints one line and exits with status 3 after the converged steps were
written (JSON, plot, XDMF); Ctrl-C exits with 130, SIGTERM with 143, a closed stdout
(`| head`) with 141 (`rve_rod.errors.cli_exit_status`). Output paths are checked before the
run (`rve_rod.outputs`).
"""

import argparse
import functools
import json
import logging
import sys

import numpy as np
from mpi4py import MPI

from fabric_dolfinx.io.plot import plot_force_strain
from fabric_dolfinx.io.rve_curve import read_rve_curve
from fabric_dolfinx.material import OrthotropicSVK, surface_material, svk_material
from fabric_dolfinx.part.tension import TensionSetup
from fabric_dolfinx.solve import LINEAR_SOLVERS, SolverOptions
from fabric_dolfinx.spec.tension import DIRECTIONS, TensionTest
from rve_rod import __version__, limits
from rve_rod.errors import (
    CommandLineParser,
    ConvergenceError,
    InputError,
    cli_exit_status,
    terminate_as_interrupt,
)
from rve_rod.help_format import HelpFormatter
from rve_rod.log_setup import add_common_flags, install_handler
from rve_rod.outputs import check_output_file, figure_formats, ignore_broken_pipe
from rve_rod.surface import read_surface

__all__ = [
    "PROGRAM",
    "build_parser",
    "main",
    "run_tension_command",
]

PROGRAM = "fabric-dolfinx"


def _svk(text: str):
    try:
        values = [float(value) for value in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 4:
        raise InputError(f"--svk {text!r} must be four numbers E1,E2,NU12,G12 (N/mm, -, N/mm)")
    return OrthotropicSVK(*values)


def _joined_negative_values(argv: list[str]) -> list[str]:
    """`--svk -1,2,0.3,1` as `--svk=-1,2,0.3,1`: argparse takes a value that starts with "-"
    and is not one number for an option (the material check then names the bad value)."""
    joined, arguments = [], iter(argv)
    for argument in arguments:
        if argument == "--svk":
            value = next(arguments, None)
            joined.append(argument if value is None else f"--svk={value}")
        else:
            joined.append(argument)
    return joined


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with its subcommands."""
    parser = CommandLineParser(
        prog=PROGRAM,
        description="Fabric-scale membrane simulations with DOLFINx.",
        formatter_class=HelpFormatter,
    )
    subparsers = parser.add_subparsers(
        dest="command",
        required=True,
        metavar="COMMAND",
        parser_class=functools.partial(CommandLineParser, formatter_class=HelpFormatter),
    )
    tension = subparsers.add_parser(
        "tension",
        help="uniaxial tension of a square patch between clamps",
        description="Uniaxial tension of a square patch: one edge clamped, the opposite edge "
        "displaced; prints the force per width (gf/cm) against the nominal strain.",
    )
    material = tension.add_mutually_exclusive_group(required=True)
    material.add_argument("--surface", help="response-surface file (HDF5) of the knit")
    material.add_argument(
        "--svk", metavar="E1,E2,NU12,G12", help="orthotropic Saint Venant-Kirchhoff instead"
    )
    tension.add_argument(
        "--direction", choices=tuple(DIRECTIONS), default="course", help="course (x) or wale (y)"
    )
    tension.add_argument("--size", type=float, default=50.0, help="side of the patch (mm)")
    low, high = limits.ELEMENTS
    tension.add_argument(
        "--elements", type=int, default=10, help=f"elements per side, {low} to {high}"
    )
    tension.add_argument("--max-strain", type=float, default=0.2, help="final nominal strain")
    low, high = limits.MACRO_STEPS
    tension.add_argument("--steps", type=int, default=20, help=f"load steps, {low} to {high}")
    tension.add_argument(
        "--angle", type=float, default=0.0, help="course direction against x (degrees)"
    )
    tension.add_argument("--degree", type=int, choices=(1, 2), default=1, help="element degree")
    tension.add_argument(
        "--linear-solver", choices=LINEAR_SOLVERS, default="lu", help="lu (MUMPS), gmres or cg"
    )
    tension.add_argument("--json", action="store_true", help="print one JSON object")
    tension.add_argument("--xdmf", help="write displacement, strain, stress per step")
    tension.add_argument("--plot", help="write the force-strain curve (PNG)")
    tension.add_argument("--rve-curve", help="JSON with strain, force_gf_per_cm to plot beside")
    tension.set_defaults(run=run_tension_command)
    add_common_flags(parser, f"{PROGRAM} {__version__}")
    return parser


def run_tension_command(args: argparse.Namespace) -> int:
    """The `tension` subcommand; returns the exit status."""
    comm = MPI.COMM_WORLD
    if args.xdmf is not None:
        check_output_file("--xdmf", args.xdmf)
    if args.plot is not None:
        check_output_file("--plot", args.plot, figure_formats())
    test = TensionTest(
        direction=args.direction,
        size=args.size,
        elements=args.elements,
        max_strain=args.max_strain,
        angle=args.angle,
        element_degree=args.degree,
    )
    options = SolverOptions(linear_solver=args.linear_solver, steps=args.steps)
    rve = read_rve_curve(args.rve_curve) if args.rve_curve else None
    if args.surface:
        material = surface_material(read_surface(args.surface), name=args.surface)
    else:
        material = svk_material(_svk(args.svk))
    setup = TensionSetup(material, test, options, comm)
    try:
        result = setup.run(xdmf=args.xdmf)
    except ConvergenceError as error:
        _report(args, test, material.name, error.history, converged=False, rve=rve)
        raise
    _report(args, test, material.name, result, converged=True, rve=rve)
    return 0


def _report(args, test, material_name, result, *, converged, rve) -> None:
    """Print (rank 0) and plot the force-strain curve of `result`."""
    comm = MPI.COMM_WORLD
    if comm.rank != 0:
        return
    if args.plot:
        curves = {f"membrane, {test.direction}": (result.strain, result.force_gf_per_cm)}
        plot_force_strain(curves, args.plot, rve=rve)
    ignore_broken_pipe()
    if args.json:
        payload = {
            "direction": test.direction,
            "material": material_name,
            "converged": converged,
            "strain": result.strain.tolist(),
            "force_gf_per_cm": result.force_gf_per_cm.tolist(),
            "force_n_per_mm": result.force_n_per_mm.tolist(),
            "newton_iterations": result.newton_iterations.tolist(),
            "cutbacks": result.cutbacks,
            "outside_domain": result.outside_domain,
            "dofs": result.dofs,
            "ranks": result.ranks,
            "wall_time_s": result.wall_time_s,
        }
        json.dump(payload, sys.stdout, indent=2, allow_nan=False)
        sys.stdout.write("\n")
        return
    print(f"{test.direction}-wise tension of a {test.size:g} mm patch, {material_name}")
    print(f"{'strain (%)':>10} {'force (gf/cm)':>14} {'force (N/mm)':>13} {'Newton':>7}")
    iterations = np.concatenate([[0], result.newton_iterations])
    for strain, gf, n, its in zip(
        result.strain, result.force_gf_per_cm, result.force_n_per_mm, iterations, strict=True
    ):
        print(f"{100 * strain:10.3f} {gf:14.4f} {n:13.6f} {its:7d}")
    print(
        f"dofs {result.dofs}, ranks {result.ranks}, Newton iterations "
        f"{int(result.newton_iterations.sum())}, cutbacks {result.cutbacks}, "
        f"wall time {result.wall_time_s:.3g} s"
        + (", strains left the surface domain" if result.outside_domain else "")
    )


def main(argv: list[str] | None = None) -> int:
    """Entry point of `fabric-dolfinx`; returns the process exit status."""
    rank = MPI.COMM_WORLD.rank
    command = ""
    terminate_as_interrupt()
    try:
        args = build_parser().parse_args(
            _joined_negative_values(sys.argv[1:] if argv is None else argv)
        )
        command = args.command
        # The level sits on the handler: the JIT's distutils build lowers the root logger's.
        handler = logging.StreamHandler()
        quiet = logging.ERROR if args.quiet else logging.WARNING
        handler.setLevel(quiet - 10 * min(args.verbose, 2))
        handler.setFormatter(
            logging.Formatter(f"[rank {rank}] %(levelname)s %(name)s: %(message)s")
        )
        install_handler(handler, handler.level)
        return int(args.run(args) or 0)
    except (Exception, KeyboardInterrupt) as error:
        return cli_exit_status(f"{PROGRAM} {command}", error, quiet=rank != 0)


if __name__ == "__main__":
    sys.exit(main())
