"""The photo-measurement demo runs and recovers the photographed fabric's w and c; its
measurement of the fixed synthetic photo is pinned (tests/pins.py, IMAGING)."""

import runpy
import sys
from pathlib import Path

import pytest
from pins import assert_pinned

DEMO = Path(__file__).parents[3] / "demos" / "demo_measure_photo.py"


def test_demo_measures_cotton_within_half_a_percent(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(sys, "argv", [str(DEMO), str(tmp_path)])
    namespace = runpy.run_path(str(DEMO), run_name="__main__")
    estimate = namespace["estimate"]
    assert estimate.wale_width == pytest.approx(1.33, rel=5e-3)
    assert estimate.course_height == pytest.approx(1.26, rel=5e-3)
    assert estimate.angle_deg == pytest.approx(8.0, abs=0.1)
    measured = {
        "wale width": estimate.wale_width,
        "course height": estimate.course_height,
        "angle": estimate.angle_deg,
    }
    assert_pinned("IMAGING", measured)
    assert (tmp_path / "knit_photo.png").exists() and (tmp_path / "knit_photo_lattice.png").exists()
    assert "knit for the geometry: w = 1.330 mm, c = 1.260 mm" in capsys.readouterr().out
