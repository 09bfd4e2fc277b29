"""RVE results: per-step records, JSON export, the homogenization's RveRun, partial runs, and
the surface engine's mapping of sampling paths to load cases (the test loop of rve_cases)."""

import dataclasses
import json
import math

import numpy as np
import pytest
from support.rve_cases import CURVES, FABRIC

from rve_rod.errors import ConvergenceError
from rve_rod.homogenize.generate import execute
from rve_rod.homogenize.samples import RveCase
from rve_rod.homogenize.sampling import LoadPath, SamplingPlan
from rve_rod.jsonable import to_jsonable
from rve_rod.newton import NewtonOptions
from rve_rod.rve import engine
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import RveResult, RveSettings, simulate
from rve_rod.rve.yarn import YarnSettings
from rve_rod.stepping import SteppingOptions
from rve_rod.units import n_per_mm_to_gf_per_cm

COARSE = RveSettings(cell=CellSettings(control_points=20), yarn=YarnSettings(friction=False))
"""20 control points per quarter loop: at 12 the test loop's contacts are under-resolved (the
course-wise run takes 25-iteration cutbacks from the first step and stalls at 0.7 % strain;
at 20 it takes 34 Newton iterations for 5 steps)."""


@pytest.fixture(scope="module")
def course():
    return simulate(FABRIC, load_case("uniaxial-course", 0.2, 5), COARSE, curves=CURVES)


def test_steps_carry_the_outputs_of_the_design(course):
    assert course.complete and len(course.steps) == 5
    np.testing.assert_allclose(course.series("strain"), [0, 0.05, 0.1, 0.15, 0.2], atol=1e-15)
    last = course.steps[-1]
    F, P = last.deformation, last.first_piola
    assert F[0, 0] == pytest.approx(1.2) and F[1, 1] == pytest.approx(1 + last.lateral_strain)
    E = 0.5 * (F.T @ F - np.eye(2))
    np.testing.assert_allclose(last.green_lagrange, [E[0, 0], E[1, 1], E[0, 1]], atol=1e-15)
    S = np.linalg.solve(F, P)
    np.testing.assert_allclose(last.second_piola[:2], np.diag(S), rtol=1e-12)
    assert last.force_gf_per_cm == pytest.approx(n_per_mm_to_gf_per_cm(P[0, 0]))
    assert last.force_n == pytest.approx(P[0, 0] * 1.26)  # through one course height
    assert course.poisson_ratio == pytest.approx(-last.lateral_strain / 0.2)
    assert all(step.newton_iterations >= 1 for step in course.steps)
    assert course.newton_iterations == sum(step.newton_iterations for step in course.steps)
    assert course.centrelines.shape == (5, course.curve.n_control_points, 3)
    period = course.centreline(4)(np.array([4.0])) - course.centreline(4)(np.array([0.0]))
    np.testing.assert_allclose(period[0], [1.2 * 1.33, 0, 0], atol=1e-9)  # end = start + F a1


def test_json_export_has_the_series_the_cli_promises(course):
    data = json.loads(json.dumps(to_jsonable(course.to_dict())))
    for key in ("strain", "force_gf_per_cm", "lateral_strain", "newton_iterations"):
        assert len(data[key]) == 5
    assert data["poisson_ratio"] == pytest.approx(course.poisson_ratio)
    assert data["wall_time_s"] > 0 and data["complete"] is True
    assert data["case"] == "uniaxial-course"


def test_rve_run_for_the_homogenization_leaves_out_the_rest_state(course):
    run = course.to_rve_run()
    assert run.deformation_gradient.shape == (4, 2, 2) and run.complete
    np.testing.assert_array_equal(run.first_piola[-1], course.steps[-1].first_piola)


def test_a_run_that_cannot_go_on_keeps_its_converged_states():
    hopeless = RveSettings(
        cell=COARSE.cell,
        yarn=COARSE.yarn,
        newton=NewtonOptions(max_iterations=2),
        stepping=SteppingOptions(max_cutbacks=1),
    )
    with pytest.raises(ConvergenceError, match="uniaxial-course stopped at strain") as caught:
        simulate(FABRIC, load_case("uniaxial-course", 0.4, 3), hopeless, curves=CURVES)
    partial = caught.value.history
    assert isinstance(partial, RveResult) and not partial.complete
    assert len(partial.steps) >= 1 and partial.message
    assert caught.value.last_converged is partial.steps[-1]


@pytest.mark.parametrize("path", SamplingPlan(rays=8, steps_per_ray=4).load_paths())
def test_sampling_paths_map_to_cases_with_the_same_deformation(path):
    case = engine.path_case(path)
    F = np.array([case.prescribed(t) for t in case.load_factors()[1:]])
    np.testing.assert_allclose(F, path.deformation_gradients(), rtol=0, atol=1e-14)


def test_surface_engine_runs_a_path_and_reports_incomplete_ones(monkeypatch):
    monkeypatch.setattr(
        engine,
        "simulate",
        lambda fabric, case, settings: simulate(fabric, case, settings, curves=CURVES),
    )
    rve = engine.RodRve(COARSE)
    path = LoadPath("biaxial", 45.0, 0.1, 2)
    run = execute(rve, RveCase(FABRIC, path))
    assert run.complete
    np.testing.assert_allclose(run.deformation_gradient, path.deformation_gradients(), atol=1e-14)
    assert run.first_piola[-1, 0, 0] > 0 and run.first_piola[-1, 1, 1] > 0
    stuck = engine.RodRve(
        RveSettings(
            cell=COARSE.cell,
            yarn=COARSE.yarn,
            newton=NewtonOptions(max_iterations=1),
            stepping=SteppingOptions(max_cutbacks=0),
        )
    )
    partial = execute(stuck, RveCase(FABRIC, LoadPath("shear", 0.0, 0.3, 3)))
    assert not partial.complete
    assert partial.deformation_gradient.shape[0] < 3
    assert math.isfinite(float(np.sum(partial.first_piola)))


def test_the_linear_solver_settings_are_not_part_of_the_cache_identity():
    """They change the cost, not the results (docs/rve.md): a cache made with one ordering
    serves another; any other solver setting is part of the identity."""
    identity = engine.RodRve(COARSE).cache_identity()
    direct = dataclasses.replace(
        COARSE, newton=NewtonOptions(line_search=4, ordering="COLAMD", refinement=0)
    )
    assert engine.RodRve(direct).cache_identity() == identity
    assert "ordering" not in json.dumps(identity)
    searched = dataclasses.replace(COARSE, newton=NewtonOptions(line_search=2))
    assert engine.RodRve(searched).cache_identity() != identity


def test_the_taut_loop_options_enter_the_cache_identity_only_when_on():
    """Off (their defaults) they leave the model as it was, so the runs and surfaces cached
    before they existed stay valid; on, they are part of the identity."""
    identity = engine.RodRve(COARSE).cache_identity()
    yarn = set(identity["settings"]["settings"]["yarn"])
    assert not {"prestrain", "natural_length", "natural_curvature"} & yarn
    for change in ({"prestrain": 0.02}, {"natural_length": "measured"}, {"natural_curvature": 0}):
        taut = dataclasses.replace(COARSE, yarn=dataclasses.replace(COARSE.yarn, **change))
        other = engine.RodRve(taut).cache_identity()
        assert other != identity
        ((name, value),) = change.items()
        assert other["settings"]["settings"]["yarn"][name] == value


def test_the_point_load_contact_enters_the_cache_identity_only_when_on():
    identity = engine.RodRve(COARSE).cache_identity()
    assert "lumping" not in identity["settings"]["settings"]["cell"]["contact"]
    contact = dataclasses.replace(COARSE.cell.contact, lumping="point")
    pointed = dataclasses.replace(COARSE, cell=dataclasses.replace(COARSE.cell, contact=contact))
    other = engine.RodRve(pointed).cache_identity()
    assert other["settings"]["settings"]["cell"]["contact"]["lumping"] == "point"
