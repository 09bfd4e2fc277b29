"""Newton solver and load stepping on small analytic systems."""

import dataclasses
import itertools
import signal
import sys

import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.linalg
from support.signals import signal_inside_an_ignoring_callback

from rve_rod import newton
from rve_rod.errors import ConvergenceError, InputError, terminate_as_interrupt
from rve_rod.newton import (
    LinearSolver,
    NewtonOptions,
    NonlinearProblem,
    newton_solve,
    node_ordering,
    softest_singular_values,
    solve_path,
)
from rve_rod.stepping import SteppingOptions


def convergence_orders(norms):
    """log(r_k+1)/log(r_k) for iterates in the asymptotic range (1e-2 > r_k, r_k+1 > 1e-15)."""
    return [np.log(b) / np.log(a) for a, b in itertools.pairwise(norms) if a < 1e-2 and b > 1e-15]


def cubic_problem():
    # R(u, t) = (u0^3 + u1 - 2t, u1^3 + 2 u1 - u0 - 2t): a regular root, (1, 1) at t = 1
    def evaluate(u, t):
        residual = np.array([u[0] ** 3 + u[1] - 2 * t, u[1] ** 3 + 2 * u[1] - u[0] - 2 * t])
        jacobian = np.array([[3 * u[0] ** 2, 1.0], [-1.0, 3 * u[1] ** 2 + 2]])
        return residual, scipy.sparse.csr_matrix(jacobian)

    return NonlinearProblem(evaluate)


def test_newton_converges_quadratically():
    result = newton_solve(cubic_problem(), np.array([3.0, 4.0]), 1.0)
    assert result.converged
    np.testing.assert_allclose(result.state, [1.0, 1.0], atol=1e-12)
    orders = convergence_orders(result.residual_norms)
    assert len(orders) >= 2
    assert min(orders) > 1.8


def arctan_problem(calls):
    # Newton on arctan(u - 10 t) diverges when started more than ~1.39 from the root.
    def evaluate(u, t):
        shifted = u[0] - 10 * t
        with np.errstate(over="ignore"):  # diverging iterates are part of the test
            slope = 1 / (1 + shifted**2)
        return np.array([np.arctan(shifted)]), scipy.sparse.csr_matrix([[slope]])

    return NonlinearProblem(evaluate, commit=lambda state, t: calls.append((t, state[0])))


def test_cutback_recovers_and_commit_runs_after_every_converged_step():
    commits = []
    result = solve_path(
        arctan_problem(commits),
        np.zeros(1),
        [0.5, 1.0],
        stepping=SteppingOptions(extrapolate=False),
    )
    assert result.final_state[0] == pytest.approx(10.0, abs=1e-9)
    assert [step.load_factor for step in result.steps] == [0.0, 0.5, 1.0]
    assert result.steps[1].cutbacks >= 2  # 0.5 and 0.25 fail before 0.125 succeeds
    assert len(commits) == sum(step.substeps for step in result.steps[1:])
    times = [t for t, _ in commits]
    assert times == sorted(times) and times[-1] == 1.0
    np.testing.assert_allclose([u for _, u in commits], [10 * t for t in times], atol=1e-9)


def test_extrapolation_saves_iterations_on_a_smooth_path():
    plain = solve_path(
        cubic_problem(),
        np.zeros(2),
        np.linspace(0.1, 1, 10),
        stepping=SteppingOptions(extrapolate=False),
    )
    predicted = solve_path(cubic_problem(), np.zeros(2), np.linspace(0.1, 1, 10))
    np.testing.assert_allclose(predicted.final_state, plain.final_state, atol=1e-12)
    assert predicted.newton_iterations < plain.newton_iterations


def test_path_beyond_a_limit_point_raises_with_the_converged_history():
    # u^2 = 0.5 - t has no real root beyond t = 0.5 (a limit point).
    def evaluate(u, t):
        return np.array([u[0] ** 2 + t - 0.5]), scipy.sparse.csr_matrix([[2 * u[0]]])

    problem = NonlinearProblem(evaluate)
    with pytest.raises(ConvergenceError) as caught:
        solve_path(
            problem,
            np.array([np.sqrt(0.5)]),
            [0.25, 1.0],
            stepping=SteppingOptions(min_increment=1e-4),
        )
    error = caught.value
    last = error.last_converged
    assert 0.49 < last.load_factor < 0.5
    assert last.state[0] ** 2 + last.load_factor - 0.5 == pytest.approx(0.0, abs=1e-9)
    assert [step.load_factor for step in error.history.steps] == [0.0, 0.25]
    assert "t=0.49" in str(error)


def test_the_softest_singular_value_falls_as_the_root_of_the_distance_to_the_fold():
    # u^2 = 0.5 - t on its branch u = sqrt(0.5 - t): J = 2u, scaled by the residual scale 4 and
    # the state scale 0.5 to u / 4, so sigma^2 = (0.5 - t) / 16, zero at the fold t = 0.5
    def evaluate(u, t):
        return np.array([u[0] ** 2 + t - 0.5]), scipy.sparse.csr_matrix([[2 * u[0]]])

    problem = NonlinearProblem(evaluate, residual_scale=4.0, state_scale=0.5)
    for t in (0.0, 0.3, 0.49, 0.4999):
        (sigma,) = softest_singular_values(problem, np.array([np.sqrt(0.5 - t)]), t, 1)
        assert sigma**2 == pytest.approx((0.5 - t) / 16, rel=1e-12)


def test_softest_singular_values_come_smallest_first_in_the_scaled_norms():
    # J = diag(3, 1, 2) with row scales (1, 2, 4) and column scales (1, 1, 8): diag(3, 0.5, 4)
    def evaluate(u, t):
        return np.zeros(3), scipy.sparse.diags([3.0, 1.0, 2.0]).tocsr()

    problem = NonlinearProblem(
        evaluate, residual_scale=np.array([1.0, 2.0, 4.0]), state_scale=np.array([1.0, 1.0, 8.0])
    )
    values = softest_singular_values(problem, np.zeros(3), 0.0, 2)
    np.testing.assert_allclose(values, [0.5, 3.0], rtol=1e-14)


def test_refused_states_cut_back_to_the_admissible_limit_and_are_never_committed():
    # The cubic problem's root u0 rises from 0 (t = 0) to 1 (t = 1); states beyond u0 = 0.6
    # are refused, so the accepted (committed) ones approach 0.6 from below to within the
    # increment resolution, and the error names the refusal.
    def admissible(state, t):
        return "" if state[0] <= 0.6 else f"u0 = {state[0]:.3f} beyond 0.6"

    commits = []
    problem = NonlinearProblem(
        cubic_problem().evaluate,
        commit=lambda state, t: commits.append(state[0]),
        admissible=admissible,
    )
    with pytest.raises(ConvergenceError, match=r"no accepted state .*: u0 = 0\.6\d+ beyond 0\.6"):
        solve_path(
            problem,
            np.zeros(2),
            np.linspace(0.1, 1.0, 10),
            stepping=SteppingOptions(min_increment=1e-5, max_cutbacks=30),
        )
    assert max(commits) <= 0.6
    assert max(commits) == pytest.approx(0.6, abs=1e-4)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (lambda: NewtonOptions(residual_tolerance=-1.0), "residual_tolerance=-1 must be > 0"),
        (lambda: NewtonOptions(max_iterations=0), "max_iterations=0 is outside"),
        (lambda: SteppingOptions(growth_factor=0.5), "growth_factor=0.5 must be >= 1"),
    ],
)
def test_bad_options_raise_input_error(options, message):
    with pytest.raises(InputError, match=message):
        options()


def test_load_factors_must_increase():
    with pytest.raises(InputError, match="increase strictly"):
        solve_path(cubic_problem(), np.zeros(2), [0.5, 0.2])


def test_singular_jacobian_is_reported_not_raised():
    def evaluate(u, t):  # rigid mode left in: the Jacobian has a zero column
        return np.array([u[0] - t, 0.0 * u[1]]), scipy.sparse.csr_matrix([[1.0, 0.0], [0.0, 0.0]])

    result = newton_solve(NonlinearProblem(evaluate), np.zeros(2), 1.0)
    assert not result.converged
    assert result.reason == "singular"
    assert result.iterations == 0


def test_line_search_breaks_a_newton_cycle():
    # x^3 - 2x + 2 = 0 from x = 0: plain Newton cycles 0 -> 1 -> 0 forever (textbook case);
    # halving steps that do not lower |R| reaches the real root.
    def evaluate(u, t):
        residual = np.array([u[0] ** 3 - 2 * u[0] + 2 * t])
        return residual, scipy.sparse.csr_matrix([[3 * u[0] ** 2 - 2]])

    problem = NonlinearProblem(evaluate)
    plain = newton_solve(problem, np.zeros(1), 1.0)
    assert not plain.converged
    np.testing.assert_allclose(plain.residual_norms[-4:], [2, 1, 2, 1])
    searched = newton_solve(problem, np.zeros(1), 1.0, NewtonOptions(line_search=8))
    assert searched.converged
    root = np.roots([1, 0, -2, 2])
    assert searched.state[0] == pytest.approx(root[np.abs(root.imag) < 1e-12].real[0], abs=1e-12)
    assert min(convergence_orders(searched.residual_norms)) > 1.8  # still Newton at the end


@pytest.mark.parametrize("ordering", ["COLAMD", "NATURAL", "MMD_ATA", "MMD_AT_PLUS_A", "NODES"])
def test_every_lu_ordering_gives_the_same_newton_path(ordering):
    reference = newton_solve(cubic_problem(), np.array([3.0, 4.0]), 1.0)
    problem = dataclasses.replace(cubic_problem(), nodes=np.array([0, 1]))
    result = newton_solve(problem, np.array([3.0, 4.0]), 1.0, NewtonOptions(ordering=ordering))
    assert result.iterations == reference.iterations
    np.testing.assert_allclose(result.residual_norms, reference.residual_norms, rtol=1e-10)
    with pytest.raises(InputError, match="ordering='AMD' is unknown"):
        NewtonOptions(ordering="AMD")


def test_a_trial_within_the_residual_tolerance_is_not_damped():
    """A residual with a round-off floor (6e-12 at the first trial, where the root is), and
    unknowns on a scale of 1e-3, so that the corrections of 5e-12 and 6e-12 exceed the
    increment tolerance: the trial's merit is higher than the start's, yet the full step is
    taken (and the next, whose merit is equal): no line-search evaluations spent on
    round-off. Each evaluation is one iteration; the third iterate, its residual at the floor
    for three iterates without falling, is accepted there (`newton.ROUND_OFF_ITERATES`)."""
    calls = []

    def evaluate(u, t):
        calls.append(u.copy())
        floor = 6e-12 if len(calls) == 2 else 0.0
        return np.array([u[0] - t + floor]), scipy.sparse.csr_matrix([[1.0]])

    problem = NonlinearProblem(evaluate, state_scale=1e-3)
    result = newton_solve(problem, np.array([1.0 + 5e-12]), 1.0, NewtonOptions(line_search=4))
    assert result.converged
    np.testing.assert_allclose(result.residual_norms, [5e-12, 6e-12, 6e-12], atol=1e-15)
    assert len(calls) == result.iterations == newton.ROUND_OFF_ITERATES == 3


def test_convergence_is_tested_on_the_correction_at_the_state_itself():
    """A state is accepted when its residual and its own Newton correction are within the
    tolerances: the correction is computed but neither applied nor evaluated, and the
    quadratic convergence shows in the norms."""
    calls = []
    problem = cubic_problem()
    counted = dataclasses.replace(
        problem, evaluate=lambda u, t: calls.append(u.copy()) or problem.evaluate(u, t)
    )
    result = newton_solve(counted, np.array([3.0, 4.0]), 1.0)
    assert result.converged
    assert len(calls) == result.iterations == len(result.residual_norms)
    assert len(result.increment_norms) == result.iterations
    assert result.residual_norms[-1] <= 1e-10 and result.increment_norms[-1] <= 1e-10
    assert result.increment_norms[-2] > 1e-10  # the increment that led to the state
    np.testing.assert_array_equal(result.state, calls[-1])  # the last evaluated state
    # the unapplied correction's size is the state's error (quadratic convergence)
    assert np.abs(result.state - 1.0).max() <= 2 * result.increment_norms[-1] + 1e-15


def ring_with_chords(points, chord, dofs=3, seed=0):
    """A block-banded periodic (ring) matrix of `points` nodes with `dofs` unknowns each,
    coupled to their neighbours within 2 and to the node `chord` further on (a rod's band,
    periodic link and contacts), plus 2 unknowns without a node coupled to everything.
    Diagonally dominant. Returns the matrix and the nodes of the unknowns."""
    rng = np.random.default_rng(seed)
    n = points * dofs + 2
    dense = np.zeros((n, n))
    for i in range(points):
        for j in [i + d for d in range(-2, 3)] + [i + chord]:
            block = rng.normal(size=(dofs, dofs))
            dense[i * dofs : (i + 1) * dofs, (j % points) * dofs : (j % points + 1) * dofs] += block
    dense[-2:, :] = rng.normal(size=(2, n))
    dense[:, -2:] = rng.normal(size=(n, 2))
    dense += np.diag(np.abs(dense).sum(axis=1) + 1.0)
    nodes = np.concatenate([np.repeat(np.arange(points), dofs), [-1, -1]])
    return scipy.sparse.csr_matrix(dense), nodes


def test_node_ordering_keeps_nodes_together_and_lowers_the_fill():
    matrix, nodes = ring_with_chords(60, 20)
    order = node_ordering(matrix, nodes)
    assert sorted(order) == list(range(nodes.size))
    ordered = nodes[order]
    assert list(ordered[-2:]) == [-1, -1]  # the unknowns without a node come last
    blocks = ordered[:-2].reshape(-1, 3)
    assert np.all(blocks == blocks[:, :1])  # each node's unknowns together ...
    assert np.all(np.diff(order[:-2].reshape(-1, 3), axis=1) == 1)  # ... in their order
    natural = scipy.sparse.linalg.splu(matrix.tocsc(), permc_spec="NATURAL")
    reordered = scipy.sparse.linalg.splu(
        matrix[order][:, order].tocsc(), permc_spec="NATURAL", diag_pivot_thresh=0.01
    )
    assert reordered.L.nnz + reordered.U.nnz < 0.7 * (natural.L.nnz + natural.U.nnz)


def test_unknowns_without_nodes_keep_their_order():
    order = node_ordering(scipy.sparse.identity(3, format="csr"), np.full(3, -1))
    np.testing.assert_array_equal(order, [0, 1, 2])


def test_linear_solver_reuses_factors_while_refinement_reaches_the_tolerance():
    matrix, nodes = ring_with_chords(40, 13)
    rng = np.random.default_rng(1)
    rhs = rng.normal(size=nodes.size)
    options = NewtonOptions(ordering="NODES", pivot_threshold=0.01, refinement=3)
    solver = LinearSolver(options, nodes)
    for change in (0.0, 1e-6, 1e-4, 0.3):  # the last too far for the old factors
        changed = matrix + change * scipy.sparse.diags(rng.normal(size=nodes.size)) @ matrix
        solution = solver.solve(changed, rhs)
        np.testing.assert_allclose(changed @ solution, rhs, atol=1e-8 * np.abs(rhs).max())
    assert solver.factorizations == 2
    assert solver.reused == 2


def test_gmres_with_old_factors_resolves_a_low_rank_change_in_as_many_iterations():
    """A rank-2 change of 30 % (a contact that closes): the old factors alone contract
    nothing useful, GMRES preconditioned by them solves the new system to the linear tolerance
    in about 3 iterations (rank + 1 in exact arithmetic), without a factorization."""
    matrix, nodes = ring_with_chords(40, 13)
    rng = np.random.default_rng(2)
    rhs = rng.normal(size=nodes.size)
    solver = LinearSolver(
        NewtonOptions(ordering="NODES", pivot_threshold=0.01, refinement=6), nodes
    )
    solver.solve(matrix, rhs)
    low_rank = rng.normal(size=(nodes.size, 2)) @ rng.normal(size=(2, nodes.size))
    changed = matrix + 0.3 * scipy.sparse.csr_matrix(low_rank) * (
        abs(matrix).max() / np.abs(low_rank).max()
    )
    solution = solver.solve(changed, rhs)
    np.testing.assert_allclose(changed @ solution, rhs, atol=1e-8 * np.abs(rhs).max())
    assert (solver.factorizations, solver.reused) == (1, 1)
    old = scipy.sparse.linalg.splu(matrix.tocsc())
    once = old.solve(rhs)
    assert np.abs(changed @ once - rhs).max() > 1e-3 * np.abs(rhs).max()  # not a small change


def test_a_looser_linear_tolerance_is_met_and_no_more():
    """solve(..., tolerance) meets the given relative linear residual with the old factors;
    the forcing terms of an inexact Newton solve follow |R| between their bounds."""
    matrix, nodes = ring_with_chords(40, 13)
    rng = np.random.default_rng(4)
    rhs = rng.normal(size=nodes.size)
    options = NewtonOptions(ordering="NODES", pivot_threshold=0.01, refinement=8)
    changed = matrix + 1e-2 * scipy.sparse.diags(rng.normal(size=nodes.size)) @ matrix
    residuals = {}
    for tolerance in (1e-2, 1e-8):
        solver = LinearSolver(options, nodes)
        solver.solve(matrix, rhs)
        solution = solver.solve(changed, rhs, tolerance)
        residuals[tolerance] = np.abs(changed @ solution - rhs).max() / np.abs(rhs).max()
        assert residuals[tolerance] <= tolerance and solver.factorizations == 1
    assert residuals[1e-2] > 1e-8  # fewer iterations: the looser solve is not exact
    options = NewtonOptions()
    assert newton._forcing(options, 1e-3) == 1e-3  # |R|
    assert newton._forcing(options, 5.0) == 0.1  # at most 0.1
    assert newton._forcing(options, 1e-9) == pytest.approx(1e-3)  # 0.01 tol / |R|
    assert newton._forcing(options, 0.0) == options.linear_tolerance


def test_inexact_newton_with_reused_factors_keeps_quadratic_convergence():
    """A path of the cubic problem with GMRES on old factors and the forcing terms: the same
    solution as with exact solves, and the residual norms still fall quadratically."""
    exact = solve_path(cubic_problem(), np.zeros(2), [0.5, 1.0])
    options = NewtonOptions(refinement=6)
    solver = LinearSolver(options)
    states = [np.zeros(2)]
    for t in (0.5, 1.0):
        result = newton_solve(cubic_problem(), states[-1], t, options, solver=solver)
        assert result.converged
        states.append(result.state)
        assert min(convergence_orders(result.residual_norms)) > 1.8
    np.testing.assert_allclose(states[-1], exact.final_state, atol=1e-12)
    assert solver.reused > 0


def test_without_refinement_every_system_is_factorized():
    matrix, nodes = ring_with_chords(20, 7)
    solver = LinearSolver(NewtonOptions(ordering="NODES"), nodes)
    rhs = np.ones(nodes.size)
    for _ in range(3):
        np.testing.assert_allclose(matrix @ solver.solve(matrix, rhs), rhs, atol=1e-12)
    assert (solver.factorizations, solver.reused) == (3, 0)


def test_nodes_ordering_needs_nodes_and_options_are_checked():
    with pytest.raises(InputError, match="needs a problem with nodes"):
        LinearSolver(NewtonOptions(ordering="NODES"))
    with pytest.raises(InputError, match="pivot_threshold=2 is outside"):
        NewtonOptions(pivot_threshold=2.0)
    with pytest.raises(InputError, match="linear_tolerance=0 is outside"):
        NewtonOptions(linear_tolerance=0.0)


def test_an_iterate_expected_to_converge_is_evaluated_without_its_jacobian():
    """With a residual-only callable, the iterate that quadratic convergence puts below the
    tolerance costs no Jacobian: the same solution, as many iterations, one full evaluation
    fewer; the correction there uses the Jacobian of the iterate before."""
    counts = {"evaluate": 0, "residual": 0}
    problem = cubic_problem()

    def evaluate(u, t):
        counts["evaluate"] += 1
        return problem.evaluate(u, t)

    def residual(u, t):
        counts["residual"] += 1
        return problem.evaluate(u, t)[0]

    full = newton_solve(problem, np.array([3.0, 4.0]), 1.0)
    split = newton_solve(
        dataclasses.replace(problem, evaluate=evaluate, residual=residual),
        np.array([3.0, 4.0]),
        1.0,
    )
    assert split.converged and split.iterations == full.iterations
    assert counts == {"evaluate": full.iterations - 1, "residual": 1}
    np.testing.assert_allclose(split.state, [1.0, 1.0], atol=1e-12)
    assert split.residual_norms[-1] <= 1e-10 and split.increment_norms[-1] <= 1e-10
    assert min(convergence_orders(split.residual_norms)) > 1.8


def test_convergence_is_expected_from_the_quadratic_extrapolation_only():
    options = NewtonOptions()  # residual tolerance 1e-10
    assert newton._expect_convergence([1e-3, 1e-6], options)  # predicted 1e-12
    assert not newton._expect_convergence([1e-3, 1e-5], options)  # predicted 1e-9
    assert not newton._expect_convergence([1e-6], options)  # no rate yet
    assert not newton._expect_convergence([2e-3, 1e-3], options)  # not converging fast


def _linear_problem(jacobian_factor: float, soft: float, noise: float):
    """R(u) = A u - b with A = diag(1, soft), b = A (1, 1), plus a round-off of relative size
    `noise`, pseudo-random at every evaluation; the Jacobian handed to Newton
    is jacobian_factor A (1: consistent; > 1: Newton converges linearly, by 1 - 1/factor)."""
    matrix = np.diag([1.0, soft])
    target = matrix @ np.ones(2)
    signs = np.random.default_rng(7)

    def evaluate(u, t):
        residual = matrix @ u - target + noise * signs.uniform(-1.0, 1.0, size=2)
        return residual, scipy.sparse.csr_matrix(jacobian_factor * matrix)

    return NonlinearProblem(evaluate)


def test_a_residual_at_round_off_in_a_soft_mode_is_accepted_at_the_floor():
    """Round-off of 1e-13 in the residual through a soft mode of 1e-4 makes corrections of
    about 1e-9, above the increment tolerance (1e-10) however long Newton goes on: the state
    is accepted once the residual has sat at its floor (module docstring), as accurate as
    the round-off allows."""
    problem = _linear_problem(1.0, 1e-4, 1e-13)
    result = newton_solve(problem, np.zeros(2), 1.0, NewtonOptions(max_iterations=25))
    assert result.converged
    assert result.iterations <= 1 + newton.ROUND_OFF_ITERATES + 5
    assert result.increment_norms[-1] > 1e-10  # the increment test alone would go on
    np.testing.assert_allclose(result.state, np.ones(2), atol=1e-8)


@pytest.mark.parametrize("factor", [2.0, 5.0])
def test_linear_convergence_below_the_residual_tolerance_is_not_taken_for_round_off(factor):
    """An inconsistent tangent converges linearly (error x 0.5 or x 0.8 per iterate): its
    residual meets a loose tolerance long before the state is accurate, and falls at every
    iterate, so the floor of round-off does not accept it; the increment test does, later."""
    problem = _linear_problem(factor, 1.0, 0.0)
    options = NewtonOptions(residual_tolerance=1e-6, increment_tolerance=1e-12, max_iterations=200)
    result = newton_solve(problem, np.zeros(2), 1.0, options)
    assert result.converged
    assert result.increment_norms[-1] <= 1e-12
    np.testing.assert_allclose(result.state, np.ones(2), atol=1e-11)


def test_a_ctrl_c_lost_in_a_callback_stops_the_path_at_its_next_step(signal_handlers, monkeypatch):
    monkeypatch.setattr(sys, "unraisablehook", lambda unraisable: None)  # printed and ignored
    terminate_as_interrupt()
    signal_inside_an_ignoring_callback(signal.SIGINT)  # lost: the path would go on
    with pytest.raises(KeyboardInterrupt):
        solve_path(cubic_problem(), np.zeros(2), [1.0])
    path = solve_path(cubic_problem(), np.zeros(2), [1.0])  # raised once
    np.testing.assert_allclose(path.final_state, [1.0, 1.0], atol=1e-9)
