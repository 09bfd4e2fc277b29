"""Boundary conditions and loads by boundary name, scaled by the load factor t in [0, 1].

Kinds (lengths mm, forces N), for a displacement of 2 components (a plane part) or 3 (a part
in space, where z takes the third number of a vector, 0 when two are given):

- `clamp`: every displacement component held at 0.
- `displacement`: the displacement t * `vector` (mm) on every node of the boundary.
- `roller`: the components `component` ("x", "y", in space also "z" or several, e.g. "yz")
  held at t * `value` (mm), the others free.
- `traction`: a dead load t * `vector` (N/mm, per undeformed length of the boundary).
- `free`: nothing imposed (listed to have its displacement reported).

A boundary takes one condition (given twice: refused); named boundaries never share a facet
(the mesh refuses overlapping physical curves) and may meet at a corner node (the later
Dirichlet value wins there). Every value that follows the load factor is a `LoadConstants`
constant.

The boundaries' lengths and mean displacements are integrals over each boundary alone: each
boundary gets facet tags of its own with its facets under one id (`_BOUNDARY_ID`), so that one
compiled form serves every boundary and component (the facets are data, only the id is
compiled in; `VectorIntegral`; docs/benchmarks.md, "Form compilations").
"""

from collections.abc import Sequence

import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI
from petsc4py import PETSc

from fabric_dolfinx.mesh.tagged import TaggedMesh
from fabric_dolfinx.part.integrals import VectorIntegral
from fabric_dolfinx.spec.part import AXES, BoundaryCondition
from rve_rod.errors import InputError

__all__ = [
    "BoundaryLoads",
    "BoundaryMeans",
    "LoadConstants",
    "check_overlaps",
]


_BOUNDARY_ID = 1
"""The id under which a boundary's own facet tags mark its facets (`BoundaryLoads.measures`)."""


class LoadConstants:
    """The constants of a problem that follow the load factor: offset + t * full each."""

    def __init__(self, mesh):
        self._mesh = mesh
        self._scaled: list[tuple[fem.Constant, np.ndarray, np.ndarray]] = []

    def constant(self, full, offset=None) -> fem.Constant:
        """A Constant holding offset + t * full (offset at t = 0; default 0)."""
        full = np.asarray(full, dtype=float)
        offset = np.zeros_like(full) if offset is None else np.asarray(offset, dtype=float)
        constant = fem.Constant(self._mesh, np.asarray(offset, dtype=PETSc.ScalarType))
        self._scaled.append((constant, full, offset))
        return constant

    def set_load_factor(self, load_factor: float) -> None:
        """Scale every constant to load factor t."""
        for constant, full, offset in self._scaled:
            constant.value = offset + load_factor * full


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


def _vector(condition: BoundaryCondition, components: int) -> np.ndarray:
    """The condition's vector with `components` entries (z = 0 when two are given)."""
    vector = np.zeros(components)
    given = np.asarray(condition.vector, dtype=float)
    if given.size > components and given[components:].any():
        raise InputError(
            f"boundary {condition.name!r}: vector={condition.vector!r} has a z component; "
            "only a part in space moves out of its plane"
        )
    vector[: min(given.size, components)] = given[:components]
    return vector


class BoundaryLoads:
    """The DOLFINx objects of a list of conditions on the displacement space (2 or 3
    components).

    Attributes:
        conditions: the conditions, in order.
        bcs: the Dirichlet conditions.
        external: the traction term sum_i int t_i . v ds_i (UFL form, at the current t), or
            None; subtract it from the residual.
        lengths: boundary name -> undeformed length (mm).
        measures: boundary name -> ds over that boundary alone (facet tags of its own, id
            `_BOUNDARY_ID`).
        components: displacement components (2 or 3).
    """

    def __init__(
        self,
        tagged: TaggedMesh,
        space: fem.FunctionSpace,
        conditions: Sequence[BoundaryCondition],
        constants: LoadConstants,
    ):
        check_overlaps(tagged, conditions)
        self.conditions = tuple(conditions)
        mesh = tagged.mesh
        fdim = mesh.topology.dim - 1
        components = space.num_sub_spaces
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=tagged.facet_tags)
        self.bcs = []
        external = None
        v = ufl.TestFunction(space)
        for condition in conditions:
            facets = tagged.facets(condition.name)
            if condition.kind in ("clamp", "displacement"):
                zero = np.zeros(components)
                full = _vector(condition, components) if condition.kind == "displacement" else zero
                value = constants.constant(full)
                dofs = fem.locate_dofs_topological(space, fdim, facets)
                self.bcs.append(fem.dirichletbc(value, dofs, space))
            elif condition.kind == "roller":
                for letter in condition.component:
                    axis = AXES.index(letter)
                    if axis >= components:
                        raise InputError(
                            f"boundary {condition.name!r}: a roller holding {letter} needs a "
                            "part in space"
                        )
                    value = constants.constant(np.array(condition.value, dtype=float))
                    dofs = fem.locate_dofs_topological(space.sub(axis), fdim, facets)
                    self.bcs.append(fem.dirichletbc(value, dofs, space.sub(axis)))
            elif condition.kind == "traction":
                value = constants.constant(_vector(condition, components))
                term = ufl.inner(value, v) * ds(tagged.boundaries[condition.name])
                external = term if external is None else external + term
        self.external = external
        self.measures = {c.name: _own_measure(tagged, c.name) for c in conditions}
        one = fem.Constant(mesh, 1.0)
        self.lengths = {name: _integrate(one * ds, mesh) for name, ds in self.measures.items()}
        self.components = components

    def applied_force(self, name: str, load_factor: float) -> np.ndarray:
        """The force (N, one entry per component) of the traction on boundary `name` at load
        factor t (dead load)."""
        condition = next(c for c in self.conditions if c.name == name)
        return load_factor * _vector(condition, self.components) * self.lengths[name]


class BoundaryMeans:
    """The mean of a vector function u over each boundary of a `BoundaryLoads` (int u ds /
    length; one compiled form for every boundary and component: `VectorIntegral`)."""

    def __init__(self, loads: BoundaryLoads, u: fem.Function):
        mesh = u.function_space.mesh
        self._integrals = {name: VectorIntegral(u, ds, mesh) for name, ds in loads.measures.items()}
        self._lengths = loads.lengths

    def __call__(self) -> dict[str, np.ndarray]:
        """Boundary name -> mean of u (one entry per component) at its current value
        (collective)."""
        return {name: total() / self._lengths[name] for name, total in self._integrals.items()}


def _own_measure(tagged: TaggedMesh, name: str) -> ufl.Measure:
    """ds over boundary `name` alone: its facets tagged `_BOUNDARY_ID` in tags of their own."""
    mesh = tagged.mesh
    facets = np.sort(tagged.facets(name)).astype(np.int32)
    tags = dmesh.meshtags(
        mesh, mesh.topology.dim - 1, facets, np.full(facets.size, _BOUNDARY_ID, np.int32)
    )
    return ufl.Measure("ds", domain=mesh, subdomain_data=tags, subdomain_id=_BOUNDARY_ID)


def _integrate(form, mesh) -> float:
    return mesh.comm.allreduce(fem.assemble_scalar(fem.form(form)), op=MPI.SUM)
