"""Cell fields of a part's state for ParaView (DG0: the value at the cell centre), one writer
for every kind of part (`fabric_dolfinx.part.problem`).

A plane part writes the displacement, the Green-Lagrange strain and the Cauchy stress in the
mesh's axes, the principal stresses and the direction of the largest, and per cell its region
number, stitch value and course direction. A part in space writes the displacement (3D), the
strain and the second Piola-Kirchhoff stress in the course/wale frame, the Cauchy stress in
space (3 x 3), the principal stresses and the direction of the largest in space, and the
slack/wrinkle indicator (0 taut, 1 wrinkled, 2 slack).
"""

from collections.abc import Sequence

import numpy as np
import ufl
from dolfinx import fem
from dolfinx.io import XDMFFile
from mpi4py import MPI

from fabric_dolfinx.membrane.forms import membrane_state
from fabric_dolfinx.part.regions import cell_field

__all__ = [
    "PartFields",
    "principal_stresses",
    "principal_stresses_in_space",
    "slack_indicator",
]


def principal_stresses(stress: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal values (n, 2), largest first, and the unit direction (n, 2) of the largest
    of symmetric 2 x 2 tensors `stress` (n, 2, 2) (closed form, Mohr's circle)."""
    mean = 0.5 * (stress[:, 0, 0] + stress[:, 1, 1])
    half = 0.5 * (stress[:, 0, 0] - stress[:, 1, 1])
    radius = np.hypot(half, stress[:, 0, 1])
    values = np.stack([mean + radius, mean - radius], axis=1)
    theta = 0.5 * np.arctan2(stress[:, 0, 1], half)
    return values, np.stack([np.cos(theta), np.sin(theta)], axis=1)


def principal_stresses_in_space(
    cauchy: np.ndarray, normal: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Principal values (n, 2), largest first, and the unit direction (n, 3) of the largest
    of membrane stresses in space `cauchy` (n, 3, 3) whose third eigenvector lies along the
    deformed unit normal `normal` (n, 3) (its eigenvalue is 0: dropped)."""
    values, vectors = np.linalg.eigh(cauchy)
    along = np.abs(np.einsum("nij,ni->nj", vectors, normal))
    keep = np.argsort(along, axis=1)[:, :2]
    rows = np.arange(values.shape[0])[:, None]
    in_plane = values[rows, keep]
    order = np.argsort(-in_plane, axis=1)
    principal = np.take_along_axis(in_plane, order, axis=1)
    first = keep[np.arange(keep.shape[0]), order[:, 0]]
    return principal, vectors[np.arange(first.size), :, first]


def slack_indicator(stress: np.ndarray) -> np.ndarray:
    """0 taut, 1 wrinkled (one principal stress <= 0), 2 slack (both <= 0) for symmetric
    2 x 2 stresses (n, 2, 2). Any membrane stress (S or Cauchy) gives the same answer: they
    are congruent, and congruence keeps the signs of the eigenvalues."""
    values = np.linalg.eigvalsh(stress)
    return np.sum(values <= 0.0, axis=1).astype(float)


class PartFields:
    """The cell fields of a `PartProblem`'s state (see the module docstring).

    Attributes:
        displacement: u in the mesh's coordinate degree (mm).
        strain: Green-Lagrange strain E (2 x 2, -): in the mesh's axes for a plane part, in
            the course/wale frame in space.
        stress: second Piola-Kirchhoff stress S (2 x 2, course/wale frame, N/mm).
        cauchy: Cauchy stress (components x components, N/mm per deformed width).
        principal_stress: (sigma_1, sigma_2), sigma_1 >= sigma_2 (N/mm).
        principal_direction: unit vector of sigma_1 (deformed configuration).
        slack: 0 taut, 1 wrinkled, 2 slack (a part in space).
        region: region number; stitch: stitch value (0 where none);
        course_direction: degrees from the x axis.
        cell_dofs: (local cells,) the DG0 dof of each cell.

    Args:
        problem: the PartProblem.
        written: the names of the attributes `write` writes (default every field of the
            part's kind, as in the module docstring).
    """

    def __init__(self, problem, written: Sequence[str] | None = None):
        mesh = problem.tagged.mesh
        self._written = tuple(written) if written is not None else None
        u = problem.u
        self.components = components = problem.components
        plane = fem.TensorFunctionSpace(mesh, ("DG", 0), shape=(2, 2))
        tensors = fem.TensorFunctionSpace(mesh, ("DG", 0), shape=(components, components))
        vectors = fem.VectorFunctionSpace(mesh, ("DG", 0), dim=components)
        scalars = fem.FunctionSpace(mesh, ("DG", 0))
        self.strain = fem.Function(plane, name="green_lagrange_strain")
        self.stress = fem.Function(plane, name="second_piola_kirchhoff")
        self.cauchy = fem.Function(tensors, name="cauchy_stress")
        self.principal_stress = fem.Function(
            fem.VectorFunctionSpace(mesh, ("DG", 0), dim=2), name="principal_stress"
        )
        self.principal_direction = fem.Function(vectors, name="principal_direction")
        self.slack = fem.Function(scalars, name="slack")
        cells = problem.cells
        self.region = cell_field(scalars, cells, list(range(len(problem.regions))), "region")
        self.stitch = problem.stitch
        self.course_direction = cell_field(
            scalars, cells, [r.angle for r in problem.regions], "course_direction"
        )
        self._normal = fem.Function(fem.VectorFunctionSpace(mesh, ("DG", 0), dim=3))
        # the material at each cell's centre: the one point of the degree-1 Gauss rule
        self._centre = problem.material_at(1)
        state = membrane_state(u, self._centre.stress, problem.frame)
        strain = state.reference_strain if components == 2 else state.strain
        pairs = [(self.strain, strain), (self.cauchy, state.cauchy)]
        if components == 3:
            pairs += [(self.stress, state.second_piola_kirchhoff), (self._normal, state.normal)]
        self._expressions = [(f, fem.Expression(e, self._centre.points)) for f, e in pairs]
        self._cells = np.flatnonzero(cells.index >= 0).astype(np.int32)  # the cells with a law
        self.cell_dofs = plane.dofmap.list.array.reshape(cells.index.size, -1)[:, 0]
        self._comm = mesh.comm
        self._owned = mesh.topology.index_map(mesh.topology.dim).size_local
        area = fem.assemble_vector(fem.form(ufl.TestFunction(scalars) * ufl.dx(domain=mesh)))
        self._areas = area.array[: self._owned].copy()  # reference area of each owned cell
        self._u = u
        degree = mesh.geometry.cmap.degree
        if u.function_space.ufl_element().degree() == degree:
            self.displacement = u
        else:
            space = fem.VectorFunctionSpace(mesh, ("Lagrange", degree), dim=components)
            self.displacement = fem.Function(space, name="displacement")

    def update(self) -> None:
        """Evaluate the fields at the current displacement."""
        self._centre.update()
        cells = self._cells
        for function, expression in self._expressions:
            size = function.function_space.dofmap.index_map_bs
            values = function.x.array.reshape(-1, size)
            values[self.cell_dofs[cells]] = expression.eval(cells).reshape(cells.size, size)
        n = self.components
        cauchy = self.cauchy.x.array.reshape(-1, n, n)
        if n == 2:
            values, directions = principal_stresses(cauchy)
        else:
            normal = self._normal.x.array.reshape(-1, 3)
            values, directions = principal_stresses_in_space(cauchy, normal)
            self.slack.x.array[:] = slack_indicator(self.stress.x.array.reshape(-1, 2, 2))
        self.principal_stress.x.array[:] = values.ravel()
        self.principal_direction.x.array[:] = directions.ravel()
        if self.displacement is not self._u:
            self.displacement.interpolate(self._u)

    def slack_areas(self) -> tuple[float, float]:
        """The fractions of the reference area that are wrinkled and slack at the last
        `update` (a part in space; collective)."""
        state = self.slack.x.array[: self._owned]
        local = [self._areas[state == 1.0].sum(), self._areas[state == 2.0].sum()]
        wrinkled, slack, total = self._comm.allreduce(
            np.array([*local, self._areas.sum()]), op=MPI.SUM
        )
        return float(wrinkled / total), float(slack / total)

    def cell_values(self, field: str, cell: int) -> np.ndarray:
        """The value of `field` ("strain", "cauchy", ...) on local `cell` (a copy)."""
        function = getattr(self, field)
        size = function.function_space.dofmap.index_map_bs
        return function.x.array.reshape(-1, size)[self.cell_dofs[cell]].copy()

    def component(self, field: str, i: int, j: int) -> np.ndarray:
        """Local cell values (num_owned_cells,) of component (i, j) of "strain" or "cauchy"."""
        function = getattr(self, field)
        n = 2 if field == "strain" else self.components
        return function.x.array.reshape(-1, n, n)[self.cell_dofs[: self._owned], i, j].copy()

    def functions(self) -> tuple[fem.Function, ...]:
        """The fields written (`written`, or every field of the part's kind), in order."""
        if self._written is not None:
            return tuple(getattr(self, name) for name in self._written)
        if self.components == 3:
            fields = (self.strain, self.stress, self.cauchy)
            return (self.displacement, *fields, *self._principal(), self.slack)
        fields = (self.strain, self.cauchy, *self._principal())
        return (self.displacement, *fields, self.region, self.stitch, self.course_direction)

    def _principal(self) -> tuple[fem.Function, fem.Function]:
        return self.principal_stress, self.principal_direction

    def write(self, output: XDMFFile, time: float) -> None:
        """Append every field at `time` (the load factor)."""
        for function in self.functions():
            output.write_function(function, time)
