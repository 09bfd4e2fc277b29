"""Uniaxial tension of a square fabric patch between clamps (the paper's macro-scale test).

Course-wise: the left edge is clamped and the right edge displaced uniformly along x;
wale-wise: the bottom edge is clamped and the top edge displaced along y (both clamps hold
the other component at 0, like the grips of a tensile tester). The reported force is the
reaction on the moving clamp along the load, per undeformed width of the patch, against the
nominal strain (clamp displacement / patch length).
"""

import math
import time
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import numpy as np
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from fabric_dolfinx.domain import StrainRangeCheck
from fabric_dolfinx.io import CellFields, XDMFOutput
from fabric_dolfinx.material import Material
from fabric_dolfinx.membrane import flat_frame, membrane_forms, membrane_state
from fabric_dolfinx.mesh import rectangle_patch
from fabric_dolfinx.solve import (
    LoadStepper,
    PathResult,
    SolverOptions,
    StepRecord,
    boundary_indicator,
)
from fabric_dolfinx.tension_spec import DIRECTIONS, TensionTest
from rve_rod.errors import ConvergenceError
from rve_rod.units import n_per_mm_to_gf_per_cm

__all__ = [
    "TensionResult",
    "TensionSetup",
]


class TensionResult(NamedTuple):
    """Force-strain curve of a tension test (index 0 is the unloaded state).

    Attributes:
        strain: (k+1,) nominal strain.
        force_n_per_mm: (k+1,) clamp reaction along the load per undeformed width (N/mm).
        force_gf_per_cm: the same in gf/cm.
        newton_iterations: (k,) Newton iterations of each converged step.
        dofs: global number of degrees of freedom.
        ranks: MPI ranks.
        wall_time_s: time of the load path (s), without mesh generation and compilation.
        cutbacks: failed attempts that were retried with half the step.
        outside_domain: whether strains left the response-surface domain.
        path: the solver's record (residual histories, reactions of both clamps).
    """

    strain: np.ndarray
    force_n_per_mm: np.ndarray
    force_gf_per_cm: np.ndarray
    newton_iterations: np.ndarray
    dofs: int
    ranks: int
    wall_time_s: float
    cutbacks: int
    outside_domain: bool
    path: PathResult


class TensionSetup:
    """Mesh, forms, boundary conditions and solver of a tension test, built once.

    Attributes:
        test, material, options: the inputs.
        mesh: the TaggedMesh of the patch.
        u: the displacement (mm).
        frame: the material frame (course at `test.angle`).
        stress: the MembraneState expressions at u.
        stepper: the LoadStepper (reactions "clamp" and "moving").
    """

    def __init__(
        self,
        material: Material,
        test: TensionTest = TensionTest(),
        options: SolverOptions | None = None,
        comm: MPI.Comm = MPI.COMM_WORLD,
    ):
        options = options or SolverOptions()
        self.test, self.material, self.options = test, material, options
        self.mesh = rectangle_patch(
            comm,
            width=test.size,
            height=test.size,
            elements_x=test.elements,
            elements_y=test.elements,
        )
        domain = self.mesh.mesh
        space = fem.VectorFunctionSpace(domain, ("Lagrange", test.element_degree))
        self.u = fem.Function(space, name="displacement")
        self.angle = fem.Constant(domain, PETSc.ScalarType(math.radians(test.angle)))
        self.quadrature_degree = test.quadrature_degree or 2 * test.element_degree
        self.frame = flat_frame(domain, self.angle)
        self.stress = membrane_state(self.u, material.law, self.frame)
        forms = membrane_forms(self.u, material.law, self.frame, self.quadrature_degree)
        clamped, moving, component = DIRECTIONS[test.direction]
        self._component = component
        self._displacement = fem.Constant(domain, np.zeros(2, dtype=PETSc.ScalarType))
        fdim = domain.topology.dim - 1
        zero = fem.Constant(domain, np.zeros(2, dtype=PETSc.ScalarType))
        bcs = [
            fem.dirichletbc(
                value,
                fem.locate_dofs_topological(space, fdim, self.mesh.facets(name)),
                space,
            )
            for value, name in ((zero, clamped), (self._displacement, moving))
        ]
        reactions = {
            "clamp": boundary_indicator(space, self.mesh.facets(clamped)),
            "moving": boundary_indicator(space, self.mesh.facets(moving)),
        }
        self.stepper = LoadStepper(
            forms.residual, forms.jacobian, self.u, bcs, options=options, reactions=reactions
        )
        self.dofs = space.dofmap.index_map.size_global * space.dofmap.index_map_bs

    def apply_load(self, load_factor: float) -> None:
        """Displace the moving clamp by load_factor * max_strain * size along the load."""
        value = np.zeros(2)
        value[self._component] = load_factor * self.test.max_strain * self.test.size
        self._displacement.value[:] = value

    def run(
        self,
        xdmf: Path | str | None = None,
        on_step: Callable[[float, CellFields | None], None] | None = None,
        fields: bool = False,
    ) -> TensionResult:
        """Follow the load path from the unloaded patch.

        Args:
            xdmf: write displacement, strain and Cauchy stress per step to this XDMF file.
            on_step: called after every converged step with (nominal strain, CellFields or
                None); the fields are up to date when `fields` or `xdmf` is given.
            fields: evaluate the cell fields after every step even without xdmf.

        Raises ConvergenceError whose `history` is the TensionResult of the converged steps
        (the XDMF file then holds them and is closed).
        """
        self.u.x.array[:] = 0.0
        self.apply_load(0.0)
        check = None
        if self.material.domain is not None:
            check = StrainRangeCheck(
                self.stress.strain,
                self.mesh.mesh,
                self.material.domain,
                self.quadrature_degree,
            )
        cell_fields = CellFields(self.u, self.stress) if (xdmf or fields) else None
        outside = False
        start = time.perf_counter()

        def after_step(step: StepRecord, output: XDMFOutput | None) -> None:
            nonlocal outside
            strain = round(step.load_factor * self.test.max_strain, 12)
            if check is not None:
                outside = check(strain) or outside
            if output is not None:
                output.write(strain)
            elif cell_fields is not None:
                cell_fields.update()
            if on_step is not None:
                on_step(strain, cell_fields)

        try:
            if xdmf is not None:
                with XDMFOutput(xdmf, cell_fields) as output:
                    output.write(0.0)
                    path = self.stepper.run(self.apply_load, lambda s: after_step(s, output))
            else:
                path = self.stepper.run(self.apply_load, lambda s: after_step(s, None))
        except ConvergenceError as error:
            partial = self._result(error.history, outside, time.perf_counter() - start)
            raise ConvergenceError(
                str(error), last_converged=error.last_converged, history=partial
            ) from None
        return self._result(path, outside, time.perf_counter() - start)

    def _result(self, path: PathResult, outside: bool, wall_time: float) -> TensionResult:
        strain = np.array([0.0] + [s.load_factor * self.test.max_strain for s in path.steps])
        force = (
            np.array([0.0] + [s.reactions["moving"][self._component] for s in path.steps])
            / self.test.size
        )
        return TensionResult(
            strain=strain,
            force_n_per_mm=force,
            force_gf_per_cm=n_per_mm_to_gf_per_cm(force),
            newton_iterations=np.array([s.iterations for s in path.steps], dtype=int),
            dofs=self.dofs,
            ranks=self.u.function_space.mesh.comm.size,
            wall_time_s=wall_time,
            cutbacks=path.cutbacks,
            outside_domain=outside,
            path=path,
        )
