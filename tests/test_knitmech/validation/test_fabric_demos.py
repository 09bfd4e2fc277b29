"""Every demo runs serially and under `mpirun -n 2` (small sizes) and pins its key numbers:
the patch forces between the material's uniaxial and strip-biaxial responses, equal on 1 and
2 ranks, and one force per demo pinned (tests/pins.py, DEMOS)."""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from pins import assert_pinned

from knitmech.scene import default_surface_path
from rve_rod.surface import homogeneous_response, read_surface
from rve_rod.units import n_per_mm_to_gf_per_cm

DEMOS = Path(__file__).resolve().parents[3] / "demos"
MPI_ENV = {
    **os.environ,
    "OMPI_ALLOW_RUN_AS_ROOT": "1",
    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1",
    "MPLBACKEND": "Agg",
}


def run_demo(name, arguments, ranks, cwd):
    command = [sys.executable, str(DEMOS / name), *arguments]
    if ranks > 1:
        command = ["mpirun", "-n", str(ranks), *command]
    process = subprocess.run(
        command, check=False, capture_output=True, text=True, env=MPI_ENV, cwd=cwd, timeout=600
    )
    assert process.returncode == 0, process.stderr
    return process.stdout


@pytest.fixture(scope="module")
def patch_tension_runs(tmp_path_factory):
    summaries = {}
    for ranks in (1, 2):
        folder = tmp_path_factory.mktemp(f"patch_tension_{ranks}")
        run_demo("demo_patch_tension.py", ["--elements", "4", "--output", "out"], ranks, folder)
        summaries[ranks] = (folder / "out", json.loads((folder / "out/summary.json").read_text()))
    return summaries


@pytest.mark.slow
@pytest.mark.mpi
@pytest.mark.parametrize("ranks", [1, 2])
def test_demo_patch_tension_writes_figures_and_bounded_forces(patch_tension_runs, ranks):
    output, summary = patch_tension_runs[ranks]
    assert summary["ranks"] == ranks
    for name in ("force_strain.png", "stress_course.png", "stress_wale.png"):
        assert (output / name).stat().st_size > 10_000
    for name in ("course.xdmf", "wale.xdmf", "course.h5", "wale.h5"):
        assert (output / name).is_file()
    strain = np.array(summary["strain"])
    assert strain[-1] == pytest.approx(0.2) and strain.size == 21
    surface = read_surface(default_surface_path())  # the demo's default: cotton from knitmech
    for direction in ("course", "wale"):
        force = np.array(summary[f"{direction}_force_gf_per_cm"])[1:]
        uniaxial = n_per_mm_to_gf_per_cm(homogeneous_response(surface, strain[1:], direction))
        strip = n_per_mm_to_gf_per_cm(
            homogeneous_response(surface, strain[1:], direction, lateral="fixed")
        )
        assert np.all((uniaxial < force) & (force < strip))


@pytest.mark.slow
@pytest.mark.mpi
def test_demo_patch_tension_course_force_at_20_percent_is_pinned(patch_tension_runs):
    summary = patch_tension_runs[1][1]
    assert summary["elements"] == 4 and summary["strain"][-1] == pytest.approx(0.2)
    force = summary["course_force_gf_per_cm"][-1]
    assert_pinned("DEMOS", {"patch tension course force 20 %": force})


@pytest.mark.slow
@pytest.mark.mpi
def test_demo_patch_tension_serial_equals_two_ranks(patch_tension_runs):
    serial, parallel = patch_tension_runs[1][1], patch_tension_runs[2][1]
    for direction in ("course", "wale"):
        key = f"{direction}_force_gf_per_cm"
        np.testing.assert_allclose(parallel[key], serial[key], rtol=1e-8, atol=1e-12)


@pytest.mark.slow
@pytest.mark.mpi
def test_demo_parallel_serial_equals_two_ranks(tmp_path):
    outputs = [run_demo("demo_parallel.py", ["--elements", "12"], n, tmp_path) for n in (1, 2)]
    values = [
        {
            key: re.search(rf"^{key}: (\S+)", text, re.MULTILINE).group(1)
            for key in ("ranks", "dofs")
        }
        | {"force": float(re.search(r"force at 10 %: (\S+) gf/cm", text).group(1))}
        for text in outputs
    ]
    assert [v["ranks"] for v in values] == ["1", "2"]
    assert values[0]["dofs"] == values[1]["dofs"] == str(2 * 13 * 13)
    assert values[1]["force"] == pytest.approx(values[0]["force"], rel=1e-8)
    assert "Newton iterations: " in outputs[1]
    assert_pinned("DEMOS", {"parallel course force 10 %": values[0]["force"]})
