"""gmsh, imported without taking Ctrl-C away from Python: import it from here.

gmsh 4.8's Python module (Debian 12's python3-gmsh) sets SIGINT to the system's default action
when it is imported, and gives the previous handler back only in `gmsh.finalize()`. Between the
import and the first finalize (in `knitmech run`: the whole RVE and surface stages, minutes)
Ctrl-C killed the process on the spot: no KeyboardInterrupt, so no "interrupted" message and
exit status 130, no cleanup of a stage's temporary folder, and a SIGINT to the main process
alone left the RVE executor's worker processes running, orphaned. Importing gmsh here puts the
handler it replaced back (in the main thread, where handlers can be set), so Ctrl-C unwinds
the run as it does in `rve-rod`; a long gmsh call is then interrupted when it returns (gmsh
does not look at Python's signals). `gmsh.finalize()` would set the import's handler again,
replacing the one a tool installed since (`rve_rod.errors.terminate_as_interrupt`, which
remembers a Ctrl-C that Python lost): its `oldsig` is cleared, so finalize leaves the handler as
it is. A gmsh that leaves SIGINT alone (no `oldsig`) is taken as it is.
"""

import signal
import threading

import gmsh

__all__ = [
    "gmsh",
]

_replaced = getattr(gmsh, "oldsig", None)
if (
    _replaced not in (None, signal.SIG_DFL)
    and signal.getsignal(signal.SIGINT) == signal.SIG_DFL
    and threading.current_thread() is threading.main_thread()
):
    signal.signal(signal.SIGINT, _replaced)
    gmsh.oldsig = None  # finalize() then leaves whatever handler is set
