"""Boundary conditions and loads by boundary name, scaled by the load factor t in [0, 1].

Kinds (lengths mm, forces N):

- `clamp`: both displacement components held at 0.
- `displacement`: the displacement t * `vector` (mm) on every node of the boundary.
- `roller`: one component (`component`, "x" or "y") held at t * `value` (mm), the other free.
- `traction`: a dead load t * `vector` (N/mm, per undeformed length of the boundary).
- `free`: nothing imposed (listed to have its displacement reported).

A boundary takes one condition (given twice: refused); named boundaries never share a facet
(the mesh refuses overlapping physical curves) and may meet at a corner node (the later
Dirichlet value wins there).
"""

from collections.abc import Sequence

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from fabric_dolfinx.mesh import TaggedMesh
from fabric_dolfinx.part_spec import COMPONENTS, BoundaryCondition
from rve_rod.errors import InputError

__all__ = [
    "BoundaryLoads",
    "check_overlaps",
]


def check_overlaps(tagged: TaggedMesh, conditions: Sequence[BoundaryCondition]) -> None:
    """InputError when a boundary is named twice or is not a physical curve of the mesh (the
    message lists the mesh's). Two named boundaries never share a facet (`mesh_gmsh_model`
    refuses overlapping physical curves); they may share a corner node."""
    names = [c.name for c in conditions]
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise InputError(f"boundary conditions overlap: {', '.join(repeated)} given twice")
    unknown = [n for n in names if n not in tagged.boundaries]
    if unknown:
        raise InputError(
            f"boundary {', '.join(map(repr, unknown))} is not a physical curve of the mesh; "
            f"its boundaries: {', '.join(sorted(tagged.boundaries))}"
        )


class BoundaryLoads:
    """The DOLFINx objects of a list of conditions on the displacement space.

    Attributes:
        bcs: the Dirichlet conditions.
        external: the traction term sum_i int t_i . v ds_i (UFL form, at the current t), or
            None; subtract it from the residual.
        lengths: boundary name -> undeformed length (mm).
    """

    def __init__(
        self,
        tagged: TaggedMesh,
        space: fem.FunctionSpace,
        conditions: Sequence[BoundaryCondition],
    ):
        check_overlaps(tagged, conditions)
        self.conditions = tuple(conditions)
        mesh = tagged.mesh
        fdim = mesh.topology.dim - 1
        self._ds = ufl.Measure("ds", domain=mesh, subdomain_data=tagged.facet_tags)
        self._constants: list[tuple[fem.Constant, np.ndarray]] = []
        self.bcs = []
        external = None
        v = ufl.TestFunction(space)
        for condition in conditions:
            facets = tagged.facets(condition.name)
            if condition.kind in ("clamp", "displacement"):
                value = self._constant(mesh, np.asarray(condition.vector, dtype=float))
                dofs = fem.locate_dofs_topological(space, fdim, facets)
                self.bcs.append(fem.dirichletbc(value, dofs, space))
            elif condition.kind == "roller":
                axis = COMPONENTS[condition.component]
                value = self._constant(mesh, np.array(condition.value, dtype=float))
                dofs = fem.locate_dofs_topological(space.sub(axis), fdim, facets)
                self.bcs.append(fem.dirichletbc(value, dofs, space.sub(axis)))
            elif condition.kind == "traction":
                value = self._constant(mesh, np.asarray(condition.vector, dtype=float))
                term = ufl.inner(value, v) * self._ds(tagged.boundaries[condition.name])
                external = term if external is None else external + term
        self.external = external
        self.lengths = {
            c.name: _integrate(fem.Constant(mesh, 1.0) * self._ds(tagged.boundaries[c.name]), mesh)
            for c in conditions
        }
        self._tagged = tagged

    def _constant(self, mesh, full: np.ndarray) -> fem.Constant:
        """A Constant holding t * full (zero at t = 0), registered for `set_load_factor`."""
        constant = fem.Constant(mesh, np.zeros_like(full, dtype=PETSc.ScalarType))
        self._constants.append((constant, full))
        return constant

    def set_load_factor(self, load_factor: float) -> None:
        """Scale every prescribed displacement and traction to load factor t."""
        for constant, full in self._constants:
            constant.value = load_factor * full

    def displacement_forms(self, u: fem.Function) -> dict[str, list[fem.forms.FormMetaClass]]:
        """Boundary name -> compiled forms of int u_x ds and int u_y ds over it (mm^2)."""
        return {
            c.name: [
                fem.form(u[axis] * self._ds(self._tagged.boundaries[c.name])) for axis in range(2)
            ]
            for c in self.conditions
        }

    def applied_force(self, name: str, load_factor: float) -> np.ndarray:
        """(Fx, Fy) N of the traction on boundary `name` at load factor t (dead load)."""
        condition = next(c for c in self.conditions if c.name == name)
        return load_factor * np.asarray(condition.vector, dtype=float) * self.lengths[name]


def _integrate(form, mesh) -> float:
    return mesh.comm.allreduce(fem.assemble_scalar(fem.form(form)), op=MPI.SUM)
