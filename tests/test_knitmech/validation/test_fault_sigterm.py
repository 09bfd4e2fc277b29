"""A fault test: SIGTERM to `knitmech run` while a stage runs under mpirun (`knitmech.jobs`):
the macro stage (the patch) and the fabric stage (a part).

The run must exit with 143 (128 + SIGTERM) and leave no process (mpirun and its ranks) and no
temporary stage folder behind; the same command then resumes: the stages that finished come
from the cache and the interrupted one is computed. The scenes are small (the shipped surface
file, or an SVK part, on 2 ranks) so that the MPI stage is all there is to interrupt.
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
from support.processes import processes_mentioning

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
steps = 40
max_strain = 0.2
ranks = 2
"""
"""A macro stage that lasts well beyond the 0.5 s the test waits after mpirun started (with 4 x 4
elements and 4 steps it ended within 2 s on a quiet machine, and the signal came after the
stage was cached)."""


def ended_early(run: subprocess.Popen) -> str:
    """Why the run is not where the test waits for it: its status and stderr."""
    if run.poll() is None:
        return "still running past the deadline"
    return f"exit {run.returncode} before SIGTERM: {run.stderr.read()}"


PART = """
name = "sigterm part"
fidelity = "fast"
[fabric]
preset = "cotton-20s2"
stitch = 5.5
[fabric.shape]
kind = "rectangle"
width = 50.0
height = 50.0
element_size = 1.25
[meso]
cases = []
[[region]]
name = "fabric"
svk = { course_stiffness = 1.0, wale_stiffness = 0.5, poissons_ratio = 0.3 }
[[boundary]]
name = "left"
kind = "clamp"
[[boundary]]
name = "right"
kind = "displacement"
displacement = [10.0, 2.0]
[macro]
steps = 40
ranks = 2
"""
"""A part (an SVK square, 40 x 40 elements, 40 steps, 2 ranks) whose fabric stage lasts well
beyond the moment the test sends the signal."""


def interrupt_and_resume(tmp_path, text: str, request: str) -> dict:
    """Run the scene `text`, SIGTERM it once mpirun runs the job whose request file is
    `request`, check that nothing is left, run it again; returns the stages' statuses."""
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    results, cache = tmp_path / "results", tmp_path / "cache"
    command = [KNITMECH, "run", str(scene), "-o", str(results), "--cache-dir", str(cache), "-q"]
    run = subprocess.Popen(command, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + 300
        while not list(results.glob(f".stage-*/{request}")):  # the MPI stage has begun
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
    assert processes_mentioning(str(tmp_path)) == {}
    assert list(results.glob(".stage-*")) == []

    rerun = subprocess.run(command, capture_output=True, text=True, timeout=600, check=False)
    assert rerun.returncode == 0, rerun.stderr
    stages = json.loads((results / "summary.json").read_text())["stages"]
    return {s["stage"]: s["status"] for s in stages}


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="needs mpirun")
def test_sigterm_in_the_mpi_macro_stage_leaves_nothing_and_the_rerun_resumes(tmp_path):
    statuses = interrupt_and_resume(
        tmp_path, SCENE.format(surface=default_surface_path()), ".patch.json"
    )
    assert statuses == {"geometry": "cached", "surface": "given", "macro": "computed"}


@pytest.mark.mpi
@pytest.mark.skipif(shutil.which("mpirun") is None, reason="needs mpirun")
def test_sigterm_in_the_mpi_fabric_stage_leaves_nothing_and_the_rerun_resumes(tmp_path):
    statuses = interrupt_and_resume(tmp_path, PART, ".fabric.json")
    assert statuses["fabric"] == "computed"
    assert set(statuses.values()) <= {"cached", "computed"}


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="needs mpirun")
def test_the_mpi_macro_stage_runs_from_a_process_that_initialized_mpi(tmp_path):
    """A parent that initialized MPI alone (e.g. imported DOLFINx) leaves Open MPI's job
    variables in the environment; an mpirun that inherits them exits 1 without a word. The
    macro stage must not pass them on (knitmech.jobs.launch.MPI_JOB_VARIABLES)."""
    scene = tmp_path / "scene.toml"
    tiny = SCENE.replace("elements = 24", "elements = 4").replace("steps = 40", "steps = 1")
    assert tiny != SCENE  # the scene above still has the lines this test shrinks
    scene.write_text(tiny.format(surface=default_surface_path()))
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
