"""A fault test: Ctrl-C (SIGINT) to `knitmech run` while the surface stage's RVE runs go.

gmsh 4.8 takes SIGINT from Python when it is imported (`fabric_dolfinx.gmsh_api`): before the
fix, Ctrl-C in the RVE or surface stage killed `knitmech run` on the spot (no message, exit by
the signal), and a SIGINT to the main process alone left the executor's worker running,
orphaned, with the run's pipes open. Now the run unwinds as it does for SIGTERM: exit 130,
one line, no process and no temporary stage folder left behind.

The children start with SIGINT at its default action, as a shell starts a command in the
foreground (`support.foreground`).
"""

import contextlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from support.foreground import foreground
from support.processes import processes_mentioning

KNITMECH = str(Path(sys.executable).parent / "knitmech")


@pytest.mark.parametrize("module", ["knitmech.cli", "fabric_dolfinx.cli"])
def test_importing_a_tool_that_meshes_leaves_ctrl_c_to_python(module):
    code = (
        f"import signal, sys; import {module}; assert 'gmsh' in sys.modules; "
        "print(signal.getsignal(signal.SIGINT) is signal.default_int_handler)"
    )
    found = subprocess.run(
        foreground([sys.executable, "-c", code]), capture_output=True, text=True, check=True
    )
    assert found.stdout.strip() == "True"


def test_gmsh_finalize_keeps_the_handler_a_tool_installed():
    """`gmsh.finalize()` would set the handler of gmsh's import again (Python's), dropping the
    one `terminate_as_interrupt` installed since, which remembers a lost Ctrl-C."""
    code = (
        "import signal; from fabric_dolfinx.gmsh_api import gmsh; "
        "from rve_rod.errors import terminate_as_interrupt; terminate_as_interrupt(); "
        "installed = signal.getsignal(signal.SIGINT); "
        "assert installed is not signal.default_int_handler; "
        "gmsh.initialize(); gmsh.finalize(); "
        "print(signal.getsignal(signal.SIGINT) is installed)"
    )
    found = subprocess.run(
        foreground([sys.executable, "-c", code]), capture_output=True, text=True, check=True
    )
    assert found.stdout.strip() == "True"


@pytest.mark.slow
def test_ctrl_c_in_the_surface_stage_unwinds_the_run_and_its_workers(tmp_path):
    results, cache = tmp_path / "results", tmp_path / "cache"
    command = [KNITMECH, "run", "-o", str(results), "--cache-dir", str(cache), "-q"]
    run = subprocess.Popen(foreground(command), stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 300
        while not list((cache / "rve-runs").rglob("*.*")):  # the surface stage's runs go
            assert run.poll() is None and time.monotonic() < deadline, run.stderr.read()
            time.sleep(0.1)
        assert run.poll() is None, "the run ended before the signal could be sent"
        os.kill(run.pid, signal.SIGINT)  # the main process alone: its workers must follow
        _, stderr = run.communicate(timeout=60)
        assert run.returncode == 130, stderr
        assert "knitmech run: interrupted; run again to resume" in stderr
        assert "Traceback" not in stderr
        gone = time.monotonic() + 10.0  # the executor's worker reads the pool's end
        while processes_mentioning(str(tmp_path)) and time.monotonic() < gone:
            time.sleep(0.1)
        assert processes_mentioning(str(tmp_path)) == {}
        assert list(results.glob(".stage-*")) == []
    finally:
        if run.poll() is None:
            run.kill()
        for pid in processes_mentioning(str(tmp_path)):  # what a failure left behind
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
