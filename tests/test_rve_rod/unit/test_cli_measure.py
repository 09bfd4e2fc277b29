"""`rve-rod synth-photo` and `rve-rod measure`: output, JSON, overlay, errors and exit codes."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from rve_rod.cli import main
from rve_rod.imaging.image_io import read_image, write_image

RVE_ROD = str(Path(sys.executable).parent / "rve-rod")


@pytest.fixture(scope="module")
def cotton_photo(tmp_path_factory):
    """A synthetic photo of cotton-20s2 at stitch 5.5, turned by 6 degrees, at 25 px/mm."""
    path = tmp_path_factory.mktemp("photos") / "cotton.png"
    arguments = ["synth-photo", "--preset", "cotton-20s2", "--stitch", "5.5", "-o", str(path)]
    assert main([*arguments, "--angle-deg", "6", "--noise", "0.1", "--blur-mm", "0.03"]) == 0
    return path


def test_synthetic_photo_has_the_requested_size(cotton_photo):
    assert read_image(cotton_photo).shape == (512, 512)


def test_measure_json_is_one_object_with_the_truth_inside(cotton_photo, capsys):
    assert main(["measure", str(cotton_photo), "--pixels-per-mm", "25", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["wale_width"] == pytest.approx(1.33, rel=0.01)
    assert result["course_height"] == pytest.approx(1.26, rel=0.01)
    assert result["angle_deg"] == pytest.approx(6.0, abs=0.2)
    for key in ("wale_width_uncertainty", "course_height_uncertainty"):
        assert 0 < result[key] < 0.01


def test_measure_text_report_and_overlay(cotton_photo, tmp_path, capsys):
    overlay = tmp_path / "overlay.png"
    arguments = ["measure", str(cotton_photo), "--pixels-per-mm", "25", "--plot", str(overlay)]
    assert main(arguments) == 0
    report = capsys.readouterr().out
    assert "wale width    w = 1.33" in report and "course height c = 1.26" in report
    assert f"wrote {overlay}" in report
    with Image.open(overlay) as image:
        assert image.size == (700, 760)  # 7 x 7.6 inches at 100 dpi


def test_measure_twice_the_scale_halves_the_lengths(cotton_photo, capsys):
    main(["measure", str(cotton_photo), "--pixels-per-mm", "50", "--json"])
    assert json.loads(capsys.readouterr().out)["wale_width"] == pytest.approx(0.665, rel=0.01)


@pytest.mark.parametrize(
    "case",
    [
        ("unreadable", "25", "cannot be read as an image"),
        ("flat", "25", "flat"),
        ("cotton", "-3", "pixels_per_mm=-3 must be > 0"),
    ],
    ids=lambda case: case[0],
)
def test_bad_input_exits_2_with_one_line(case, cotton_photo, tmp_path, capsys):
    kind, scale, message = case
    path = {"cotton": cotton_photo, "flat": tmp_path / "flat.png"}.get(kind, tmp_path / "x.png")
    if kind == "flat":
        write_image(path, np.full((100, 100), 0.5))
    elif kind == "unreadable":
        path.write_bytes(b"not an image")
    assert main(["measure", str(path), "--pixels-per-mm", scale]) == 2
    error = capsys.readouterr().err
    assert error.startswith("rve-rod measure: error: ") and error.count("\n") == 1
    assert message in error


def test_synth_photo_needs_a_fabric(tmp_path, capsys):
    assert main(["synth-photo", "-o", str(tmp_path / "x.png"), "--wale-width", "1.3"]) == 2
    assert "give a preset, or all of course_height, yarn_radius" in capsys.readouterr().err


def test_installed_command_prints_no_traceback(tmp_path):
    path = tmp_path / "noise.png"
    write_image(path, np.random.default_rng(0).random((200, 200)))
    result = subprocess.run(
        [RVE_ROD, "measure", str(path), "--pixels-per-mm", "20", "--json"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 2 and result.stdout == ""
    assert "no periodic structure" in result.stderr and "Traceback" not in result.stderr
