"""The membrane in space under in-plane loads equals the plane membrane to round-off, and its
consistent tangent: central differences and quadratic Newton convergence."""

import dolfinx.fem.petsc
import numpy as np
import pytest
import ufl
from dolfinx import fem
from support.surface_cases import synthetic_surface

from fabric_dolfinx.material import OrthotropicSVK, surface_material, svk_material
from fabric_dolfinx.membrane.forms import flat_frame, green_lagrange, membrane_forms
from fabric_dolfinx.membrane.loads import pressure_residual
from fabric_dolfinx.membrane.quadrature import QuadratureMaterial
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.part.problem import PartProblem
from fabric_dolfinx.part.regions import Region
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.part import BoundaryCondition, MeshSpec
from fabric_dolfinx.spec.space import SpaceSpec

SURFACE = surface_material(synthetic_surface())
SVK = svk_material(OrthotropicSVK(1.0, 0.5, 0.3, 0.2))


@pytest.mark.parametrize("material", [SVK, SURFACE], ids=["svk", "surface"])
def test_in_plane_loading_equals_the_plane_membrane(material):
    """A plate with a hole, course at 30 degrees, clamped left and pulled right by (5, 1) mm:
    reactions and displacements of the plane membrane, with z staying exactly 0."""
    tagged = make_mesh(MeshSpec("plate_with_hole", {"radius": 8.0}, element_size=8.0))
    options = SolverOptions(steps=3)
    regions = [Region("fabric", material, angle=30.0)]
    conditions = [BoundaryCondition("left"), BoundaryCondition("right", "displacement", (5, 1))]
    plane = PartProblem(tagged, regions, conditions, options=options)
    expected = plane.run()
    space = PartProblem(
        tagged, regions, conditions, space=SpaceSpec(stabilization=1e-3), options=options
    )
    result = space.run()
    displacement = space.u.x.array.reshape(-1, 3)
    assert np.all(displacement[:, 2] == 0.0)
    np.testing.assert_allclose(
        displacement[:, :2].ravel(),
        plane.u.x.array,
        rtol=0,
        atol=1e-12 * np.abs(plane.u.x.array).max(),
    )
    for name in ("left", "right"):
        force = result.boundaries[name].force
        assert np.all(force[:, 2] == 0.0)
        np.testing.assert_allclose(
            force[:, :2], expected.boundaries[name].force, rtol=1e-10, atol=1e-12
        )
    assert np.all(result.space.stabilization_force == 0.0)
    assert expected.boundaries["right"].force[-1, 0] > 0.3


def dome_state(material):
    """A disc clamped at its rim under pressure, and its converged state (a tension field)."""
    tagged = make_mesh(MeshSpec("disc", {"radius": 20.0}, element_size=5.0))
    problem = PartProblem(
        tagged,
        [Region("fabric", material, angle=np.degrees(0.4))],
        [BoundaryCondition("rim")],
        space=SpaceSpec(pressure=2e-3),
        options=SolverOptions(steps=1),
    )
    return problem, problem.run()


def assembled(residual, jacobian):
    vector = dolfinx.fem.petsc.assemble_vector(fem.form(residual))
    vector.ghostUpdate()
    matrix = dolfinx.fem.petsc.assemble_matrix(fem.form(jacobian))
    matrix.assemble()
    return vector.array.copy(), matrix.convert("dense").getDenseArray()


@pytest.mark.parametrize("material", [SVK, SURFACE], ids=["svk", "surface"])
def test_tangent_is_the_derivative_of_the_residual(material):
    """The Jacobian (the material tangent at the quadrature points by the chain rule, the
    follower pressure's by ufl.derivative) matches central differences of the residual."""
    problem, _ = dome_state(material)
    u = problem.u
    mesh = u.function_space.mesh
    frame = flat_frame(mesh, 0.4, components=3)
    points = QuadratureMaterial(green_lagrange(u, frame), mesh, [material], 2)
    forms = membrane_forms(u, points, frame)
    pressure = fem.Constant(mesh, 2e-3)
    follower = pressure_residual(u, pressure, frame, ufl.dx(metadata={"quadrature_degree": 2}))
    residual = forms.residual - follower
    jacobian = forms.jacobian - ufl.derivative(follower, u, ufl.TrialFunction(u.function_space))
    points.update()
    _, matrix = assembled(residual, jacobian)
    state = u.x.array.copy()
    direction = np.random.default_rng(4).normal(size=state.size) * 0.05
    step = 1e-6
    values = []
    for sign in (1.0, -1.0):
        u.x.array[:] = state + sign * step * direction
        points.update()
        values.append(assembled(residual, jacobian)[0])
    u.x.array[:] = state
    difference = (values[0] - values[1]) / (2 * step)
    action = matrix @ direction
    assert np.linalg.norm(difference - action) <= 1e-6 * np.linalg.norm(action)


def test_newton_converges_quadratically_from_the_dome():
    """One pressure step from the flat disc: after the one-mode dome, e_(k+1) <= C e_k^2."""
    _, result = dome_state(SURFACE)
    assert result.space.dome_amplitude > 0.0
    norms = np.array(result.path.steps[0].residual_norms)
    relative = norms / norms[0]
    assert relative[-1] < 1e-10
    tail = relative[1:]
    order = np.log(tail[-1] / tail[-2]) / np.log(tail[-2] / tail[-3])
    assert order > 1.8


@pytest.mark.parametrize(
    ("moved", "held", "wrinkled", "slack"),
    [
        ((1.0, 0.0, 0.0), (), 0.0, 0.0),
        ((-1.0, 0.0, 0.0), ("top", "bottom"), 0.0, 1.0),
        ((0.0, 1.0, 0.0), (), 1.0, 0.0),
    ],
    ids=["stretched", "compressed", "sheared"],
)
def test_the_wrinkled_and_slack_areas(moved, held, wrinkled, slack):
    """A square clamped left and moved right in its plane (isotropic SVK): stretched, it is
    taut everywhere; compressed with its top and bottom held in y, both principal stresses
    are negative everywhere (slack); sheared, the principal stresses are about +-tau in
    every cell (wrinkled). The unloaded state is slack everywhere."""
    tagged = make_mesh(MeshSpec("rectangle", {"width": 10.0, "height": 10.0}, element_size=2.5))
    conditions = [BoundaryCondition("left"), BoundaryCondition("right", "displacement", moved)]
    conditions += [BoundaryCondition(name, "roller", component="yz") for name in held]
    problem = PartProblem(
        tagged,
        [Region("fabric", svk_material(OrthotropicSVK(1.0, 1.0, 0.3, 1.0 / 2.6)))],
        conditions,
        space=SpaceSpec(stabilization=1e-3),
        options=SolverOptions(steps=1),
    )
    result = problem.run()
    curves = result.space
    assert (curves.wrinkled_area[0], curves.slack_area[0]) == (0.0, 1.0)
    assert curves.wrinkled_area[-1] == pytest.approx(wrinkled, abs=1e-12)
    assert curves.slack_area[-1] == pytest.approx(slack, abs=1e-12)
