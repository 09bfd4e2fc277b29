"""`rve-rod surface` (generate a response-surface file) and `rve-rod surface-info` (describe one).

`surface` runs the rod RVE along the sampling plan (in parallel on local processes or MPI
ranks, cached, resumable), fits the surface and writes it.
"""

import argparse
import json
import sys

from rve_rod import limits
from rve_rod.cache import ResultCache, default_runs_dir
from rve_rod.cli.common import (
    add_bending_argument,
    add_control_points_argument,
    add_fabric_arguments,
    fabric_from_args,
    print_json,
)
from rve_rod.homogenize.executors import add_executor_argument
from rve_rod.homogenize.fit import FitOptions, FitReport
from rve_rod.homogenize.generate import GenerationError, generate_surface
from rve_rod.homogenize.sampling import SamplingPlan
from rve_rod.limits import available_cores, check_count
from rve_rod.outputs import check_output_file, check_output_folder, figure_formats
from rve_rod.rve.engine import fabric_settings, surface_engine
from rve_rod.rve.yarn import bending_model
from rve_rod.surface import (
    STRESS_GROUPS,
    ResponseSurface,
    read_surface,
    tangent_asymmetry,
    write_surface,
)

__all__ = [
    "describe",
    "print_checks",
    "print_report",
    "register",
    "run_info",
    "run_surface",
]


def register(subparsers) -> None:
    """Add the `surface` and `surface-info` subcommands."""
    parser = subparsers.add_parser(
        "surface",
        help="generate a response-surface file from RVE runs",
        description="Run the RVE along biaxial rays and pure shear, fit B-spline response "
        "surfaces and write them as an HDF5 surface file (docs/surfaces.md).",
    )
    add_fabric_arguments(parser)
    parser.add_argument("-o", "--output", required=True, help="surface file to write (.h5)")
    defaults = SamplingPlan()
    parser.add_argument(
        "--rays",
        type=int,
        default=defaults.rays,
        help=f"biaxial rays over the full circle, {limits.RAYS[0]} to {limits.RAYS[1]}",
    )
    parser.add_argument(
        "--steps", type=int, default=defaults.steps_per_ray, help="output steps per ray"
    )
    parser.add_argument(
        "--shear-steps", type=int, default=defaults.shear_steps, help="output steps of the shear"
    )
    parser.add_argument(
        "--max-strain",
        type=float,
        default=defaults.max_tension,
        help="largest tensile strain of a ray component (the sampled domain's upper end)",
    )
    add_control_points_argument(parser)
    add_bending_argument(parser)
    parser.add_argument(
        "--spans",
        type=int,
        help="knot spans per input of the S11, S22 fit (default: from the samples)",
    )
    parser.add_argument(
        "--shear-spans", type=int, help="knot spans of the S12 fit (default: from the samples)"
    )
    add_executor_argument(parser)
    parser.add_argument(
        "--jobs",
        type=int,
        default=available_cores(),
        help=f"local worker processes (default: all cores, {available_cores()}; not for mpi)",
    )
    parser.add_argument(
        "--energy", action="store_true", help="write the energy fit (symmetric tangent)"
    )
    parser.add_argument("--plot", help="PNG of S11, S22 and S12 with their samples")
    parser.add_argument(
        "--cache-dir",
        default=None,
        help=f"where RVE runs are cached (default {default_runs_dir()})",
    )
    parser.set_defaults(run=run_surface)

    info = subparsers.add_parser(
        "surface-info",
        help="describe a response-surface file",
        description="Print the parameters, domain, fit residuals and provenance of a surface file.",
    )
    info.add_argument("surface", help="surface file (.h5)")
    info.add_argument("--json", action="store_true", help="print one JSON object")
    info.set_defaults(run=run_info)


def run_surface(args: argparse.Namespace) -> int:
    output = check_output_file("--output", args.output)
    if args.plot is not None:
        check_output_file("--plot", args.plot, figure_formats())
    cache_dir = check_output_folder("--cache-dir", args.cache_dir) if args.cache_dir else None
    check_count("--rays", args.rays, limits.RAYS)
    check_count("--control-points", args.control_points, limits.CONTROL_POINTS)
    fabric = fabric_from_args(args)
    plan = SamplingPlan(
        rays=args.rays,
        steps_per_ray=args.steps,
        shear_steps=args.shear_steps,
        max_tension=args.max_strain,
        max_compression=None,  # follows the fabric's contraction (the scenes' default)
    )
    fit = FitOptions(spans=args.spans, shear_spans=args.shear_spans)
    engine = surface_engine(fabric_settings(fabric, args.control_points, args.bending))
    bending_model(fabric, args.bending, report=True)  # warns of a fallback
    cache = ResultCache(cache_dir or default_runs_dir())
    try:
        generated = generate_surface(
            fabric,
            engine,
            plan,
            fit,
            kind="energy" if args.energy else "stress",
            cache=cache,
            executor=args.executor,
            jobs=args.jobs,
            progress=None if args.quiet else sys.stderr,
        )
    except GenerationError as error:
        print(f"rve-rod surface: stopped: {error}", file=sys.stderr)
        return 1
    write_surface(output, generated.surface)
    runs = generated.runs
    print(
        f"{runs.computed + runs.cached} RVE runs ({runs.computed} computed, {runs.cached} "
        f"cached) in {runs.wall_time_s:.1f} s"
    )
    for report in generated.reports.values():
        written = " (written)" if report.kind == generated.surface.kind else ""
        print_report(report, f"{report.kind} fit{written}")
    print(f"wrote {output} (kind {generated.surface.kind})")
    print_checks(generated.surface)
    if args.plot:
        from rve_rod.homogenize.plot import plot_surface  # noqa: PLC0415 (matplotlib on demand)

        print(f"wrote {plot_surface(generated.surface, args.plot)}")
    return 0


def print_checks(surface: ResponseSurface) -> None:
    """The surface's acceptance checks (`rve_rod.homogenize.acceptance`), one line each."""
    checks = surface.parameters.get("checks")
    if checks is None:
        print("checks: not recorded (a file from before the checks)")
        return
    print("checks: sign, monotonicity, coverage passed" if not checks else "checks FAILED:")
    for problem in checks:
        print(f"  {problem}")


def print_report(report: FitReport, title: str) -> None:
    """Residual table and tangent asymmetry of one fit."""
    print(f"{title}: tangent asymmetry {report.tangent_asymmetry:.2e}")
    print(f"  {'group':<6}{'max abs':>11}{'rms abs':>11}{'max rel':>11}{'rms rel':>11}  N/mm, -")
    for name, stats in report.residuals.items():
        print(
            f"  {name:<6}{stats.max_abs:>11.3e}{stats.rms_abs:>11.3e}"
            f"{stats.max_rel:>11.3e}{stats.rms_rel:>11.3e}"
        )


def describe(surface: ResponseSurface) -> dict:
    """Everything `surface-info` reports, as a JSON-ready dict."""
    groups = {}
    for name, spline in surface.groups().items():
        degrees = [spline.degree] if hasattr(spline, "degree") else list(spline.degrees)
        entry = {"degree": degrees, "coefficients": list(spline.coefficients.shape)}
        if name in STRESS_GROUPS:
            samples = surface.samples.get(name)
            entry["samples"] = 0 if samples is None else int(samples.values.size)
            entry["residuals"] = surface.residual_stats()[name]._asdict()
        groups[name] = entry
    domain = surface.domain
    return {
        "kind": surface.kind,
        "created": surface.created,
        "generator": dict(surface.generator),
        "domain": {label: domain[a].tolist() for a, label in enumerate(("E11", "E22", "E12"))},
        "groups": groups,
        "tangent_asymmetry": tangent_asymmetry(surface),
        "parameters": dict(surface.parameters),
    }


def run_info(args: argparse.Namespace) -> int:
    surface = read_surface(args.surface)
    info = describe(surface)
    if args.json:
        print_json({"file": args.surface, **info})
        return 0
    generator = info["generator"]
    print(f"{args.surface}: response surface, kind {surface.kind}")
    print(
        f"created {info['created']} by {generator.get('package')} {generator.get('version')} "
        f"(git {generator.get('git_revision') or 'unknown'})"
    )
    print("domain: " + ", ".join(f"{k} [{a:.4g}, {b:.4g}]" for k, (a, b) in info["domain"].items()))
    for name, entry in info["groups"].items():
        print(f"{name}: degree {entry['degree']}, coefficients {entry['coefficients']}", end="")
        print(f", {entry['samples']} samples" if "samples" in entry else "")
    report = FitReport(surface.kind, surface.residual_stats(), info["tangent_asymmetry"])
    print_report(report, "fit residuals (relative to the largest |sample| of each group)")
    print_checks(surface)
    print("parameters:")
    print(json.dumps(info["parameters"], indent=2, sort_keys=True))
    return 0
