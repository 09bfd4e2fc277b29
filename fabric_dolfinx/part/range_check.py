"""Checks that the strains of a solution stay in the sampled domain of the response surface.

Outside its domain a surface is extrapolated (C1 Taylor extension, docs/surface-format.md):
the run continues, but the user must know the stresses there are not data. The check
evaluates the material-frame strain at the quadrature points of every cell after each
converged step and logs one warning per run (on rank 0) the first time a component leaves
the domain.
"""

import logging

import basix
import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

__all__ = [
    "StrainRangeCheck",
]

logger = logging.getLogger(__name__)


class StrainRangeCheck:
    """Material-frame strain range at the quadrature points, against a surface domain.

    Args:
        material_strain: UFL (2, 2) strain in the material frame (`MembraneState.strain`).
        mesh: the mesh it lives on.
        domain: (3, 2) [min, max] of E11, E22, E12.
        quadrature_degree: degree of the Gauss rule of the forms (same points).
        cells: local cells to check (a region's); default all owned cells.

    Attributes:
        warned: whether the warning was issued (at most once per instance).
        first_outside: load factor (or label) of the first step outside, or None.
    """

    def __init__(
        self,
        material_strain: ufl.core.expr.Expr,
        mesh,
        domain: np.ndarray,
        quadrature_degree: int,
        cells: np.ndarray | None = None,
    ):
        points, _ = basix.make_quadrature(basix.CellType.quadrilateral, quadrature_degree)
        components = ufl.as_vector(
            [material_strain[0, 0], material_strain[1, 1], material_strain[0, 1]]
        )
        self._expression = fem.Expression(components, points)
        owned = mesh.topology.index_map(2).size_local
        if cells is None:
            cells = np.arange(owned, dtype=np.int32)
        self._cells = np.asarray(cells, dtype=np.int32)[np.asarray(cells) < owned]
        self._comm = mesh.comm
        self.domain = np.asarray(domain, dtype=float)
        self.warned = False
        self.first_outside = None

    def strain_range(self) -> np.ndarray:
        """(3, 2) [min, max] of E11, E22, E12 over all quadrature points of all ranks."""
        values = self._expression.eval(self._cells).reshape(-1, 3)
        local_low = values.min(axis=0) if values.size else np.full(3, np.inf)
        local_high = values.max(axis=0) if values.size else np.full(3, -np.inf)
        low, high = np.empty(3), np.empty(3)
        self._comm.Allreduce(local_low, low, op=MPI.MIN)
        self._comm.Allreduce(local_high, high, op=MPI.MAX)
        return np.column_stack([low, high])

    def __call__(self, load_factor: float) -> bool:
        """Check the current state; warn the first time it is outside. Returns outside."""
        extent = self.strain_range()
        outside = bool(
            np.any(extent[:, 0] < self.domain[:, 0]) or np.any(extent[:, 1] > self.domain[:, 1])
        )
        if outside and not self.warned:
            self.warned = True
            self.first_outside = load_factor
            if self._comm.rank == 0:
                names = ("E11", "E22", "E12")
                ranges = ", ".join(
                    f"{name} [{lo:.4g}, {hi:.4g}] (data [{a:.4g}, {b:.4g}])"
                    for name, (lo, hi), (a, b) in zip(names, extent, self.domain, strict=True)
                )
                logger.warning(
                    "strains left the response-surface domain at load %.4g: %s; continuing "
                    "on the C1 extension (warned once per run)",
                    load_factor,
                    ranges,
                )
        return outside
