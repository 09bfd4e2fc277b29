"""Why the squeezed rest's shear stops in a 6-state run (docs/validation.md, "Why the squeezed
rest's shear stops: a fold of its frictional path"): the path reaches a limit point.

At a fold of R(u, t) = 0 one singular value of the Jacobian goes to zero as the square root of
the distance to the fold's load factor, so along the converged states that creep towards the
stop the product of the two smallest singular values (the other one stays put) squared falls
linearly in t and crosses zero where the run stops: no Newton iteration can reach a state
beyond it, whatever the increment. The test fits that line to the converged states within
1e-4 of the stop and checks that it is a line that crosses zero within 1e-5 beyond the last.
(Frictionless, the same 6 states converge: test_pinned_paper_comparison.py.)
"""

import dataclasses

import numpy as np
import pytest

from rve_rod.newton import softest_singular_values
from rve_rod.presets import load_preset
from rve_rod.rve import simulation
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.paper.comparison import compare_run
from rve_rod.rve.paper.data import shear_run
from rve_rod.rve.simulation import RveSettings
from rve_rod.rve.yarn import YarnSettings


@pytest.mark.slow
def test_the_six_state_run_stops_at_a_fold_of_its_path(monkeypatch):
    accepted = []  # (load factor, product) of every accepted state
    solve_path = simulation.solve_path

    def recording_path(problem, initial_state, load_factors, **options):
        commit = problem.commit

        def measured_commit(state, load_factor):
            accepted.append(
                (load_factor, np.prod(softest_singular_values(problem, state, load_factor, 2)))
            )
            commit(state, load_factor)

        recording = dataclasses.replace(problem, commit=measured_commit)
        return solve_path(recording, initial_state, load_factors, **options)

    monkeypatch.setattr(simulation, "solve_path", recording_path)
    settings = RveSettings(
        cell=CellSettings(control_points=28), yarn=YarnSettings(contact_radius="measured")
    )
    run = compare_run(load_preset("cotton-20s2", 5.5), shear_run(5.5), settings, states=6)

    assert run.reached == 0  # it stops before their first state (3.3 degrees)
    load_factor, product = np.array(accepted).T
    near = load_factor > load_factor[-1] - 1e-4  # the states within 1e-4 of the stop
    t, p2 = load_factor[near], product[near] ** 2
    assert t.size >= 4
    slope, intercept = np.polyfit(t, p2, 1)
    fitted = slope * t + intercept
    assert np.max(np.abs(fitted - p2)) < 0.1 * p2.max()
    fold = -intercept / slope
    assert slope < 0.0
    assert t[-1] <= fold < t[-1] + 1e-5
    assert 0.146 < t[-1] < 0.1463
