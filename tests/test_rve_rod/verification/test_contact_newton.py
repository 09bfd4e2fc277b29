"""Newton's method with the contact tangent converges quadratically (normal, stick, slip)."""

import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.linalg
from support.contact_scenes import crossed_rods, wrapped_rods

from rve_rod.contact import CompressibleYarnLaw, ContactModel, ContactOptions, CoulombFriction
from rve_rod.geometry.bspline import basis_matrix

N = 30
LAW = CompressibleYarnLaw(stiffness=5.0, exponent=1.5, yarn_radius=0.15)
SPRING = 2.0  # N/mm^2: every point of rod 0 is pulled towards its target
STATES = [
    (None, "normal"),
    (CoulombFriction(coefficient=5.0, tangential_stiffness=0.5), "stick"),
    (CoulombFriction(coefficient=0.1, tangential_stiffness=5.0), "slip"),
]
"""Friction settings that put the contacts in normal contact, stick and slip."""


def solve(friction, target_shift, iterations=12, scene=None, law=LAW, balance=False):
    """Rod 0 held by springs at its collocation points, pulled into the fixed rod 1 (of the
    crossed-rods scene unless another two-rod scene is given, both rods of one size).

    Residual at rod 0's collocation points: SPRING (x_j - target_j) - f_j = 0, unknowns
    rod 0's control points. Returns the residual norms of the Newton iterations and the
    final contact result. `balance`: `ContactOptions.balance` (rod 0 also takes the reactions
    of rod 1's loads).
    """
    if scene is None:
        scene = crossed_rods(separation=0.3, length=2.0, n_control_points=N)
    n = scene.patches[0].n_control_points
    options = ContactOptions(balance=balance)
    model = ContactModel(
        scene.patches, scene.positions, law, friction=friction, yarns=scene.yarns, options=options
    )
    basis = basis_matrix(scene.patches[0].knots, 4, scene.patches[0].collocation_parameters)
    collocation = scipy.sparse.kron(basis, scipy.sparse.eye(3)).tocsr()  # (3m, 3n) on rod 0
    target = (basis @ scene.positions[:n] + target_shift).ravel()
    positions = scene.positions.copy()
    norms = []
    # Residual rows point by point (3j + c); the contact Jacobian's rows are c M + j.
    rows = (np.arange(3)[None, :] * 2 * n + np.arange(n)[:, None]).ravel()
    for _ in range(iterations):
        result = model.evaluate(positions)
        residual = (
            SPRING * (collocation @ positions[:n].ravel() - target)
            - result.line_load[:, :n].T.ravel()
        )
        norms.append(np.linalg.norm(residual))
        if norms[-1] < 1e-14:
            break
        jacobian = SPRING * collocation - result.jacobian.tocsr()[rows][:, : 3 * n]
        step = scipy.sparse.linalg.spsolve(jacobian.tocsc(), -residual)
        positions[:n] += step.reshape(-1, 3)
    return np.array(norms), result


@pytest.mark.parametrize(("friction", "state"), STATES)
def test_newton_converges_quadratically(friction, state):
    norms, result = solve(friction, np.array([0.0, 0.01, -0.06]))
    stats = result.statistics
    assert norms[-1] < 1e-13 and stats.active_contacts > 4
    if state == "stick":
        assert stats.sticking == stats.active_contacts
    if state == "slip":
        assert stats.sliding == stats.active_contacts
    # Quadratic: e_{k+1} / e_k^2 stays bounded over the last three iterates above round-off
    # (for a linearly convergent method it would grow like 1 / e_k, here to ~1e8).
    tail = norms[norms > 1e-12][-3:]
    assert tail[-1] < 1e-7
    assert np.all(tail[1:] / tail[:-1] ** 2 < 5.0)
    assert len(norms) <= 8


@pytest.mark.parametrize(("friction", "state"), STATES)
def test_newton_converges_quadratically_with_shared_minima(friction, state):
    """The straight rod pulled into a rod wrapped around it: points with two close distance
    minima share one contact (weights strictly between 0 and 1 at the solution), and the
    weights' derivatives keep Newton quadratic."""
    law = CompressibleYarnLaw(stiffness=5.0, exponent=1.5, yarn_radius=0.2)
    norms, result = solve(
        friction, np.array([0.0, 0.0, -0.01]), scene=wrapped_rods(tilt=0.01), law=law
    )
    stats = result.statistics
    weight = result.contacts.weight
    assert norms[-1] < 1e-13
    assert np.count_nonzero((weight > 0.05) & (weight < 0.95)) >= 2
    if state == "stick":
        assert stats.sticking == stats.active_contacts
    if state == "slip":  # the two contacts with the smallest normal load stick
        assert stats.sliding >= 0.8 * stats.active_contacts
    # e_{k+1} / e_k^2 measured 2.9-8.8 over the last iterates (the residual falls from 4e-7 or
    # 3e-8 to round-off in one step); a linearly convergent method would grow like 1 / e_k, to
    # ~1e4 here.
    tail = norms[norms > 1e-12][-3:]
    assert tail[-1] < 1e-6
    assert np.all(tail[1:] / tail[:-1] ** 2 < 10.0)
    assert len(norms) <= 8


@pytest.mark.parametrize(("friction", "state"), STATES)
def test_newton_converges_quadratically_with_the_balanced_contact(friction, state):
    """`ContactOptions.balance`: the reactions on the master (with the master parameter's
    sensitivity) keep the tangent consistent, so Newton stays quadratic. Measured: normal and
    stick e_{k+1} / e_k^2 = 0.4-2.4 down to 6e-15; slip (two more contacts join on the way,
    10 sliding) 28 and 9 down to 3e-9, then the round-off floor of a few 1e-13."""
    norms, result = solve(friction, np.array([0.0, 0.01, -0.06]), balance=True)
    assert result.statistics.active_contacts > 4
    tail = norms[norms > 1e-12][-3:]
    assert tail[-1] < 1e-7
    assert np.all(tail[1:] / tail[:-1] ** 2 < (5.0 if state != "slip" else 50.0))
    assert norms.min() < (1e-13 if state != "slip" else 1e-12)
