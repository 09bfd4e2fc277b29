"""`rve-rod simulate`: JSON, report, plot and VTK files, partial runs (exit 3), bad input (exit 2),
at a coarse resolution."""

import json
import logging
import re
from xml.etree import ElementTree

import meshio
import numpy as np
import pytest

import rve_rod.cli.simulate as cli_simulate
import rve_rod.rve.simulation as rve_simulation
from rve_rod.cli import main
from rve_rod.newton import NewtonOptions
from rve_rod.stepping import SteppingOptions

ARGS = ["simulate", "--wale-width", "1.33", "--course-height", "1.26", "--yarn-radius", "0.16"]
# 24 control points per quarter loop: at 12-20 this loop's contacts are under-resolved and the
# wale-wise run stalls (at 12 % strain with 20; 41 Newton iterations for 5 steps with 24).
ARGS += ["--youngs-modulus", "80", "--control-points", "24", "--steps", "5"]


def test_json_is_the_only_stdout_and_progress_goes_to_stderr(tmp_path, capsys):
    plot, vtk = tmp_path / "curve.png", tmp_path / "vtk"
    assert main([*ARGS, "--json", "--frictionless", "--plot", str(plot), "--vtk", str(vtk)]) == 0
    captured = capsys.readouterr()
    data = json.loads(captured.out)
    for key in ("strain", "force_gf_per_cm", "lateral_strain", "newton_iterations"):
        assert len(data[key]) == 5
    assert data["poisson_ratio"] == pytest.approx(-data["lateral_strain"][-1] / 0.2)
    assert data["wall_time_s"] > 0 and data["case"] == "uniaxial-course"
    assert captured.err.count("strain") == 5  # one progress line per state
    assert plot.stat().st_size > 10_000
    files = sorted(vtk.glob("*.vtu"))
    assert [f.name for f in files] == [f"state_{k:03d}.vtu" for k in range(5)]
    assert data["files"] == [str(plot), *map(str, files), str(vtk / "states.pvd")]
    collection = ElementTree.parse(vtk / "states.pvd").getroot()
    datasets = collection.findall("Collection/DataSet")
    assert [d.get("file") for d in datasets] == [f.name for f in files]
    assert [float(d.get("timestep")) for d in datasets] == pytest.approx(data["strain"])
    mesh = meshio.read(files[-1])
    assert mesh.point_data["radius"][0] == pytest.approx(0.16)
    # 9 yarn pieces (cell and neighbours); the cell's one spans F a1 = (1.2 w, 0, 0)
    cell = (mesh.point_data["image_i"] == 0) & (mesh.point_data["image_j"] == 0)
    points = mesh.points[cell]
    np.testing.assert_allclose(points[-1] - points[0], [1.2 * 1.33, 0, 0], atol=1e-9)
    assert cell.sum() * 9 == len(mesh.points)


def test_report_without_json(capsys):
    assert main([*ARGS, "--case", "uniaxial-wale", "--frictionless"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("uniaxial-wale: yarn radius 0.16 mm")
    # --control-points counts per quarter loop; the run says so and gives the joined curve's
    # count (the four quarters share their end points: fewer than 4 x 24, more than 3 x 24)
    said = re.search(r"24 control points per quarter loop \((\d+) on the periodic curve\)", out)
    assert said and 3 * 24 < int(said.group(1)) < 4 * 24
    assert "Poisson ratio" in out and "Newton iterations" in out


def test_a_run_that_stops_writes_what_converged_and_exits_3(tmp_path, monkeypatch, capsys):
    def hopeless(fabric, case, settings, on_step, moments):
        settings = rve_simulation.RveSettings(
            cell=settings.cell,
            yarn=settings.yarn,
            newton=NewtonOptions(max_iterations=2),
            stepping=SteppingOptions(max_cutbacks=1),
        )
        return rve_simulation.simulate(fabric, case, settings, on_step=on_step, moments=moments)

    monkeypatch.setattr(cli_simulate, "simulate", hopeless)
    plot = tmp_path / "curve.png"
    code = main([*ARGS, "--max-strain", "0.4", "--steps", "3", "--json", "--plot", str(plot)])
    assert code == 3
    captured = capsys.readouterr()
    data = json.loads(captured.out)
    assert data["complete"] is False and 1 <= len(data["strain"]) < 3
    assert captured.err.strip().splitlines()[-1].startswith("rve-rod simulate: not converged:")
    assert plot.exists()


def test_a_run_beyond_the_penetration_limit_stops_at_it(capsys, caplog):
    caplog.set_level(logging.INFO)
    caplog.set_level(logging.INFO, logger="rve_rod.newton")  # `knitmech run` quiets it
    limit = 0.1
    extra = ["--case", "uniaxial-wale", "--steps", "11", "--penetration-limit", str(limit)]
    code = main(["-v", *ARGS, *extra, "--json"])  # -v: the INFO records are made
    assert code == 3
    captured = capsys.readouterr()
    data = json.loads(captured.out)
    assert data["complete"] is False and len(data["strain"]) >= 2
    penetration = np.array(data["max_penetration"]) / data["adjusted_radius"]
    assert 0.0 < penetration.max() <= limit
    assert "exceeds the limit of 0.1 r" in captured.err
    # the expected stop is one message; the step cutbacks on the way are details (-v)
    cutbacks = [r for r in caplog.records if "increment cut" in r.getMessage()]
    assert cutbacks and all(r.levelno == logging.INFO for r in cutbacks)


def test_a_yarn_that_keeps_half_its_set_shows_the_curl_at_rest(capsys):
    """--natural-curvature 0.5: the unloaded jersey cell carries M11 < 0 < M22 (the curl at
    rest, docs/patterns.md), where the set-keeping yarn's carries none."""
    moments = {}
    for share in ("1", "0.5"):
        extra = ["--natural-curvature", share, "--max-strain", "0.02", "--steps", "2", "--json"]
        assert main([*ARGS, *extra]) == 0
        moments[share] = json.loads(capsys.readouterr().out)["bending_moment_gf_cm_per_cm"][0]
    assert moments["0.5"][0] < 0.0 < moments["0.5"][1]
    assert np.abs(moments["1"]).max() < 1e-6 * np.abs(moments["0.5"]).max()


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--max-strain", "1.5"], "max_strain=1.5 is outside the valid range"),
        (["--steps", "1"], "steps=1 is outside the valid range"),
        (["--control-points", "8"], "--control-points=8 is outside the valid range [20, 300]"),
        (["--penetration-limit", "2"], "penetration_limit=2 is outside the valid range (0, 2)"),
        (["--natural-curvature", "1.5"], "--natural-curvature=1.5 is outside the valid range"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(extra, message, capsys):
    assert main([*ARGS, *extra]) == 2
    error = capsys.readouterr().err
    assert message in error and error.count("\n") == 1
