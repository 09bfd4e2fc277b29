"""Load stepping with Newton's method on PETSc: automatic cutback, reaction forces, step records.

The solver receives only forms (residual and Jacobian, UFL), the unknown, the Dirichlet
conditions and a callable that sets the load for a load factor t in [0, 1]. Linear systems
are solved by MUMPS (direct LU, the default) or by GMRES/CG preconditioned with hypre
BoomerAMG for large meshes; PETSc options with the prefix `fabric_` override either (e.g.
`-fabric_ksp_monitor`). When Newton fails (no convergence, a non-finite or exploding
residual, a failed linear solve) the step is halved and retried from the last converged state,
down to a minimum step; then `ConvergenceError` carries every converged step.

The Newton loop is written here rather than taken from `dolfinx.nls.petsc.NewtonSolver`: in
DOLFINx 0.5.2 the Python binding offers no convergence-check hook, and the built-in relative
criterion divides the residual by the norm of the first Newton increment (different units), so
neither the residual history nor a residual-based tolerance would be available.
"""

import logging
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import NamedTuple

import dolfinx.fem.petsc
import numpy as np
import ufl
from dolfinx import fem
from petsc4py import PETSc

from rve_rod.errors import (
    ConvergenceError,
    InputError,
    check_integer,
    check_positive,
    check_range,
)

logger = logging.getLogger(__name__)

LINEAR_SOLVERS = ("lu", "gmres", "cg")
"""Linear solvers: MUMPS LU; GMRES or CG (symmetric tangents only) with hypre BoomerAMG."""


@dataclass(frozen=True)
class SolverOptions:
    """Newton, load-stepping and linear-solver settings.

    Attributes:
        linear_solver: "lu" (MUMPS, default), "gmres" or "cg" with hypre BoomerAMG. CG needs
            a symmetric tangent (SVK, `energy` surfaces); `stress` surfaces are not symmetric.
        steps: equal load steps from t = 0 to 1; every step end is reached exactly.
        relative_tolerance: Newton converges when the residual 2-norm falls below this times
            the residual at the start of the step (Dirichlet increment included) ...
        absolute_tolerance: ... or below this (N).
        floor_tolerance: ... or, once below this times the initial residual, when it stops
            decreasing (halves no more): the round-off floor, reached before a tight
            relative tolerance on very small steps.
        max_iterations: Newton iterations per attempt before the step is cut back.
        divergence_factor: an attempt fails at once if the residual exceeds this times its
            initial value.
        min_step: the smallest load-factor increment cutbacks may reach.
        krylov_tolerance: relative tolerance of GMRES/CG (unused by LU).
    """

    linear_solver: str = "lu"
    steps: int = 20
    relative_tolerance: float = 1e-10
    absolute_tolerance: float = 1e-12
    floor_tolerance: float = 1e-8
    max_iterations: int = 25
    divergence_factor: float = 1e6
    min_step: float = 1.0 / 1024
    krylov_tolerance: float = 1e-10

    def __post_init__(self):
        if self.linear_solver not in LINEAR_SOLVERS:
            raise InputError(
                f"linear_solver={self.linear_solver!r} is not one of {', '.join(LINEAR_SOLVERS)}"
            )
        check_integer("steps", self.steps, 1)
        check_positive("relative_tolerance", self.relative_tolerance)
        check_positive("absolute_tolerance", self.absolute_tolerance, "N")
        check_range("floor_tolerance", self.floor_tolerance, 0.0, 1.0)
        check_integer("max_iterations", self.max_iterations, 1)
        check_positive("divergence_factor", self.divergence_factor)
        check_positive("min_step", self.min_step)
        check_positive("krylov_tolerance", self.krylov_tolerance)


class BoundaryIndicator(NamedTuple):
    """Functions equal to 1 at the boundary's degrees of freedom of one displacement
    component (x, resp. y) and 0 elsewhere; the residual's action on them is the reaction."""

    x: fem.Function
    y: fem.Function


def boundary_indicator(space: fem.FunctionSpace, facets: np.ndarray) -> BoundaryIndicator:
    """The BoundaryIndicator of the (local) boundary `facets` of the vector space `space`."""
    fdim = space.mesh.topology.dim - 1
    indicators = []
    for component in range(2):
        function = fem.Function(space)
        dofs = fem.locate_dofs_topological(space.sub(component), fdim, facets)
        function.x.array[dofs] = 1.0
        function.x.scatter_forward()
        indicators.append(function)
    return BoundaryIndicator(*indicators)


class NewtonResult(NamedTuple):
    """One Newton attempt at a fixed load.

    Attributes:
        converged: whether the residual met the tolerance.
        residual_norms: 2-norms of the residual (N) before each iteration, iteration 0 first.
        failure: why the attempt failed ("" if it converged).
        linear_iterations: Krylov iterations of all its linear solves (1 per solve for LU).
    """

    converged: bool
    residual_norms: tuple[float, ...]
    failure: str
    linear_iterations: int

    @property
    def iterations(self) -> int:
        return len(self.residual_norms) - 1


class StepResult(NamedTuple):
    """A converged load step.

    Attributes:
        load_factor: t in (0, 1].
        newton_iterations: iterations of the converged attempt.
        residual_norms: its residual history (N), see NewtonResult.
        linear_iterations: its Krylov iterations (1 per Newton iteration for LU).
        reactions: boundary name -> total reaction force (Fx, Fy) in N, summed over ranks.
        wall_time_s: time since the previous converged step (failed attempts included).
    """

    load_factor: float
    newton_iterations: int
    residual_norms: tuple[float, ...]
    linear_iterations: int
    reactions: dict[str, np.ndarray]
    wall_time_s: float


class LoadPathResult(NamedTuple):
    """All converged steps of a load path.

    Attributes:
        steps: the converged steps in order.
        cutbacks: how many attempts failed and were retried with half the step.
        wall_time_s: total time (s).
    """

    steps: tuple[StepResult, ...]
    cutbacks: int
    wall_time_s: float

    @property
    def newton_iterations(self) -> int:
        return sum(step.newton_iterations for step in self.steps)


class LoadStepper:
    """Newton's method with load stepping for one residual/Jacobian pair.

    Owns the compiled forms and the PETSc matrix, vectors and KSP, so several load paths on
    the same forms (reset `u` in between) compile and allocate once.
    """

    def __init__(
        self,
        residual: ufl.Form,
        jacobian: ufl.Form,
        u: fem.Function,
        bcs: list,
        *,
        options: SolverOptions = SolverOptions(),
        reactions: Mapping[str, BoundaryIndicator] | None = None,
    ):
        self.options = options
        self.u = u
        self.bcs = list(bcs)
        self.reactions = dict(reactions or {})
        self._residual_form = fem.form(residual)
        self._jacobian_form = fem.form(jacobian)
        self._matrix = dolfinx.fem.petsc.create_matrix(self._jacobian_form)
        self._vector = dolfinx.fem.petsc.create_vector(self._residual_form)
        self._increment = self._matrix.createVecRight()
        self._ksp = _linear_solver(self._matrix, options)

    def _assemble_residual(self) -> float:
        """Residual with the Dirichlet conditions (rows hold u - g); returns its 2-norm (N)."""
        b = self._vector
        with b.localForm() as local:
            local.set(0.0)
        dolfinx.fem.petsc.assemble_vector(b, self._residual_form)
        dolfinx.fem.petsc.apply_lifting(
            b, [self._jacobian_form], bcs=[self.bcs], x0=[self.u.vector], scale=-1.0
        )
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        dolfinx.fem.petsc.set_bc(b, self.bcs, self.u.vector, -1.0)
        return b.norm()

    def newton(self) -> NewtonResult:
        """Newton iterations at the current load, starting from the current `u`."""
        options = self.options
        norms = [self._assemble_residual()]
        linear = 0
        tolerance = max(options.absolute_tolerance, options.relative_tolerance * norms[0])
        for _ in range(options.max_iterations):
            if _converged(norms, tolerance, options.floor_tolerance):
                return NewtonResult(True, tuple(norms), "", linear)
            self._matrix.zeroEntries()
            dolfinx.fem.petsc.assemble_matrix(self._matrix, self._jacobian_form, bcs=self.bcs)
            self._matrix.assemble()
            self._ksp.solve(self._vector, self._increment)
            linear += max(self._ksp.getIterationNumber(), 1)
            reason = self._ksp.getConvergedReason()
            if reason < 0:
                failure = f"linear solver failed (reason {reason})"
                return NewtonResult(False, tuple(norms), failure, linear)
            self.u.vector.axpy(-1.0, self._increment)
            self.u.x.scatter_forward()
            norms.append(self._assemble_residual())
            if not math.isfinite(norms[-1]):
                return NewtonResult(False, tuple(norms), "residual is not finite", linear)
            if norms[-1] > options.divergence_factor * norms[0]:
                return NewtonResult(False, tuple(norms), "residual diverged", linear)
        if _converged(norms, tolerance, options.floor_tolerance):
            return NewtonResult(True, tuple(norms), "", linear)
        failure = f"not converged in {options.max_iterations}"
        return NewtonResult(False, tuple(norms), failure, linear)

    def reaction_forces(self) -> dict[str, np.ndarray]:
        """Boundary name -> (Fx, Fy) N: the residual without Dirichlet rows, acting on the
        boundary's indicator functions (equal on all ranks)."""
        b = dolfinx.fem.petsc.assemble_vector(self._residual_form)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        forces = {
            name: np.array([b.dot(indicator.x.vector), b.dot(indicator.y.vector)])
            for name, indicator in self.reactions.items()
        }
        b.destroy()
        return forces

    def run(
        self,
        apply_load: Callable[[float], None],
        on_step: Callable[[StepResult], None] | None = None,
    ) -> LoadPathResult:
        """Follow the load path t = 0 -> 1 from the current `u` (the state at t = 0).

        `apply_load(t)` sets every load-dependent value (Dirichlet data, constants) for the
        load factor t. `on_step` is called after every converged step (e.g. to write output).
        Raises ConvergenceError (history: the LoadPathResult so far) when a step cannot be
        completed even at `min_step`; `u` then holds the last converged state.
        """
        options = self.options
        start = last = time.perf_counter()
        steps: list[StepResult] = []
        cutbacks = 0
        converged_state = self.u.x.array.copy()
        nominal = 1.0 / options.steps
        load, step = 0.0, nominal
        for station in np.linspace(0.0, 1.0, options.steps + 1)[1:]:
            while load < station:
                target = station if station - (load + step) < 1e-12 else load + step
                apply_load(target)
                attempt = self.newton()
                if attempt.converged:
                    now = time.perf_counter()
                    record = StepResult(
                        load_factor=float(target),
                        newton_iterations=attempt.iterations,
                        residual_norms=attempt.residual_norms,
                        linear_iterations=attempt.linear_iterations,
                        reactions=self.reaction_forces(),
                        wall_time_s=now - last,
                    )
                    last, load = now, target
                    converged_state[:] = self.u.x.array
                    steps.append(record)
                    logger.info(
                        "load factor %.6g: %d Newton iterations, residual %.3g N",
                        target,
                        attempt.iterations,
                        attempt.residual_norms[-1],
                    )
                    if on_step is not None:
                        on_step(record)
                    step = min(2.0 * step, nominal)
                    continue
                self.u.x.array[:] = converged_state
                cutbacks += 1
                step /= 2.0
                logger.info(
                    "load factor %.6g: %s; cutting the step to %.3g", target, attempt.failure, step
                )
                if step < options.min_step:
                    apply_load(load)
                    history = LoadPathResult(tuple(steps), cutbacks, time.perf_counter() - start)
                    raise ConvergenceError(
                        f"Newton failed at load factor {target:.6g} ({attempt.failure}) even "
                        f"with the step cut to {step:.3g} < min_step {options.min_step:.3g}; "
                        f"{len(steps)} steps converged up to load factor {load:.6g}",
                        last_converged=steps[-1] if steps else None,
                        history=history,
                    )
        return LoadPathResult(tuple(steps), cutbacks, time.perf_counter() - start)


def _converged(norms: list[float], tolerance: float, floor_tolerance: float) -> bool:
    if norms[-1] <= tolerance:
        return True
    stalled = len(norms) > 2 and norms[-1] > 0.5 * norms[-2]
    return stalled and norms[-1] <= floor_tolerance * norms[0]


def _linear_solver(matrix: PETSc.Mat, options: SolverOptions) -> PETSc.KSP:
    ksp = PETSc.KSP().create(matrix.getComm())
    ksp.setOperators(matrix)
    ksp.setOptionsPrefix("fabric_")
    pc = ksp.getPC()
    if options.linear_solver == "lu":
        ksp.setType("preonly")
        pc.setType("lu")
        pc.setFactorSolverType("mumps")
    else:
        ksp.setType(options.linear_solver)
        pc.setType("hypre")
        pc.setHYPREType("boomeramg")
        ksp.setTolerances(rtol=options.krylov_tolerance, atol=0.0, max_it=2000)
    ksp.setFromOptions()
    return ksp
