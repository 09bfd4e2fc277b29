"""Uniaxial tension of a square fabric patch between clamps (the paper's macro-scale test),
as an ordinary part (`fabric_dolfinx.part.problem`).

Course-wise: the left edge is clamped and the right edge displaced uniformly along x;
wale-wise: the bottom edge is clamped and the top edge displaced along y (both clamps hold
the other component at 0, like the grips of a tensile tester). The part is the structured
`rectangle` shape of side `size` with `elements` quadrilaterals per side; the displaced edge
is a `displacement` boundary. The reported force is the reaction on the moving clamp along
the load, per undeformed width of the patch, against the nominal strain (clamp displacement
/ patch length), which also labels the XDMF output and `on_step`.
"""

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import NamedTuple

import numpy as np
from mpi4py import MPI

from fabric_dolfinx.material import Material
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.part.fields import PartFields
from fabric_dolfinx.part.problem import Observer, PartProblem, PartResult
from fabric_dolfinx.part.regions import Region
from fabric_dolfinx.solve import LoadPath, SolverOptions, with_history
from fabric_dolfinx.spec.part import BoundaryCondition, MeshSpec
from fabric_dolfinx.spec.tension import DIRECTIONS, TensionTest
from rve_rod.units import n_per_mm_to_gf_per_cm

__all__ = [
    "TENSION_FIELDS",
    "TensionResult",
    "TensionSetup",
    "tension_part",
]

TENSION_FIELDS = ("displacement", "strain", "cauchy")
"""The cell fields the patch writes per step (`PartFields`)."""


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
        observed: name -> (k+1) values of each observer given to `run`.
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
    observed: dict[str, list]
    path: LoadPath


def tension_part(test: TensionTest) -> tuple[MeshSpec, tuple[BoundaryCondition, ...]]:
    """The patch of `test` as a part: its mesh and its clamp and displaced edge."""
    clamped, moving, component = DIRECTIONS[test.direction]
    size = test.size
    mesh = MeshSpec("rectangle", {"width": size, "height": size}, element_size=size / test.elements)
    displacement = [0.0, 0.0]
    displacement[component] = test.max_strain * size
    conditions = (
        BoundaryCondition(clamped),
        BoundaryCondition(moving, "displacement", tuple(displacement)),
    )
    return mesh, conditions


class TensionSetup:
    """The part problem of a tension test, built once (several `run`s reuse it).

    Attributes:
        test, material, options: the inputs.
        problem: the PartProblem (boundaries "clamp"ed and "moving" as DIRECTIONS names).
        u: the displacement (mm); frame: the material frame; stepper: the LoadStepper.
    """

    def __init__(
        self,
        material: Material,
        test: TensionTest = TensionTest(),
        options: SolverOptions | None = None,
        comm: MPI.Comm = MPI.COMM_WORLD,
    ):
        self.test, self.material = test, material
        self.options = options or SolverOptions()
        mesh, conditions = tension_part(test)
        self.problem = PartProblem(
            make_mesh(mesh, comm),
            [Region("fabric", material, angle=test.angle)],
            conditions,
            element_degree=test.element_degree,
            quadrature_degree=test.quadrature_degree,
            options=self.options,
        )
        self.u, self.frame, self.stepper = self.problem.u, self.problem.frame, self.problem.stepper
        self.dofs = self.problem.dofs

    def run(
        self,
        xdmf: Path | str | None = None,
        on_step: Callable[[float, PartFields | None], None] | None = None,
        fields: bool = False,
        observers: Mapping[str, Observer] | None = None,
    ) -> TensionResult:
        """Follow the load path from the unloaded patch (`PartProblem.run`; the nominal
        strain labels the steps).

        Raises ConvergenceError whose `history` is the TensionResult of the converged steps
        (the XDMF file then holds them and is closed).
        """
        max_strain = self.test.max_strain

        def solve() -> PartResult:
            return self.problem.run(
                xdmf,
                on_step,
                fields,
                observers,
                label=lambda t: round(t * max_strain, 12),
                written=TENSION_FIELDS,
            )

        return with_history(solve, self._result)

    def _result(self, result: PartResult) -> TensionResult:
        _, moving, component = DIRECTIONS[self.test.direction]
        force = result.boundaries[moving].force[:, component] / self.test.size
        return TensionResult(
            strain=result.load_factor * self.test.max_strain,
            force_n_per_mm=force,
            force_gf_per_cm=n_per_mm_to_gf_per_cm(force),
            newton_iterations=result.newton_iterations,
            dofs=result.dofs,
            ranks=result.ranks,
            wall_time_s=result.wall_time_s,
            cutbacks=result.cutbacks,
            outside_domain=any(result.outside_domain.values()),
            observed=result.observed,
            path=result.path,
        )
