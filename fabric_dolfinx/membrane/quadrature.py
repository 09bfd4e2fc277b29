"""The material at the quadrature points: S and its tangent as Functions on quadrature
elements, evaluated with NumPy before every assembly.

The membrane forms (`fabric_dolfinx.membrane.forms`) hold no number of the material law: they
see the second Piola-Kirchhoff stress S (S11, S22, S12) and its tangent (dS11/dE11,
dS11/dE22, dS22/dE11, dS22/dE22, dS12/dE12: the surface contract S11(E11, E22),
S22(E11, E22), S12(E12) of docs/surface-format.md) as Functions on quadrature elements of
the forms' Gauss rule. `QuadratureMaterial.update` brings them to the current displacement:
a compiled `fem.Expression` gives the material-frame strain at the quadrature points of every
local cell (ghosts included: a quadrature value belongs to one cell, so every rank fills the
values of the cells it holds and no scatter is needed), and each cell's law
(`fabric_dolfinx.material`, `fabric_dolfinx.graded`; a region's, at the cell's stitch value)
gives S and the tangent there with NumPy. So every surface, region layout and graded family
gives the same forms: FFCx compiles one residual, one Jacobian and one strain Expression per
kind of part (plane or in space, element and quadrature degree), not one per surface
(docs/benchmarks.md, "The material at the quadrature points").
"""

from collections.abc import Sequence

import basix
import numpy as np
import ufl
from dolfinx import fem

from fabric_dolfinx.material import Material
from rve_rod.errors import InputError

__all__ = [
    "TANGENT_COMPONENTS",
    "QuadratureMaterial",
]

TANGENT_COMPONENTS = ((0, 0), (0, 1), (1, 0), (1, 1), (2, 2))
"""The (a, b) of the tangent dS_a/dE_b stored, with E = (E11, E22, E12) and S = (S11, S22,
S12): every other entry of a law's tangent is 0 (the surface contract)."""


class QuadratureMaterial:
    """S and dS/dE of the cells' laws at the quadrature points of degree `degree`.

    Args:
        strain: the Green-Lagrange strain (2, 2) in the material frame, a UFL expression of
            the displacement (`membrane.forms.green_lagrange`).
        mesh: the mesh.
        materials: the laws (at least one).
        degree: the Gauss rule's exactness (the forms' quadrature degree).
        cell_material: (local cells incl. ghosts,) index into `materials` of each cell, -1
            for a cell without a law (a ghost of a region not held on this rank); default
            every cell materials[0].
        stitch: (local cells incl. ghosts,) the stitch value of each cell (mm, read by
            graded laws); default 0.

    Attributes:
        points: (q, 2) the reference points of a cell; stress_values: S (3 per point);
        tangent_values: the tangent (5 per point, TANGENT_COMPONENTS).
    """

    def __init__(
        self,
        strain: ufl.core.expr.Expr,
        mesh,
        materials: Sequence[Material],
        degree: int,
        cell_material: np.ndarray | None = None,
        stitch: np.ndarray | None = None,
    ):
        self.materials = tuple(materials)
        self.degree = degree
        cell = mesh.ufl_cell()
        cell_type = basix.cell.string_to_type(mesh.topology.cell_type.name)
        self.points, _ = basix.make_quadrature(cell_type, degree)
        self.mesh = mesh
        spaces = [
            fem.FunctionSpace(
                mesh, ufl.VectorElement("Quadrature", cell, degree, dim=n, quad_scheme="default")
            )
            for n in (3, len(TANGENT_COMPONENTS))
        ]
        self.stress_values = fem.Function(spaces[0], name="stress_at_quadrature_points")
        self.tangent_values = fem.Function(spaces[1], name="tangent_at_quadrature_points")
        self._strain = fem.Expression(
            ufl.as_vector([strain[0, 0], strain[1, 1], strain[0, 1]]), self.points
        )
        count = mesh.topology.index_map(2).size_local + mesh.topology.index_map(2).num_ghosts
        cell_material = np.zeros(count, int) if cell_material is None else np.asarray(cell_material)
        stitch = np.zeros(count) if stitch is None else np.asarray(stitch, dtype=float)
        if len(cell_material) != count or len(stitch) != count:
            raise InputError(
                f"cell_material and stitch need one value per local cell ({count}), got "
                f"{len(cell_material)} and {len(stitch)}"
            )
        dofs = spaces[0].dofmap.list.array.reshape(count, -1)
        points = self.points.shape[0]
        self._cells = []  # per law: (its cells, their points' dofs, their points' stitch)
        for number in range(len(self.materials)):
            cells = np.flatnonzero(cell_material == number).astype(np.int32)
            self._cells.append((cells, dofs[cells].ravel(), np.repeat(stitch[cells], points)))

    @property
    def stress(self) -> ufl.core.expr.Expr:
        """S (2, 2) N/mm, material frame, at the quadrature points (UFL)."""
        s = self.stress_values
        return ufl.as_matrix([[s[0], s[2]], [s[2], s[1]]])

    def stress_increment(self, strain_increment: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        """dS = dS/dE : dE (2, 2) for a strain increment dE (2, 2, symmetric), UFL."""
        t, dE = self.tangent_values, strain_increment
        shear = t[4] * dE[0, 1]
        return ufl.as_matrix(
            [[t[0] * dE[0, 0] + t[1] * dE[1, 1], shear], [shear, t[2] * dE[0, 0] + t[3] * dE[1, 1]]]
        )

    def measure(self) -> ufl.Measure:
        """The cells of the mesh with this Gauss rule (basix's default rule, exact to
        `degree`): the measure of every form that reads S or the tangent."""
        metadata = {"quadrature_degree": self.degree, "quadrature_scheme": "default"}
        return ufl.dx(domain=self.mesh, metadata=metadata)

    def update(self) -> None:
        """S and the tangent of every cell with a law at the current displacement.

        Where the strain is not finite (a Newton step that blew up) S and the tangent are
        NaN, so the residual is not finite and the solver cuts the step back."""
        stress = self.stress_values.x.array.reshape(-1, 3)
        tangent = self.tangent_values.x.array.reshape(-1, len(TANGENT_COMPONENTS))
        rows, columns = np.array(TANGENT_COMPONENTS).T
        for material, (cells, dofs, stitch) in zip(self.materials, self._cells, strict=True):
            if cells.size == 0:
                continue
            E = self._strain.eval(cells).reshape(-1, 3)
            finite = np.all(np.isfinite(E), axis=1)
            stress[dofs[~finite]], tangent[dofs[~finite]] = np.nan, np.nan
            if not np.any(finite):
                continue
            result = material.law(E[finite], stitch[finite])
            stress[dofs[finite]] = result.S
            tangent[dofs[finite]] = result.tangent[:, rows, columns]
