"""The periodic loop cell: rest state, independence of the cut, P as the energy derivative,
the macro equations' tangents, Newton's rate, and friction's dissipation.

All on the test loop of `rve_cases` (the cotton stitch-5.5 loop with a yarn radius of 0.16 mm
that touches nothing at rest).
"""

import dataclasses
import itertools
from dataclasses import dataclass

import numpy as np
import pytest
import scipy.sparse.linalg
from pins import assert_pinned
from support.rve_cases import CURVES, FABRIC

from rve_rod.contact import ContactOptions
from rve_rod.newton import NewtonOptions, newton_solve, solve_path
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import LoadCase, load_case
from rve_rod.rve.simulation import RveSettings, build_cell, run_cell
from rve_rod.rve.yarn import YarnSettings


def settings(friction=False, control_points=20, cut=1.0):
    return RveSettings(
        cell=CellSettings(control_points=control_points, cut=cut),
        yarn=YarnSettings(friction=friction),
    )


@dataclass(frozen=True)
class Fixed(LoadCase):
    """All four components prescribed: F(t) = I + t (final - I)."""

    final: tuple = ((1.0, 0.0), (0.0, 1.0))
    name = "fixed"

    def final_deformation(self):
        return np.array(self.final)

    def control(self):
        return 1.0


@dataclass(frozen=True)
class Cycle(LoadCase):
    """Strip-biaxial course-wise loading to `max_strain` at t = 1/2 and back to 0 at t = 1."""

    max_strain: float = 0.15
    name = "cycle"

    def final_deformation(self):
        return np.diag([1.0 + self.max_strain, 1.0])

    def prescribed(self, load_factor):
        return super().prescribed(1.0 - abs(2.0 * load_factor - 1.0))

    def control(self):
        return self.max_strain


def equilibrium(cell, targets):
    return solve_path(cell.problem(), cell.reference_state(), targets).final_state


@pytest.mark.parametrize("friction", [False, True])
def test_unloaded_cell_stays_in_its_reference_state_with_zero_force(friction):
    chosen = settings(friction)
    cell = build_cell(CURVES, FABRIC, load_case("strip-biaxial-course", 0.1, 3), chosen)
    result = run_cell(cell, FABRIC, chosen)
    rest = result.steps[0]
    assert rest.active_contacts == 0
    np.testing.assert_allclose(result.centrelines[0], cell.curve.control_points, atol=1e-12)
    scale = np.abs(result.steps[-1].first_piola).max()
    assert scale > 1e-4  # the loaded state carries force ...
    assert np.abs(rest.first_piola).max() < 1e-10 * scale  # ... the rest state none


def test_forces_do_not_depend_on_where_the_yarn_is_cut():
    """Cuts at mirror or glide images of each other give the same discrete cell; other cuts
    change only the knot layout, i.e. the discretization. The cuts stay in the contact-free
    arc around the leg point L (quarter curve 1), which on this loop reaches to about 0.85
    at 20 % (a cut at 0.8 is touched at 20 %)."""
    finals = {}
    for cut in (1.0, 3.0, 0.9, 1.1, 0.85):
        chosen = settings(cut=cut)
        cell = build_cell(CURVES, FABRIC, load_case("uniaxial-course", 0.2, 5), chosen)
        result = run_cell(cell, FABRIC, chosen)
        assert result.series("contacts_at_cut").max() == 0
        assert result.steps[-1].active_contacts > 10
        finals[cut] = np.array([result.steps[-1].first_piola[0, 0], result.poisson_ratio])
    assert np.abs(finals[3.0] / finals[1.0] - 1).max() < 1e-8  # glide image (x + w/2, -y)
    assert np.abs(finals[1.1] / finals[0.9] - 1).max() < 1e-8  # 2-fold rotation about L
    assert np.abs(finals[0.85] / finals[1.0] - 1).max() < 2e-2  # other knots


def stored_energy(cell, state, load_factor):
    """Strain energy of the rod plus contact energy (N mm), both integrated with the
    collocation weights; each contact appears in both passes, hence the contact half."""
    model = cell.model
    section = model.patches[0].section
    evaluation = model.evaluate(state, load_factor, with_jacobian=False)
    frames = model.rotations(state, 0, model.collocation[0].parameters)
    force = np.einsum("mji,jm->im", frames, evaluation.section.force)
    moment = np.einsum("mji,jm->im", frames, evaluation.section.moment)
    density = 0.5 * (force**2 / section.translational[:, None]).sum(0)
    density += 0.5 * (moment**2 / section.rotational[:, None]).sum(0)
    weights = cell.coupling.weights
    contacts = cell.coupling.result(state, load_factor, tangent=False).contacts
    applied = ~np.isin(contacts.slave, cell.coupling.end_points)
    contact = (
        0.5
        * weights[contacts.slave[applied]]
        @ cell.yarn.law.line_energy(contacts.penetration[applied])
    )
    stick = 0.0
    if cell.yarn.friction is not None:
        friction = contacts.friction_load[:, applied]
        stick = (
            0.5
            * weights[contacts.slave[applied]]
            @ (0.5 * (friction**2).sum(0) / cell.yarn.friction.tangential_stiffness)
        )
    return weights @ density + contact + stick


@pytest.mark.parametrize(
    ("balance", "tolerances"),
    [(False, (3e-3, 2.5e-2)), (True, (5e-3, 6e-3))],
    ids=["two-pass", "balanced"],
)
def test_macro_stress_is_the_derivative_of_the_stored_energy(balance, tolerances):
    """Frictionless: P_ab = dW/dF_ab / (w c) by central differences of re-equilibrated
    states. P12 and P22 are carried by the image contacts alone (with the 1/2 of the two
    collocation passes). The two-pass contact forces are not exactly conservative nor in
    balance (the support takes a net force), which limits the agreement to 3e-4 of |P| in
    P11, P22 and 1-1.7e-2 in P12, P21 at 20, 36 and 68 control points alike (docs/rve.md).
    The balanced contact (`ContactOptions.balance`) is in balance but not conservative either:
    at 36 control points 2.7e-3 / 2.2e-4 in P11, P22 and 3.3e-3 / 1.2e-3 in P12, P21 (two-pass
    1.0e-3 / 6.9e-4 and 1.1e-2 / 7.2e-3)."""
    chosen = settings(control_points=36)
    chosen = dataclasses.replace(
        chosen, cell=dataclasses.replace(chosen.cell, contact=ContactOptions(balance=balance))
    )
    final = np.array([[1.12, 0.03], [0.02, 0.93]])
    cell = build_cell(CURVES, FABRIC, Fixed(final=tuple(map(tuple, final))), chosen)
    state = equilibrium(cell, [0.5, 1.0])
    derived = cell.evaluate_state(state, 1.0)
    P = derived.stress.first_piola
    assert derived.stress.images[0, 1] == pytest.approx(P[0, 1], rel=1e-12)  # images only
    assert abs(P[0, 1]) > 0.2 * np.abs(P).max()
    step, area = 1e-4, 1.33 * 1.26
    for a, b in itertools.product(range(2), repeat=2):
        energies = []
        for sign in (1.0, -1.0):
            perturbed = final.copy()
            perturbed[a, b] += sign * step
            other = build_cell(CURVES, FABRIC, Fixed(final=tuple(map(tuple, perturbed))), chosen)
            solved = newton_solve(other.problem(), state, 1.0)
            assert solved.converged
            energies.append(stored_energy(other, solved.state, 1.0))
        derivative = (energies[0] - energies[1]) / (2 * step * area)
        tolerance = tolerances[0] if a == b else tolerances[1]
        assert abs(derivative - P[a, b]) < tolerance * np.abs(P).max(), (a, b, derivative, P)


UNLOADED = 0.98
"""Load factor of `loaded_state`: back from 15 % to 14.7 % strain."""


def loaded_state(name, friction, control_points=20):
    """A converged state at 14.7 % strain whose friction anchors are those of 15 %. Under
    monotonic loading every contact slides (its elastic slip stays on the Coulomb cone); on the
    reversal some contacts stick and some slip, so both branches of the friction law act.
    20 control points per quarter loop: at 12 the flat loop's contacts are under-resolved and
    Newton on this path stalls (wale-wise at t = 0.73, course-wise with friction at t = 0.98).
    The converged state is polished by one more Newton step: its error is up to its last
    (unapplied) correction, 1e-10 of the state scale, after the step round-off."""
    chosen = settings(friction, control_points)
    cell = build_cell(CURVES, FABRIC, load_case(name, 0.15, 4), chosen)
    previous = solve_path(cell.problem(), cell.reference_state(), [1 / 3, 2 / 3, 1.0]).final_state
    solved = newton_solve(cell.problem(), previous, UNLOADED)
    assert solved.converged
    residual, jacobian = cell.problem().evaluate(solved.state, UNLOADED)
    return cell, solved.state - scipy.sparse.linalg.spsolve(jacobian.tocsc(), residual)


@pytest.mark.parametrize(
    ("name", "friction"),
    [("uniaxial-course", False), ("uniaxial-wale", False), ("uniaxial-course", True)],
)
def test_cell_jacobian_matches_central_differences(name, friction):
    """The whole cell: rod, periodic joint with F a1, support, the contact coupling with its
    F columns, and the macro equations of the free component (with friction in slip)."""
    cell, state = loaded_state(name, friction)
    model = cell.model
    evaluation = model.evaluate(state, UNLOADED)
    contacts = cell.coupling.result(state, UNLOADED).statistics
    assert contacts.active_contacts > 4
    if friction:
        assert contacts.sliding > 0 and contacts.sticking > 0
    step = 1e-7
    jacobian = evaluation.jacobian.toarray()
    differences = np.empty_like(jacobian)
    for column in range(state.size):
        plus, minus = state.copy(), state.copy()
        plus[column] += step
        minus[column] -= step
        differences[:, column] = (
            model.residual(plus, UNLOADED) - model.residual(minus, UNLOADED)
        ) / (2 * step)
    scale = np.abs(differences).max(axis=1, keepdims=True)
    assert np.all(np.abs(jacobian - differences) <= 1e-6 * np.maximum(scale, 1e-12))
    macro = cell.macro.columns[0]
    assert np.abs(differences[:, macro]).max() > 0  # the free F component enters the equations


@pytest.mark.parametrize("friction", [False, True])
def test_coupling_assembles_the_contact_derivatives_entry_by_entry(friction):
    """The coupling's derivatives (the contacts' blocks chained straight into the rod's
    numbering by one kernel pass) are the contact's per-point matrices mapped to the state:
    d line load / d positions at columns 7i + c, and d line load / d F at the free unknowns."""
    cell, state = loaded_state("uniaxial-course", friction)
    result = cell.coupling.result(state, UNLOADED)
    assert result.contacts.slave.size > 4
    assembled = cell.coupling(cell.model, state, UNLOADED).force_jacobian.toarray()
    by_positions = result.jacobian.toarray()
    expected = np.zeros_like(assembled)
    for c in range(3):
        expected[:, 7 * np.arange(by_positions.shape[1] // 3) + c] = by_positions[:, c::3]
    components = cell.macro.contact_components()
    expected[:, cell.macro.columns] = result.deformation_jacobian[:, components]
    assert np.abs(expected).max() > 0
    np.testing.assert_allclose(assembled, expected, rtol=1e-14, atol=1e-14 * np.abs(expected).max())


@pytest.mark.parametrize("friction", [False, True])
def test_newton_error_after_one_step_is_quadratic(friction):
    """Error after one Newton step from perturbed solutions: slope 2 in the perturbation size.
    Beyond relative perturbations of about 1e-7 a contact near the Coulomb cone may switch
    between stick and slip, which the tangent at the solution cannot foresee."""
    cell, solution = loaded_state("uniaxial-course", friction)
    problem = cell.problem()
    scale = cell.model.state_scale()
    direction = np.random.default_rng(3).normal(size=solution.size) * scale
    errors = []
    sizes = np.array([1e-7, 3e-8, 1e-8])
    for size in sizes:
        one_step = newton_solve(
            problem, solution + size * direction, UNLOADED, NewtonOptions(max_iterations=1)
        )
        errors.append(np.max(np.abs(one_step.state - solution) / scale))
    slope = np.polyfit(np.log(sizes), np.log(errors), 1)[0]
    assert 1.8 < slope < 2.2, errors
    assert errors[-1] < 1e-10


def test_free_direction_carries_no_stress():
    chosen = settings()
    for name, free in (("uniaxial-course", (1, 1)), ("uniaxial-wale", (0, 0))):
        cell = build_cell(CURVES, FABRIC, load_case(name, 0.2, 5), chosen)
        result = run_cell(cell, FABRIC, chosen)
        loaded = np.abs(result.steps[-1].first_piola).max()
        for step in result.steps:
            assert abs(step.first_piola[free]) <= step.regularization + 1e-9 * loaded
            assert step.regularization < 1e-3 * loaded


def test_friction_dissipates_on_a_load_cycle():
    """Loading to 15 % and back: with friction the work done exceeds the stored energy at
    every state, the unloading force is lower (hysteresis) and the cycle dissipates; without
    it the cycle returns all its work (in between, the two-pass contact's non-conservativeness
    shows as an apparent dissipation of up to 0.3 % of the work, the trapezoid rule's error at
    the reversal as 0.2 %)."""
    dissipated = {}
    for friction in (False, True):
        chosen = settings(friction)
        cell = build_cell(CURVES, FABRIC, Cycle(steps=31), chosen)
        result = run_cell(cell, FABRIC, chosen)
        F = result.series("deformation")
        P = result.series("first_piola")
        work = np.concatenate(
            [[0.0], np.cumsum(np.einsum("kab,kab->k", 0.5 * (P[1:] + P[:-1]), np.diff(F, axis=0)))]
        )
        work *= 1.33 * 1.26
        # the stored energy needs the rotations too: follow the same path again
        path = solve_path(cell.problem(), cell.reference_state(), cell.case.load_factors()[1:])
        states = [step.state for step in path.steps]
        energy = np.array(
            [
                stored_energy(cell, state, t)
                for state, t in zip(states, cell.case.load_factors(), strict=True)
            ]
        )
        dissipation = work - (energy - energy[0])
        peak = work.max()
        assert dissipation.min() > -1e-3 * peak  # never more out than in (trapezoid error)
        dissipated[friction] = dissipation[-1] / peak
        loading, unloading = P[1:15, 0, 0], P[29:15:-1, 0, 0]  # at the same strains
        if friction:
            assert np.all(unloading <= loading + 1e-8 * loading.max())
            assert (loading - unloading).max() > 0.02 * loading.max()
    assert abs(dissipated[False]) < 1e-6
    assert dissipated[True] > 0.02
    assert_pinned("RVE_FRICTION_CYCLE", {"dissipated fraction": dissipated[True]})
