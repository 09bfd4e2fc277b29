"""The consistent tangent of the membrane: finite differences of the residual, quadratic Newton
convergence, symmetry for energy surfaces (and Krylov solvers on it), cutback and failure, and
a Ctrl-C that Python lost stopping the load path."""

import dataclasses
import re
import signal
import sys

import dolfinx.fem.petsc
import numpy as np
import pytest
from dolfinx import fem
from support.signals import signal_inside_an_ignoring_callback
from support.surface_cases import COTTON_LIKE_LAW, synthetic_surface

from fabric_dolfinx.material import surface_material
from fabric_dolfinx.membrane.forms import green_lagrange, membrane_forms
from fabric_dolfinx.membrane.quadrature import QuadratureMaterial
from fabric_dolfinx.part.tension import TensionSetup
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.tension import TensionTest
from rve_rod.errors import ConvergenceError, terminate_as_interrupt
from rve_rod.stepping import SteppingOptions
from rve_rod.surface import ResponseSurface

# A stress fit need not derive from a potential: take S22 from a law with another coupling,
# so that dS11/dE22 != dS22/dE11 as in surfaces fitted to RVE data.
SYMMETRIC = synthetic_surface(kind="stress")
ASYMMETRIC = ResponseSurface(
    kind="stress",
    s11=SYMMETRIC.s11,
    s22=synthetic_surface(dataclasses.replace(COTTON_LIKE_LAW, coupling_22_11=-0.01)).s22,
    s12=SYMMETRIC.s12,
)
STRESS = surface_material(ASYMMETRIC)
ENERGY = surface_material(synthetic_surface(kind="energy"))


@pytest.fixture(scope="module")
def stretched():
    """A course-wise tension at 35 % (strains beyond the surface domain) at 30 degrees."""
    setup = TensionSetup(STRESS, TensionTest(max_strain=0.35, angle=30.0), SolverOptions(steps=7))
    result = setup.run()
    return setup, result


def membrane(setup, material):
    """(MembraneForms, QuadratureMaterial) of `material` on the setup's displacement."""
    points = QuadratureMaterial(
        green_lagrange(setup.u, setup.frame), setup.u.function_space.mesh, [material], 2
    )
    return membrane_forms(setup.u, points, setup.frame), points


def assembled(forms, u):
    """Residual vector and Jacobian matrix without boundary conditions, as numpy arrays
    (forms: (MembraneForms, QuadratureMaterial) brought to u first)."""
    forms, points = forms
    points.update()
    vector = dolfinx.fem.petsc.assemble_vector(fem.form(forms.residual))
    vector.ghostUpdate()
    matrix = dolfinx.fem.petsc.assemble_matrix(fem.form(forms.jacobian))
    matrix.assemble()
    return vector.array.copy(), matrix.convert("dense").getDenseArray()


def test_jacobian_matches_central_differences_of_the_residual(stretched):
    setup, result = stretched
    assert result.outside_domain
    forms = membrane(setup, STRESS)
    state = setup.u.x.array.copy()
    _, jacobian = assembled(forms, setup.u)
    direction = np.random.default_rng(3).normal(size=state.size) * 0.05
    step = 1e-5
    residuals = []
    for sign in (1.0, -1.0):
        setup.u.x.array[:] = state + sign * step * direction
        residuals.append(assembled(forms, setup.u)[0])
    setup.u.x.array[:] = state
    difference = (residuals[0] - residuals[1]) / (2 * step)
    action = jacobian @ direction
    assert np.linalg.norm(difference - action) <= 1e-7 * np.linalg.norm(action)


def test_newton_converges_quadratically():
    """One load step to 20 %: relative residuals e_k obey e_(k+1) <= C e_k^2."""
    setup = TensionSetup(STRESS, TensionTest(max_strain=0.2), SolverOptions(steps=1))
    norms = np.array(setup.run().path.steps[0].residual_norms)
    relative = norms / norms[0]
    assert relative.size >= 5 and relative[-1] < 1e-10
    order = np.log(relative[-1] / relative[-2]) / np.log(relative[-2] / relative[-3])
    assert order > 1.8
    tail = relative[2:]
    assert np.all(tail[1:] <= 20.0 * tail[:-1] ** 2)


def test_energy_surface_tangent_is_symmetric_and_stress_surface_is_not(stretched):
    setup, _ = stretched
    energy, stress = membrane(setup, ENERGY), membrane(setup, STRESS)
    _, symmetric = assembled(energy, setup.u)
    _, general = assembled(stress, setup.u)
    assert np.abs(symmetric - symmetric.T).max() <= 1e-12 * np.abs(symmetric).max()
    assert np.abs(general - general.T).max() > 1e-4 * np.abs(general).max()


@pytest.mark.parametrize("linear_solver", ["cg", "gmres"])
def test_krylov_solvers_with_amg_match_lu(linear_solver):
    test = TensionTest(direction="wale", max_strain=0.2, angle=20.0)
    direct = TensionSetup(ENERGY, test, SolverOptions(steps=4)).run()
    krylov = TensionSetup(ENERGY, test, SolverOptions(steps=4, linear_solver=linear_solver))
    result = krylov.run()
    np.testing.assert_allclose(result.force_n_per_mm, direct.force_n_per_mm, rtol=1e-7, atol=0)


def test_failed_steps_are_cut_back_and_the_error_keeps_the_converged_steps(tmp_path):
    """Beyond half of the path the clamp displacement is NaN: Newton fails, the step halves
    down to min_increment, and ConvergenceError carries the converged steps; XDMF stays
    valid."""
    stepping = SteppingOptions(
        initial_increment=0.25, max_increment=0.25, min_increment=1.0 / 16, extrapolate=False
    )
    options = SolverOptions(steps=4, stepping=stepping)
    setup = TensionSetup(STRESS, TensionTest(max_strain=0.1), options)
    apply_load = setup.problem.set_load_factor
    setup.problem.set_load_factor = lambda t: apply_load(t if t <= 0.5 else np.nan)
    xdmf = tmp_path / "failed.xdmf"
    with pytest.raises(ConvergenceError) as error:
        setup.run(xdmf=xdmf)
    partial = error.value.history
    np.testing.assert_allclose(partial.strain, [0.0, 0.025, 0.05])
    assert partial.force_n_per_mm[-1] > partial.force_n_per_mm[-2] > 0.0
    assert partial.cutbacks == 3  # steps 0.25 -> 0.125 -> 0.0625 -> 0.03125 < 1/16
    assert error.value.last_converged.load_factor == 0.5
    assert "load factor 0.5" in str(error.value)
    text = xdmf.read_text()
    assert text.rstrip().endswith("</Xdmf>")
    times = [float(value) for value in re.findall(r'<Time Value="([^"]+)"', text)]
    # displacement, strain and stress at the unloaded state and the two converged steps
    np.testing.assert_allclose(sorted(times), np.repeat([0.0, 0.025, 0.05], 3))


def test_extrapolated_start_saves_iterations_and_keeps_the_forces():
    """The shared stepping's linear predictor, on the membrane: same equilibria (to the
    Newton tolerance), fewer iterations than starting each step from the last state."""
    test = TensionTest(max_strain=0.3, angle=30.0)
    plain = TensionSetup(STRESS, test, SolverOptions(steps=6)).run()
    predicting = SteppingOptions(initial_increment=1 / 6, max_increment=1 / 6, extrapolate=True)
    predicted = TensionSetup(STRESS, test, SolverOptions(steps=6, stepping=predicting)).run()
    np.testing.assert_allclose(predicted.strain, plain.strain, rtol=0, atol=1e-15)
    np.testing.assert_allclose(predicted.force_n_per_mm, plain.force_n_per_mm, rtol=1e-8)
    assert predicted.newton_iterations.sum() < plain.newton_iterations.sum()


def test_a_ctrl_c_lost_in_a_callback_stops_the_load_path_at_its_next_step(
    signal_handlers, monkeypatch
):
    setup = TensionSetup(STRESS, TensionTest(max_strain=0.1), SolverOptions(steps=2))
    monkeypatch.setattr(sys, "unraisablehook", lambda unraisable: None)  # printed and ignored
    terminate_as_interrupt()
    signal_inside_an_ignoring_callback(signal.SIGINT)  # lost: the run would go on
    with pytest.raises(KeyboardInterrupt):
        setup.run()
    assert setup.run().strain[-1] == pytest.approx(0.1)  # raised once: the next run goes through
