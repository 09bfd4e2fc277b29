"""The same tension run on 1 and 2 MPI ranks gives the same reaction forces (1e-8 relative)."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from support.surface_cases import synthetic_surface

from rve_rod.surface import write_surface

MPI_ENV = {
    **os.environ,
    "OMPI_ALLOW_RUN_AS_ROOT": "1",
    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1",
}


def tension_json(surface, ranks):
    command = [sys.executable, "-m", "fabric_dolfinx.cli", "tension", "--surface", str(surface)]
    command += ["--elements", "12", "--steps", "5", "--angle", "30", "--direction", "wale"]
    command += ["--max-strain", "0.3", "--json"]
    if ranks > 1:
        command = ["mpirun", "-n", str(ranks), *command]
    process = subprocess.run(
        command, check=False, capture_output=True, text=True, env=MPI_ENV, timeout=300
    )
    assert process.returncode == 0, process.stderr
    return json.loads(process.stdout)


@pytest.mark.mpi
@pytest.mark.slow
def test_one_and_two_ranks_give_equal_reactions(tmp_path):
    surface = write_surface(tmp_path / "surface.h5", synthetic_surface())
    serial, parallel = tension_json(surface, 1), tension_json(surface, 2)
    assert (serial["ranks"], parallel["ranks"]) == (1, 2)
    assert serial["dofs"] == parallel["dofs"] == 2 * 13 * 13
    assert serial["outside_domain"] and parallel["outside_domain"]
    np.testing.assert_allclose(parallel["strain"], serial["strain"], rtol=0, atol=0)
    np.testing.assert_allclose(
        parallel["force_n_per_mm"], serial["force_n_per_mm"], rtol=1e-8, atol=0
    )
    assert serial["force_n_per_mm"][-1] > 0.05
