"""Why the squeezed rest's shear stops in a 6-state run: a fold of its frictional path (issue 27).

Cotton 20s/2 at stitch 5.5, the squeezed rest (`YarnSettings(contact_radius="measured")`), 28
control points, along the paper group's picture-frame shear: the run of 6 states with friction,
of 7 states with friction and of 6 states without. At every accepted state (substeps included)
the three smallest singular values of the scaled Jacobian (`rve_rod.newton.
softest_singular_values`); for a run that stops, the line through the squared product of the
two smallest over the states within 1e-4 of the stop and where it crosses zero (a fold: one
singular value goes to zero as the square root of the distance to it), and at the last failed
attempt's final iterate the Newton step's nonlinear part R(u + s du) - R(u) - s J du at s =
0.001 ... 1 (growing as s squared: the system is smooth there, the tangent consistent).
docs/validation.md, "Why the squeezed rest's shear stops: a fold of its frictional path", has
the numbers (about 1.5 minutes).

    .venv/bin/python benchmarks/paper_rve_fold.py
"""

import dataclasses
from unittest import mock

import numpy as np
import scipy.sparse.linalg

from rve_rod import newton
from rve_rod.presets import load_preset
from rve_rod.rve import simulation
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.paper.comparison import compare_run
from rve_rod.rve.paper.data import shear_run
from rve_rod.rve.simulation import RveSettings
from rve_rod.rve.yarn import YarnSettings

RUNS = (("friction", True, 6), ("friction", True, 7), ("frictionless", False, 6))
NEAR = 1e-4
"""States within this distance in t of the stop enter the fold's line."""
STEPS = (1e-3, 1e-2, 0.1, 1.0)


def recorded_run(friction: bool, states: int):
    """(run comparison, accepted [(t, three smallest singular values)], the problem, the last
    failed attempt or None)."""
    accepted, record = [], {"problem": None, "failed": None}
    solve_path, newton_solve = simulation.solve_path, newton.newton_solve

    def recording_path(problem, initial_state, load_factors, **options):
        def measured_commit(state, load_factor):
            values = newton.softest_singular_values(problem, state, load_factor)
            accepted.append((load_factor, values))
            problem.commit(state, load_factor)

        record["problem"] = problem
        recording = dataclasses.replace(problem, commit=measured_commit)
        return solve_path(recording, initial_state, load_factors, **options)

    def recording_solve(*arguments, **options):
        attempt = newton_solve(*arguments, **options)
        if not attempt.converged:
            record["failed"] = attempt
        return attempt

    settings = RveSettings(
        cell=CellSettings(control_points=28),
        yarn=YarnSettings(contact_radius="measured", friction=friction),
    )
    with (
        mock.patch.object(simulation, "solve_path", recording_path),
        mock.patch.object(newton, "newton_solve", recording_solve),
    ):
        run = compare_run(load_preset("cotton-20s2", 5.5), shear_run(5.5), settings, states=states)
    return run, accepted, record["problem"], record["failed"]


def nonlinear_parts(problem, attempt) -> list[float]:
    """max |R(u + s du) - R(u) - s J du| (scaled) at the attempt's final iterate, per s."""
    state, t = attempt.state, attempt.load_factor
    scale = np.broadcast_to(problem.residual_scale, state.shape)
    residual, jacobian = problem.evaluate(state, t)
    step = scipy.sparse.linalg.spsolve(jacobian.tocsc(), -residual)
    parts = []
    for s in STEPS:
        moved, _ = problem.evaluate(state + s * step, t)
        parts.append(float(np.max(np.abs(moved - residual - s * (jacobian @ step)) / scale)))
    return parts


def main() -> None:
    first = shear_run(5.5).deformation[0]
    degrees_per_state = float(np.degrees(np.arctan2(first[0, 1], first[1, 1])))
    for label, friction, states in RUNS:
        run, accepted, problem, failed = recorded_run(friction, states)
        print(f"\n## {label}, {states} states: reached {run.reached} of {states}")
        print("| t | angle (deg) | smallest singular values (scaled Jacobian) |")
        print("|---:|---:|---|")
        for t, values in accepted:
            angle = t * states * degrees_per_state
            print(f"| {t:.6f} | {angle:.3f} | {' / '.join(f'{v:.3e}' for v in values)} |")
        if run.reached == states:
            continue
        t = np.array([a[0] for a in accepted])
        squared = np.array([np.prod(a[1][:2]) ** 2 for a in accepted])
        near = t > t[-1] - NEAR
        slope, intercept = np.polyfit(t[near], squared[near], 1)
        print(
            f"\nfold: (s1 s2)^2 over the {near.sum()} states within {NEAR:g} of the stop, slope "
            f"{slope:.3e}, zero at t = {-intercept / slope:.7f} ({-intercept / slope - t[-1]:.2e} "
            f"beyond the last converged state, t = {t[-1]:.6f})"
        )
        if failed is not None:
            print(
                f"last failed attempt, t = {failed.load_factor:.7f} ({failed.reason}), final "
                f"residual {failed.residual_norms[-1]:.3e}; the Newton step's nonlinear part at "
                + ", ".join(
                    f"s = {s:g}: {v:.2e}"
                    for s, v in zip(STEPS, nonlinear_parts(problem, failed), strict=True)
                )
            )


if __name__ == "__main__":
    main()
