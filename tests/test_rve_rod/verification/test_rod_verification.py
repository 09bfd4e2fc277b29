"""Rod engine against known solutions: exact tension, Newton's quadratic convergence, the
cantilever rolled into a circle (convergence rates), the tip-loaded elastica (shooting), the
45-degree bend (published tip positions), multi-patch consistency and lumped point loads."""

import itertools

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from support.rod_cases import arc, straight

from rve_rod.newton import NewtonOptions, newton_solve, solve_path
from rve_rod.rod import (
    END,
    START,
    Clamp,
    EndLoad,
    Joint,
    PointLoad,
    RodEnd,
    RodModel,
    RodPatch,
    SectionStiffness,
)
from rve_rod.stepping import SteppingOptions

LENGTH = 10.0
OUT_OF_PLANE = np.array([0.0, 0.0, 1.0])  # d1 = z: bending in the xy-plane is about d1


def cantilever(curves, section, *, force=(0, 0, 0), moment=(0, 0, 0), loads=(), joint_force=None):
    """Clamped at the start of the first curve, loaded at the end of the last one."""
    patches = RodPatch.chain(curves, section, initial_normal=OUT_OF_PLANE)
    last = len(curves) - 1
    joints = (
        [
            Joint(RodEnd(k, END), RodEnd(k + 1, START), force=joint_force if k == 0 else (0, 0, 0))
            for k in range(last)
        ]
        if joint_force is not None
        else [Joint(RodEnd(k, END), RodEnd(k + 1, START)) for k in range(last)]
    )
    conditions = [
        Clamp(RodEnd(0, START)),
        *joints,
        EndLoad(RodEnd(last, END), force=force, moment=moment),
    ]
    return RodModel(patches, conditions, loads)


def tip(model, state):
    return model.positions(state, model.layout.n_patches - 1, np.array([1.0]))[0]


@pytest.mark.parametrize("degree", [2, 3, 4])
def test_straight_rod_in_tension_is_exact(degree):
    section = SectionStiffness.circular(0.3, 200.0)
    force = 0.2 * section.axial  # 20 % strain: far from small
    model = cantilever([straight(LENGTH, degree, 7)], section, force=(force, 0, 0))
    result = solve_path(model.problem(), model.reference_state(), [1.0])
    stretch = 1.0 + force / section.axial
    np.testing.assert_allclose(
        tip(model, result.final_state), [stretch * LENGTH, 0, 0], rtol=1e-13, atol=1e-12
    )
    params = np.linspace(0, 1, 11)
    np.testing.assert_allclose(
        model.positions(result.final_state, 0, params)[:, 0],
        stretch * LENGTH * params,
        rtol=1e-12,
        atol=1e-12,
    )
    sections = model.evaluate(result.final_state).section
    np.testing.assert_allclose(sections.force[0], force, rtol=1e-12)


def test_prescribed_end_rotation_twists_the_rod_uniformly():
    # Rotation control: the END is turned by pi about the axis; torque = GJ pi / L exactly,
    # the centreline stays straight and every section is turned by pi s / L.
    section = SectionStiffness.circular(0.3, 200.0)
    patches = RodPatch.chain([straight(LENGTH, 4, 16)], section, initial_normal=OUT_OF_PLANE)
    conditions = [Clamp(RodEnd(0, START)), Clamp(RodEnd(0, END), rotation=(np.pi, 0, 0))]
    model = RodModel(patches, conditions)
    result = solve_path(model.problem(), model.reference_state(), [0.5, 1.0])
    torque = model.evaluate(result.final_state).section.moment[0]
    np.testing.assert_allclose(torque, section.torsion * np.pi / LENGTH, rtol=1e-6)
    params = np.linspace(0, 1, 21)
    positions = model.positions(result.final_state, 0, params)
    np.testing.assert_allclose(positions, np.outer(params, [LENGTH, 0, 0]), atol=1e-9 * LENGTH)
    d1 = model.rotations(result.final_state, 0, params)[:, :, 0]
    angle = np.pi * params
    np.testing.assert_allclose(d1[:, 1:], np.stack([-np.sin(angle), np.cos(angle)], 1), atol=1e-6)


def tip_loaded_cantilever(radius=0.2, load_parameter=3.0, degree=4, n=32):
    """Straight cantilever along x under a dead tip load -P e_y with P L^2 / EI given."""
    section = SectionStiffness.circular(radius, 1000.0)
    force = load_parameter * section.bending_1 / LENGTH**2
    model = cantilever([straight(LENGTH, degree, n)], section, force=(0, -force, 0))
    return model, section, force


def test_newton_error_after_one_step_is_quadratic_in_the_initial_error():
    model, _, _ = tip_loaded_cantilever(radius=0.5)
    problem = model.problem()
    solution = solve_path(problem, model.reference_state(), [1.0]).final_state
    direction = np.random.default_rng(2).normal(size=solution.size) * model.state_scale()
    errors = []
    for size in (1e-5, 1e-6, 1e-7):
        one_step = newton_solve(
            problem, solution + size * direction, 1.0, NewtonOptions(max_iterations=1)
        )
        errors.append(np.max(np.abs(one_step.state - solution) / model.state_scale()))
    # e1 = C e0^2: a tenfold smaller start gives a hundredfold smaller error.
    ratios = [a / b for a, b in itertools.pairwise(errors)]
    assert all(90 < ratio < 110 for ratio in ratios), ratios


def elastica_tip(section, force):
    """Tip of the planar extensible, shearable (Reissner) cantilever under a dead tip load
    -force e_y, by shooting on the clamp curvature (solve_ivp + brentq)."""
    ei, ea, ga = section.bending_1, section.axial, section.shear_2
    load = np.array([0.0, -force])

    def rhs(_, y):
        angle, curvature = y[2], y[3]
        d3 = np.array([np.cos(angle), np.sin(angle)])
        d2 = np.array([np.sin(angle), -np.cos(angle)])  # d2 = d3 x d1 with d1 = z
        tangent = (1 + load @ d3 / ea) * d3 + (load @ d2 / ga) * d2
        # m' + (r' x n)_z = 0 with m = EI angle'
        return [
            tangent[0],
            tangent[1],
            curvature,
            -(tangent[0] * load[1] - tangent[1] * load[0]) / ei,
        ]

    def end(curvature0):
        return solve_ivp(rhs, [0, LENGTH], [0, 0, 0, curvature0], rtol=1e-12, atol=1e-14).y[:, -1]

    linear = force * LENGTH / ei
    curvature0 = brentq(lambda k: end(k)[3], -1.2 * linear, 0.0, xtol=1e-14)
    return end(curvature0)[:2]


def test_tip_loaded_cantilever_matches_shooting_elastica():
    model, section, force = tip_loaded_cantilever()
    result = solve_path(model.problem(), model.reference_state(), [0.5, 1.0])
    expected = elastica_tip(section, force)
    computed = tip(model, result.final_state)
    assert expected[0] < 0.8 * LENGTH and expected[1] < -0.5 * LENGTH  # truly large deflection
    assert np.linalg.norm(computed[:2] - expected) < 0.005 * np.linalg.norm(expected)
    assert np.linalg.norm(computed[:2] - expected) < 1e-4 * LENGTH  # the actual accuracy
    assert abs(computed[2]) < 1e-12


# (degree, control-point counts, expected order): Greville collocation converges at order p
# for even p and p - 1 for odd p.
CIRCLE_CASES = [(2, [32, 64, 128, 256], 2.0), (3, [32, 64, 128, 256], 2.0), (4, [24, 48, 96], 4.0)]
CIRCLE_FINEST_ERROR = {2: 5e-3, 3: 2e-3, 4: 1.5e-6}  # max position error / L at the finest n


@pytest.mark.parametrize(("degree", "counts", "order"), CIRCLE_CASES)
def test_end_moment_rolls_cantilever_into_a_circle(degree, counts, order):
    # A moment 2 pi EI / L bends the cantilever into a full circle (no axial or shear force:
    # the exact solution has zero strain but full rotation). L/r = 20.
    section = SectionStiffness.circular(0.5, 1000.0)
    moment = 2 * np.pi * section.bending_1 / LENGTH
    radius = LENGTH / (2 * np.pi)
    params = np.linspace(0, 1, 401)
    angle = 2 * np.pi * params
    exact = np.stack([radius * np.sin(angle), radius * (1 - np.cos(angle)), 0 * angle], axis=1)
    errors, tips = [], []
    for n in counts:
        model = cantilever([straight(LENGTH, degree, n)], section, moment=(0, 0, moment))
        result = solve_path(
            model.problem(),
            model.reference_state(),
            [1.0],
            stepping=SteppingOptions(initial_increment=0.125, max_increment=0.25),
        )
        deviation = model.positions(result.final_state, 0, params) - exact
        errors.append(np.linalg.norm(deviation, axis=1).max() / LENGTH)
        tips.append(np.linalg.norm(tip(model, result.final_state)) / LENGTH)
    spans = np.array(counts) - degree
    slope = -np.polyfit(np.log(spans), np.log(errors), 1)[0]
    assert order - 0.25 < slope < order + 0.75, (slope, errors)
    assert errors[-1] < CIRCLE_FINEST_ERROR[degree], errors
    assert tips[-1] < CIRCLE_FINEST_ERROR[degree]  # the tip closes the circle at the clamp


# Simo & Vu-Quoc (1986), tip positions of the 45-degree bend under a dead out-of-plane load.
BEND_REFERENCE = {
    300.0: (58.84, 22.33, 40.08),
    450.0: (52.32, 18.62, 48.39),
    600.0: (47.23, 15.79, 53.37),
}


def bend_model(patch_count=1, n=32):
    """Bathe & Bolourchi's 45-degree bend: R = 100, unit square section, E = 1e7, G = E/2,
    in the xy-plane from the origin; clamped at the origin, tip force along z."""
    modulus, shear = 1e7, 0.5e7
    section = SectionStiffness(
        shear_1=5 / 6 * shear,
        shear_2=5 / 6 * shear,
        axial=modulus,
        bending_1=modulus / 12,
        bending_2=modulus / 12,
        torsion=shear / 6,
    )
    bounds = np.linspace(0.0, 1.0, patch_count + 1)
    curves = [arc(100.0, np.pi / 4, 4, n, start=a, stop=b) for a, b in itertools.pairwise(bounds)]
    return cantilever(curves, section, force=(0, 0, 600.0))


def test_45_degree_bend_matches_published_tip_positions():
    model = bend_model()
    loads = sorted(BEND_REFERENCE)
    result = solve_path(model.problem(), model.reference_state(), [f / 600.0 for f in loads])
    for step, load in zip(result.steps[1:], loads, strict=True):
        computed = tip(model, step.state)
        np.testing.assert_allclose(computed, BEND_REFERENCE[load], rtol=0.01)


@pytest.mark.parametrize("patch_count", [2, 3, 4])
def test_patches_give_the_same_answer_as_one_patch(patch_count):
    single = bend_model(1, n=64)
    split = bend_model(patch_count, n=64 // patch_count + 2)
    answers = []
    for model in (single, split):
        result = solve_path(model.problem(), model.reference_state(), [0.5, 1.0])
        answers.append(tip(model, result.final_state))
    np.testing.assert_allclose(answers[1], answers[0], rtol=1e-4)


def test_lumped_point_load_converges_to_the_load_at_a_joint():
    # A point force inside one patch (lumped onto collocation points) against the same force
    # applied exactly at a joint between two patches.
    section = SectionStiffness.circular(0.5, 1000.0)
    force = np.array([0.0, -2.0 * section.bending_1 / LENGTH**2, 0.0])
    where = 0.43
    pieces = [straight(LENGTH, 4, 48, stop=where), straight(LENGTH, 4, 48, start=where)]
    exact_model = cantilever(pieces, section, joint_force=force)
    exact = tip(
        exact_model,
        solve_path(exact_model.problem(), exact_model.reference_state(), [1.0]).final_state,
    )
    errors = []
    counts = [32, 64, 128]
    for n in counts:
        model = cantilever([straight(LENGTH, 4, n)], section, loads=[PointLoad(0, where, force)])
        state = solve_path(model.problem(), model.reference_state(), [1.0]).final_state
        errors.append(np.linalg.norm(tip(model, state) - exact) / LENGTH)
    slope = -np.polyfit(np.log(np.array(counts) - 4), np.log(errors), 1)[0]
    assert 1.8 < slope < 2.6, errors
    assert errors[-1] < 3e-5
