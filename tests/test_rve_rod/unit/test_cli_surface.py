"""`rve-rod surface` and `rve-rod surface-info`: output, errors and exit codes."""

import json
import subprocess
import sys
from pathlib import Path

import rve_rod.cli.surface as cli_surface
from rve_rod.cli import main
from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.surface import read_surface

RVE_ROD = str(Path(sys.executable).parent / "rve-rod")
ARGS = ["surface", "--preset", "cotton-20s2", "--stitch", "5.5", "--rays", "16", "--steps", "5"]


def test_surface_with_an_engine_writes_file_plot_and_reports(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(cli_surface, "surface_engine", lambda settings: AnalyticRve())
    output, plot = tmp_path / "surface.h5", tmp_path / "surfaces.png"
    arguments = [*ARGS, "-o", str(output), "--energy", "--jobs", "2", "--plot", str(plot)]
    assert main([*arguments, "--cache-dir", str(tmp_path / "cache")]) == 0
    captured = capsys.readouterr()
    assert "17 RVE runs (17 computed, 0 cached)" in captured.out
    assert "energy fit (written): tangent asymmetry" in captured.out
    assert "stress fit: tangent asymmetry" in captured.out
    assert "RVE runs" not in captured.err  # no progress bar when stderr is not a terminal
    surface = read_surface(output)
    assert surface.kind == "energy" and surface.parameters["sampling"]["rays"] == 16
    assert plot.stat().st_size > 10_000
    assert main([*arguments, "--cache-dir", str(tmp_path / "cache")]) == 0
    assert "17 RVE runs (0 computed, 17 cached)" in capsys.readouterr().out


def test_surface_info_text_and_json(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(cli_surface, "surface_engine", lambda settings: AnalyticRve())
    output = tmp_path / "surface.h5"
    main([*ARGS, "-o", str(output), "--cache-dir", str(tmp_path / "cache")])
    capsys.readouterr()
    assert main(["surface-info", str(output)]) == 0
    text = capsys.readouterr().out
    assert "kind stress" in text and "domain: E11 [" in text and "S12: degree [2]" in text
    assert '"rays": 16' in text
    assert main(["surface-info", str(output), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    surface = read_surface(output)
    assert info["groups"]["S11"]["residuals"]["max_abs"] == surface.residual_stats()["S11"].max_abs
    assert info["domain"]["E12"] == surface.domain[2].tolist()
    assert info["generator"]["package"] == "knitmech"


def test_bad_input_exits_2_with_one_line(tmp_path):
    broken = tmp_path / "broken.h5"
    broken.write_text("not a surface")
    for arguments in (
        ["surface-info", str(broken)],
        ["surface-info", str(tmp_path / "missing.h5")],
        [*ARGS[:5], "--rays", "2", "-o", str(tmp_path / "s.h5")],
        [*ARGS, "-o", str(tmp_path / "no" / "such" / "s.h5")],
    ):
        completed = subprocess.run(
            [RVE_ROD, *arguments], check=False, capture_output=True, text=True
        )
        assert completed.returncode == 2, completed.stderr
        assert completed.stderr.count("\n") == 1 and "Traceback" not in completed.stderr
