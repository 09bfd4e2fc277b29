"""Logging of the command-line tools: one handler on the root logger, in the tool's format.

Importing DOLFINx (through UFL) calls `logging.basicConfig()`, which puts a plain stderr
handler on the root logger: the tools' own `basicConfig` then did nothing (the `[rank N]`
format of `fabric-dolfinx` never took effect), and FFCx's JIT build, which lowers the root
logger's level, printed its gcc command lines through that handler at default verbosity.
`install_handler` replaces such plain handlers and keeps the others (e.g. pytest's).
`add_common_flags` gives the three tools the same `--version`, `-q` and `-v`, accepted before
and after the subcommand.
"""

import argparse
import logging

__all__ = [
    "add_common_flags",
    "install_handler",
]


def add_common_flags(parser: argparse.ArgumentParser, version: str) -> None:
    """`--version` (prints `version`), `-q/--quiet` (warnings and errors only, no progress)
    and `-v/--verbose` (more log output, -vv more still) on `parser` and on every subcommand's
    parser (call it after adding the subcommands), so that `tool -v run` and `tool run -v`
    both work; `args.quiet` is a bool, `args.verbose` a count (0 when not given)."""
    subcommands = [
        sub
        for action in parser._actions
        if isinstance(action, argparse._SubParsersAction)
        for sub in dict.fromkeys(action.choices.values())
    ]
    for target in (parser, *subcommands):
        top = target is parser  # a subcommand's flag, when not given, keeps the top's value
        target.add_argument("--version", action="version", version=version)
        group = target.add_mutually_exclusive_group()
        group.add_argument(
            "-q",
            "--quiet",
            action="store_true",
            default=False if top else argparse.SUPPRESS,
            help="warnings and errors only, no progress",
        )
        group.add_argument(
            "-v",
            "--verbose",
            action="count",
            default=0 if top else argparse.SUPPRESS,
            help="more log output (-vv: more still)",
        )


def install_handler(handler: logging.Handler, level: int) -> None:
    """Make `handler` the root logger's stream handler and set the root level to `level`.

    Handlers of exactly `logging.StreamHandler` (what `logging.basicConfig` and an earlier
    call install) are removed first; subclasses and other handlers stay. The handler's own
    level is what shows: the JIT's build may lower the root logger's level later.
    """
    root = logging.getLogger()
    for old in list(root.handlers):
        if type(old) is logging.StreamHandler:
            root.removeHandler(old)
    root.addHandler(handler)
    root.setLevel(level)
