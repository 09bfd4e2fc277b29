"""FFCx's just-in-time compilation made safe to interrupt, and quiet.

FFCx 0.5 (DOLFINx 0.5.2) marks a module being compiled by creating its `.c` file in the cache
(`$XDG_CACHE_HOME/fenics`) and a finished one by its `.c.cached` file; a process that finds
the `.c` without the `.c.cached` waits for it (10 s) and then fails with `TimeoutError: JIT
compilation timed out`. FFCx removes the `.c` only when the compilation raises an
`Exception`: Ctrl-C or SIGTERM during a compilation (KeyboardInterrupt, `Terminated`) left it,
and every later run waited 10 s and failed until the user deleted it by hand.

`install` (run when this module is imported: every module of the package that makes meshes
or forms imports it) wraps FFCx's compile functions so that

- a process compiling a module holds an exclusive `flock` on `<module>.lock` in the cache
  from before it creates the `.c` file until the compilation has ended (the kernel releases
  it when the process dies, whatever kills it); a process that wants the module waits for
  that lock instead of polling for 10 s (so concurrent runs no longer time out either), then
  loads the finished module, or, when there is none, takes a `.c` left behind as the relic of
  a compilation that died and compiles the module itself;
- an interrupted compilation moves its `.c` aside (`.c.failed`) as FFCx does for errors, and
  a Ctrl-C or SIGTERM that Python lost during the build (raised inside a finalizer of the C
  build's objects, whose exceptions Python prints and ignores: "Exception ignored in ...")
  stops the run as soon as the compilation has ended (`rve_rod.errors.
  raise_pending_interrupt`), instead of being lost;
- the build's compiler command lines (distutils logs them on the root logger at INFO while
  it lowers the root logger's level) are kept out of the user's logs: one DEBUG line per
  compiled module on this module's logger instead.

A process that compiles with FFCx without this module (a plain DOLFINx script) takes no lock;
a knitmech process compiling the same module at the very same time may then take its `.c` for
a relic and compile the module too (both write the same files; the one that finishes second
fails as FFCx fails on any clash).
"""

import fcntl
import functools
import logging
import os
import time
from pathlib import Path

import ffcx.codegeneration.jit as ffcx_jit

from rve_rod.errors import raise_pending_interrupt

__all__ = [
    "COMPILE_FUNCTIONS",
    "install",
]

logger = logging.getLogger(__name__)

COMPILE_FUNCTIONS = ("compile_forms", "compile_elements", "compile_expressions")
"""The compile functions of `ffcx.codegeneration.jit` that DOLFINx calls (by module attribute,
so wrapping them there wraps DOLFINx's calls)."""

_WRAPPED = "_knitmech_guarded"


class _Compilation:
    """The lock and `.c` file of the module this process is compiling (at most one at a time:
    a compilation does not start another)."""

    lock: int | None = None
    source: Path | None = None


def _locked_lookup(lookup):
    """FFCx's `get_cached_module` behind the module's lock (see the module docstring)."""

    @functools.wraps(lookup)
    def locked(module_name, object_names, cache_dir, timeout):
        cache_dir = Path(cache_dir)
        cache_dir.mkdir(parents=True, exist_ok=True)
        source = cache_dir / f"{module_name}.c"
        lock = os.open(cache_dir / f"{module_name}.lock", os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(lock, fcntl.LOCK_EX)  # waits while another process compiles it
            if not source.with_suffix(".c.cached").exists() and source.exists():
                logger.info("removing %s, left by a compilation that was stopped", source)
                os.replace(source, source.with_suffix(".c.failed"))
            found = lookup(module_name, object_names, cache_dir, timeout)
        except BaseException:
            os.close(lock)
            raise
        if found[0] is not None:  # loaded from the cache
            os.close(lock)
        else:  # this process compiles it, holding the lock until `guarded` ends
            _Compilation.lock, _Compilation.source = lock, source
        return found

    return locked


def _guarded(compile_function):
    """An FFCx compile function that releases the module's lock when it ends, moves the `.c`
    file aside when it is interrupted and keeps the build's log lines out of the user's."""

    @functools.wraps(compile_function)
    def guarded(*args, **kwargs):
        started = time.perf_counter()
        root = logging.getLogger()
        root.addFilter(_not_the_build)
        try:
            compiled = compile_function(*args, **kwargs)
        except BaseException as error:
            source = _Compilation.source
            if not isinstance(error, Exception) and source is not None and source.exists():
                os.replace(source, source.with_suffix(".c.failed"))  # FFCx does it for errors
            raise
        finally:
            root.removeFilter(_not_the_build)
            if _Compilation.lock is not None:
                logger.debug(
                    "compiled %s in %.2f s", _Compilation.source.stem, time.perf_counter() - started
                )
                os.close(_Compilation.lock)
                _Compilation.lock = _Compilation.source = None
        raise_pending_interrupt()  # a Ctrl-C the build's finalizers swallowed: stop here
        return compiled

    setattr(guarded, _WRAPPED, True)
    return guarded


def _not_the_build(record: logging.LogRecord) -> bool:
    """False for the log records of the C build (distutils logs them on the root logger)."""
    return not (record.name == "root" and "distutils" in record.pathname)


def install() -> None:
    """Wrap FFCx's compile functions (idempotent; see the module docstring)."""
    if getattr(ffcx_jit.compile_forms, _WRAPPED, False):
        return
    ffcx_jit.get_cached_module = _locked_lookup(ffcx_jit.get_cached_module)
    for name in COMPILE_FUNCTIONS:
        setattr(ffcx_jit, name, _guarded(getattr(ffcx_jit, name)))


install()
