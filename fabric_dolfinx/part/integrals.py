"""Integrals of a vector integrand over a part or a boundary, as one compiled form.

The components of int f dA (or ds) for a vector f are int f . e for the unit axes e: with e a
Constant, one compiled form serves every component, and every measure of one kind (two
boundaries under the same id with facet tags of their own: `fabric_dolfinx.part.boundary`).
"""

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

__all__ = ["VectorIntegral"]


class VectorIntegral:
    """int f dmeasure for a UFL vector integrand f of n components (collective when called).

    Args:
        integrand: the vector f (UFL, shape (n,)).
        measure: the measure (dx, ds, with its subdomain).
        mesh: the mesh of both.
    """

    def __init__(self, integrand, measure: ufl.Measure, mesh):
        self._size = ufl.shape(integrand)[0]
        self._axis = fem.Constant(mesh, np.zeros(self._size, PETSc.ScalarType))
        self._form = fem.form(ufl.dot(integrand, self._axis) * measure)
        self._comm = mesh.comm

    def __call__(self) -> np.ndarray:
        """(n,) the integral's components at the current values of its coefficients."""
        values = np.empty(self._size)
        for axis in range(self._size):
            self._axis.value = np.eye(self._size)[axis]
            values[axis] = self._comm.allreduce(fem.assemble_scalar(self._form), op=MPI.SUM)
        return values
