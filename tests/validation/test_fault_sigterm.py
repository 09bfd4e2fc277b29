"""A fault test: SIGTERM to `knitmech run` while its macro stage runs under mpirun.

The run must exit with 143 (128 + SIGTERM) and leave no process (mpirun and its ranks) and no
temporary stage folder behind; the same command then resumes: the geometry stage comes from
the cache and the macro stage is computed. The scene is small (the shipped surface file, one
direction on a 4 x 4 patch, 2 ranks) so that the macro stage is all there is to interrupt.
"""

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from knitmech.scene import default_surface_path

KNITMECH = str(Path(sys.executable).parent / "knitmech")

SCENE = """
name = "sigterm"
fidelity = "fast"
[fabric]
preset = "cotton-20s2"
stitch = 5.5
[meso]
cases = []
[surface]
path = "{surface}"
[macro]
directions = ["course"]
elements = 24
steps = 80
max_strain = 0.2
ranks = 2
"""
"""A macro stage that lasts well beyond the 0.5 s the test waits after mpirun started (with 4 x 4
elements and 4 steps it ended within 2 s on a quiet machine, and the signal came after the
stage was cached)."""


def processes_mentioning(text: str) -> list[str]:
    """Command lines of the running processes that contain `text`."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            command = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode()
        except OSError:
            continue
        if text in command:
            found.append(command)
    return found


def ended_early(run: subprocess.Popen) -> str:
    """Why the run is not where the test waits for it: its status and stderr."""
    if run.poll() is None:
        return "still running past the deadline"
    return f"exit {run.returncode} before SIGTERM: {run.stderr.read()}"


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="needs mpirun")
def test_sigterm_in_the_mpi_macro_stage_leaves_nothing_and_the_rerun_resumes(tmp_path):
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE.format(surface=default_surface_path()))
    results, cache = tmp_path / "results", tmp_path / "cache"
    command = [KNITMECH, "run", str(scene), "-o", str(results), "--cache-dir", str(cache), "-q"]
    run = subprocess.Popen(command, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + 300
        while not list(results.glob(".stage-*/.patch.json")):  # the macro stage has begun
            assert run.poll() is None and time.monotonic() < deadline, ended_early(run)
            time.sleep(0.2)
        while not processes_mentioning(f"{results}/.stage-"):  # mpirun has started
            assert run.poll() is None and time.monotonic() < deadline, ended_early(run)
            time.sleep(0.2)
        time.sleep(0.5)  # the ranks are starting up or solving
        run.send_signal(signal.SIGTERM)
        _, stderr = run.communicate(timeout=60)
    finally:
        if run.poll() is None:
            os.killpg(run.pid, signal.SIGKILL)
    assert run.returncode == 143, stderr
    assert "knitmech run: terminated; run again to resume" in stderr
    assert "Traceback" not in stderr
    assert processes_mentioning(str(tmp_path)) == []
    assert list(results.glob(".stage-*")) == []

    rerun = subprocess.run(command, capture_output=True, text=True, timeout=600, check=False)
    assert rerun.returncode == 0, rerun.stderr
    stages = json.loads((results / "summary.json").read_text())["stages"]
    assert {s["stage"]: s["status"] for s in stages} == {
        "geometry": "cached",
        "surface": "given",
        "macro": "computed",
    }


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="needs mpirun")
def test_the_mpi_macro_stage_runs_from_a_process_that_initialized_mpi(tmp_path):
    """A parent that initialized MPI alone (e.g. imported DOLFINx) leaves Open MPI's job
    variables in the environment; an mpirun that inherits them exits 1 without a word. The
    macro stage must not pass them on (knitmech.stages.MPI_JOB_VARIABLES)."""
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE.format(surface=default_surface_path()).replace("steps = 4", "steps = 1"))
    command = [KNITMECH, "run", str(scene), "-o", str(tmp_path / "results")]
    command += ["--cache-dir", str(tmp_path / "cache"), "-q", "--json"]
    parent = (
        "import subprocess, sys\n"
        "from mpi4py import MPI\n"
        "assert MPI.COMM_WORLD.size == 1\n"
        f"sys.exit(subprocess.run({command!r}, stdout=subprocess.DEVNULL).returncode)\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", parent], capture_output=True, text=True, timeout=600, check=False
    )
    assert run.returncode == 0, run.stderr
    summary = json.loads((tmp_path / "results" / "summary.json").read_text())
    assert summary["macro"]["course"]["ranks"] == 2
