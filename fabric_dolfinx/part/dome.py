"""The first step of a flat part in space under pressure or indentation: a one-mode dome.

A flat, unstressed membrane has no stiffness out of its plane (the tangent is singular in the
normal direction), so Newton cannot take a first step under pressure or indentation from it.
Whenever a step starts from a flat state (the first step, and its retries after a cutback)
the problem first finds the best dome of one shape: phi solves -lap(phi) = 1 with phi = 0
where the conditions hold z (max phi = 1), and the amplitude A of u = A phi e_z solves the
scalar equation R(A phi e_z; phi e_z) = 0 (a one-mode Galerkin solution, found by bracketing
and Brent's method). Newton starts from that dome, which is stressed and so has out-of-plane
stiffness; the dome amplitude is reported.
"""

import logging
from collections.abc import Callable

import dolfinx.fem.petsc
import numpy as np
import scipy.optimize
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from rve_rod.errors import ConvergenceError

__all__ = ["Dome"]

logger = logging.getLogger(__name__)


class Dome:
    """The one-mode dome of a flat part in space (module docstring).

    Args:
        u: the displacement (3 components on a flat mesh).
        residual: the part's residual form R(u; v).
        facets: the local boundary facets where z is held (phi = 0 there).
        update: brings the Functions the residual reads to the current u (the material at
            the quadrature points), called before each evaluation of the residual.

    Attributes:
        amplitude: the last dome height (mm), 0 until one was needed.
    """

    def __init__(
        self, u: fem.Function, residual: ufl.Form, facets: np.ndarray, update: Callable[[], None]
    ):
        self.u = u
        self._update = update
        space = u.function_space
        mesh = space.mesh
        self._comm = mesh.comm
        scalars = fem.FunctionSpace(mesh, ("Lagrange", space.ufl_element().degree()))
        phi, w = ufl.TrialFunction(scalars), ufl.TestFunction(scalars)
        zero = fem.dirichletbc(
            PETSc.ScalarType(0.0),
            fem.locate_dofs_topological(scalars, mesh.topology.dim - 1, facets),
            scalars,
        )
        problem = dolfinx.fem.petsc.LinearProblem(
            ufl.inner(ufl.grad(phi), ufl.grad(w)) * ufl.dx,
            fem.Constant(mesh, PETSc.ScalarType(1.0)) * w * ufl.dx,
            bcs=[zero],
            petsc_options={"ksp_type": "preonly", "pc_type": "lu"},
        )
        bubble = problem.solve()
        peak = self._comm.allreduce(float(np.abs(bubble.x.array).max()), op=MPI.MAX)
        self.shape = fem.Function(space)
        self.shape.x.array.reshape(-1, 3)[:, 2] = bubble.x.array / peak
        v = ufl.TestFunction(space)
        self._projected = fem.form(ufl.replace(residual, {v: self.shape}))
        self._size = self._comm.allreduce(float(np.ptp(mesh.geometry.x, axis=0).max()), MPI.MAX)
        self.amplitude = 0.0

    def is_flat(self) -> bool:
        """Whether u has no z component anywhere (collective)."""
        normal = self.u.x.array.reshape(-1, 3)[:, 2]
        local = float(np.abs(normal).max()) if normal.size else 0.0
        return self._comm.allreduce(local, op=MPI.MAX) == 0.0

    def place(self) -> None:
        """Put the dome of the current load in place: u = A phi e_z."""
        self.amplitude = self._amplitude()
        self.u.x.array[:] = self.amplitude * self.shape.x.array

    def _projected_residual(self, amplitude: float) -> float:
        self.u.x.array[:] = amplitude * self.shape.x.array
        self._update()
        return self._comm.allreduce(fem.assemble_scalar(self._projected), op=MPI.SUM)

    def _amplitude(self) -> float:
        """The root A of R(A phi e_z; phi e_z) (mm), bracketed from the side the load pushes."""
        start = self._projected_residual(0.0)
        if start == 0.0:
            return 0.0
        sign = 1.0 if start < 0.0 else -1.0
        size = self._size
        high = 1e-4 * size
        for _ in range(60):
            if self._projected_residual(sign * high) * start < 0.0:
                break
            high *= 2.0
        else:
            raise ConvergenceError("no dome amplitude balances the first load step")
        low = 0.5 * high if high > 1e-4 * size else 0.0
        root = scipy.optimize.brentq(
            lambda a: self._projected_residual(sign * a), low, high, xtol=1e-12 * size
        )
        logger.info("first step starts from a dome of height %.4g mm", sign * root)
        return sign * root
