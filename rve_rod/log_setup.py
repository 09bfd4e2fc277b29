"""Logging of the command-line tools: one handler on the root logger, in the tool's format.

Importing DOLFINx (through UFL) calls `logging.basicConfig()`, which puts a plain stderr
handler on the root logger: the tools' own `basicConfig` then did nothing (the `[rank N]`
format of `fabric-dolfinx` never took effect), and FFCx's JIT build, which lowers the root
logger's level, printed its gcc command lines through that handler at default verbosity.
`install_handler` replaces such plain handlers and keeps the others (e.g. pytest's).
"""

import logging

__all__ = [
    "install_handler",
]


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
