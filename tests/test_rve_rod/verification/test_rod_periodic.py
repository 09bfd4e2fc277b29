"""A periodic rod cell built with the extension API as the knit RVE will build it: a Joint from
the last END to the first START whose offset depends on a macro-stretch unknown, a user
condition closing that unknown with a force, and a PointSupport removing the rigid modes."""

import numpy as np
import pytest
from support.rod_cases import ForceControl, interpolated_curve, straight

from rve_rod.newton import solve_path
from rve_rod.rod import (
    END,
    START,
    Joint,
    Offset,
    PointSupport,
    RodEnd,
    RodModel,
    RodPatch,
    SectionStiffness,
)

LENGTH = 4.0
SECTION = SectionStiffness.circular(0.2, 500.0)


def periodic_cell(curve, force):
    """One patch closed on itself: x(start) - x(end) = -(1 + e) * period, e = extra unknown 0;
    extra unknowns 1..4: support reaction force, and moment about the period axis, at u = 0.5
    (the rigid modes: three translations and the rotation about the period vector)."""
    patches = RodPatch.chain([curve], SECTION, initial_normal=[0.0, 0.0, 1.0])
    period = curve.control_points[-1] - curve.control_points[0]
    stretch = 7 * curve.n_control_points  # state index of extra unknown 0

    def offset(state, load_factor):
        return Offset(-(1.0 + state[stretch]) * period, np.array([stretch]), -period[:, None])

    conditions = [
        Joint(RodEnd(0, END), RodEnd(0, START), offset=offset),
        ForceControl(RodEnd(0, END), period / np.linalg.norm(period), force),
        PointSupport(0, 0.5, first_unknown=1, rotation_axes=(period,)),
    ]
    return RodModel(patches, conditions, extra_unknowns=5, extra_state_scale=[0.01] + [1.0] * 4)


def test_straight_periodic_rod_stretches_exactly():
    force = 0.05 * SECTION.axial
    model = periodic_cell(straight(LENGTH, 4, 12), force)
    state = solve_path(model.problem(), model.reference_state(), [1.0]).final_state
    extra = state[model.layout.extra_dofs()]
    assert extra[0] == pytest.approx(force / SECTION.axial, rel=1e-12)
    assert np.abs(extra[1:]).max() < 1e-12 * force
    params = np.linspace(0, 1, 9)
    positions = model.positions(state, 0, params)
    # stretched about the supported midpoint
    expected = LENGTH * (0.5 + (1 + extra[0]) * (params - 0.5))
    np.testing.assert_allclose(positions[:, 0], expected, atol=1e-12)


def wavy(n, amplitude=0.6):
    """One period of a crimped yarn: y = a sin(2 pi x / L), z = a/2 sin(4 pi x / L)."""

    def points(u):
        return np.stack(
            [
                LENGTH * u,
                amplitude * np.sin(2 * np.pi * u),
                0.5 * amplitude * np.sin(4 * np.pi * u),
            ],
            axis=1,
        )

    return interpolated_curve(points, 4, n)


def test_crimped_periodic_rod_decrimps_and_the_support_reaction_vanishes():
    force = 0.02 * SECTION.axial
    reactions, stretches = [], []
    for n in (16, 32, 64):
        model = periodic_cell(wavy(n), force)
        state = solve_path(model.problem(), model.reference_state(), [0.5, 1.0]).final_state
        extra = state[model.layout.extra_dofs()]
        stretches.append(extra[0])
        assert np.abs(extra[1:4]).max() < 1e-10 * force  # the joint transmits all the force
        reactions.append(abs(extra[4]) / (force * LENGTH))
        positions = model.positions(state, 0, np.linspace(0, 1, 41))
        assert np.ptp(positions[:, 1]) < 0.5 * 2 * 0.6  # the crimp is pulled much flatter
    # Decrimping makes the cell far softer than the straight yarn (force / EA = 0.02).
    assert stretches[-1] > 10 * force / SECTION.axial
    assert abs(stretches[-1] - stretches[-2]) < 2e-3 * stretches[-1]
    # The support only removes rigid modes: its reaction moment is a discretization error.
    assert reactions[-1] < 1e-6
    assert reactions[-1] < reactions[0] / 100


@pytest.mark.parametrize("prestrain", [0.01, 0.04])
def test_a_prestrained_rod_pulls_with_ea_eps0_over_one_plus_eps0_at_its_reference_length(
    prestrain,
):
    """`RodModel.set_prestrain`: natural length L / (1 + eps0). Held at L the rod pulls with
    N = EA eps0 / (1 + eps0) (the strain per reference length is 1 - 1 / (1 + eps0)); free of
    load it shortens to its natural length, e = -eps0 / (1 + eps0)."""
    held = SECTION.axial * prestrain / (1.0 + prestrain)
    for force, stretch in ((held, 0.0), (0.0, -prestrain / (1.0 + prestrain))):
        model = periodic_cell(straight(LENGTH, 4, 12), force)
        model.set_prestrain(prestrain)
        state = solve_path(model.problem(), model.reference_state(), [1.0]).final_state
        assert state[model.layout.extra_dofs()][0] == pytest.approx(stretch, abs=1e-12)


def test_undoing_the_prestrain_restores_the_model_bit_for_bit():
    """set_prestrain(0) after another prestrain gives the residual of the model as built,
    bit for bit (eps0 = 0 is the default model), and a prestrain changes it."""
    model = periodic_cell(wavy(16), 0.01 * SECTION.axial)
    state = model.reference_state()
    state[: 7 * 16] += 1e-3 * np.sin(np.arange(7 * 16))
    before = model.residual(state)
    model.set_prestrain(0.03)
    assert np.abs(model.residual(state) - before).max() > 1e-3 * SECTION.axial
    model.set_prestrain(0.0)
    np.testing.assert_array_equal(model.residual(state), before)
