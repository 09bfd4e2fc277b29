"""Test fixture: the plate with a hole on rollers, stretched by 10 %, with the synthetic
surface (`surface_cases.synthetic_surface`): the problem of the mesh-convergence test, shared
with the accuracy table of `benchmarks/bench_membrane.py` (which imports this file from
tests/).

Left and right edges are rollers (u_x = 0, u_x = 5 mm); the corner (0, 0) is pinned in y,
which only removes the rigid translation (its reaction is the total y force, zero). So no
clamp corner singularity spoils the rate: the solution is smooth up to the hole boundary.
"""

import time
from typing import NamedTuple

import numpy as np
from dolfinx import fem
from dolfinx import mesh as dolfinx_mesh
from petsc4py import PETSc

from fabric_dolfinx.material import surface_material
from fabric_dolfinx.membrane.forms import flat_frame, green_lagrange, membrane_forms
from fabric_dolfinx.membrane.quadrature import QuadratureMaterial
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.solve import LoadStepper, SolverOptions, boundary_indicator
from fabric_dolfinx.spec.part import MeshSpec
from support.surface_cases import synthetic_surface

__all__ = [
    "PlateStretch",
    "stretched_plate",
]


class PlateStretch(NamedTuple):
    """The stretched plate's result.

    Attributes:
        reaction: (Fx, Fy) on the right edge (N); seconds: the load path's time (s);
        dofs: global degrees of freedom.
    """

    reaction: np.ndarray
    seconds: float
    dofs: int


def stretched_plate(
    refinements: int, degree: int = 1, quadrature_degree: int = 2, element_size: float = 5.0
) -> PlateStretch:
    """The 50 x 50 mm plate with a 10 mm hole (`element_size` mm, refined `refinements`
    times, Lagrange `degree`, Gauss rule exact to `quadrature_degree`) stretched in 2 steps."""
    tagged = make_mesh(
        MeshSpec("plate_with_hole", element_size=element_size, refinements=refinements)
    )
    domain = tagged.mesh
    space = fem.VectorFunctionSpace(domain, ("Lagrange", degree))
    u = fem.Function(space)
    frame = flat_frame(domain)
    material = surface_material(synthetic_surface())
    points = QuadratureMaterial(green_lagrange(u, frame), domain, [material], quadrature_degree)
    forms = membrane_forms(u, points, frame)
    stretch = fem.Constant(domain, PETSc.ScalarType(0.0))
    corner = dolfinx_mesh.locate_entities_boundary(
        domain, 0, lambda x: np.isclose(x[0], 0.0) & np.isclose(x[1], 0.0)
    )
    x_space, y_space = space.sub(0), space.sub(1)
    zero = PETSc.ScalarType(0.0)
    bcs = [
        fem.dirichletbc(
            zero, fem.locate_dofs_topological(x_space, 1, tagged.facets("left")), x_space
        ),
        fem.dirichletbc(
            stretch, fem.locate_dofs_topological(x_space, 1, tagged.facets("right")), x_space
        ),
        fem.dirichletbc(zero, fem.locate_dofs_topological(y_space, 0, corner), y_space),
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
    start = time.perf_counter()
    path = stepper.run(lambda t: setattr(stretch, "value", 5.0 * t))
    dofs = space.dofmap.index_map.size_global * space.dofmap.index_map_bs
    return PlateStretch(path.steps[-1].reactions["right"], time.perf_counter() - start, dofs)
