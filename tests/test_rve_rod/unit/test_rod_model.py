"""The assembled rod model: Jacobian vs finite differences, stress-free reference, rigid-body
invariance, load lumping and the checks on conditions."""

import itertools

import numpy as np
import pytest
import scipy.sparse
from support.rod_cases import ForceControl, helix, interpolated_curve, straight, twisted_patches

from rve_rod.errors import InputError
from rve_rod.rod import (
    END,
    START,
    Clamp,
    DistributedLoad,
    EndLoad,
    Joint,
    LineLoads,
    Offset,
    Pin,
    PointLoad,
    PointSupport,
    RodEnd,
    RodModel,
    RodPatch,
    SectionStiffness,
)
from rve_rod.rod.quaternion import from_rotation_vector, multiply, rotation_matrix

SECTION = SectionStiffness.circular(radius=0.2, youngs_modulus=100.0, rotational_modulus=50.0)


def helix_pieces(n_patches, n=8, degree=4):
    """Consecutive pieces of one helix (each its own interpolation)."""
    full = helix(radius=1.0, pitch=1.2, turns=0.8, degree=degree, n=4 * n)
    bounds = np.linspace(0.0, 1.0, n_patches + 1)
    pieces = []
    for a, b in itertools.pairwise(bounds):
        pieces.append(_resample(full, a, b, degree, n))
    return pieces


def _resample(curve, a, b, degree, n):
    return interpolated_curve(lambda u: curve(a + (b - a) * u), degree, n)


class Foundation:
    """Elastic foundation f = -k (x - x0) at the collocation points (a state-dependent load
    built the way contact builds its Jacobian: from the collocation basis and the layout)."""

    def __init__(self, model, stiffness):
        self.stiffness = stiffness
        self.anchor = model.centreline_at_collocation(model.reference_state())

    def __call__(self, model, state, load_factor):
        m = model.n_collocation
        x = model.centreline_at_collocation(state)
        rows, columns, values = [], [], []
        for k, data in enumerate(model.collocation):
            positions = model.layout.position_dofs(k)
            local = data.first - model.layout.first_point(k)
            width = data.basis.shape[1]
            for c in range(3):
                for a in range(width):
                    rows.append(c * m + data.points)
                    columns.append(positions[local + a, c])
                    values.append(-self.stiffness * load_factor * data.basis[0, a])
        jacobian = scipy.sparse.csr_matrix(
            (np.concatenate(values), (np.concatenate(rows), np.concatenate(columns))),
            shape=(3 * m, model.n_dofs),
        )
        return LineLoads(
            force=-self.stiffness * load_factor * (x - self.anchor), force_jacobian=jacobian
        )


def stretch_offset(index, lattice):
    """Offset x_second - x_first = (1 + state[index]) * lattice for a periodic joint."""

    def offset(state, load_factor):
        return Offset((1.0 + state[index]) * lattice, np.array([index]), lattice[:, None])

    return offset


def open_chain_model():
    patches = twisted_patches(helix_pieces(3), SECTION, twist=0.7)
    conditions = [
        Clamp(RodEnd(0, START), displacement=[0.1, -0.2, 0.05], rotation=[0.3, 0.1, -0.2]),
        Joint(RodEnd(0, END), RodEnd(1, START), force=[0.01, 0.02, -0.01], moment=[0, 0.01, 0]),
        Joint(RodEnd(1, END), RodEnd(2, START)),
        EndLoad(RodEnd(2, END), force=[0.05, -0.02, 0.1], moment=[0.01, 0.0, 0.02]),
    ]
    loads = [
        DistributedLoad(force=[0.0, 0.0, -0.02], moment=[0.001, 0, 0]),
        PointLoad(patch=1, parameter=0.37, force=[0.02, 0.01, 0.0], moment=[0, 0, 0.003]),
    ]
    model = RodModel(patches, conditions, loads)
    return RodModel(patches, conditions, [*loads, Foundation(model, 0.5)])


def pinned_model():
    patches = twisted_patches([straight(2.0, 3, 9)], SECTION, twist=1.3)
    conditions = [
        Pin(RodEnd(0, START), displacement=[0.0, 0.1, 0.0], moment=[0.02, 0.0, 0.01]),
        EndLoad(RodEnd(0, END), force=[0.0, 0.05, 0.0]),
    ]
    return RodModel(patches, conditions)


def periodic_model(rotation_stiffness=np.inf):
    pieces = helix_pieces(2)
    patches = twisted_patches(pieces, SECTION, twist=-0.4)
    lattice = pieces[0].control_points[0] - pieces[1].control_points[-1]
    stretch = 7 * sum(patch.n_control_points for patch in patches)  # extra unknown 0
    conditions = [
        Joint(RodEnd(0, END), RodEnd(1, START)),
        Joint(RodEnd(1, END), RodEnd(0, START), offset=stretch_offset(stretch, lattice)),
        ForceControl(RodEnd(0, START), np.array([0.0, 0.0, 1.0]), 0.03),
        PointSupport(
            1,
            0.4,
            first_unknown=1,
            rotation_axes=([0.0, 0.0, 2.0], [1.0, 1.0, 0.0]),
            rotation_stiffness=rotation_stiffness,
        ),
    ]
    return RodModel(patches, conditions, extra_unknowns=6, extra_state_scale=0.1)


def perturbed_state(model, rng, size=0.05):
    state = model.reference_state()
    layout = model.layout
    for k in range(layout.n_patches):
        state[layout.position_dofs(k)] += size * rng.normal(size=layout.position_dofs(k).shape)
        state[layout.quaternion_dofs(k)] += size * rng.normal(size=layout.quaternion_dofs(k).shape)
    state[layout.extra_dofs()] += size * rng.normal(size=layout.n_extra)
    return state


def finite_difference_jacobian(model, state, load_factor, step=1e-6):
    columns = []
    for i in range(state.size):
        plus, minus = state.copy(), state.copy()
        plus[i] += step
        minus[i] -= step
        columns.append(
            (model.residual(plus, load_factor) - model.residual(minus, load_factor)) / (2 * step)
        )
    return np.array(columns).T


def compliant_periodic_model():
    """The periodic model with its support's rotations held by springs (0.7 N mm / rad)."""
    return periodic_model(rotation_stiffness=0.7)


@pytest.mark.parametrize(
    "build", [open_chain_model, pinned_model, periodic_model, compliant_periodic_model]
)
def test_jacobian_matches_finite_differences(build):
    model = build()
    state = perturbed_state(model, np.random.default_rng(3))
    analytic = model.evaluate(state, 0.7).jacobian.toarray()
    numeric = finite_difference_jacobian(model, state, 0.7)
    row_scale = np.abs(analytic).max(axis=1, keepdims=True)
    assert np.all(row_scale > 0)
    np.testing.assert_array_less(np.abs(analytic - numeric) / row_scale, 1e-6)


def test_end_values_follow_the_state_asked_for():
    # end_values reuses the local equations of the last evaluation with its Jacobian when
    # asked at the same state: it gives what the end's own kernels give, at every state.
    model = periodic_model()
    rng = np.random.default_rng(5)
    first, second = perturbed_state(model, rng), perturbed_state(model, rng)
    end = RodEnd(1, END)
    alone = [model.end_values(state, end) for state in (first, second)]
    model.evaluate(first, 0.7)
    for state, expected in ((first, alone[0]), (second, alone[1]), (first, alone[0])):
        values = model.end_values(state, end)
        for name in ("position", "quaternion", "force", "moment", "d_force", "d_moment"):
            np.testing.assert_allclose(
                getattr(values, name), getattr(expected, name), rtol=1e-13, atol=1e-15
            )
    assert not np.allclose(alone[0].force, alone[1].force)
    # a new natural length changes the end's forces at the evaluated state
    model.evaluate(first, 0.7)
    model.set_prestrain(0.02)
    stretched = model.end_values(first, end)
    fresh = periodic_model()
    fresh.set_prestrain(0.02)
    np.testing.assert_allclose(stretched.force, fresh.end_values(first, end).force, rtol=1e-13)
    assert not np.allclose(stretched.force, alone[0].force)


@pytest.mark.parametrize("build", [open_chain_model, pinned_model, periodic_model])
def test_curved_twisted_reference_is_stress_free(build):
    model = build()
    evaluation = model.evaluate(model.reference_state(), 0.0)
    residual = evaluation.residual / model.residual_scale()
    extra = model.layout.extra_dofs()
    residual[extra] = 0.0  # the extra equation of the periodic model asks for a force
    assert np.abs(residual).max() < 1e-12
    assert np.abs(evaluation.section.force).max() < 1e-12 * SECTION.axial
    assert np.abs(evaluation.section.moment).max() < 1e-12 * SECTION.axial


def free_model():
    patches = twisted_patches(helix_pieces(2), SECTION, twist=0.9)
    return RodModel(
        patches,
        [
            EndLoad(RodEnd(0, START)),
            Joint(RodEnd(0, END), RodEnd(1, START)),
            EndLoad(RodEnd(1, END)),
        ],
    )


def rigidly_moved(model, state, rotation_vector, translation):
    q_rotation = from_rotation_vector(rotation_vector)
    moved = state.copy()
    for k in range(model.layout.n_patches):
        x, q = model.control_points(state, k)
        moved[model.layout.position_dofs(k)] = x @ rotation_matrix(q_rotation).T + translation
        moved[model.layout.quaternion_dofs(k)] = multiply(q_rotation, q)
    return moved


def test_rigid_motion_of_reference_gives_no_strain_and_no_force():
    model = free_model()
    moved = rigidly_moved(model, model.reference_state(), np.array([2.0, -1.0, 0.5]), [3, 1, -2])
    evaluation = model.evaluate(moved, 0.0)
    assert np.abs(evaluation.residual / model.residual_scale()).max() < 1e-12
    assert np.abs(evaluation.section.force).max() < 1e-12 * SECTION.axial
    assert np.abs(evaluation.section.moment).max() < 1e-12 * SECTION.axial


def test_rigid_motion_of_deformed_state_rotates_forces_and_residual():
    model = free_model()
    state = perturbed_state(model, np.random.default_rng(5))
    rotation_vector = np.array([0.4, 1.1, -2.0])
    rotation = rotation_matrix(from_rotation_vector(rotation_vector))
    before = model.evaluate(state, 0.0)
    after = model.evaluate(rigidly_moved(model, state, rotation_vector, [1, 2, 3]), 0.0)
    np.testing.assert_allclose(after.section.force, rotation @ before.section.force, atol=1e-10)
    np.testing.assert_allclose(after.section.moment, rotation @ before.section.moment, atol=1e-10)
    # The joint's rotation rows measure the relative rotation in the material frame: invariant.
    joint_rows = model.layout.end_rows(RodEnd(0, END))[3:]
    np.testing.assert_allclose(after.residual[joint_rows], before.residual[joint_rows], atol=1e-12)
    rows = before.residual.copy()
    rows[joint_rows] = after.residual[joint_rows] = 0.0
    rows, moved_rows = rows.reshape(-1, 7), after.residual.reshape(-1, 7)
    np.testing.assert_allclose(moved_rows[:, :3], rows[:, :3] @ rotation.T, atol=1e-10)
    np.testing.assert_allclose(moved_rows[:, 3:6], rows[:, 3:6] @ rotation.T, atol=1e-10)
    np.testing.assert_allclose(moved_rows[:, 6], rows[:, 6], atol=1e-12)


@pytest.mark.parametrize("parameter", [0.0, 0.01, 0.5, 0.93, 1.0])
def test_point_load_weights_conserve_the_resultant(parameter):
    model = pinned_model()
    points, weights = model.point_load_weights(0, parameter)
    assert np.sum(weights * model.tributary_lengths[points]) == pytest.approx(1.0, rel=1e-12)
    interior = model.layout.points(0)[1:-1]
    assert np.all(np.isin(points, interior))


def test_tributary_lengths_add_up_to_the_arc_length():
    model = open_chain_model()
    assert model.tributary_lengths.sum() == pytest.approx(model.characteristic_length, rel=1e-10)


def test_layout_numbers_control_points_patch_after_patch():
    model = open_chain_model()
    layout = model.layout
    assert layout.n_dofs == 7 * 24
    np.testing.assert_array_equal(layout.position_dofs(1)[0], [56, 57, 58])
    np.testing.assert_array_equal(layout.quaternion_dofs(2)[-1], [164, 165, 166, 167])
    np.testing.assert_array_equal(layout.end_rows(RodEnd(1, END)), 7 * 15 + np.arange(6))
    state = model.reference_state()
    np.testing.assert_allclose(
        model.centreline_at_collocation(state)[:, 8:16].T,
        model.positions(state, 1, model.collocation[1].parameters),
        atol=1e-14,
    )
    np.testing.assert_allclose(
        model.collocation[1].matrix(2).toarray() @ model.control_points(state, 1)[0],
        model.patches[1].centreline(model.collocation[1].parameters, 2),
        atol=1e-10,
    )


def test_bad_setups_raise_input_error():
    patches = twisted_patches([straight(1.0, 2, 5)], SECTION, twist=0.0)
    with pytest.raises(InputError, match=r"without a condition: RodEnd\(patch=0, side='end'\)"):
        RodModel(patches, [Clamp(RodEnd(0, START))])
    with pytest.raises(InputError, match="claimed by conditions 0 and 1"):
        RodModel(patches, [Clamp(RodEnd(0, START)), EndLoad(RodEnd(0, START))])
    with pytest.raises(InputError, match="0 extra equations for 2 extra unknowns"):
        RodModel(patches, [Clamp(RodEnd(0, START)), EndLoad(RodEnd(0, END))], extra_unknowns=2)
    with pytest.raises(InputError, match="links an 'end' side to a 'start' side"):
        Joint(RodEnd(0, START), RodEnd(0, END))
    with pytest.raises(InputError, match="degree=1"):
        RodPatch(straight(1.0, 1, 4), np.tile([1.0, 0, 0, 0], (4, 1)), SECTION)
    model = RodModel(patches, [Clamp(RodEnd(0, START)), EndLoad(RodEnd(0, END))])
    with pytest.raises(InputError, match="state has shape"):
        model.evaluate(np.zeros(3))
    with pytest.raises(InputError, match=r"parameter=1\.5 is outside"):
        model.point_load_weights(0, 1.5)


@pytest.mark.parametrize("stiffness", [0.0, -1.0, float("nan")])
def test_a_support_rotation_stiffness_must_be_positive(stiffness):
    with pytest.raises(InputError, match=r"rotation_stiffness=.* must be > 0"):
        PointSupport(0, 0.5, rotation_axes=([1.0, 0.0, 0.0],), rotation_stiffness=stiffness)
