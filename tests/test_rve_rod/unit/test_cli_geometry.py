"""`rve-rod geometry`: the JSON report, the files, and one-line errors with exit status 2."""

import json

import meshio
import numpy as np
import pytest

from rve_rod.cli import main


def test_json_report_of_a_preset(capsys, tmp_path):
    status = main(
        [
            "geometry",
            "--preset",
            "cotton-20s2",
            "--stitch",
            "5.5",
            "--json",
            "--plot",
            str(tmp_path / "loop.png"),
            "--vtk",
            str(tmp_path / "loop.vtu"),
        ]
    )
    assert status == 0
    report = json.loads(capsys.readouterr().out)
    for key in ("loop_length", "adjusted_radius", "shape_parameter", "min_clearance"):
        assert isinstance(report[key], float)
    assert report["adjusted_radius"] == pytest.approx(1.33 / 8)
    assert np.array(report["control_points"]).shape == (4, 12, 3)
    assert report["measured_loop_length"] == 5.5
    assert (tmp_path / "loop.png").stat().st_size > 10_000
    mesh = meshio.read(tmp_path / "loop.vtu")
    # 9 loops (the cell and its 8 neighbours) of 4 x 60 - 3 points each
    assert mesh.points.shape == (9 * 237, 3)
    np.testing.assert_allclose(mesh.point_data["radius"], 1.33 / 8)


def test_explicit_parameters_without_material(capsys):
    status = main(
        ["geometry", "--wale-width", "0.833", "--course-height", "0.486", "--yarn-radius", "0.0923"]
    )
    assert status == 0
    out = capsys.readouterr().out
    assert "loop length" in out
    assert "adjusted" not in out  # r0 = 0.0923 < w/8 = 0.104


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--wale-width", "1", "--course-height", "nan", "--yarn-radius", "0.1"], "course_height"),
        (["--wale-width", "-1", "--course-height", "1", "--yarn-radius", "0.1"], "wale_width"),
        (["--preset", "wool"], "preset='wool' is unknown"),
        (["--preset", "cotton-20s2", "--stitch", "5.2"], "valid stitch values"),
        (["--wale-width", "1", "--course-height", "0.05", "--yarn-radius", "0.12"], "no loop fits"),
        (["--wale-width", "1"], "give a preset"),
        (["--from-photo", "x.png", "--yarn-radius", "0.1"], "--pixels-per-mm"),
    ],
)
def test_bad_input_is_one_line_with_status_2(capsys, arguments, message):
    assert main(["geometry", *arguments]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert message in captured.err
    assert len(captured.err.strip().splitlines()) == 1
