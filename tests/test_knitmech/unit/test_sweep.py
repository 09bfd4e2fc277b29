"""Sweeps: the knits of a file, one batch of runs, a surface per knit, failures reported."""

import numpy as np
import pytest
from support.failing_engines import FailingRve

from knitmech.fidelity import fidelity_level
from knitmech.scene import SceneError
from knitmech.stages import plan_run
from knitmech.sweep import FAILED_EXIT_STATUS, knit_label, load_sweep, run_sweep, sweep_from_dict
from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.homogenize.generate import generate_surface
from rve_rod.surface import read_surface

SWEEP = {
    "name": "two stitches",
    "fidelity": "fast",
    "surface": {"rays": 16},
    "grid": {"preset": "cotton-20s2", "stitch": [4.5, 7.0]},
}


def analytic(plan):
    return AnalyticRve()


def test_grid_and_list_give_every_knit_once():
    data = {
        **SWEEP,
        "grid": {"preset": "cotton-20s2", "stitch": [4.5, 5.0], "friction": [0.1, 0.2]},
        "knits": [{"preset": "vassiliadis-sample2"}, {"preset": "cotton-20s2", "stitch": 5.5}],
    }
    sweep = sweep_from_dict(data)
    labels = [knit.label for knit in sweep.knits]
    assert labels[:2] == [
        "cotton-20s2_stitch-4.5_friction-0.1",
        "cotton-20s2_stitch-4.5_friction-0.2",
    ]
    assert labels[4:] == ["vassiliadis-sample2", "cotton-20s2_stitch-5.5"]
    assert len(set(labels)) == 6
    third = sweep.knits[2].scene
    assert (third.fabric.stitch, third.fabric.friction, third.surface.rays) == (5.0, 0.1, 16)
    assert third.fabric_model().yarn.friction_coefficient == 0.1


def test_every_problem_of_every_knit_is_reported_at_once():
    data = {
        "fidelity": "fastest",
        "colour": "red",
        "surface": {"path": "x.h5"},
        "grid": {"preset": "cotton-20s2", "stitch": [4.5, 4.7]},
        "knits": [
            {"preset": "cotton-20s2", "stitch": 4.5},
            {"preset": "cotton-20s2", "yarn_radius": -1.0},
        ],
    }
    with pytest.raises(SceneError) as info:
        sweep_from_dict(data, source="bad.toml")
    problems = info.value.problems
    assert any(p.startswith("colour: unknown key") for p in problems)
    assert any(p.startswith("fidelity: 'fastest'") for p in problems)
    assert any(p.startswith("surface: ") for p in problems)
    assert any(p.startswith("grid[1] (cotton-20s2_stitch-4.7): fabric.stitch") for p in problems)
    assert "knits[0]: the same knit as grid[0] (cotton-20s2_stitch-4.5)" in problems
    assert any(
        p.startswith("knits[1] (cotton-20s2_yarn_radius--1.0): fabric.yarn_radius")
        for p in problems
    )


def test_knit_label_names_the_preset_and_the_other_keys():
    assert knit_label({"preset": "cotton-20s2", "stitch": 5.5}) == "cotton-20s2_stitch-5.5"
    assert knit_label({"wale_width": 1.3, "course_height": 1}) == "wale_width-1.3_course_height-1"


def test_a_sweep_writes_the_surfaces_generate_surface_makes(tmp_path):
    sweep = sweep_from_dict(SWEEP)
    result = run_sweep(
        sweep, tmp_path / "out", cache_dir=tmp_path / "cache", jobs=2, engine=analytic
    )
    # 16 rays and the shear run per knit (its 2 uniaxial runs, which the box follows, ran first)
    assert not result.failed and result.runs.computed == 2 * 17
    level = fidelity_level("fast")
    for knit, outcome in zip(sweep.knits, result.knits, strict=True):
        plan = plan_run(knit.scene, level)
        alone = generate_surface(plan.fabric, AnalyticRve(), plan.sampling, plan.fit).surface
        written = read_surface(outcome.surface_file)
        assert outcome.surface_file.name == f"{knit.label}.h5"
        box = written.parameters["sampling"]["max_compression"]  # followed the fabric
        assert plan.sampling.max_compression is None and box == alone.parameters["sampling"][
            "max_compression"
        ] == pytest.approx(0.10)
        for name, spline in alone.groups().items():
            np.testing.assert_array_equal(written.groups()[name].coefficients, spline.coefficients)
    again = run_sweep(sweep, tmp_path / "out", cache_dir=tmp_path / "cache", engine=analytic)
    assert (again.runs.computed, again.runs.cached) == (0, 34)
    assert "two stitches" in (tmp_path / "out" / "summary.txt").read_text()


@pytest.mark.parametrize(("how", "jobs"), [("raise", 1), ("raise", 2), ("kill", 2)])
def test_failed_runs_are_reported_and_only_they_are_rerun(tmp_path, how, jobs):
    sweep = sweep_from_dict(SWEEP)
    wale_width = sweep.knits[1].scene.fabric_model().knit.wale_width

    def failing(plan):
        return FailingRve(how=how, wale_width=wale_width)

    cache = tmp_path / "cache"
    result = run_sweep(sweep, tmp_path / "out", cache_dir=cache, jobs=jobs, engine=failing)
    assert result.failed
    good, bad = result.knits
    assert (good.computed, len(good.failures), good.surface_file.is_file()) == (17, 0, True)
    assert (bad.computed, len(bad.failures), bad.surface_file) == (16, 1, None)
    assert bad.failures[0].case.load.angle_deg == 90.0
    reason = "simulated crash" if how == "raise" else "worker process died"
    assert reason in bad.failures[0].reason
    table = result.table.splitlines()
    assert "cotton-20s2_stitch-7.0: biaxial angle 90 deg: " in table[-2]
    assert FAILED_EXIT_STATUS == 3
    rerun = run_sweep(sweep, tmp_path / "out", cache_dir=cache, jobs=jobs, engine=analytic)
    assert (rerun.runs.computed, rerun.runs.cached, rerun.failed) == (1, 33, False)


def test_load_sweep_reads_the_example(tmp_path):
    sweep = load_sweep("examples/sweeps/cotton_stitch.toml")
    assert [knit.scene.fabric.stitch for knit in sweep.knits] == [4.5, 5.0, 5.5, 6.0, 6.5, 7.0]
    assert sweep.fidelity == "fast"
