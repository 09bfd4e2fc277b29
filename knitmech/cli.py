"""The `knitmech` command: run a scene from the yarn to the fabric patch.

    knitmech run [SCENE.toml] [--fidelity fast|balanced|accurate] [-o results] [--jobs N]
                 [--executor local|mpi] [--cache-dir DIR] [--json] [-q | -v]
    knitmech sweep SWEEP.toml [-o sweep] [--jobs N] [--executor local|mpi] [--cache-dir DIR]
    knitmech init [SCENE.toml] [--force]      # a commented scene to start from
    knitmech design DESIGN.toml [-o design] [--fidelity LEVEL] [--jobs N] [--cache-dir DIR]

Without a scene file it runs the built-in default scene (cotton 20s/2, stitch 5.5, the
paper's 50 mm patch course- and wale-wise). Progress goes to stderr; the summary table (or,
with --json, summary.json) to stdout. Exit status (`rve_rod.errors.cli_exit_status`): 0 done;
1 a stage failed, 130 interrupted (Ctrl-C) and 143 terminated (SIGTERM; the MPI children
are stopped too): run the same command again to resume from what finished; 2 bad input, with
one line per problem of a scene; 3 a solver gave up; 141 stdout closed by its reader.
"""

import argparse
import functools
import json
import logging
import sys

from knitmech.design.run import run_design
from knitmech.design.spec import load_design
from knitmech.fidelity import LEVELS
from knitmech.jobs.launch import StageError
from knitmech.pipeline import run_scene
from knitmech.scene import load_scene, starter_scene_path
from knitmech.sweep import FAILED_EXIT_STATUS, SUMMARY_FILE, load_sweep, run_sweep
from rve_rod import __version__
from rve_rod.cache import default_cache_root
from rve_rod.errors import (
    CommandLineParser,
    InputError,
    cli_exit_status,
    terminate_as_interrupt,
)
from rve_rod.help_format import HelpFormatter
from rve_rod.homogenize.executors import add_executor_argument
from rve_rod.homogenize.generate import GenerationError
from rve_rod.limits import available_cores
from rve_rod.log_setup import add_common_flags, install_handler
from rve_rod.outputs import check_output_file, check_output_folder, ignore_broken_pipe

__all__ = [
    "PROGRAM",
    "build_parser",
    "design_command",
    "init_command",
    "main",
    "run_command",
    "sweep_command",
]

PROGRAM = "knitmech"


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with its subcommands."""
    parser = CommandLineParser(
        prog=PROGRAM,
        description="Knitted-fabric mechanics from yarn to fabric.",
        formatter_class=HelpFormatter,
    )
    subparsers = parser.add_subparsers(
        dest="command",
        required=True,
        metavar="COMMAND",
        parser_class=functools.partial(CommandLineParser, formatter_class=HelpFormatter),
    )
    run = subparsers.add_parser(
        "run",
        help="run a scene: geometry, RVE runs, response surface, fabric patch",
        description="Run every stage of a scene (cached: unchanged stages are reused, an "
        "interrupted run resumes) and write a results folder (docs/pipeline.md).",
    )
    run.add_argument("scene", nargs="?", help="scene file (TOML; default: the built-in scene)")
    run.add_argument(
        "--fidelity",
        choices=tuple(LEVELS),
        help="the level of detail (default: the scene's fidelity key, else balanced)",
    )
    run.add_argument("-o", "--output", default="results", help="results folder")
    _add_compute_options(run)
    run.add_argument(
        "--oversubscribe",
        action="store_true",
        help=f"allow macro.ranks above the cores ({available_cores()})",
    )
    run.add_argument("--json", action="store_true", help="print summary.json instead of a table")
    run.set_defaults(run=run_command)
    _add_sweep(subparsers)
    init = subparsers.add_parser(
        "init",
        help="write a commented scene to start from",
        description="Write a commented scene file (a strip of single jersey clamped at its "
        "bottom and pulled at its top; every key explained) to edit and run.",
    )
    init.add_argument("scene", nargs="?", default="scene.toml", help="file to write")
    init.add_argument("--force", action="store_true", help="replace an existing file")
    init.set_defaults(run=init_command)
    _add_design(subparsers)
    add_common_flags(parser, f"{PROGRAM} {__version__}")
    return parser


def _add_compute_options(parser: argparse.ArgumentParser) -> None:
    """--jobs, --executor and --cache-dir, as `run` and `design` take them."""
    parser.add_argument(
        "--jobs",
        type=int,
        default=available_cores(),
        help=f"worker processes for the RVE runs (default: all cores, {available_cores()})",
    )
    add_executor_argument(parser)
    parser.add_argument(
        "--cache-dir", help=f"stage and RVE-run cache (default {default_cache_root()})"
    )


def _add_design(subparsers) -> None:
    design = subparsers.add_parser(
        "design",
        help="design the knit that meets targets (stitch values per region or course band)",
        description="Search the stitch values (and a sleeve's needles) whose response meets "
        "the targets of a design file's [design] table; write the design, the knitting "
        "instructions and target against achieved into a results folder (docs/design.md).",
    )
    design.add_argument("design", help="design file (TOML: a scene with a [design] table)")
    design.add_argument("--fidelity", choices=tuple(LEVELS), help="override the scene's level")
    design.add_argument("-o", "--output", default="design", help="results folder")
    _add_compute_options(design)
    design.add_argument("--json", action="store_true", help="print design.json instead")
    design.set_defaults(run=design_command)


def _add_sweep(subparsers) -> None:
    sweep = subparsers.add_parser(
        "sweep",
        help="build the response surfaces of many knits from one sweep file",
        description="Run the RVE runs of every knit of a sweep file together (cached, "
        "resumable), fit and write one surface file per knit, print a summary table "
        "(docs/cluster.md).",
    )
    sweep.add_argument("sweep", help="sweep file (TOML)")
    sweep.add_argument("-o", "--output", default="sweep", help="output folder")
    sweep.add_argument(
        "--jobs",
        type=int,
        default=available_cores(),
        help=f"local worker processes (default: all cores, {available_cores()})",
    )
    add_executor_argument(sweep)
    sweep.add_argument("--cache-dir", help=f"RVE-run cache root (default {default_cache_root()})")
    sweep.set_defaults(run=sweep_command)


def _our_progress_or_warnings(record: logging.LogRecord) -> bool:
    """Progress (INFO) of knitmech's stages; warnings and errors of everything."""
    return record.levelno >= logging.WARNING or record.name.startswith(f"{PROGRAM}.")


def _configure_logging(args: argparse.Namespace) -> None:
    # The level sits on the handler: the JIT's distutils build lowers the root logger's.
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s"))
    level = logging.WARNING if args.quiet else logging.DEBUG if args.verbose else logging.INFO
    handler.setLevel(level)
    if not args.verbose:
        handler.addFilter(_our_progress_or_warnings)
        # the RVE's step cutbacks are solver details (-v shows them)
        logging.getLogger("rve_rod.newton").setLevel(logging.ERROR)
    install_handler(handler, level)


def run_command(args: argparse.Namespace) -> int:
    """The `run` subcommand; returns the exit status."""
    _configure_logging(args)
    check_output_folder("--output", args.output)
    if args.cache_dir is not None:
        check_output_folder("--cache-dir", args.cache_dir)
    scene = load_scene(args.scene)
    result = run_scene(
        scene,
        fidelity=args.fidelity,
        output=args.output,
        cache_dir=args.cache_dir,
        jobs=args.jobs,
        executor=args.executor,
        progress=None if args.quiet else sys.stderr,
        oversubscribe=args.oversubscribe,
    )
    ignore_broken_pipe()
    if args.json:
        json.dump(result.summary, sys.stdout, indent=1)
        sys.stdout.write("\n")
    else:
        print(result.table)
        print(f"results in {result.folder}/ (summary.json, figures/, paraview/, surface.h5)")
    part = result.summary.get("part")
    # the fabric solver gave up: the converged steps are written, the status says so
    return 3 if part is not None and not part["complete"] else 0


def sweep_command(args: argparse.Namespace) -> int:
    """The `sweep` subcommand; returns the exit status (3 when runs failed)."""
    _configure_logging(args)
    check_output_folder("--output", args.output)
    if args.cache_dir is not None:
        check_output_folder("--cache-dir", args.cache_dir)
    result = run_sweep(
        load_sweep(args.sweep),
        args.output,
        cache_dir=args.cache_dir,
        executor=args.executor,
        jobs=args.jobs,
        progress=None if args.quiet else sys.stderr,
    )
    ignore_broken_pipe()
    print(result.table)
    print(f"results in {result.folder}/ ({SUMMARY_FILE}, summary.txt, one .h5 per knit)")
    return FAILED_EXIT_STATUS if result.failed else 0


def init_command(args: argparse.Namespace) -> int:
    """The `init` subcommand: the starter scene into `args.scene` (not over a file unless
    --force); returns the exit status."""
    path = check_output_file("scene", args.scene)
    if path.exists() and not args.force:
        raise InputError(f"scene {path}: exists already; give another name or --force")
    path.write_text(starter_scene_path().read_text(encoding="utf-8"), encoding="utf-8")
    print(f"wrote {path}; edit it, then: {PROGRAM} run {path} -o results")
    return 0


def design_command(args: argparse.Namespace) -> int:
    """The `design` subcommand; returns the exit status (0 also when a target is missed: the
    report says by how much, design.json has `met`)."""
    _configure_logging(args)
    check_output_folder("--output", args.output)
    if args.cache_dir is not None:
        check_output_folder("--cache-dir", args.cache_dir)
    scene, design = load_design(args.design)
    result = run_design(
        scene,
        design,
        fidelity=args.fidelity,
        output=args.output,
        cache_dir=args.cache_dir,
        jobs=args.jobs,
        executor=args.executor,
        progress=None if args.quiet else sys.stderr,
    )
    ignore_broken_pipe()
    if args.json:
        json.dump(result.summary, sys.stdout, indent=1)
        sys.stdout.write("\n")
    else:
        print(result.table)
        print(f"results in {result.folder}/ (design.json, design.txt, figures/design.png)")
    return 0


def main(argv: list[str] | None = None) -> int:
    """Entry point of `knitmech`; returns the process exit status."""
    command = ""
    terminate_as_interrupt()
    try:
        args = build_parser().parse_args(argv)
        command = args.command
        return int(args.run(args) or 0)
    except (Exception, KeyboardInterrupt) as error:
        resumable = (GenerationError, StageError)
        return cli_exit_status(f"{PROGRAM} {command}", error, resumable=resumable)


if __name__ == "__main__":
    sys.exit(main())
