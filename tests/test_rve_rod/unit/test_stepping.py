"""The shared step controller on scripted solvers: the load factors it tries are known in
closed form (halving on failure, doubling after easy steps, every target hit exactly)."""

import pytest

from rve_rod.errors import InputError
from rve_rod.stepping import StepController, SteppingOptions


def drive(controller, outcome):
    """Run the controller with `outcome(load, trial) -> iterations or None (failed)`.

    Returns the tried load factors, the accepted ones with their StepCounts, and whether the
    path stopped early."""
    tried, accepted = [], []
    while not controller.finished:
        load, trial = controller.load_factor, controller.trial()
        tried.append(trial)
        iterations = outcome(load, trial)
        if iterations is None:
            if controller.reject(trial):
                return tried, accepted, True
            continue
        accepted.append((trial, controller.accept(trial, iterations)))
    return tried, accepted, False


def test_cutbacks_halve_the_failed_increment_and_then_grow_again():
    # Steps longer than 0.2 fail; easy steps (3 iterations) double the increment.
    options = SteppingOptions(initial_increment=1.0, min_increment=1e-3)
    controller = StepController([1.0], options)
    tried, accepted, stopped = drive(controller, lambda t0, t1: None if t1 - t0 > 0.2 else 3)
    assert not stopped
    assert tried[:5] == [1.0, 0.5, 0.25, 0.125, 0.375]  # 0.125 ok, doubled to 0.25: fails
    assert tried[5] == 0.25  # half of the failed 0.25 from 0.125
    load_factors = [t for t, _ in accepted]
    assert load_factors[-1] == 1.0 and load_factors == sorted(load_factors)
    assert all(b - a <= 0.2 for a, b in zip([0.0, *load_factors], load_factors, strict=False))
    final = accepted[-1][1]
    assert final.reached and final.substeps == len(accepted)
    assert final.cutbacks == controller.total_cutbacks == len(tried) - len(accepted)


def test_hard_steps_do_not_grow_the_increment():
    options = SteppingOptions(initial_increment=0.1, easy_iterations=5)
    hard = StepController([1.0], options)
    tried, _, _ = drive(hard, lambda t0, t1: 6)
    assert tried == pytest.approx([0.1 * k for k in range(1, 11)])
    easy = StepController([1.0], options)
    tried, _, _ = drive(easy, lambda t0, t1: 5)
    assert tried == pytest.approx([0.1, 0.3, 0.7, 1.0])  # 0.1, 0.2, 0.4, then capped


def test_every_target_is_reached_exactly_with_counts_per_target():
    targets = [0.1, 0.2, 0.3, 0.4, 0.5]
    controller = StepController(targets, SteppingOptions(initial_increment=0.1))
    _, accepted, _ = drive(controller, lambda t0, t1: 2)
    reached = [(t, count) for t, count in accepted if count.reached]
    assert [t for t, _ in reached] == targets  # 0.1 + 0.1 + 0.1 would be 0.30000000000000004
    assert all(count.substeps == 1 and count.cutbacks == 0 for _, count in reached)


def test_the_path_stops_below_the_minimum_increment():
    # Nothing beyond 0.3 converges: the increment halves from 0.5 until below 1/64.
    options = SteppingOptions(initial_increment=0.5, max_increment=0.5, min_increment=1 / 64)
    controller = StepController([0.5, 1.0], options)
    tried, accepted, stopped = drive(controller, lambda t0, t1: None if t1 > 0.3 else 1)
    assert stopped
    assert tried[0] == 0.5 and tried[1] == 0.25  # 0.5 fails, 0.25 converges
    assert controller.load_factor < 0.3 and controller.increment < 1 / 64
    assert controller.increment >= 1 / 128  # it stopped at the first increment below
    assert [t for t, _ in accepted] == [t for t in tried if t <= 0.3]


def test_the_path_stops_after_max_cutbacks_in_a_row():
    options = SteppingOptions(max_cutbacks=3, min_increment=1e-12)
    controller = StepController([1.0], options)
    tried, accepted, stopped = drive(controller, lambda t0, t1: None)
    assert stopped and accepted == []
    assert tried == [1.0, 0.5, 0.25, 0.125]  # the 4th failure in a row exceeds 3
    assert controller.consecutive == 4


def test_a_refused_state_cuts_back_towards_the_admissible_limit():
    """A solver's admissibility check is a failed attempt for the controller: the accepted
    load factors approach the limit 0.6 from below to within the increment resolution."""
    options = SteppingOptions(initial_increment=0.25, min_increment=1e-4, max_cutbacks=40)
    controller = StepController([1.0], options)
    _, accepted, stopped = drive(controller, lambda t0, t1: 1 if t1 <= 0.6 else None)
    assert stopped
    assert max(t for t, _ in accepted) == pytest.approx(0.6, abs=2e-4)
    assert max(t for t, _ in accepted) <= 0.6


def test_targets_must_increase_from_the_start():
    with pytest.raises(InputError, match=r"must increase strictly from start=0\.5"):
        StepController([0.5, 1.0], SteppingOptions(), start=0.5)
    with pytest.raises(InputError, match=r"growth_factor=0\.5 must be >= 1"):
        SteppingOptions(growth_factor=0.5)
