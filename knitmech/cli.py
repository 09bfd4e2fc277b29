"""The `knitmech` command: run a scene from the yarn to the fabric patch.

    knitmech run [SCENE.toml] [--fidelity fast|balanced|accurate] [-o results] [--jobs N]
                 [--executor local|mpi] [--cache-dir DIR] [--json] [-q | -v]
    knitmech sweep SWEEP.toml [-o sweep] [--jobs N] [--executor local|mpi] [--cache-dir DIR]

Without a scene file it runs the built-in default scene (cotton 20s/2, stitch 5.5, the
paper's 50 mm patch course- and wale-wise). Progress goes to stderr; the summary table (or,
with --json, summary.json) to stdout. Exit status: 0 done; 1 interrupted or a stage failed
(run the same command again to resume from what finished); 2 bad input, with one line per
problem of a scene; 3 a solver gave up.
"""

import argparse
import json
import logging
import os
import sys

from knitmech import sweep
from knitmech.fidelity import LEVELS
from knitmech.pipeline import default_cache_dir, run_scene
from knitmech.scene import load_scene
from knitmech.stages import StageError
from rve_rod import __version__
from rve_rod.errors import ConvergenceError, InputError
from rve_rod.homogenize.executors import add_executor_argument
from rve_rod.homogenize.generate import GenerationError

PROGRAM = "knitmech"


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as InputError (one line, exit status 2)."""

    def error(self, message):
        raise InputError(message)


def available_cores() -> int:
    """CPU cores this process may use."""
    return len(os.sched_getaffinity(0))


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with its subcommands."""
    parser = _Parser(prog=PROGRAM, description="Knitted-fabric mechanics from yarn to fabric.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    run = subparsers.add_parser(
        "run",
        help="run a scene: geometry, RVE runs, response surface, fabric patch",
        description="Run every stage of a scene (cached: unchanged stages are reused, an "
        "interrupted run resumes) and write a results folder (docs/pipeline.md).",
    )
    run.add_argument("scene", nargs="?", help="scene file (TOML; default: the built-in scene)")
    run.add_argument("--fidelity", choices=tuple(LEVELS), help="override the scene's level")
    run.add_argument("-o", "--output", default="results", help="results folder (default results)")
    run.add_argument(
        "--jobs",
        type=int,
        default=available_cores(),
        help=f"worker processes for the RVE runs (default: all cores, {available_cores()})",
    )
    add_executor_argument(run)
    run.add_argument("--cache-dir", help=f"stage and RVE-run cache (default {default_cache_dir()})")
    run.add_argument("--json", action="store_true", help="print summary.json instead of a table")
    verbosity = run.add_mutually_exclusive_group()
    verbosity.add_argument("-q", "--quiet", action="store_true", help="warnings only")
    verbosity.add_argument("-v", "--verbose", action="store_true", help="solver details too")
    run.set_defaults(run=run_command)
    sweep.register(subparsers)
    return parser


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
    logging.basicConfig(level=level, handlers=[handler])


def run_command(args: argparse.Namespace) -> int:
    """The `run` subcommand; returns the exit status."""
    _configure_logging(args)
    scene = load_scene(args.scene)
    result = run_scene(
        scene,
        fidelity=args.fidelity,
        output=args.output,
        cache_dir=args.cache_dir,
        jobs=args.jobs,
        executor=args.executor,
        progress=None if args.quiet else sys.stderr,
    )
    if args.json:
        json.dump(result.summary, sys.stdout, indent=1)
        sys.stdout.write("\n")
    else:
        print(result.table)
        print(f"results in {result.folder}/ (summary.json, figures/, paraview/, surface.h5)")
    return 0


def main(argv: list[str] | None = None) -> int:
    """Entry point of `knitmech`; returns the process exit status."""
    command = ""
    try:
        args = build_parser().parse_args(argv)
        command = args.command
        return int(args.run(args) or 0)
    except InputError as error:
        print(f"{PROGRAM} {command}: error: {error}".replace(" :", ":"), file=sys.stderr)
        return 2
    except ConvergenceError as error:
        print(f"{PROGRAM} {command}: not converged: {error}", file=sys.stderr)
        return 3
    except (GenerationError, StageError) as error:
        print(f"{PROGRAM} {command}: stopped: {error}; run again to resume", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"{PROGRAM} {command}: interrupted; run again to resume", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
