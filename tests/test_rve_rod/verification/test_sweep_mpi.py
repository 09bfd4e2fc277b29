"""The mpi executor (`mpirun -n 2 python -m mpi4py.futures`) gives what the local one gives:
the same surface file coefficients and cache keys; a run raising on a worker rank loses no
other run."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from rve_rod.surface import read_surface

TESTS = Path(__file__).resolve().parents[2]
MPI_ENV = {
    **os.environ,
    "OMPI_ALLOW_RUN_AS_ROOT": "1",
    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1",
    # the worker ranks unpickle the test engines of tests/support/failing_engines.py
    "PYTHONPATH": os.pathsep.join(filter(None, [str(TESTS), os.environ.get("PYTHONPATH")])),
}
MPI_FUTURES = ["mpirun", "-n", "2", sys.executable, "-m", "mpi4py.futures"]
SWEEP = """
name = "tiny"
fidelity = "fast"
[surface]
rays = 16
[grid]
preset = "cotton-20s2"
stitch = [5.5]
"""
SCENE = """
fidelity = "fast"
[fabric]
preset = "cotton-20s2"
stitch = 5.5
[meso]
cases = []
[surface]
rays = 16
[macro]
elements = 3
steps = 3
directions = ["course"]
"""


def run(command, **kwargs):
    return subprocess.run(
        command, check=False, capture_output=True, text=True, env=MPI_ENV, timeout=300, **kwargs
    )


@pytest.mark.mpi
def test_mpi_sweep_writes_the_surface_of_the_local_sweep(tmp_path):
    (tmp_path / "tiny.toml").write_text(SWEEP)
    surfaces, keys = {}, {}
    for executor, launch in (("local", [sys.executable]), ("mpi", MPI_FUTURES)):
        command = [*launch, "-m", "knitmech", "sweep", "tiny.toml", "-o", executor, "-q"]
        command += ["--executor", executor, "--jobs", "1", "--cache-dir", f"cache-{executor}"]
        process = run(command, cwd=tmp_path)
        assert process.returncode == 0, process.stderr
        assert f", {executor}, 1 " in process.stdout  # "local, 1 job" / "mpi, 1 worker rank"
        surfaces[executor] = read_surface(tmp_path / executor / "cotton-20s2_stitch-5.5.h5")
        keys[executor] = sorted(p.name for p in (tmp_path / f"cache-{executor}").rglob("*.npz"))
    # 16 rays and the shear run, and the 2 uniaxial runs the sampled box follows
    assert len(keys["local"]) == 19 and keys["mpi"] == keys["local"]
    local, mpi = surfaces["local"].groups(), surfaces["mpi"].groups()
    assert set(local) == set(mpi)
    for name, spline in local.items():
        np.testing.assert_allclose(mpi[name].coefficients, spline.coefficients, rtol=1e-12)


@pytest.mark.mpi
def test_knitmech_run_under_mpi_makes_the_surface_of_the_sweep(tmp_path):
    # the patch runs on rank 0 alone while the other ranks serve RVE runs (no collective
    # call on COMM_WORLD, PETSc's initialization included: it used to hang here)
    (tmp_path / "scene.toml").write_text(SCENE)
    (tmp_path / "tiny.toml").write_text(SWEEP)
    command = [*MPI_FUTURES, "-m", "knitmech", "run", "scene.toml", "--executor", "mpi", "-q"]
    process = run([*command, "-o", "results", "--cache-dir", "cache-run"], cwd=tmp_path)
    assert process.returncode == 0, process.stderr
    summary = json.loads((tmp_path / "results" / "summary.json").read_text())
    assert summary["surface"]["runs_computed"] == 17 and summary["macro"]["course"]["complete"]
    command = [sys.executable, "-m", "knitmech", "sweep", "tiny.toml", "-o", "sweep", "-q"]
    process = run([*command, "--jobs", "2", "--cache-dir", "cache-sweep"], cwd=tmp_path)
    assert process.returncode == 0, process.stderr
    scene = read_surface(tmp_path / "results" / "surface.h5").groups()
    sweep = read_surface(tmp_path / "sweep" / "cotton-20s2_stitch-5.5.h5").groups()
    for name, spline in sweep.items():
        np.testing.assert_allclose(scene[name].coefficients, spline.coefficients, rtol=1e-12)


@pytest.mark.mpi
def test_a_run_raising_on_a_worker_rank_loses_no_other_run(tmp_path):
    # a script, not -c: the worker ranks import the driver's main module (as __mp_main__)
    driver = tmp_path / "driver.py"
    driver.write_text(
        textwrap.dedent(
            """
            import json, sys
            from support.failing_engines import FailingRve
            from knitmech.sweep import sweep_from_dict, run_sweep

            if __name__ == "__main__":
                grid = {"preset": "cotton-20s2", "stitch": [4.5, 7.0]}
                sweep = sweep_from_dict({"fidelity": "fast", "surface": {"rays": 16}, "grid": grid})
                wale = sweep.knits[1].scene.fabric_model().knit.wale_width
                result = run_sweep(sweep, sys.argv[1], cache_dir=sys.argv[2], executor="mpi",
                                   engine=lambda plan: FailingRve(wale_width=wale))
                print(json.dumps([[k.label, k.computed, [f.reason for f in k.failures],
                                   k.surface_file is not None] for k in result.knits]))
            """
        )
    )
    process = run([*MPI_FUTURES, str(driver), str(tmp_path / "out"), str(tmp_path / "cache")])
    assert process.returncode == 0, process.stderr
    good, bad = json.loads(process.stdout.splitlines()[-1])
    assert good == ["cotton-20s2_stitch-4.5", 17, [], True]
    assert bad == ["cotton-20s2_stitch-7.0", 16, ["RuntimeError: simulated crash"], False]
    assert len(list((tmp_path / "cache").rglob("*.npz"))) == 33 + 4  # and 2 uniaxial each
