"""A command as a shell starts it in the foreground: SIGINT at its default action.

A background job of a non-interactive shell (`make test &`, a CI step run that way) inherits
SIGINT ignored, and Python started with SIGINT ignored leaves it ignored: Ctrl-C tests of a
child would then test the shell, not the tool. `foreground(command)` prefixes the command with
a Python trampoline that puts SIGINT back to its default action and execs the command (no
`preexec_fn`, which is unsafe in a process with threads).
"""

import sys

TRAMPOLINE = (
    "import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); "
    "os.execv(sys.argv[1], sys.argv[1:])"
)


def foreground(command: list[str]) -> list[str]:
    """`command` (its first item an executable's path) started with SIGINT at its default."""
    return [sys.executable, "-c", TRAMPOLINE, *command]
