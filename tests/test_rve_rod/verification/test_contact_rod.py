"""Contact coupled to the rod engine: two clamped Cosserat rods crossing at right angles, the
upper one loaded, solved by the rod's Newton with the contact loads as a state-dependent load.

The adapter below is the whole coupling (docs/contact.md): contact positions are the rod's
control-point positions, the Jacobian columns 3 i + c map to the rod's state index 7 i + c.
"""

import numpy as np
import pytest
import scipy.sparse
from support.contact_scenes import crossed_rods

from rve_rod.contact import CompressibleYarnLaw, ContactModel, CoulombFriction
from rve_rod.geometry.bspline import BSplineCurve
from rve_rod.newton import solve_path
from rve_rod.rod import (
    END,
    START,
    Clamp,
    DistributedLoad,
    LineLoads,
    RodEnd,
    RodModel,
    RodPatch,
    SectionStiffness,
)

RADIUS, LENGTH, N = 0.15, 2.0, 33
SECTION = SectionStiffness.circular(RADIUS, 80.0, rotational_modulus=40.0)
LAW = CompressibleYarnLaw(stiffness=400.0, exponent=1.5, yarn_radius=RADIUS)


class ContactLoad:
    """rve_rod.rod state-dependent load: the contact line loads at the rod's collocation points."""

    def __init__(self, contact: ContactModel):
        self.contact = contact
        self.calls = 0

    def positions(self, model: RodModel, state: np.ndarray) -> np.ndarray:
        return state[: 7 * model.n_collocation].reshape(-1, 7)[:, :3]

    def __call__(self, model, state, load_factor) -> LineLoads:
        self.calls += 1
        result = self.contact.evaluate(self.positions(model, state))
        jacobian = result.jacobian
        columns = 7 * (jacobian.col // 3) + jacobian.col % 3
        force_jacobian = scipy.sparse.csr_matrix(
            (jacobian.data, (jacobian.row, columns)), shape=(jacobian.shape[0], model.n_dofs)
        )
        return LineLoads(force=result.line_load, force_jacobian=force_jacobian)

    def commit(self, model, state):
        positions = self.positions(model, state)
        self.contact.commit(self.contact.evaluate(positions, tangent=False))


def crossed_rod_model(friction, load):
    scene = crossed_rods(separation=2 * RADIUS, length=LENGTH, n_control_points=N)
    curves = [
        BSplineCurve(4, patch.knots, scene.positions[k * N : (k + 1) * N])
        for k, patch in enumerate(scene.patches)
    ]
    contact = ContactModel(
        scene.patches, scene.positions, LAW, friction=friction, yarns=scene.yarns
    )
    coupling = ContactLoad(contact)
    patches = [RodPatch.chain([curve], SECTION)[0] for curve in curves]
    conditions = [Clamp(RodEnd(k, side)) for k in (0, 1) for side in (START, END)]
    model = RodModel(
        patches, conditions, loads=[DistributedLoad(force=load, patches=(0,)), coupling]
    )
    return model, coupling


@pytest.mark.parametrize("friction", [None, CoulombFriction(0.3, 400.0)], ids=["normal", "mu"])
def test_pressed_rods_share_the_load_as_beam_theory_predicts(friction):
    q = 0.004  # N/mm downward on rod 0
    model, coupling = crossed_rod_model(friction, [0.0, 0.0, -q])
    path = solve_path(
        model.problem(commit=lambda state, _: coupling.commit(model, state)),
        model.reference_state(),
        [0.25, 0.5, 0.75, 1.0],
    )
    final = path.steps[-1]
    # Newton converges quadratically on the coupled system.
    norms = np.array(final.residual_norms)
    tail = norms[norms > 1e-12][-3:]
    assert final.iterations <= 8 and np.all(tail[1:] / tail[:-1] ** 2 < 1e3)

    result = coupling.contact.evaluate(coupling.positions(model, final.state))
    weights = model.tributary_lengths
    force_0 = (result.line_load[:, :N] * weights[:N]).sum(axis=1)
    force_1 = (result.line_load[:, N:] * weights[N:]).sum(axis=1)
    # Clamped-clamped beams, rigid contact: rod 0 under q and -P, rod 1 under P meet at the
    # crossing when q L^4/384 - P L^3/192 = P L^3/192, i.e. P = q L / 4 (measured: 0.90 of
    # it); the penalty's compliance lets rod 0 sink into rod 1 and carry more itself.
    expected = q * LENGTH / 4
    assert 0.8 * expected < force_0[2] < expected
    assert force_1[2] == pytest.approx(-force_0[2], rel=0.02)
    assert result.statistics.max_penetration < 0.05 * RADIUS
    assert abs(force_0[0]) + abs(force_0[1]) < 1e-6 * force_0[2]
