"""Known solutions of the membrane with the response-surface material: the patch test
(homogeneous deformations against the numpy surface evaluation), objectivity under a
superposed rigid rotation, and the exchange of course and wale by a 90-degree orientation."""

import basix
import numpy as np
import pytest
import ufl
from dolfinx import fem
from support.surface_cases import synthetic_surface

from fabric_dolfinx.material import surface_material
from fabric_dolfinx.membrane.forms import (
    flat_frame,
    green_lagrange,
    membrane_forms,
    membrane_state,
)
from fabric_dolfinx.membrane.quadrature import QuadratureMaterial
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.part.tension import TensionSetup
from fabric_dolfinx.solve import LoadStepper, SolverOptions, boundary_indicator
from fabric_dolfinx.spec.part import MeshSpec
from fabric_dolfinx.spec.tension import TensionTest

SURFACE = synthetic_surface()
MATERIAL = surface_material(SURFACE)
ANGLE = 0.4  # radians between x and the course direction


def rotation(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


def numpy_pk2(F, angle):
    """S (m, 2, 2) = R S_m(R^T E R) R^T from rve_rod.surface's numpy evaluation."""
    E = 0.5 * (np.einsum("mki,mkj->mij", F, F) - np.eye(2))
    R = rotation(angle)
    local = np.einsum("ki,mkl,lj->mij", R, E, R)
    S = SURFACE.stress(np.stack([local[:, 0, 0], local[:, 1, 1], local[:, 0, 1]], axis=1)).S
    S_local = np.stack([S[:, 0], S[:, 2], S[:, 2], S[:, 1]], axis=1).reshape(-1, 2, 2)
    return np.einsum("ik,mkl,jl->mij", R, S_local, R)


def global_stress(state, frame):
    """S in the mesh's axes, T S T^T (UFL (2, 2), N/mm)."""
    return frame.tangents * state.second_piola_kirchhoff * frame.tangents.T


class Membrane:
    """A membrane on `tagged`, with F and S at the quadrature points and one stepper."""

    def __init__(self, tagged, boundaries, angle=ANGLE):
        domain = tagged.mesh
        space = fem.VectorFunctionSpace(domain, ("Lagrange", 1))
        self.u = fem.Function(space)
        angle_constant = fem.Constant(domain, angle)
        frame = flat_frame(domain, angle_constant)
        self.material = QuadratureMaterial(green_lagrange(self.u, frame), domain, [MATERIAL], 2)
        forms = membrane_forms(self.u, self.material, frame)
        S = global_stress(membrane_state(self.u, self.material.stress, frame), frame)
        F = ufl.Identity(2) + ufl.grad(self.u)
        points, _ = basix.make_quadrature(basix.CellType.quadrilateral, 2)
        values = ufl.as_vector(
            [F[i, j] for i in range(2) for j in range(2)]
            + [S[i, j] for i in range(2) for j in range(2)]
        )
        self._expression = fem.Expression(values, points)
        self._cells = np.arange(domain.topology.index_map(2).size_local, dtype=np.int32)
        fdim = domain.topology.dim - 1
        self.boundary_data = {name: fem.Function(space) for name in boundaries}
        bcs = [
            fem.dirichletbc(g, fem.locate_dofs_topological(space, fdim, tagged.facets(name)))
            for name, g in self.boundary_data.items()
        ]
        reactions = {name: boundary_indicator(space, tagged.facets(name)) for name in boundaries}
        options = SolverOptions(steps=4, relative_tolerance=1e-12, absolute_tolerance=1e-14)
        self.stepper = LoadStepper(
            forms.residual,
            forms.jacobian,
            self.u,
            bcs,
            options=options,
            reactions=reactions,
            update=self.material.update,
        )

    def quadrature_values(self):
        """(F, S) at all local quadrature points, each (m, 2, 2)."""
        self.material.update()
        table = self._expression.eval(self._cells).reshape(-1, 8)
        return table[:, :4].reshape(-1, 2, 2), table[:, 4:].reshape(-1, 2, 2)


@pytest.fixture(scope="module")
def hole():
    tagged = make_mesh(MeshSpec("plate_with_hole", element_size=10.0))
    return Membrane(tagged, ("left", "right", "bottom", "top", "hole"))


@pytest.fixture(scope="module")
def rectangle():
    return make_mesh(MeshSpec("rectangle", {"width": 40.0, "height": 30.0}, element_size=5.0))


@pytest.fixture(scope="module")
def patch(rectangle):
    return Membrane(rectangle, ("left", "right", "bottom", "top"))


@pytest.fixture(scope="module")
def clamped(rectangle):
    """Clamps on the left and right edges; top and bottom free."""
    return Membrane(rectangle, ("left", "right"))


HOMOGENEOUS = {
    "biaxial-shear": np.array([[1.15, 0.05], [0.02, 0.97]]),
    "beyond-domain": np.array([[1.35, 0.1], [-0.05, 0.88]]),
    "rotated-stretch": rotation(0.7) @ np.array([[1.1, 0.0], [0.0, 1.06]]),
}


def solve_homogeneous(membrane, F):
    membrane.u.x.array[:] = 0.0

    def apply_load(t):
        for g in membrane.boundary_data.values():
            g.interpolate(lambda x: t * ((F - np.eye(2)) @ x[:2]))

    return membrane.stepper.run(apply_load)


@pytest.mark.parametrize("case", HOMOGENEOUS)
@pytest.mark.parametrize("mesh_name", ["hole", "patch"])
def test_homogeneous_deformation_reproduces_the_surface_stress(request, mesh_name, case):
    membrane = request.getfixturevalue(mesh_name)
    F = HOMOGENEOUS[case]
    path = solve_homogeneous(membrane, F)
    space = membrane.u.function_space
    X = space.tabulate_dof_coordinates()[:, :2]
    exact = X @ (F - np.eye(2)).T
    np.testing.assert_allclose(membrane.u.x.array.reshape(-1, 2), exact, rtol=0, atol=1e-10)
    F_h, S_h = membrane.quadrature_values()
    np.testing.assert_allclose(F_h, np.broadcast_to(F, F_h.shape), rtol=0, atol=1e-12)
    S_exact = numpy_pk2(F_h, ANGLE)
    scale = np.abs(S_exact).max()
    np.testing.assert_allclose(S_h, S_exact, rtol=0, atol=1e-10 * scale)
    if case == "beyond-domain":
        assert SURFACE.stress(np.array([0.41, 0.0, 0.0])).outside[0]
    if mesh_name == "patch":
        # Uniform mesh: the corner nodes' shares of top and bottom cancel, so the residual on
        # the right-edge indicator is exactly the traction P n times the edge length.
        P = F @ S_exact[0]
        reaction = path.steps[-1].reactions["right"]
        np.testing.assert_allclose(reaction, P[:, 0] * 30.0, rtol=1e-10)


@pytest.fixture(scope="module")
def rotated_runs(clamped):
    """Course-wise tension to 10 % with and without a superposed rotation of both clamps."""
    membrane = clamped
    stretch, theta = 0.1 * 40.0, np.radians(50.0)
    runs = {}
    for name, angle in (("reference", 0.0), ("rotated", theta)):
        membrane.u.x.array[:] = 0.0

        def apply_load(t, angle=angle):
            Q = rotation(t * angle)
            membrane.boundary_data["left"].interpolate(lambda x, Q=Q: Q @ x[:2] - x[:2])
            membrane.boundary_data["right"].interpolate(
                lambda x, Q=Q: Q @ (x[:2] + np.array([[t * stretch], [0.0]])) - x[:2]
            )

        path = membrane.stepper.run(apply_load)
        runs[name] = (path.steps[-1].reactions["right"], *membrane.quadrature_values())
    return runs, rotation(theta)


def test_objectivity_rotation_changes_no_stress_invariant(rotated_runs):
    runs, Q = rotated_runs
    _, F_ref, S_ref = runs["reference"]
    _, F_rot, S_rot = runs["rotated"]
    np.testing.assert_allclose(F_rot, np.einsum("ik,mkj->mij", Q, F_ref), atol=1e-9)
    scale = np.abs(S_ref).max()
    np.testing.assert_allclose(S_rot, S_ref, rtol=0, atol=1e-9 * scale)

    def cauchy(F, S):
        J = np.linalg.det(F)
        return np.einsum("mik,mkl,mjl->mij", F, S, F) / J[:, None, None]

    sigma_ref, sigma_rot = cauchy(F_ref, S_ref), cauchy(F_rot, S_rot)
    for invariant in (np.trace, np.linalg.det):
        ref = invariant(sigma_ref.T).T if invariant is np.trace else invariant(sigma_ref)
        rot = invariant(sigma_rot.T).T if invariant is np.trace else invariant(sigma_rot)
        np.testing.assert_allclose(rot, ref, rtol=0, atol=1e-9 * np.abs(ref).max())


def test_objectivity_rotation_rotates_the_reaction(rotated_runs):
    runs, Q = rotated_runs
    reaction_ref, reaction_rot = runs["reference"][0], runs["rotated"][0]
    assert reaction_ref[0] > 0.0
    np.testing.assert_allclose(
        np.linalg.norm(reaction_rot), np.linalg.norm(reaction_ref), rtol=1e-9
    )
    np.testing.assert_allclose(reaction_rot, Q @ reaction_ref, rtol=0, atol=1e-9 * reaction_ref[0])


@pytest.mark.parametrize("direction", ["course", "wale"])
def test_orientation_90_degrees_exchanges_course_and_wale(direction):
    other = {"course": "wale", "wale": "course"}[direction]
    options = SolverOptions(steps=5)
    rotated = TensionSetup(MATERIAL, TensionTest(direction=direction, angle=90.0), options)
    aligned = TensionSetup(MATERIAL, TensionTest(direction=other, angle=0.0), options)
    force_rotated = rotated.run().force_n_per_mm
    force_aligned = aligned.run().force_n_per_mm
    np.testing.assert_allclose(force_rotated, force_aligned, rtol=1e-10, atol=0)
    native = TensionSetup(MATERIAL, TensionTest(direction=direction), options).run()
    assert abs(native.force_n_per_mm[-1] - force_rotated[-1]) > 0.1 * force_rotated[-1]


def test_spatially_varying_orientation_field():
    """A DG0 angle field (courses running around the hole): S at every quadrature point is the
    numpy surface stress rotated by that cell's angle."""
    tagged = make_mesh(MeshSpec("plate_with_hole", element_size=10.0))
    domain = tagged.mesh
    space = fem.VectorFunctionSpace(domain, ("Lagrange", 1))
    u = fem.Function(space)
    F = HOMOGENEOUS["biaxial-shear"]
    u.interpolate(lambda x: (F - np.eye(2)) @ x[:2])
    angle = fem.Function(fem.FunctionSpace(domain, ("DG", 0)))
    angle.interpolate(lambda x: np.arctan2(x[1] - 25.0, x[0] - 25.0) + np.pi / 2)
    frame = flat_frame(domain, angle)
    material = QuadratureMaterial(green_lagrange(u, frame), domain, [MATERIAL], 2)
    material.update()
    S = global_stress(membrane_state(u, material.stress, frame), frame)
    points, _ = basix.make_quadrature(basix.CellType.quadrilateral, 2)
    values = ufl.as_vector([angle] + [S[i, j] for i in range(2) for j in range(2)])
    cells = np.arange(domain.topology.index_map(2).size_local, dtype=np.int32)
    table = fem.Expression(values, points).eval(cells).reshape(-1, 5)
    angles = table[:, 0]
    assert np.ptp(angles) > 3.0  # the field really varies
    expected = np.array([numpy_pk2(F[None], a)[0] for a in angles])
    scale = np.abs(expected).max()
    np.testing.assert_allclose(table[:, 1:].reshape(-1, 2, 2), expected, atol=1e-12 * scale)
