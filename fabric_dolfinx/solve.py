"""Load stepping with Newton's method on PETSc: automatic cutback, reaction forces, step records.

The solver receives only forms (residual and Jacobian, UFL), the unknown, the Dirichlet
conditions and a callable that sets the load for a load factor t in [0, 1]. Linear systems
are solved by MUMPS (direct LU, the default) or by GMRES/CG preconditioned with hypre
BoomerAMG for large meshes; PETSc options with the prefix `fabric_` override either (e.g.
`-fabric_ksp_monitor`). The load factor is stepped by `rve_rod.stepping.StepController`, the
step controller of the rod RVE too (`SteppingOptions`; its records `NewtonAttempt`,
`LoadStep`, `LoadPath` are named apart from the RVE's `rve_rod.newton` records, whose fields
differ): when Newton fails (no convergence, a non-finite
or exploding residual, a failed linear solve) the increment is halved and retried from the
last converged state, down to `min_increment`; then `ConvergenceError` carries every
converged step.

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
from typing import Any, NamedTuple

import dolfinx.fem.petsc
import numpy as np
import ufl
from dolfinx import fem
from petsc4py import PETSc

import fabric_dolfinx.jit  # noqa: F401 (FFCx's compilation safe to interrupt, and quiet)
from rve_rod import limits
from rve_rod.errors import (
    ConvergenceError,
    InputError,
    check_integer,
    check_positive,
    check_range,
    raise_pending_interrupt,
)
from rve_rod.limits import check_count
from rve_rod.stepping import StepController, SteppingOptions

__all__ = [
    "LINEAR_SOLVERS",
    "MIN_INCREMENT",
    "BoundaryIndicator",
    "LoadPath",
    "LoadStep",
    "LoadStepper",
    "NewtonAttempt",
    "SolverOptions",
    "boundary_indicator",
    "with_history",
]

logger = logging.getLogger(__name__)

MIN_INCREMENT = 1e-6
"""The smallest load-factor increment of the default stepping. A knit at rest is about a
hundred times softer than at a few per cent of strain, so Newton's first step from the
unloaded part under a force overshoots unless the load is tiny: the L-shaped example's first
converged increment is 1e-5 of its load (docs/scenes.md, "Forces on a slack part"); with
1/1024, the floor before, such a part stopped at 0 steps whatever the number of steps."""

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
        krylov_tolerance: relative tolerance of GMRES/CG (unused by LU).
        line_search: backtracking on the residual: a Newton step that does not lower the
            residual 2-norm (by 1e-4 of the step's fraction) is halved, at most
            `line_search` times, the last half kept (0: full Newton steps, the default).
        stepping: the load stepping between the equal steps; None (default): start with one
            equal step (1/steps) and never exceed it, halve on failure down to
            MIN_INCREMENT (1e-6), double again after every converged step, no
            extrapolation (`stepping_options()`).
    """

    linear_solver: str = "lu"
    steps: int = 20
    relative_tolerance: float = 1e-10
    absolute_tolerance: float = 1e-12
    floor_tolerance: float = 1e-8
    max_iterations: int = 25
    divergence_factor: float = 1e6
    krylov_tolerance: float = 1e-10
    line_search: int = 0
    stepping: SteppingOptions | None = None

    def __post_init__(self):
        if self.linear_solver not in LINEAR_SOLVERS:
            raise InputError(
                f"linear_solver={self.linear_solver!r} is not one of {', '.join(LINEAR_SOLVERS)}"
            )
        check_count("steps", self.steps, limits.MACRO_STEPS)
        check_positive("relative_tolerance", self.relative_tolerance)
        check_positive("absolute_tolerance", self.absolute_tolerance, "N")
        check_range("floor_tolerance", self.floor_tolerance, 0.0, 1.0)
        check_integer("max_iterations", self.max_iterations, 1)
        check_positive("divergence_factor", self.divergence_factor)
        check_positive("krylov_tolerance", self.krylov_tolerance)
        check_integer("line_search", self.line_search, 0, 30)

    def stepping_options(self) -> SteppingOptions:
        """`stepping`, or the default for `steps` equal steps (see the attribute)."""
        if self.stepping is not None:
            return self.stepping
        nominal = 1.0 / self.steps
        return SteppingOptions(
            initial_increment=nominal,
            max_increment=nominal,
            min_increment=MIN_INCREMENT,
            max_cutbacks=32,
            easy_iterations=self.max_iterations,
            extrapolate=False,
        )


class BoundaryIndicator(NamedTuple):
    """Functions equal to 1 at the boundary's degrees of freedom of one displacement
    component (x, y, and z for a membrane in space) and 0 elsewhere; the residual's action on
    them is the reaction."""

    x: fem.Function
    y: fem.Function
    z: fem.Function | None = None


def boundary_indicator(space: fem.FunctionSpace, facets: np.ndarray) -> BoundaryIndicator:
    """The BoundaryIndicator of the (local) boundary `facets` of the vector space `space`."""
    fdim = space.mesh.topology.dim - 1
    indicators = []
    for component in range(space.num_sub_spaces):
        function = fem.Function(space)
        dofs = fem.locate_dofs_topological(space.sub(component), fdim, facets)
        function.x.array[dofs] = 1.0
        function.x.scatter_forward()
        indicators.append(function)
    return BoundaryIndicator(*indicators)


class NewtonAttempt(NamedTuple):
    """One Newton attempt at a fixed load.

    Attributes:
        converged: whether the residual met the tolerance.
        iterations: Newton iterations (linear solves).
        residual_norms: 2-norms of the residual (N) before each iteration, iteration 0 first.
        reason: "converged", or why the attempt failed.
        linear_iterations: Krylov iterations of all its linear solves (1 per solve for LU).
    """

    converged: bool
    iterations: int
    residual_norms: tuple[float, ...]
    reason: str
    linear_iterations: int


class LoadStep(NamedTuple):
    """A converged load step (substeps after a cutback included).

    Attributes:
        load_factor: t in (0, 1].
        iterations: Newton iterations of the converged attempt.
        residual_norms: its residual history (N), see NewtonAttempt.
        substeps: converged steps since the previous of the equal steps, this one included.
        cutbacks: failed attempts since the previous of the equal steps.
        linear_iterations: its Krylov iterations (1 per Newton iteration for LU).
        reactions: boundary name -> total reaction force (Fx, Fy) in N, summed over ranks.
        wall_time_s: time since the previous converged step (failed attempts included).
    """

    load_factor: float
    iterations: int
    residual_norms: tuple[float, ...]
    substeps: int
    cutbacks: int
    linear_iterations: int
    reactions: dict[str, np.ndarray]
    wall_time_s: float


class LoadPath(NamedTuple):
    """All converged steps of a load path.

    Attributes:
        steps: the converged steps in order.
        newton_iterations: all Newton iterations, failed attempts included.
        cutbacks: how many attempts failed and were retried with half the increment.
        wall_time_s: total time (s).
    """

    steps: tuple[LoadStep, ...]
    newton_iterations: int
    cutbacks: int
    wall_time_s: float


class LoadStepper:
    """Newton's method with load stepping for one residual/Jacobian pair.

    Owns the compiled forms and the PETSc matrix, vectors and KSP, so several load paths on
    the same forms (reset `u` in between) compile and allocate once. `update`, when given,
    is called at every new `u` before the residual is assembled (the Jacobian is assembled
    at the `u` of the last residual): it brings the Functions the forms read to `u` (the
    material at the quadrature points, `QuadratureMaterial.update`).
    """

    def __init__(  # noqa: PLR0913 (the forms, the unknown, the conditions and 3 options)
        self,
        residual: ufl.Form,
        jacobian: ufl.Form,
        u: fem.Function,
        bcs: list,
        *,
        options: SolverOptions = SolverOptions(),
        reactions: Mapping[str, BoundaryIndicator] | None = None,
        update: Callable[[], None] | None = None,
    ):
        self.options = options
        self._update = update or (lambda: None)
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
        self._update()
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

    def newton(self) -> NewtonAttempt:
        """Newton iterations at the current load, starting from the current `u`."""
        options = self.options
        norms = [self._assemble_residual()]
        linear = 0

        def result(reason: str) -> NewtonAttempt:
            converged = reason == "converged"
            return NewtonAttempt(converged, len(norms) - 1, tuple(norms), reason, linear)

        tolerance = max(options.absolute_tolerance, options.relative_tolerance * norms[0])
        for _ in range(options.max_iterations):
            if _converged(norms, tolerance, options.floor_tolerance):
                return result("converged")
            self._matrix.zeroEntries()
            dolfinx.fem.petsc.assemble_matrix(self._matrix, self._jacobian_form, bcs=self.bcs)
            self._matrix.assemble()
            self._ksp.solve(self._vector, self._increment)
            linear += max(self._ksp.getIterationNumber(), 1)
            reason = self._ksp.getConvergedReason()
            if reason < 0:
                return result(f"linear solver failed (reason {reason})")
            norms.append(self._step(norms[-1]))
            if not math.isfinite(norms[-1]):
                return result("residual is not finite")
            if norms[-1] > options.divergence_factor * norms[0]:
                return result("residual diverged")
        if _converged(norms, tolerance, options.floor_tolerance):
            return result("converged")
        return result(f"not converged in {options.max_iterations}")

    def _step(self, norm: float) -> float:
        """u -= the Newton increment, halved while the residual does not fall below `norm`
        (`SolverOptions.line_search`); returns the new residual norm (N)."""
        start = self.u.vector.copy() if self.options.line_search else None
        fraction = 1.0
        for halving in range(self.options.line_search + 1):
            if halving:
                fraction *= 0.5
                start.copy(self.u.vector)
            self.u.vector.axpy(-fraction, self._increment)
            self.u.x.scatter_forward()
            new = self._assemble_residual()
            if math.isfinite(new) and new <= (1.0 - 1e-4 * fraction) * norm:
                break
        if start is not None:
            start.destroy()
        return new

    def reaction_forces(self) -> dict[str, np.ndarray]:
        """Boundary name -> (Fx, Fy) N, or (Fx, Fy, Fz) for a membrane in space: the residual
        without Dirichlet rows, acting on the boundary's indicator functions (equal on all
        ranks)."""
        self._update()
        b = dolfinx.fem.petsc.assemble_vector(self._residual_form)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        forces = {
            name: np.array([b.dot(f.vector) for f in indicator if f is not None])
            for name, indicator in self.reactions.items()
        }
        b.destroy()
        return forces

    def run(
        self,
        apply_load: Callable[[float], None],
        on_step: Callable[[LoadStep], None] | None = None,
        finish_step: Callable[[], None] | None = None,
    ) -> LoadPath:
        """Follow the load path t = 0 -> 1 from the current `u` (the state at t = 0).

        `apply_load(t)` sets every load-dependent value (Dirichlet data, constants) for the
        load factor t. `finish_step` is called after every converged Newton solve, before the
        step and its reactions are recorded, and may change `u` (a part in space releases its
        stabilization there; the state a cutback returns to and extrapolation starts from is
        the Newton solution). `on_step` is called after every converged step (e.g. to record
        or write output).
        Raises ConvergenceError (history: the LoadPath so far) when a step cannot be
        completed even at `min_increment`; `u` then holds the last converged state.
        """
        stepping = self.options.stepping_options()
        start = last = time.perf_counter()
        targets = np.linspace(0.0, 1.0, self.options.steps + 1)[1:]
        controller = StepController(targets, stepping)
        steps: list[LoadStep] = []
        iterations = 0
        converged_state = self.u.x.array.copy()
        previous_state = None  # the converged state before `converged_state`
        while not controller.finished:
            raise_pending_interrupt()  # a Ctrl-C Python lost in a callback stops the run here
            load, trial = controller.load_factor, controller.trial()
            if stepping.extrapolate and previous_state is not None:
                ratio = (trial - load) / (load - controller.previous)
                self.u.x.array[:] = converged_state + ratio * (converged_state - previous_state)
            apply_load(trial)
            attempt = self.newton()
            iterations += attempt.iterations
            if attempt.converged:
                count = controller.accept(trial, attempt.iterations)
                if stepping.extrapolate:
                    previous_state = converged_state.copy()
                converged_state[:] = self.u.x.array
                if finish_step is not None:
                    finish_step()
                now = time.perf_counter()
                record = LoadStep(
                    load_factor=float(trial),
                    iterations=attempt.iterations,
                    residual_norms=attempt.residual_norms,
                    substeps=count.substeps,
                    cutbacks=count.cutbacks,
                    linear_iterations=attempt.linear_iterations,
                    reactions=self.reaction_forces(),
                    wall_time_s=now - last,
                )
                last = now
                steps.append(record)
                logger.info(
                    "load factor %.6g: %d Newton iterations, residual %.3g N",
                    trial,
                    attempt.iterations,
                    attempt.residual_norms[-1],
                )
                if on_step is not None:
                    on_step(record)
                continue
            self.u.x.array[:] = converged_state
            stop = controller.reject(trial)
            logger.info(
                "load factor %.6g: %s; cutting the increment to %.3g",
                trial,
                attempt.reason,
                controller.increment,
            )
            if stop:
                apply_load(load)
                history = LoadPath(
                    tuple(steps), iterations, controller.total_cutbacks, time.perf_counter() - start
                )
                raise ConvergenceError(
                    f"Newton failed at load factor {trial:.6g} ({attempt.reason}) even with "
                    f"the increment cut to {controller.increment:.3g} (min_increment "
                    f"{stepping.min_increment:.3g}, {controller.consecutive} cutbacks); "
                    f"{len(steps)} steps converged up to load factor {load:.6g}",
                    last_converged=steps[-1] if steps else None,
                    history=history,
                )
        return LoadPath(
            tuple(steps), iterations, controller.total_cutbacks, time.perf_counter() - start
        )


def with_history(solve: Callable[[], Any], result: Callable[[Any], Any]) -> Any:
    """`result(solve())`; when `solve` raises ConvergenceError, the same error with its
    history (the record of the converged steps, of solve's type) made a `result` too, so
    that every caller gets the partial result in its own type."""
    try:
        solved = solve()
    except ConvergenceError as error:
        raise ConvergenceError(
            str(error), last_converged=error.last_converged, history=result(error.history)
        ) from None
    return result(solved)


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
