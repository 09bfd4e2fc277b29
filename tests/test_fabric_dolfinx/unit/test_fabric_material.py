"""Material laws and the material at the quadrature points against independent evaluations:
the orthotropic compliance matrix, the numpy surface at each point's strain, a plain numpy
rotation, each cell's own law and stitch value, NaN strains; and one compiled form for every
surface (the forms' signatures, the forms asked of FFCx recorded)."""

import contextlib
import dataclasses

import cffi
import dolfinx.jit
import numpy as np
import pytest
import ufl
from dolfinx import fem, mesh
from dolfinx.fem.petsc import set_bc
from mpi4py import MPI
from support.surface_cases import synthetic_surface

from fabric_dolfinx.graded import graded_material
from fabric_dolfinx.material import OrthotropicSVK, surface_material, svk_material
from fabric_dolfinx.membrane.forms import flat_frame, green_lagrange, membrane_state
from fabric_dolfinx.membrane.quadrature import TANGENT_COMPONENTS, QuadratureMaterial
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.part.problem import PartProblem
from fabric_dolfinx.part.regions import Region
from fabric_dolfinx.spec.expression import FieldExpression
from fabric_dolfinx.spec.part import BoundaryCondition, MeshSpec
from fabric_dolfinx.spec.space import IndenterSpec, SpaceSpec
from rve_rod.errors import InputError

SURFACE = synthetic_surface()
STIFFER = dataclasses.replace(
    SURFACE,
    s11=dataclasses.replace(SURFACE.s11, coefficients=2.0 * SURFACE.s11.coefficients),
    s12=dataclasses.replace(SURFACE.s12, coefficients=3.0 * SURFACE.s12.coefficients),
)


def test_svk_matrix_inverts_to_the_orthotropic_compliance():
    material = OrthotropicSVK(2.0, 0.5, 0.4, 0.3)
    C = material.plane_stress_matrix()
    E1, E2, nu12 = 2.0, 0.5, 0.4
    compliance = np.array([[1 / E1, -nu12 / E1], [-nu12 / E1, 1 / E2]])
    np.testing.assert_allclose(np.linalg.inv(C[:2, :2]), compliance, rtol=1e-14)
    assert C[2, 2] == pytest.approx(2 * 0.3)
    E = np.array([[0.1, -0.02, 0.03]])
    result = material.stress(E)
    S11 = (E1 * 0.1 + nu12 * E2 * -0.02) / (1 - nu12**2 * E2 / E1)
    np.testing.assert_allclose(result.S[0], [S11, C[1] @ E[0], 2 * 0.3 * 0.03], rtol=1e-14)
    np.testing.assert_array_equal(result.tangent[0], C)


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("course_stiffness", -1.0, "course_stiffness=-1 N/mm must be > 0"),
        ("shear_stiffness", 0.0, "shear_stiffness=0 N/mm must be > 0"),
        ("poissons_ratio", 1.5, "poissons_ratio=1.5 is outside the valid range (-1.41421"),
    ],
)
def test_svk_rejects_bad_parameters(field, value, message):
    with pytest.raises(InputError) as error:
        OrthotropicSVK(**{field: value, "wale_stiffness": 0.5})
    assert message in str(error.value)


def homogeneous(strain, angle=0.0, cells=2):
    """u = (U - I) X on the unit square (cells x cells) with U^T U = I + 2 `strain` (global
    frame), course at `angle` radians: (mesh, u, frame)."""
    domain = mesh.create_unit_square(MPI.COMM_SELF, cells, cells, mesh.CellType.quadrilateral)
    values, vectors = np.linalg.eigh(np.eye(2) + 2 * np.asarray(strain))
    stretch = vectors @ np.diag(np.sqrt(values)) @ vectors.T
    u = fem.Function(fem.VectorFunctionSpace(domain, ("Lagrange", 1)))
    u.interpolate(lambda x: (stretch - np.eye(2)) @ x[:2])
    return domain, u, flat_frame(domain, fem.Constant(domain, angle))


def test_the_quadrature_values_are_the_law_at_the_strain_of_each_point():
    """A homogeneous strain beyond the surface domain: at every one of the 3 x 3 points of
    every cell S and the five tangent entries of the numpy surface at the rotated strain."""
    angle, strain = 0.3, np.array([[0.4, 0.05], [0.05, -0.1]])
    domain, u, frame = homogeneous(strain, angle)
    points = QuadratureMaterial(green_lagrange(u, frame), domain, [surface_material(SURFACE)], 4)
    assert points.points.shape == (9, 2)
    points.update()
    c, s = np.cos(angle), np.sin(angle)
    R = np.array([[c, -s], [s, c]])
    local = R.T @ strain @ R
    expected = SURFACE.stress(np.array([local[0, 0], local[1, 1], local[0, 1]]))
    assert expected.outside[0]
    stress = points.stress_values.x.array.reshape(-1, 3)
    tangent = points.tangent_values.x.array.reshape(-1, 5)
    assert stress.shape[0] == 4 * 9
    np.testing.assert_allclose(stress, np.repeat(expected.S, 36, axis=0), rtol=1e-12)
    stored = np.array([expected.tangent[0][a, b] for a, b in TANGENT_COMPONENTS])
    np.testing.assert_allclose(tangent, np.repeat(stored[None], 36, axis=0), rtol=1e-12)
    # the entries left out are 0 in the surface contract
    mask = np.ones((3, 3), bool)
    mask[tuple(np.array(TANGENT_COMPONENTS).T)] = False
    assert np.all(expected.tangent[0][mask] == 0.0)


def test_rotated_svk_stress_matches_numpy_rotation():
    """The membrane's law sees R^T E R and R S R^T is C(R^T E R) rotated back, for a constant
    angle and a homogeneous stretch u = (U - I) X, against a plain numpy evaluation."""
    material = OrthotropicSVK(1.0, 0.4, 0.3, 0.1)
    angle, strain = 0.7, np.array([[0.1, 0.03], [0.03, -0.02]])
    domain, u, frame = homogeneous(strain, angle, cells=1)
    points = QuadratureMaterial(green_lagrange(u, frame), domain, [svk_material(material)], 1)
    points.update()
    state = membrane_state(u, points.stress, frame)
    T = frame.tangents
    S = T * state.second_piola_kirchhoff * T.T
    fields = ufl.as_vector(
        [state.reference_strain[0, 1]] + [S[i, j] for i in (0, 1) for j in (0, 1)]
    )
    table = fem.Expression(fields, points.points).eval(np.array([0], dtype=np.int32))
    assert table[0, 0] == pytest.approx(strain[0, 1], abs=1e-15)
    value = table[0, 1:].reshape(2, 2)
    c, s = np.cos(angle), np.sin(angle)
    R = np.array([[c, -s], [s, c]])
    local = R.T @ strain @ R
    voigt = material.plane_stress_matrix() @ [local[0, 0], local[1, 1], local[0, 1]]
    expected = R @ np.array([[voigt[0], voigt[2]], [voigt[2], voigt[1]]]) @ R.T
    np.testing.assert_allclose(value, expected, rtol=0, atol=1e-15)


def test_each_cell_has_its_own_law_and_stitch_value():
    """Cell 0 SVK, cells 1-2 graded between two SVK laws at stitch 4.5 and 5.5, cell 3 no
    law (left 0): S at its points is C E of its own law, the graded one with the weights of
    its cell's stitch value. A NaN strain gives NaN S (the solver then cuts back)."""
    strain = np.array([[0.02, 0.01], [0.01, 0.03]])
    domain, u, frame = homogeneous(strain)
    laws = [OrthotropicSVK(1.0, 0.5, 0.2, 0.1), OrthotropicSVK(3.0, 2.0, 0.1, 0.5)]
    graded = graded_material([(5.5, svk_material(laws[1])), (4.5, svk_material(laws[0]))])
    materials = [svk_material(OrthotropicSVK(2.0, 2.0, 0.0, 1.0)), graded]
    stitch = np.array([0.0, 4.5 + 0.25, 4.5 + 0.75, 0.0])
    points = QuadratureMaterial(
        green_lagrange(u, frame), domain, materials, 2, np.array([0, 1, 1, -1]), stitch
    )
    points.update()
    E = np.array([0.02, 0.03, 0.01])
    dofs = points.stress_values.function_space.dofmap.list.array.reshape(4, -1)
    stress = points.stress_values.x.array.reshape(-1, 3)
    C = [law.plane_stress_matrix() for law in laws]
    expected = {
        0: np.diag([2.0, 2.0, 2.0]) @ E,
        1: (0.75 * C[0] + 0.25 * C[1]) @ E,
        2: (0.25 * C[0] + 0.75 * C[1]) @ E,
        3: np.zeros(3),
    }
    for cell, value in expected.items():
        np.testing.assert_allclose(stress[dofs[cell]], np.tile(value, (4, 1)), atol=1e-15)
    u.x.array[0] = np.nan
    points.update()
    assert np.isnan(points.stress_values.x.array).any()
    assert np.isfinite(stress[dofs[2]]).all()  # the cell away from the NaN node


@contextlib.contextmanager
def requested_forms():
    """The signatures of the UFL forms DOLFINx asks FFCx for inside the block (compiled or
    found in the cache: equal signatures share one compiled module)."""
    requested = []
    original = dolfinx.jit.ffcx_jit

    def recorded(comm, ufl_object, *args, **kwargs):
        if isinstance(ufl_object, ufl.Form):
            requested.append(ufl_object.signature())
        return original(comm, ufl_object, *args, **kwargs)

    dolfinx.jit.ffcx_jit = recorded
    try:
        yield requested
    finally:
        dolfinx.jit.ffcx_jit = original


def test_other_boundaries_compile_no_new_form_and_their_means_are_exact():
    """The lengths and mean displacements of the boundaries are integrals over each boundary
    alone (facet tags of its own under one id): a part with other boundaries asks for no form
    the first did not (before, one per boundary and component). Each length is the rectangle's side,
    each held boundary's mean its prescribed vector at t = 0.5 (the conditions applied)."""
    tagged = make_mesh(MeshSpec("rectangle", {"width": 20.0, "height": 10.0}, element_size=5.0))
    material = [Region("fabric", surface_material(SURFACE))]

    def part(conditions):
        problem = PartProblem(tagged, material, conditions)
        problem.set_load_factor(0.5)
        set_bc(problem.u.vector, problem.loads.bcs)
        problem.u.x.scatter_forward()
        return problem

    with requested_forms() as first:
        part([BoundaryCondition("left"), BoundaryCondition("right", "displacement", (1.0, 0.0))])
    others = [
        BoundaryCondition("bottom"),
        BoundaryCondition("top", "displacement", (0.4, 2.0)),
        BoundaryCondition("left", "free"),
    ]
    with requested_forms() as second:
        problem = part(others)
    assert set(second) <= set(first)
    assert problem.loads.lengths == pytest.approx({"bottom": 20.0, "top": 20.0, "left": 10.0})
    means = problem.boundary_displacements()
    np.testing.assert_allclose(means["top"], [0.2, 1.0], rtol=1e-12)
    np.testing.assert_allclose(means["bottom"], [0.0, 0.0], atol=1e-15)


def test_other_indenters_and_penalties_ask_for_no_new_form():
    """An indenter's numbers (a sphere's radius, a plane's normal, the penalty) are a
    Constant's, and its force is one form with the axis a Constant: a disc pressed by another
    sphere or plane asks FFCx for no form the first did not (before, a residual, a Jacobian
    and three force forms for each)."""
    tagged = make_mesh(MeshSpec("disc", {"radius": 10.0}, element_size=5.0))
    svk = [Region("fabric", svk_material(OrthotropicSVK(10.0, 10.0, 0.3, 10.0 / 2.6)))]

    def disc(indenter):
        space = SpaceSpec(indenter=indenter)
        return PartProblem(tagged, svk, [BoundaryCondition("rim")], space=space)

    sphere = {"travel": (0.0, 0.0, -1.0), "shape": "sphere"}
    plane = {"travel": (0.0, 0.0, -1.0), "shape": "plane", "point": (0.0, 0.0, 1.0)}
    for first, other in (
        (
            IndenterSpec(**sphere, radius=3.0, centre=(0.0, 0.0, 4.0), penalty=100.0),
            IndenterSpec(**sphere, radius=5.0, centre=(1.0, 0.0, 6.0), penalty=1e4),
        ),
        (
            IndenterSpec(**plane, normal=(0.0, 0.0, -1.0), penalty=100.0),
            IndenterSpec(**plane, normal=(0.1, 0.0, -1.0), penalty=10.0),
        ),
    ):
        with requested_forms() as requested_first:
            disc(first)
        with requested_forms() as requested_other:
            problem = disc(other)
        assert set(requested_other) <= set(requested_first)
        assert problem.indenter_force() == pytest.approx(np.zeros(3), abs=1e-15)


def test_different_surfaces_and_regions_compile_no_new_form():
    """The forms hold no number of the law: parts with another surface, with two regions or
    with a graded family have the residual and Jacobian of the first (equal signatures), and
    building them asks FFCx for no form the first did not (the requests recorded)."""
    tagged = make_mesh(MeshSpec("rectangle", {"width": 20.0, "height": 10.0}, element_size=5.0))
    conditions = [BoundaryCondition("left"), BoundaryCondition("right", "traction", (0.01, 0))]
    first, stiffer = surface_material(SURFACE), surface_material(STIFFER)

    def forms(regions):
        stepper = PartProblem(tagged, regions, conditions).stepper
        return stepper._residual_form, stepper._jacobian_form

    with requested_forms() as reference_requests:
        reference = forms([Region("fabric", first, angle=10.0)])
    with requested_forms() as requested:
        others = [
            forms([Region("fabric", stiffer, angle=10.0)]),
            forms(
                [
                    Region("fabric", first, angle=FieldExpression("x")),
                    Region("band", stiffer, where=FieldExpression("x > 10")),
                ]
            ),
            forms(
                [
                    Region(
                        "fabric",
                        None,
                        stitch=FieldExpression("4 + x / 10"),
                        family=((4.0, first), (6.0, stiffer)),
                    )
                ]
            ),
        ]
    assert set(requested) <= set(reference_requests)
    signature = [[cffi.FFI().string(f.ufcx_form.signature) for f in pair] for pair in others]
    assert signature == [[cffi.FFI().string(f.ufcx_form.signature) for f in reference]] * 3
