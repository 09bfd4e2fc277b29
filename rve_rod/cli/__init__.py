"""The `rve-rod` command: one module per subcommand, each with `register(subparsers)`.

Every subcommand module adds its parser and sets `run=callable(args) -> int`. Bad input
(`InputError`, including unusable arguments) prints one line and exits with status 2; a
solver that cannot converge (`ConvergenceError`) prints one line and exits with status 3
after the subcommand has saved what converged; Ctrl-C exits with 130 and SIGTERM with 143;
a reader that closes stdout (`| head`) ends it quietly with 141
(`rve_rod.errors.cli_exit_status`). Output paths are checked before anything is computed
(`rve_rod.outputs`).
"""

import argparse
import functools
import logging
import sys

from rve_rod import __version__
from rve_rod.errors import CommandLineParser, cli_exit_status, terminate_as_interrupt
from rve_rod.help_format import HelpFormatter
from rve_rod.log_setup import add_common_flags, install_handler

__all__ = [
    "SUBCOMMANDS",
    "build_parser",
    "main",
]

SUBCOMMANDS: tuple[str, ...] = ("geometry", "simulate", "surface", "measure", "synth_photo")
"""Names of the subcommand modules in this package, in the order `--help` lists them."""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with all subcommands registered."""
    parser = CommandLineParser(
        prog="rve-rod",
        description="Yarn-level model of single-jersey knits: loop geometry, Cosserat-rod RVE, "
        "response surfaces.",
    )
    subparsers = parser.add_subparsers(
        dest="command",
        required=True,
        metavar="COMMAND",
        parser_class=functools.partial(CommandLineParser, formatter_class=HelpFormatter),
    )
    for name in SUBCOMMANDS:
        module = __import__(f"rve_rod.cli.{name}", fromlist=["register"])
        module.register(subparsers)
    add_common_flags(parser, f"rve-rod {__version__}")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of `rve-rod`; returns the process exit status."""
    terminate_as_interrupt()
    command = ""
    try:
        args = build_parser().parse_args(argv)
        command = args.command
        handler = logging.StreamHandler()
        quiet = logging.ERROR if args.quiet else logging.WARNING
        handler.setLevel(quiet - 10 * min(args.verbose, 2))
        handler.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s"))
        install_handler(handler, handler.level)
        return int(args.run(args) or 0)
    except (Exception, KeyboardInterrupt) as error:
        return cli_exit_status(f"rve-rod {command}", error)


if __name__ == "__main__":
    sys.exit(main())
