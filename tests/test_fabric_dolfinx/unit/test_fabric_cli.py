"""The fabric-dolfinx command: output of a run, one-line errors with exit status 2 for bad
input, exit status 3 with the converged part kept when the solver gives up."""

import json
import subprocess
import sys

import numpy as np
import pytest
from support.surface_cases import synthetic_surface

from fabric_dolfinx.cli import main
from fabric_dolfinx.part.problem import PartProblem
from rve_rod.surface import write_surface
from rve_rod.units import GF_PER_CM_PER_N_PER_MM


@pytest.fixture(scope="module")
def surface_file(tmp_path_factory):
    return str(
        write_surface(tmp_path_factory.mktemp("surface") / "surface.h5", synthetic_surface())
    )


def test_tension_json_plot_and_xdmf(surface_file, tmp_path, capsys):
    rve = tmp_path / "rve.json"
    rve.write_text(json.dumps({"strain": [0, 0.1, 0.2], "force_gf_per_cm": [0, 20, 90]}))
    plot, xdmf = tmp_path / "curve.png", tmp_path / "out.xdmf"
    argv = ["tension", "--surface", surface_file, "--direction", "wale", "--steps", "4"]
    argv += ["--json", "--plot", str(plot), "--rve-curve", str(rve), "--xdmf", str(xdmf)]
    assert main(argv) == 0
    payload = json.loads(capsys.readouterr().out)
    for key in ("strain", "force_gf_per_cm", "newton_iterations", "dofs", "ranks", "wall_time_s"):
        assert key in payload
    np.testing.assert_allclose(payload["strain"], [0.0, 0.05, 0.1, 0.15, 0.2])
    np.testing.assert_allclose(
        payload["force_gf_per_cm"],
        np.array(payload["force_n_per_mm"]) * GF_PER_CM_PER_N_PER_MM,
        rtol=1e-14,
    )
    assert payload["dofs"] == 2 * 11 * 11 and payload["ranks"] == 1
    assert len(payload["newton_iterations"]) == 4 and payload["converged"] is True
    assert plot.stat().st_size > 10_000 and xdmf.with_suffix(".h5").is_file()


@pytest.fixture
def corrupt_file(tmp_path):
    path = tmp_path / "corrupt.h5"
    path.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(range(200)))
    return str(path)


BAD_ARGUMENTS = {
    "missing surface": (["--surface", "nowhere.h5"], "nowhere.h5: no such file"),
    "corrupt surface": (["--surface", "CORRUPT"], "truncated or corrupt file"),
    "unknown direction": (
        ["--direction", "bias"],
        "argument --direction: invalid choice: 'bias' (choose from 'course', 'wale')",
    ),
    "negative size": (["--size", "-50"], "size=-50 mm must be > 0"),
    "negative elements": (["--elements", "-3"], "elements=-3 is outside the valid range"),
    "non-numeric": (["--max-strain", "lots"], "argument --max-strain: invalid float value"),
    "bad svk": (["--svk", "1,2"], "--svk '1,2' must be four numbers"),
    "unknown solver": (
        ["--linear-solver", "jacobi"],
        "argument --linear-solver: invalid choice: 'jacobi' (choose from 'lu', 'gmres', 'cg')",
    ),
}


@pytest.mark.parametrize("case", BAD_ARGUMENTS)
def test_bad_input_is_one_line_and_exit_status_2(surface_file, corrupt_file, capsys, case):
    extra, message = BAD_ARGUMENTS[case]
    extra = [corrupt_file if value == "CORRUPT" else value for value in extra]
    argv = ["tension"] + (
        [] if {"--surface", "--svk"} & set(extra) else ["--surface", surface_file]
    )
    assert main(argv + extra) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], captured.err


def test_installed_command_exits_2_without_traceback(tmp_path):
    command = [sys.executable, "-m", "fabric_dolfinx.cli", "tension", "--surface", "none.h5"]
    process = subprocess.run(
        command, check=False, capture_output=True, text=True, cwd=tmp_path, timeout=120
    )
    assert process.returncode == 2
    assert process.stderr.strip() == "fabric-dolfinx tension: error: none.h5: no such file"


def test_convergence_failure_exits_3_and_keeps_the_converged_steps(
    surface_file, capsys, monkeypatch
):
    apply_load = PartProblem.set_load_factor
    monkeypatch.setattr(
        PartProblem, "set_load_factor", lambda self, t: apply_load(self, t if t <= 0.5 else np.nan)
    )
    argv = ["tension", "--surface", surface_file, "--steps", "4", "--json"]
    assert main(argv) == 3
    captured = capsys.readouterr()
    payload = json.loads(captured.out)
    assert payload["converged"] is False
    np.testing.assert_allclose(payload["strain"], [0.0, 0.05, 0.1])
    assert "not converged: Newton failed at load factor" in captured.err
    assert len(captured.err.strip().splitlines()) == 1
