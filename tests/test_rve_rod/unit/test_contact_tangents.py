"""Contact tangents (normal, stick, slip) against central finite differences, relative 1e-6."""

import numpy as np
import pytest
from support.contact_scenes import knit_loop, wrapped_rods

from rve_rod.contact import (
    CompressibleYarnLaw,
    ContactModel,
    ContactOptions,
    CoulombFriction,
    Patch,
    YarnChain,
)
from rve_rod.errors import InputError
from rve_rod.geometry.bspline import greville_abscissae, open_knot_vector

STEP = 1e-7


def loads(model, positions, deformation):
    return model.evaluate(positions, deformation, tangent=False).line_load.ravel()


def finite_difference_jacobians(model, positions, deformation):
    """Central differences of the line loads w.r.t. all positions and F11, F12, F21, F22."""
    flat = positions.ravel()
    columns = []
    for i in range(flat.size):
        plus, minus = flat.copy(), flat.copy()
        plus[i] += STEP
        minus[i] -= STEP
        columns.append(
            loads(model, plus.reshape(-1, 3), deformation)
            - loads(model, minus.reshape(-1, 3), deformation)
        )
    position_jacobian = np.array(columns).T / (2 * STEP)
    columns = []
    for a, b in ((0, 0), (0, 1), (1, 0), (1, 1)):
        plus, minus = deformation.copy(), deformation.copy()
        plus[a, b] += STEP
        minus[a, b] -= STEP
        columns.append(loads(model, positions, plus) - loads(model, positions, minus))
    return position_jacobian, np.array(columns).T / (2 * STEP)


def assert_relative(actual, expected, tolerance=1e-6):
    scale = np.abs(expected).max()
    assert scale > 0
    assert np.abs(actual - expected).max() <= tolerance * scale


def assert_tangent(result, model, positions, deformation):
    """`result`'s line-load derivatives (positions and F) match central differences."""
    fd_positions, fd_deformation = finite_difference_jacobians(model, positions, deformation)
    assert_relative(result.jacobian.toarray(), fd_positions)
    assert_relative(result.deformation_jacobian, fd_deformation)


def curved_crossed_rods(n=14, degree=4):
    """Two curved rods crossing near the origin, centrelines about 0.2 apart (r = 0.2)."""
    knots = open_knot_vector(degree, n)
    g = greville_abscissae(knots, degree)
    rod_0 = np.stack([-1 + 2 * g, 0.2 * np.sin(3 * g), 0.1 * np.cos(2 * g) + 0.05], axis=1)
    rod_1 = np.stack([0.15 * np.cos(2 * g), -1 + 2 * g, -0.05 * g - 0.1], axis=1)
    return [Patch(degree, knots), Patch(degree, knots)], np.vstack([rod_0, rod_1])


LAW = CompressibleYarnLaw(stiffness=10.0, exponent=1.5, yarn_radius=0.2)


@pytest.mark.parametrize(
    ("friction", "shift", "state"),
    [
        (None, 0.01, "normal"),
        (CoulombFriction(coefficient=5.0, tangential_stiffness=10.0), 0.01, "stick"),
        (CoulombFriction(coefficient=0.3, tangential_stiffness=10.0), 0.05, "slip"),
    ],
)
def test_crossed_rods_tangent(friction, shift, state):
    patches, reference = curved_crossed_rods()
    model = ContactModel(
        patches, reference, LAW, friction=friction, yarns=[YarnChain((0,)), YarnChain((1,))]
    )
    positions = reference.copy()
    positions[:14, 0] += shift
    positions[:14, 1] += 0.5 * shift
    positions[14:, 2] += 0.3 * shift * np.linspace(-1, 1, 14)
    result = model.evaluate(positions)
    stats = result.statistics
    assert stats.active_contacts >= 4
    if state == "stick":
        assert stats.sticking == stats.active_contacts
    if state == "slip":
        assert stats.sliding == stats.active_contacts
    fd_positions, _ = finite_difference_jacobians(model, positions, np.eye(3))
    assert_relative(result.jacobian.toarray(), fd_positions)


KNIT_CELL_STATES = [
    (None, "normal"),
    (CoulombFriction(coefficient=10.0, tangential_stiffness=0.3), "stick"),
    (CoulombFriction(coefficient=0.05, tangential_stiffness=30.0), "slip"),
]
"""Friction laws that put every active contact of the knit cells below in one state."""

SHEAR = np.array([[0.96, 0.04, 0.0], [0.02, 0.95, 0.0], [0.0, 0.0, 1.0]])
"""A compressive shear F of the knit cells below (as built their loops only touch)."""


def knit_cell_model(scene, law, friction, **options):
    """The contact model of a knit cell scene with `ContactOptions(**options)`."""
    return ContactModel(
        scene.patches,
        scene.positions,
        law,
        friction=friction,
        lattice=scene.lattice,
        options=ContactOptions(**options),
    )


def sheared_positions(scene):
    """The scene's control points mapped by SHEAR and perturbed (seed 5, 0.004 mm)."""
    positions = scene.positions @ SHEAR.T
    return positions + 0.004 * np.random.default_rng(5).normal(size=positions.shape)


@pytest.mark.parametrize(("friction", "state"), KNIT_CELL_STATES)
def test_knit_cell_tangent_with_images_under_shear(cotton_loop, friction, state):
    # The cotton loop and its images mapped by a compressive shear F (as built they only
    # touch), the control points then perturbed.
    scene = knit_loop(cotton_loop, 20)
    law = CompressibleYarnLaw(stiffness=3.0, exponent=1.3, yarn_radius=cotton_loop.yarn_radius)
    model = knit_cell_model(scene, law, friction)
    deformation, positions = SHEAR, sheared_positions(scene)
    result = model.evaluate(positions, deformation)
    stats = result.statistics
    images = {tuple(image) for image in result.contacts.image}
    assert stats.active_contacts > 20
    assert len(images - {(0, 0)}) >= 4  # contacts with several periodic images
    anchored = stats.active_contacts - stats.without_anchor
    if state == "stick":  # contacts with a tiny normal force may still slip
        assert stats.sticking >= 0.9 * anchored > 0
    if state == "slip":
        assert stats.sliding >= 0.9 * anchored > 0
    assert_tangent(result, model, positions, deformation)


def test_per_contact_derivatives_sum_to_the_line_load_ones_and_match_differences(cotton_loop):
    """The per-contact loads (what the macro stress weights by lattice image) have their own
    derivatives: they sum to the per-point ones, and a weighted sum of them matches central
    differences of the same weighted sum (contacts keep their order under tiny steps)."""
    scene = knit_loop(cotton_loop, 12)
    law = CompressibleYarnLaw(stiffness=3.0, exponent=1.3, yarn_radius=cotton_loop.yarn_radius)
    friction = CoulombFriction(coefficient=0.05, tangential_stiffness=30.0)
    model = ContactModel(
        scene.patches, scene.positions, law, friction=friction, lattice=scene.lattice
    )
    deformation = np.array([[1.03, 0.04, 0.0], [0.02, 0.985, 0.0], [0.0, 0.0, 1.0]])
    positions = scene.positions + 0.004 * np.random.default_rng(5).normal(
        size=scene.positions.shape
    )
    result = model.evaluate(positions, deformation)
    contacts = result.contacts
    k, m = contacts.slave.size, model.n_collocation_points
    summed = np.zeros((3 * m, 3 * k))  # contact rows c k + i -> point rows c m + slave
    for c in range(3):
        summed[c * m + contacts.slave, c * k + np.arange(k)] = 1.0
    assert_relative(summed @ result.contact_jacobian.toarray(), result.jacobian.toarray(), 1e-12)
    assert_relative(
        summed @ result.contact_deformation_jacobian, result.deformation_jacobian, 1e-12
    )
    per_point = np.stack([np.bincount(contacts.slave, contacts.load[c], m) for c in range(3)])
    np.testing.assert_allclose(per_point, result.line_load, rtol=0, atol=1e-14)
    # weights: each contact's lattice image row j and column i (as the virial uses them)
    weights = np.concatenate([contacts.image[:, 1] + 0.5, contacts.image[:, 0] - 0.25, np.ones(k)])

    def weighted(points, F):
        other = model.evaluate(points, F, tangent=False).contacts
        assert np.array_equal(other.slave, contacts.slave)
        assert np.array_equal(other.image, contacts.image)
        return weights @ other.load.ravel()

    flat = positions.ravel()
    gradient = np.empty(flat.size)
    for i in range(flat.size):
        plus, minus = flat.copy(), flat.copy()
        plus[i] += STEP
        minus[i] -= STEP
        gradient[i] = weighted(plus.reshape(-1, 3), deformation) - weighted(
            minus.reshape(-1, 3), deformation
        )
    assert_relative(weights @ result.contact_jacobian.toarray(), gradient / (2 * STEP))
    by_deformation = []
    for a, b in ((0, 0), (0, 1), (1, 0), (1, 1)):
        plus, minus = deformation.copy(), deformation.copy()
        plus[a, b] += STEP
        minus[a, b] -= STEP
        by_deformation.append(weighted(positions, plus) - weighted(positions, minus))
    assert_relative(
        weights @ result.contact_deformation_jacobian, np.array(by_deformation) / (2 * STEP)
    )


@pytest.mark.parametrize(
    ("friction", "state"),
    [
        (None, "normal"),
        (CoulombFriction(coefficient=10.0, tangential_stiffness=1.0), "stick"),
        (CoulombFriction(coefficient=0.05, tangential_stiffness=10.0), "slip"),
    ],
)
@pytest.mark.parametrize("tilt", [0.0, 0.012])
def test_shared_minima_tangent_with_images_under_shear(friction, state, tilt):
    """A rod wrapped around another (through a lattice image): slave points with two close
    distance minima share one contact by prominence weights (rve_rod.contact.regions), whose
    derivatives (through the separating maximum) are part of the tangent."""
    scene = wrapped_rods(tilt=tilt, periodic=True)
    model = ContactModel(
        scene.patches,
        scene.positions,
        LAW,
        friction=friction,
        yarns=scene.yarns,
        lattice=scene.lattice,
    )
    deformation = np.array([[1.02, 0.004, 0.0], [0.003, 1.002, 0.0], [0.0, 0.0, 1.0]])
    rng = np.random.default_rng(3)
    positions = scene.positions + 0.001 * rng.normal(size=scene.positions.shape)
    result = model.evaluate(positions, deformation)
    stats = result.statistics
    weight = result.contacts.weight
    assert np.count_nonzero((weight > 0.05) & (weight < 0.95)) >= 2
    assert {tuple(image) for image in result.contacts.image} == {(0, 1), (0, -1)}
    if state == "stick":
        assert stats.sticking == stats.active_contacts
    if state == "slip":
        assert stats.sliding == stats.active_contacts
    assert_tangent(result, model, positions, deformation)


@pytest.mark.parametrize(("friction", "state"), KNIT_CELL_STATES)
def test_point_lumping_tangent_and_scale(cotton_loop, friction, state):
    """`lumping="point"`: the force r f_n at each slave point spread over its collocation
    weight h_i. The loads, friction and stick/slip states are the line lumping's times r / h_i
    point by point, and the tangent (positions and F) matches central differences."""
    scene = knit_loop(cotton_loop, 12)
    radius = cotton_loop.yarn_radius
    law = CompressibleYarnLaw(stiffness=3.0, exponent=1.3, yarn_radius=radius)

    line = knit_cell_model(scene, law, friction, lumping="line")
    point = knit_cell_model(scene, law, friction, lumping="point")
    deformation, positions = SHEAR, sheared_positions(scene)
    by_line = line.evaluate(positions, deformation)
    result = point.evaluate(positions, deformation)
    stats = result.statistics
    assert stats.active_contacts > 20
    anchored = stats.active_contacts - stats.without_anchor
    if state == "stick":
        assert stats.sticking >= 0.9 * anchored > 0
    if state == "slip":
        assert stats.sliding >= 0.9 * anchored > 0
    assert stats == by_line.statistics
    scale = radius / point.collocation_weights
    assert np.all(scale > 0.5)  # r / h_i: the weights are positive, a few times r at most
    np.testing.assert_allclose(result.line_load, by_line.line_load * scale, rtol=1e-13, atol=0)
    m = point.n_collocation_points
    line_jacobian = by_line.jacobian.toarray()
    np.testing.assert_allclose(
        result.jacobian.toarray(),
        line_jacobian * np.tile(scale, 3)[:, None],
        rtol=1e-12,
        atol=1e-12 * np.abs(line_jacobian).max(),
    )
    assert result.deformation_jacobian.shape == (3 * m, 4)
    assert_tangent(result, point, positions, deformation)


def test_point_lumping_tangent_of_shared_minima():
    """The region weights' derivatives are scaled with the loads (`lumping="point"`)."""
    scene = wrapped_rods(tilt=0.012, periodic=True)
    model = ContactModel(
        scene.patches,
        scene.positions,
        LAW,
        friction=CoulombFriction(coefficient=0.05, tangential_stiffness=10.0),
        yarns=scene.yarns,
        lattice=scene.lattice,
        options=ContactOptions(lumping="point"),
    )
    deformation = np.array([[1.02, 0.004, 0.0], [0.003, 1.002, 0.0], [0.0, 0.0, 1.0]])
    positions = scene.positions + 0.001 * np.random.default_rng(3).normal(
        size=scene.positions.shape
    )
    result = model.evaluate(positions, deformation)
    weight = result.contacts.weight
    assert np.count_nonzero((weight > 0.05) & (weight < 0.95)) >= 2
    assert_tangent(result, model, positions, deformation)


def test_unknown_lumping_is_refused():
    with pytest.raises(InputError, match="lumping='lumped' is unknown; valid: 'line', 'point'"):
        ContactOptions(lumping="lumped")


@pytest.mark.parametrize(("friction", "state"), KNIT_CELL_STATES)
def test_balanced_contact_sums_to_zero_and_its_tangent_matches_differences(
    cotton_loop, friction, state
):
    """`balance=True`: each slave load also acts, reversed, on its master's collocation points
    (each pass at half). By periodicity the cell's net contact force, summed with the
    collocation weights, is then zero to round-off (the two-pass one is not: the z part of a
    curved loop's contacts), and the tangent (positions and F, including the master
    parameter's sensitivity) matches central differences."""
    scene = knit_loop(cotton_loop, 20)
    law = CompressibleYarnLaw(stiffness=3.0, exponent=1.3, yarn_radius=cotton_loop.yarn_radius)

    two_pass = knit_cell_model(scene, law, friction)
    balanced = knit_cell_model(scene, law, friction, balance=True)
    deformation, positions = SHEAR, sheared_positions(scene)
    result = balanced.evaluate(positions, deformation)
    assert result.statistics.active_contacts > 20
    weights = balanced.collocation_weights
    unbalanced = two_pass.evaluate(positions, deformation, tangent=False).line_load @ weights
    net = result.line_load @ weights
    scale = np.abs(result.line_load).max() * weights.sum()
    assert np.abs(unbalanced).max() > 1e-3 * scale
    assert np.abs(net).max() <= 1e-12 * scale
    assert_tangent(result, balanced, positions, deformation)


def test_balance_must_be_a_bool():
    with pytest.raises(InputError, match="balance='yes' must be True or False"):
        ContactOptions(balance="yes")
