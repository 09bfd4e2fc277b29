"""A fault test: a run stopped while FFCx compiles a form, then run again (issue 31).

FFCx marks a module being compiled by its `.c` file in the cache; Ctrl-C or SIGTERM during the
compilation used to leave that file, and every later run waited 10 s and died with
`TimeoutError: JIT compilation timed out` until the user deleted it. Here `fabric-dolfinx
tension` is stopped the moment the first `.c` file appears in a fresh cache (by SIGINT,
SIGTERM, or SIGKILL, which leaves no chance to clean up); the same command then runs to the
end, quietly, without waiting for the timeout (`fabric_dolfinx.jit`).
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from support.foreground import foreground

FABRIC_DOLFINX = str(Path(sys.executable).parent / "fabric-dolfinx")
ARGS = ["tension", "--svk", "10,8,0.3,2", "--elements", "2", "--steps", "2", "--json"]


def stop_while_compiling(cache: Path, signum: int) -> subprocess.CompletedProcess:
    """Start the command in a fresh cache (in the foreground's signal state:
    `support.foreground`), send `signum` once a `.c` file appears in it (to the process
    itself, checked alive just before: `Popen.send_signal` sends nothing to a process that
    has ended)."""
    environment = {**os.environ, "XDG_CACHE_HOME": str(cache)}
    run = subprocess.Popen(
        foreground([FABRIC_DOLFINX, *ARGS]),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env=environment,
    )
    deadline = time.monotonic() + 60.0
    while not list((cache / "fenics").glob("*.c")):
        assert run.poll() is None and time.monotonic() < deadline, "no compilation to stop"
        time.sleep(0.01)
    assert run.poll() is None, "the run ended before the signal could be sent"
    os.kill(run.pid, signum)
    signalled = sorted(p.name for p in (cache / "fenics").iterdir())
    out, err = run.communicate(timeout=60)
    stopped = subprocess.CompletedProcess(run.args, run.returncode, out.decode(), err.decode())
    stopped.signalled = signalled  # the cache when the signal was sent, for a failure's message
    return stopped


@pytest.mark.slow
@pytest.mark.parametrize(
    ("signum", "status", "message"),
    [
        (signal.SIGINT, 130, "fabric-dolfinx tension: interrupted\n"),
        (signal.SIGTERM, 143, "fabric-dolfinx tension: terminated\n"),
        (signal.SIGKILL, -signal.SIGKILL, ""),
    ],
    ids=["SIGINT", "SIGTERM", "SIGKILL"],
)
def test_a_run_stopped_during_compilation_does_not_break_the_next(
    tmp_path, signum, status, message
):
    stopped = stop_while_compiling(tmp_path, signum)
    assert (stopped.returncode, stopped.stderr) == (status, message), (
        f"cache when signalled: {stopped.signalled}; stdout: {stopped.stdout[-500:]!r}; "
        f"stderr: {stopped.stderr[-1000:]!r}"
    )
    started = time.perf_counter()
    rerun = subprocess.run(
        [FABRIC_DOLFINX, *ARGS],
        capture_output=True,
        text=True,
        env={**os.environ, "XDG_CACHE_HOME": str(tmp_path)},
        check=False,
        timeout=300,
    )
    took = time.perf_counter() - started
    assert rerun.returncode == 0, rerun.stderr[-2000:]
    assert rerun.stderr == ""  # no traceback, no compiler lines
    assert '"converged": true' in rerun.stdout
    # every module compiled: a .c with its .c.cached beside it, none waiting
    cache = tmp_path / "fenics"
    sources = {p.name for p in cache.glob("*.c")}
    assert sources and {f"{name}.cached" for name in sources} <= {p.name for p in cache.iterdir()}
    print(f"rerun after {signal.Signals(signum).name}: {took:.1f} s")
