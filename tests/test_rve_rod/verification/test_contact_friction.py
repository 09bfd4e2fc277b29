"""Friction: dissipation and hysteresis on load-unload sliding paths, Coulomb's limit, the
commit semantics of the history, and friction switched off entirely at mu = 0."""

import numpy as np
import pytest
from support.contact_scenes import crossed_rods

from rve_rod.contact import CompressibleYarnLaw, ContactModel, CoulombFriction
from rve_rod.errors import InputError

RADIUS = 0.15
LAW = CompressibleYarnLaw(stiffness=5.0, exponent=1.5, yarn_radius=RADIUS)
FRICTION = CoulombFriction(coefficient=0.15, tangential_stiffness=50.0)
N = 96


def pressed_rods(friction=FRICTION):
    """Rod 0 (along x) pressed 0.03 mm into rod 1 (along y) and committed there."""
    scene = crossed_rods(separation=2 * RADIUS, length=3.0, n_control_points=N)
    model = ContactModel(scene.patches, scene.positions, LAW, friction=friction, yarns=scene.yarns)
    pressed = scene.positions.copy()
    pressed[:N, 2] -= 0.03
    model.commit(model.evaluate(pressed))
    return model, pressed


def stored_energy(model, result):
    """Energy stored on rod 0's slave points: normal potential plus elastic stick springs."""
    contacts = result.contacts
    on_rod_0 = contacts.slave < N
    weights = model.collocation_weights[contacts.slave[on_rod_0]]
    elastic = np.sum(contacts.friction_load[:, on_rod_0] ** 2, axis=0) / (
        2 * FRICTION.tangential_stiffness
    )
    return np.sum(weights * (LAW.line_energy(contacts.penetration[on_rod_0]) + elastic))


def rod_0_resultants(model, result):
    """Normal and friction resultants (3,) on rod 0: sum of weight times line load."""
    contacts = result.contacts
    on_rod_0 = contacts.slave < N
    weights = model.collocation_weights[contacts.slave[on_rod_0]]
    normal = (weights * contacts.normal_load[on_rod_0] * contacts.normal[:, on_rod_0]).sum(axis=1)
    friction = (weights * contacts.friction_load[:, on_rod_0]).sum(axis=1)
    return normal, friction


def run_path(model, start, displacements):
    """Move rod 0 rigidly through `displacements` (k, 3), committing every step.

    Returns rod-0 resultants (k, 3), rod-1 resultants (k, 3), the work done on rod 0 by the
    agent (k,), the stored energy (k,) and the results. The work of a step is integrated
    like the state is: trapezoidal for the conservative normal loads, with the end-of-step
    friction for the backward-Euler return mapping.
    """
    weights = model.collocation_weights
    resultants_0, resultants_1, work, energy, results = [], [], [0.0], [], []
    previous = None
    for k, shift in enumerate(displacements):
        positions = start.copy()
        positions[:N] += shift
        result = model.evaluate(positions, tangent=False)
        model.commit(result)
        loads = result.line_load * weights
        resultants_0.append(loads[:, :N].sum(axis=1))
        resultants_1.append(loads[:, N:].sum(axis=1))
        energy.append(stored_energy(model, result))
        normal, friction = rod_0_resultants(model, result)
        if previous is not None:
            step = shift - displacements[k - 1]
            work.append(work[-1] - (0.5 * (normal + previous) + friction) @ step)
        previous = normal
        results.append(result)
    return np.array(resultants_0), np.array(resultants_1), np.array(work), np.array(energy), results


def cycle(amplitude, steps, axis):
    """0 -> +a -> -a -> 0 along `axis` in 4 * steps equal steps."""
    path = np.concatenate(
        [
            np.linspace(0, amplitude, steps + 1),
            np.linspace(amplitude, -amplitude, 2 * steps + 1)[1:],
            np.linspace(-amplitude, 0, steps + 1)[1:],
        ]
    )
    displacements = np.zeros((path.size, 3))
    displacements[:, axis] = path
    return path, displacements


def test_sliding_along_the_crossing_rod_follows_coulomb_and_dissipates():
    model, pressed = pressed_rods()
    amplitude = 0.05
    path, displacements = cycle(amplitude, 20, axis=1)
    force_0, force_1, work, energy, results = run_path(model, pressed, displacements)
    normal = force_0[:, 2]
    assert np.all(normal > 0)
    # Every sliding contact carries |f_t| = mu f_n exactly (the return mapping).
    for result in results:
        contacts = result.contacts
        slipping = contacts.sliding
        np.testing.assert_allclose(
            np.linalg.norm(contacts.friction_load[:, slipping], axis=0),
            0.15 * contacts.normal_load[slipping],
            rtol=1e-12,
        )
    # Rod 0's contact points keep their place on rod 0 and slide along rod 1. A few steps
    # into each stroke the stick loads of pressing and reversing are gone and the friction
    # resultant is mu times the sum of the normal line loads, against the motion.
    magnitude = np.array(
        [
            np.sum(
                (model.collocation_weights[r.contacts.slave] * r.contacts.normal_load)[
                    r.contacts.slave < N
                ]
            )
            for r in results
        ]
    )
    velocity = np.gradient(path)
    forward = (velocity > 0) & (path > 0.3 * amplitude) | (velocity > 0) & (
        path > -0.7 * amplitude
    ) & (np.arange(path.size) > path.size // 2)
    backward = (velocity < 0) & (path < 0.7 * amplitude)
    assert forward.sum() > 10 and backward.sum() > 10
    np.testing.assert_allclose(force_0[forward, 1], -0.15 * magnitude[forward], rtol=1e-6)
    np.testing.assert_allclose(force_0[backward, 1], 0.15 * magnitude[backward], rtol=1e-6)
    # Rod 1's points are passed over by the moving crossing: each point's friction builds up
    # from its anchor as it enters, so the two passes balance only approximately (9 % at 48
    # points, 3 % at 96, 2 % at 192).
    steady = forward | backward
    np.testing.assert_allclose(force_1[steady, 1], -force_0[steady, 1], rtol=0.05)
    # Dissipation = work - stored energy change: never negative, never decreasing.
    dissipation = work - (energy - energy[0])
    assert np.all(np.diff(dissipation) >= -1e-12 * work[-1])
    # Hysteresis: the loop encloses mu N times the path length, less the stick phases.
    stick = 0.15 * LAW.line_load(0.03) / FRICTION.tangential_stiffness
    upper = 0.15 * magnitude.mean() * 4 * amplitude
    assert upper * (1 - 3 * stick / amplitude) < work[-1] < upper * (1 + 1e-6)


def test_sliding_through_the_contact_never_gains_energy():
    # Rod 0 slides along its own axis: its material points run through the contact zone
    # (anchors appear and vanish) while rod 1's points slip along rod 0.
    model, pressed = pressed_rods()
    _, displacements = cycle(0.12, 24, axis=0)
    force_0, _, work, energy, results = run_path(model, pressed, displacements)
    assert any(r.statistics.sliding > 0 for r in results)
    dissipation = work - (energy - energy[0])
    scale = np.abs(force_0).max() * 0.12
    assert np.all(np.diff(dissipation) >= -1e-6 * scale)
    assert dissipation[-1] > 0.05 * 0.15 * np.abs(force_0[:, 2]).mean() * 4 * 0.12


def test_evaluation_is_a_trial_and_commit_adopts_it():
    model, pressed = pressed_rods()
    before = model.history
    moved = pressed.copy()
    moved[:N, 1] += 0.02
    first = model.evaluate(moved)
    assert model.history is before  # a trial leaves the history alone
    np.testing.assert_array_equal(model.evaluate(moved).line_load, first.line_load)
    model.commit(first)
    assert model.history is first.trial_history
    # From the new anchors the same state is the committed one: its friction is unchanged.
    again = model.evaluate(moved)
    np.testing.assert_allclose(again.line_load, first.line_load, atol=1e-15)


def test_zero_friction_skips_the_friction_path():
    frictionless, pressed = pressed_rods(friction=None)
    zero, _ = pressed_rods(friction=CoulombFriction(coefficient=0.0, tangential_stiffness=1.0))
    assert zero.friction is None and len(zero.history) == 0
    moved = pressed.copy()
    moved[:N, 1] += 0.02
    result = zero.evaluate(moved)
    assert result.trial_history is None
    assert result.statistics.sticking == result.statistics.sliding == 0
    assert np.all(result.contacts.friction_load == 0)
    np.testing.assert_array_equal(result.line_load, frictionless.evaluate(moved).line_load)


def test_first_touch_has_no_friction_until_committed():
    scene = crossed_rods(separation=2 * RADIUS, length=3.0, n_control_points=N)
    model = ContactModel(
        scene.patches,
        scene.positions + np.array([0, 0, 1.0]) * (np.arange(2 * N) < N)[:, None],
        LAW,
        friction=FRICTION,
        yarns=scene.yarns,
    )
    assert len(model.history) == 0  # far apart at the reference: no anchors
    pressed = scene.positions.copy()
    pressed[:N, 2] -= 0.03
    result = model.evaluate(pressed)
    stats = result.statistics
    assert stats.without_anchor == stats.active_contacts > 0
    assert np.all(result.contacts.friction_load == 0)
    model.commit(result)
    moved = pressed.copy()
    moved[:N, 1] += 1e-4
    after = model.evaluate(moved)
    assert after.statistics.without_anchor == 0
    # Now rod 0 feels friction against its motion and rod 1 is dragged along.
    on_rod_0 = after.contacts.slave < N
    assert np.all(after.contacts.friction_load[1, on_rod_0] < 0)
    assert np.all(after.contacts.friction_load[1, ~on_rod_0] > 0)


@pytest.mark.parametrize("bad", ["shape", "nan", "deformation"])
def test_bad_input_is_an_input_error(bad):
    model, pressed = pressed_rods()
    with pytest.raises(InputError):
        if bad == "shape":
            model.evaluate(pressed[:-1])
        elif bad == "nan":
            model.evaluate(np.where(np.arange(pressed.size).reshape(-1, 3) == 4, np.nan, pressed))
        else:
            model.evaluate(pressed, np.eye(2))
