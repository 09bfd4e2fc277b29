"""`rve-rod --pattern`: the template cell of a pattern reported, a pattern's run, and bad
patterns refused with one line and exit status 2."""

import json

import meshio
import pytest

from rve_rod.cli import main

MEASURED = ["--preset", "cotton-20s2", "--stitch", "5.5", "--wale-width", "1.33"]


def test_the_geometry_of_a_patterns_cell(capsys, tmp_path):
    arguments = [*MEASURED, "--course-height", "1.26", "--pattern", "KP,PK", "--json"]
    status = main(["geometry", *arguments, "--vtk", str(tmp_path / "seed.vtu")])
    assert status == 0
    report = json.loads(capsys.readouterr().out)
    assert report["pattern"] == "seed"
    assert report["lattice_loops"] == [[2, 0], [1, 1]]
    assert report["loops_per_cell"] == 2
    assert report["clearance_over_diameter"] == pytest.approx(1.0, abs=1e-6)
    mesh = meshio.read(tmp_path / "seed.vtu")
    assert mesh.points.shape == (9 * 8 * 40, 3)  # 9 cells of one yarn of 2 loops


def test_a_run_of_a_pattern(capsys):
    status = main(
        [
            "simulate",
            *MEASURED,
            "--course-height",
            "1.26",
            "--pattern",
            "garter",
            "--case",
            "uniaxial-wale",
            "--max-strain",
            "0.1",
            "--steps",
            "3",
            "--control-points",
            "20",
            "--json",
        ]
    )
    assert status == 0
    report = json.loads(capsys.readouterr().out)
    assert report["complete"]
    assert report["force_gf_per_cm"][-1] > 0.0


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--pattern", "ribb"], "pattern='ribb' is unknown"),
        (["--pattern", "KX"], "pattern='KX' is unknown"),
        (["--pattern", "KP,KPP"], "chart rows have unequal lengths"),
        (["--pattern", "KT,KK"], "has a tuck ('T') in column 2"),
        (["--relaxed"], "give either relaxed or wale_width and course_height, not both"),
    ],
)
def test_bad_patterns_are_refused_with_one_line(capsys, arguments, message):
    status = main(["geometry", *MEASURED, *arguments])
    assert status == 2
    error = capsys.readouterr().err.strip()
    assert message in error
    assert len(error.splitlines()) == 1
