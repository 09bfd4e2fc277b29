"""The reaction force of a non-homogeneous problem converges under mesh refinement: a plate
with a hole on rollers, stretched by 10 %, on uniformly refined unstructured quad meshes."""

import numpy as np
import pytest
from dolfinx import fem
from dolfinx import mesh as dolfinx_mesh
from petsc4py import PETSc
from support.surface_cases import synthetic_surface

from fabric_dolfinx.material import surface_material
from fabric_dolfinx.membrane.forms import flat_frame, green_lagrange, membrane_forms
from fabric_dolfinx.membrane.quadrature import QuadratureMaterial
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.solve import LoadStepper, SolverOptions, boundary_indicator
from fabric_dolfinx.spec.part import MeshSpec

MATERIAL = surface_material(synthetic_surface())
ELEMENT_SIZE = 5.0  # mm, halved by every refinement


def stretched_plate_reaction(refinements: int) -> float:
    """Reaction (N) on the right edge of the 50 x 50 mm plate with a 10 mm hole.

    Left and right edges are rollers (u_x = 0, u_x = 5 mm); the corner (0, 0) is pinned in y,
    which only removes the rigid translation (its reaction is the total y force, zero). So no
    clamp corner singularity spoils the rate: the solution is smooth up to the hole boundary.
    """
    tagged = make_mesh(
        MeshSpec("plate_with_hole", element_size=ELEMENT_SIZE, refinements=refinements)
    )
    domain = tagged.mesh
    space = fem.VectorFunctionSpace(domain, ("Lagrange", 1))
    u = fem.Function(space)
    frame = flat_frame(domain)
    points = QuadratureMaterial(green_lagrange(u, frame), domain, [MATERIAL], 2)
    forms = membrane_forms(u, points, frame)
    stretch = fem.Constant(domain, PETSc.ScalarType(0.0))
    corner = dolfinx_mesh.locate_entities_boundary(
        domain, 0, lambda x: np.isclose(x[0], 0.0) & np.isclose(x[1], 0.0)
    )
    zero = PETSc.ScalarType(0.0)
    bcs = [
        fem.dirichletbc(
            zero, fem.locate_dofs_topological(space.sub(0), 1, tagged.facets("left")), space.sub(0)
        ),
        fem.dirichletbc(
            stretch,
            fem.locate_dofs_topological(space.sub(0), 1, tagged.facets("right")),
            space.sub(0),
        ),
        fem.dirichletbc(zero, fem.locate_dofs_topological(space.sub(1), 0, corner), space.sub(1)),
    ]
    reactions = {"right": boundary_indicator(space, tagged.facets("right"))}
    stepper = LoadStepper(
        forms.residual,
        forms.jacobian,
        u,
        bcs,
        options=SolverOptions(steps=2),
        reactions=reactions,
        update=points.update,
    )

    def apply_load(t):
        stretch.value = 5.0 * t

    reaction = stepper.run(apply_load).steps[-1].reactions["right"]
    assert abs(reaction[1]) < 1e-12 * abs(reaction[0])
    return float(reaction[0])


@pytest.mark.slow
def test_reaction_converges_at_second_order_under_refinement():
    levels = np.arange(4)
    reactions = np.array([stretched_plate_reaction(int(level)) for level in levels])
    sizes = ELEMENT_SIZE / 2.0**levels
    changes = np.abs(np.diff(reactions))
    slope = np.polyfit(np.log(sizes[1:]), np.log(changes), 1)[0]
    # Q1 reactions (a functional) and the polygonal hole both converge as h^2; the fit over
    # these levels sees 1.7 (pre-asymptotic on the coarsest mesh).
    assert 1.5 < slope < 2.5
    finest_error = changes[-1] / (2.0**slope - 1.0)  # Richardson estimate of |R_3 - R|
    assert finest_error < 1.5e-3 * reactions[-1]
    assert np.all(np.diff(reactions) < 0.0)  # monotone: coarse meshes are too stiff
