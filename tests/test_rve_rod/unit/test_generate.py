"""Generation: parallel == serial, cached runs are never repeated, interrupted batches resume."""

import dataclasses
import io
import logging

import numpy as np
import pytest
from support.failing_engines import FailingRve

from rve_rod.cache import ResultCache
from rve_rod.errors import ConvergenceError
from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.homogenize.generate import (
    PENETRATION_STOP,
    WORKER_DIED,
    GenerationError,
    execute,
    generate_surface,
    run_cases,
)
from rve_rod.homogenize.progress import Progress
from rve_rod.homogenize.samples import RveCase, RveRun
from rve_rod.homogenize.sampling import SamplingPlan
from rve_rod.presets import load_preset

FABRIC = load_preset("cotton-20s2", 5.5)
PLAN = SamplingPlan(rays=8, steps_per_ray=6, shear_steps=6)
CASES = [RveCase(FABRIC, path) for path in PLAN.load_paths()]


def assert_same_runs(first, second):
    assert len(first) == len(second)
    for a, b in zip(first, second, strict=True):
        np.testing.assert_array_equal(a.deformation_gradient, b.deformation_gradient)
        np.testing.assert_array_equal(a.first_piola, b.first_piola)
        assert a.complete == b.complete


def test_two_jobs_give_the_same_surface_as_one(tmp_path):
    serial = generate_surface(FABRIC, AnalyticRve(), PLAN, jobs=1)
    parallel = generate_surface(FABRIC, AnalyticRve(), PLAN, jobs=2)
    assert_same_runs(serial.runs.runs, parallel.runs.runs)
    for name, spline in serial.surface.groups().items():
        np.testing.assert_array_equal(
            spline.coefficients, parallel.surface.groups()[name].coefficients
        )


def test_cached_runs_are_not_repeated(tmp_path):
    cache = ResultCache(tmp_path)
    first = run_cases(CASES, AnalyticRve(), cache=cache, jobs=2)
    assert (first.computed, first.cached) == (len(CASES), 0)
    again = run_cases(CASES, AnalyticRve(), cache=cache, jobs=2)
    assert (again.computed, again.cached) == (0, len(CASES))
    assert_same_runs(first.runs, again.runs)
    # one more ray: only it is computed; another engine setting: everything
    more = [*CASES, RveCase(FABRIC, dataclasses.replace(CASES[0].load, angle_deg=10.0))]
    assert run_cases(more, AnalyticRve(), cache=cache).computed == 1
    stiffer = AnalyticRve(course_stiffness=0.3)
    assert run_cases(CASES, stiffer, cache=cache).computed == len(CASES)


@pytest.mark.parametrize(("how", "jobs"), [("raise", 1), ("raise", 2), ("kill", 2)])
def test_a_failing_run_loses_no_other_run(tmp_path, how, jobs):
    cache = ResultCache(tmp_path)
    with pytest.raises(GenerationError) as info:
        run_cases(CASES, FailingRve(how=how), cache=cache, jobs=jobs)
    (failure,) = info.value.failures
    assert failure.case.load.angle_deg == 90.0
    assert failure.reason == (WORKER_DIED if how == "kill" else "RuntimeError: simulated crash")
    assert "1 of 9 runs failed; the 8 others are cached" in str(info.value)
    finals = list(tmp_path.rglob("*.npz"))
    assert len(finals) == len(CASES) - 1
    for path in finals:  # every entry under a final name is complete and readable
        assert np.load(path)["first_piola"].shape[1:] == (2, 2)
    assert not list(tmp_path.rglob("*.tmp"))
    resumed = run_cases(CASES, AnalyticRve(), cache=cache, jobs=jobs)
    assert (resumed.computed, resumed.cached) == (1, len(CASES) - 1)
    assert_same_runs(resumed.runs, run_cases(CASES, AnalyticRve()).runs)


def test_runs_stopped_early_are_kept_and_reported():
    rve = AnalyticRve(compression_limit=0.04)
    generated = generate_surface(FABRIC, rve, PLAN)
    incomplete = generated.surface.parameters["incomplete_runs"]
    complete = generated.samples.complete
    assert len(incomplete) == (~complete).sum() > 0
    assert all(
        np.cos(np.radians(run["angle_deg"])) < 0 or np.sin(np.radians(run["angle_deg"])) < 0
        for run in incomplete
    )
    assert generated.samples.biaxial_strain[:, :2].min() >= -0.04 - 1e-12


def test_a_convergence_error_without_history_is_a_failure():
    def broken(case):
        raise ConvergenceError("no converged step")

    with pytest.raises(GenerationError, match="ConvergenceError: no converged step"):
        run_cases(CASES[:1], broken)


def test_engine_must_return_an_rve_run():
    with pytest.raises(GenerationError, match="TypeError: the RVE engine returned dict"):
        run_cases(CASES[:1], lambda case: {"F": 1})


def test_surface_parameters_regenerate_it():
    generated = generate_surface(FABRIC, AnalyticRve(), PLAN, kind="energy")
    parameters = generated.surface.parameters
    assert parameters["sampling"]["rays"] == 8
    assert parameters["fabric"]["knit"]["wale_width"] == FABRIC.knit.wale_width
    assert parameters["fit"]["kind"] == "energy" and generated.surface.kind == "energy"
    assert parameters["engine"] == "rve_rod.homogenize.analytic.AnalyticRve"
    assert set(generated.reports) == {"stress", "energy"}
    assert isinstance(generated.runs.runs[0], RveRun)


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_on_a_terminal_counts_cached_computed_and_failed_runs():
    stream = Terminal()
    bar = Progress(stream, total=4, cached=1)
    bar.draw()
    assert "RVE runs" in stream.getvalue() and "1/4" in stream.getvalue()
    bar.advance()
    bar.advance(failed=True)
    assert (bar.computed, bar.failed, bar.done) == (1, 1, 3)
    bar.advance()
    final = stream.getvalue().split("\r")[-1]
    assert "4/4" in final and "cached=1" in final and "failed=1" in final
    assert final.endswith("\n")  # the last run ends the line


def test_progress_is_quiet_when_not_a_terminal():
    stream = io.StringIO()
    bar = Progress(stream, total=2)
    bar.draw()
    bar.advance()
    bar.advance()
    assert stream.getvalue() == ""


def test_progress_during_generation():
    stream = Terminal()
    run_cases(CASES, AnalyticRve(), progress=stream)
    final = stream.getvalue().split("\r")[-1]
    assert f"{len(CASES)}/{len(CASES)}" in final and final.endswith("\n")


@pytest.mark.parametrize("jammed", [True, False])
def test_a_run_stopped_at_the_penetration_limit_is_logged_as_expected(jammed, caplog):
    """A ray that stops where the yarns would pass through each other is an expected event
    (INFO, counted in the run's summary); another stop is a WARNING (issue 31: make demo
    printed four 300-character warnings a user cannot act on)."""
    rve = AnalyticRve(compression_limit=0.04)
    case = next(c for c in CASES if c.load.kind == "biaxial" and c.load.angle_deg == 180.0)

    def engine(case):
        try:
            return rve(case)
        except ConvergenceError as error:
            reason = f"refused ({PENETRATION_STOP})" if jammed else "no convergence"
            raise ConvergenceError(reason, history=error.history) from None

    with caplog.at_level(logging.INFO, logger="rve_rod.homogenize.generate"):
        run = execute(engine, case)
    assert not run.complete
    (record,) = caplog.records
    assert record.levelno == (logging.INFO if jammed else logging.WARNING)
    assert record.getMessage().endswith("at the penetration limit" if jammed else "no convergence")
