"""Newton-Raphson with load (or displacement) stepping and automatic cutback.

The solver knows nothing about rods: it takes a `NonlinearProblem`, i.e. a callable returning
the residual R(u, t) and its sparse Jacobian at state u and load factor t, plus the scales
that make the convergence norms dimensionless. A state u of the Newton iteration at t_n+1 is
accepted when

    max_i |R_i| / residual_scale_i <= residual_tolerance   and
    max_i |du_i| / state_scale_i    <= increment_tolerance,

du = -J^-1 R the Newton correction at u itself (an estimate of u's error: the correction is
computed, and the residual at u + du is not evaluated, one evaluation fewer per step than
testing the increment that led to u). Where the last two residual norms, extrapolated
quadratically, put the next iterate 100 times below the residual tolerance and the problem
has a residual-only callable (`NonlinearProblem.residual`), the next iterate's residual is
evaluated alone and its correction computed with the Jacobian of the iterate before (at
convergence the two differ by the order of the last increment); only if that iterate is not
accepted is it evaluated with its Jacobian. A converged step then costs no Jacobian that is
not used.

The floor of round-off. Where J has soft modes (a cell of several yarn patches held by weak
ties: condition numbers of 1e15), the correction of a state whose residual is at round-off
is that round-off through the soft modes, and it need not fall below the increment tolerance
however long Newton goes on. So a state is also accepted when the scaled residual has met its
tolerance at the last `ROUND_OFF_ITERATES` iterates without falling over them (it grew at
least once, and the last is at least half the first): quadratic convergence would have cut
it by orders, linear convergence (an inconsistent tangent) would have lowered it at every
iterate, so what is left is round-off, not the state's error (C. T. Kelley, Iterative
Methods for Linear and Nonlinear Equations, SIAM 1995, 5.4: the attainable accuracy).

A step whose Newton iteration fails (non-finite values, residual growth beyond
`divergence_factor`, or `max_iterations` reached) is retried with half the increment, down to
`min_increment` and at most `max_cutbacks` times in a row; easy steps let the increment grow
again (the step controller and `SteppingOptions` of `rve_rod.stepping`, shared with the
membrane's PETSc solver). A converged state the problem's `admissible` hook refuses (a state
the model does not describe, e.g. yarns squeezed through each other) counts as a failed
attempt, so the increment is cut back towards the last admissible state. After every
accepted step the problem's `commit` hook runs (history variables such as friction slip). If
the path cannot be continued, `ConvergenceError` carries the last accepted step and every
step before it.

Linear systems are solved by SuperLU (scipy.sparse.linalg.splu) through `LinearSolver`: in the
column ordering of `NewtonOptions.ordering`, where "NODES" orders the graph of the problem's
nodes (`NonlinearProblem.nodes`, e.g. the control points of a rod, 7 unknowns each) by minimum
degree and keeps each node's unknowns together, and with threshold pivoting
(`pivot_threshold`). With `refinement` > 0 the factors of the last factorized Jacobian are kept
along the path: the next system is first solved by GMRES-based iterative refinement with them
(GMRES on the system right-preconditioned by the old factors, Carson and Higham, SIAM J. Sci.
Comput. 39 (2017) A2834), and the Jacobian is factorized anew only when that does not bring
the linear residual down to `linear_tolerance` of the right-hand side within `refinement`
GMRES iterations. The Jacobians of a load path change by small and low-rank parts (a contact
that closes or opens, friction that starts to slip), which GMRES resolves in a few
iterations, each one solve with the old factors (0.15 ms on the knit cell against 6 ms for a
factorization); most systems of a path need no factorization.

Inexact Newton. A system solved with reused factors needs not be solved to `linear_tolerance`:
J du = -R is solved to a linear residual of eta |R| with the forcing term eta = min(0.1,
max(linear_tolerance, |R|, 0.01 residual_tolerance / |R|)) (scaled max-norms). eta of the
order of |R| keeps Newton's quadratic convergence (Dembo, Eisenstat and Steihaug, SIAM J.
Numer. Anal. 19 (1982) 400; Eisenstat and Walker, SIAM J. Sci. Comput. 17 (1996) 16), and no
linear residual below 1 % of the residual tolerance is asked for.
"""

import itertools
import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from rve_rod.errors import (
    ConvergenceError,
    InputError,
    check_integer,
    check_positive,
    check_range,
    raise_pending_interrupt,
)
from rve_rod.stepping import StepController, SteppingOptions

__all__ = [
    "LINEAR_SOLVER_OPTIONS",
    "ROUND_OFF_ITERATES",
    "LinearSolver",
    "NewtonOptions",
    "NewtonResult",
    "NonlinearProblem",
    "PathResult",
    "StepRecord",
    "newton_solve",
    "softest_singular_values",
    "solve_path",
]

logger = logging.getLogger(__name__)

Evaluate = Callable[[np.ndarray, float], tuple[np.ndarray, scipy.sparse.spmatrix]]
"""evaluate(state, load_factor) -> (residual (n,), jacobian (n, n) sparse)."""


@dataclass(frozen=True, eq=False)
class NonlinearProblem:
    """A parameterized nonlinear system R(u, t) = 0.

    Attributes:
        evaluate: (state, load_factor) -> (residual, sparse Jacobian).
        residual_scale: typical magnitude of each residual entry, scalar or (n,).
        state_scale: typical magnitude of each unknown, scalar or (n,).
        commit: called as commit(state, load_factor) after every accepted step, or None.
        admissible: called as admissible(state, load_factor) on every converged state before
            it is accepted; returns "" to accept it, else why it is refused (the path then
            cuts back as after a failed solve). None accepts every converged state.
        nodes: (n,) the node of each unknown, for the "NODES" ordering of the LU (unknowns of
            one node, e.g. one control point's, are ordered together); -1 for unknowns to be
            ordered last (few dense rows and columns, e.g. macro unknowns). None: no nodes.
        residual: (state, load_factor) -> the residual alone, cheaper than `evaluate`; where
            Newton expects the next iterate to converge it evaluates only the residual there
            (module docstring). None: every iterate is evaluated with its Jacobian.
    """

    evaluate: Evaluate
    residual_scale: float | np.ndarray = 1.0
    state_scale: float | np.ndarray = 1.0
    commit: Callable[[np.ndarray, float], None] | None = None
    admissible: Callable[[np.ndarray, float], str] | None = None
    nodes: np.ndarray | None = None
    residual: Callable[[np.ndarray, float], np.ndarray] | None = None


_ORDERINGS = ("COLAMD", "NATURAL", "MMD_ATA", "MMD_AT_PLUS_A", "NODES")

LINEAR_SOLVER_OPTIONS = ("ordering", "pivot_threshold", "refinement", "linear_tolerance")
"""The fields of `NewtonOptions` that choose how the linear systems are solved: they change
the cost of a solve, not its solution beyond the Newton tolerances (every increment is a
direct solve or meets its linear tolerance, and every converged state meets the residual
and increment tolerances), so cache keys leave them out (`rve_rod.rve.RodRve`)."""


ROUND_OFF_ITERATES = 3
"""Iterates in a row whose residual meets its tolerance without falling before a state is
accepted at the floor of round-off (module docstring)."""


@dataclass(frozen=True)
class NewtonOptions:
    """Options of one Newton solve.

    Attributes:
        residual_tolerance: bound on the scaled residual max-norm (default 1e-10).
        increment_tolerance: bound on the scaled max-norm of the last increment (1e-10).
        max_iterations: iterations before the solve counts as failed (25).
        divergence_factor: the solve fails when the scaled residual exceeds this factor times
            max(first scaled residual, 1) (1e8).
        line_search: most step halvings per iteration when the Newton step does not lower
            the scaled residual's root mean square (default 0: plain Newton). Each halving
            costs one evaluation; it damps the cycles Newton can fall into on non-smooth or
            nearly singular systems (contact that barely touches, a free direction that is
            almost unloaded).
            A trial whose scaled residual already meets `residual_tolerance` is not damped
            (at that level the merit is round-off, and damping only slows the increment's
            convergence).
        ordering: column ordering of the sparse LU: SuperLU's permc_spec "COLAMD" (default),
            "NATURAL" (for banded systems whose few dense rows and columns come last),
            "MMD_ATA" or "MMD_AT_PLUS_A", or "NODES": minimum degree on the graph of the
            problem's nodes (`NonlinearProblem.nodes`; the unknowns without a node last).
        pivot_threshold: SuperLU's diag_pivot_thresh in [0, 1]: the diagonal is taken as the
            pivot when its magnitude is at least this fraction of its column's largest (1,
            the default: partial pivoting; 0.01 keeps the ordering's fill and is stable on
            the rod's systems).
        refinement: GMRES iterations preconditioned by the last LU factors tried before a
            Jacobian is factorized anew (default 0: every Jacobian is factorized and solved
            directly; module docstring).
        linear_tolerance: a refined solution is accepted when the scaled max-norm of its
            linear residual J du + R is at most this fraction of that of R (default 1e-8;
            a direct solve of the rod RVE's systems reaches 1e-11 to 1e-10).
    """

    residual_tolerance: float = 1e-10
    increment_tolerance: float = 1e-10
    max_iterations: int = 25
    divergence_factor: float = 1e8
    line_search: int = 0
    ordering: str = "COLAMD"
    pivot_threshold: float = 1.0
    refinement: int = 0
    linear_tolerance: float = 1e-8

    def __post_init__(self):
        check_positive("residual_tolerance", self.residual_tolerance)
        check_positive("increment_tolerance", self.increment_tolerance)
        check_integer("max_iterations", self.max_iterations, 1)
        check_positive("divergence_factor", self.divergence_factor)
        check_integer("line_search", self.line_search, 0, 60)
        if self.ordering not in _ORDERINGS:
            raise InputError(
                f"ordering={self.ordering!r} is unknown; valid: {', '.join(_ORDERINGS)}"
            )
        check_range("pivot_threshold", self.pivot_threshold, 0.0, 1.0)
        check_integer("refinement", self.refinement, 0, 20)
        check_range("linear_tolerance", self.linear_tolerance, 0.0, 1.0, closed=False)


@dataclass(frozen=True, eq=False)
class NewtonResult:
    """Outcome of one Newton solve at a fixed load factor.

    Attributes:
        state: the last iterate (the solution if `converged`).
        load_factor: t.
        converged: whether both norms met their tolerances (or the residual sat at the floor
            of round-off: module docstring).
        iterations: Newton iterations done (linear solves; the last of a converged solve
            finds the correction within tolerance and is not applied).
        residual_norms: scaled residual max-norm before the first and after every applied
            iteration (one per evaluation of the residual).
        increment_norms: scaled max-norm of every iteration's increment (as applied, after
            any line-search halving; the last of a converged solve: the correction found
            within tolerance).
        reason: "converged", "diverged", "not finite", "singular" or "max iterations".
    """

    state: np.ndarray
    load_factor: float
    converged: bool
    iterations: int
    residual_norms: tuple[float, ...]
    increment_norms: tuple[float, ...]
    reason: str


@dataclass(frozen=True, eq=False)
class StepRecord:
    """A converged point of the load path.

    Attributes:
        load_factor: t.
        state: the converged state (a copy).
        iterations: Newton iterations of the last substep that reached t.
        residual_norms: that substep's scaled residual norms per iteration.
        substeps: converged substeps since the previous record.
        cutbacks: failed attempts (halvings) since the previous record.
    """

    load_factor: float
    state: np.ndarray
    iterations: int
    residual_norms: tuple[float, ...]
    substeps: int = 1
    cutbacks: int = 0


@dataclass(eq=False)
class PathResult:
    """The converged load path: one record per requested load factor (the start included).

    Attributes:
        steps: StepRecord per requested load factor, in order.
        newton_iterations: total Newton iterations, including failed attempts.
        cutbacks: all failed (or refused) attempts.
    """

    steps: list[StepRecord] = field(default_factory=list)
    newton_iterations: int = 0
    cutbacks: int = 0

    @property
    def final_state(self) -> np.ndarray:
        return self.steps[-1].state

    @property
    def load_factors(self) -> np.ndarray:
        return np.array([step.load_factor for step in self.steps])


def _scaled_norm(values: np.ndarray, scale) -> float:
    if values.size == 0:
        return 0.0
    return float(np.max(np.abs(values) / scale))


def _mean_square(values: np.ndarray, scale) -> float:
    """Mean square of the scaled residual (inf if not finite): the line search's merit."""
    with np.errstate(over="ignore", invalid="ignore"):
        value = float(np.mean((values / scale) ** 2)) if values.size else 0.0
    return value if np.isfinite(value) else np.inf


def softest_singular_values(
    problem: NonlinearProblem, state: np.ndarray, load_factor: float, count: int = 3
) -> np.ndarray:
    """The `count` smallest singular values of the Jacobian at (state, t), smallest first, in
    the problem's dimensionless norms (rows divided by `residual_scale`, columns multiplied by
    `state_scale`, as Newton measures residuals and increments). A diagnosis of a path that
    stops: at a fold (limit point) one of them falls to zero as the square root of the
    distance to the fold's load factor (docs/validation.md, "Why the squeezed rest's shear
    stops"). A dense SVD: for problems of up to a few thousand unknowns."""
    residual, jacobian = problem.evaluate(state, load_factor)
    columns = np.broadcast_to(problem.state_scale, residual.shape)
    rows = np.broadcast_to(problem.residual_scale, residual.shape)
    scaled = jacobian.toarray() / rows[:, None] * columns[None, :]
    return np.linalg.svd(scaled, compute_uv=False)[::-1][:count]


def node_ordering(pattern: scipy.sparse.spmatrix, nodes: np.ndarray) -> np.ndarray:
    """The "NODES" ordering: a permutation (n,) of the unknowns, new position k holding
    unknown order[k].

    The graph of the nodes (an edge where any unknown of one node couples with any of the
    other in `pattern`, either way) is ordered by minimum degree (SuperLU's MMD on A^T + A,
    applied to the node graph); each node's unknowns follow in their own order, and the
    unknowns without a node (-1) come last in theirs.

    Args:
        pattern: (n, n) sparse matrix whose nonzeros are the couplings.
        nodes: (n,) node of each unknown in [0, N), or -1.
    """
    nodes = np.asarray(nodes, dtype=np.int64)
    count = int(nodes.max()) + 1 if nodes.size else 0
    if count == 0:
        return np.arange(nodes.size)
    coupling = pattern.tocoo()
    rows, columns = nodes[coupling.row], nodes[coupling.col]
    inside = (rows >= 0) & (columns >= 0)
    graph = scipy.sparse.coo_matrix(
        (np.ones(np.count_nonzero(inside)), (rows[inside], columns[inside])), shape=(count, count)
    ).tocsc()
    graph = abs(graph) + abs(graph.T)
    # A diagonally dominant matrix on the graph: SuperLU factorizes it without pivoting and
    # reports the minimum-degree column permutation it used.
    degree = np.asarray(graph.sum(axis=1)).ravel()
    symmetric = (scipy.sparse.diags(degree + 1.0) - 0.5 * graph).tocsc()
    factors = scipy.sparse.linalg.splu(
        symmetric,
        permc_spec="MMD_AT_PLUS_A",
        diag_pivot_thresh=0.0,
        options={"SymmetricMode": True},
    )
    rank = np.empty(count + 1, dtype=np.int64)
    rank[:count] = factors.perm_c  # node j is eliminated at position perm_c[j]
    rank[count] = count  # unknowns without a node: last
    return np.argsort(rank[nodes], kind="stable")


_FORCING_MAX = 0.1
"""Largest forcing term of an inexact Newton solve (`_forcing`)."""

_FORCING_FLOOR = 0.01
"""Linear residuals below this fraction of the residual tolerance are not asked for."""


def _forcing(options: NewtonOptions, size: float) -> float:
    """The forcing term eta of a Newton system J du = -R whose residual has the scaled
    max-norm `size`: the linear residual may be eta |R| (module docstring, "Inexact Newton")."""
    if size == 0.0:
        return options.linear_tolerance
    floor = _FORCING_FLOOR * options.residual_tolerance / size
    return min(_FORCING_MAX, max(options.linear_tolerance, size, floor))


def _at_round_off(residual_norms: list[float], options: NewtonOptions) -> bool:
    """Whether the residual sits at the floor of round-off (module docstring)."""
    last = residual_norms[-ROUND_OFF_ITERATES:]
    if len(last) < ROUND_OFF_ITERATES or max(last) > options.residual_tolerance:
        return False
    grew = any(later > earlier for earlier, later in itertools.pairwise(last))
    return grew and last[-1] >= 0.5 * last[0]


def _expect_convergence(residual_norms: list[float], options: NewtonOptions) -> bool:
    """Whether quadratic convergence, extrapolated from the last two residual norms
    (r_k+1 ~ r_k^3 / r_k-1^2), brings the next residual 100 times below the tolerance."""
    if len(residual_norms) < 2 or not residual_norms[-2] > 0.0:
        return False
    predicted = residual_norms[-1] ** 3 / residual_norms[-2] ** 2
    return predicted <= 0.01 * options.residual_tolerance


_HOPELESS = 1e3
"""GMRES with old factors is given up when its residual after j of k iterations exceeds
this multiple of the geometric path from the start to the target."""

_REORDER_FILL = 1.05
"""The "NODES" ordering is made anew once the factors' nonzeros exceed this multiple of their
count right after it was made."""


def _permuted(matrix: scipy.sparse.spmatrix, order: np.ndarray) -> scipy.sparse.csc_matrix:
    """P A P^T in CSC form (sorted indices): row and column k of the result are row and column
    order[k] of A (one gather of A's CSR rows and one transposition)."""
    rows = scipy.sparse.csr_matrix(matrix)
    inverse = np.empty_like(order)
    inverse[order] = np.arange(order.size)
    lengths = np.diff(rows.indptr)[order]
    indptr = np.concatenate([[0], np.cumsum(lengths)])
    gather = np.repeat(rows.indptr[order] - indptr[:-1], lengths) + np.arange(indptr[-1])
    permuted = scipy.sparse.csr_matrix(
        (rows.data[gather], inverse[rows.indices[gather]], indptr), shape=rows.shape
    )
    return permuted.tocsc()


class _Factors(NamedTuple):
    """LU factors of a Jacobian and the permutation they were made in (None: none)."""

    lu: scipy.sparse.linalg.SuperLU
    order: np.ndarray | None

    def apply(self, rhs: np.ndarray) -> np.ndarray:
        """The solution of J x = rhs for the factorized J."""
        if self.order is None:
            return self.lu.solve(rhs)
        solution = np.empty_like(rhs)
        solution[self.order] = self.lu.solve(rhs[self.order])
        return solution


class LinearSolver:
    """The Newton systems J du = -R of one problem, solved with SuperLU (module docstring).

    With `NewtonOptions.refinement` = 0 every system is factorized and solved directly. With
    k > 0 a system is first solved by at most k GMRES iterations preconditioned by the
    factors of an earlier Jacobian; if that does not reach `linear_tolerance`, J is factorized
    and the solve refined with its own factors; if even those fall short (threshold pivoting
    on an ordering made for an earlier pattern can lose accuracy), J is factorized again in a
    new ordering with partial pivoting and that solution is taken.

    Args:
        options: ordering, pivot threshold, refinement and its tolerance.
        nodes: (n,) node of each unknown for the "NODES" ordering (`NonlinearProblem.nodes`).
        residual_scale: typical magnitude of each residual entry, for the linear residual's
            scaled norm.

    Attributes:
        factorizations: Jacobians factorized so far.
        reused: systems solved with the factors of an earlier Jacobian.
    """

    def __init__(
        self,
        options: NewtonOptions,
        nodes: np.ndarray | None = None,
        residual_scale: float | np.ndarray = 1.0,
    ):
        if options.ordering == "NODES" and nodes is None:
            raise InputError('ordering="NODES" needs a problem with nodes (NonlinearProblem.nodes)')
        self.options = options
        self.nodes = nodes
        self.residual_scale = residual_scale
        self.factorizations = 0
        self.reused = 0
        self._factors: _Factors | None = None
        self._order: np.ndarray | None = None  # the "NODES" ordering in use
        self._ordered_fill = 0  # nonzeros of the factors made right after it was made

    def solve(
        self, jacobian: scipy.sparse.spmatrix, rhs: np.ndarray, tolerance: float | None = None
    ) -> np.ndarray:
        """du with J du = rhs, to a scaled linear residual of at most `tolerance` (default
        `linear_tolerance`) times that of rhs where the factors of an earlier J are reused.
        Raises RuntimeError if J is exactly singular (SuperLU)."""
        options = self.options
        tolerance = options.linear_tolerance if tolerance is None else tolerance
        if not options.refinement:
            self._factorize(jacobian, options.pivot_threshold)
            return self._factors.apply(rhs)
        if self._factors is not None:
            solution = self._refine(jacobian, rhs, tolerance)
            if solution is not None:
                self.reused += 1
                return solution
        self._factorize(jacobian, options.pivot_threshold)
        solution = self._refine(jacobian, rhs, tolerance)
        if solution is None:
            self._order = None
            self._factorize(jacobian, 1.0)
            solution = self._refine(jacobian, rhs, tolerance, final=True)
        return solution

    def _factorize(self, jacobian, pivot_threshold: float) -> None:
        """Factorize J; the "NODES" ordering is kept while the factors it gives stay within
        `_REORDER_FILL` of their fill when it was made (the couplings of a rod's contacts
        drift slowly), and made anew from J's pattern otherwise."""
        self._factors = None
        ordering = self.options.ordering
        order = None
        matrix = jacobian
        if ordering == "NODES":
            fresh = self._order is None
            if fresh:
                self._order = node_ordering(jacobian, self.nodes)
            order, ordering = self._order, "NATURAL"
            matrix = _permuted(jacobian, order)
        lu = scipy.sparse.linalg.splu(
            scipy.sparse.csc_matrix(matrix), permc_spec=ordering, diag_pivot_thresh=pivot_threshold
        )
        self._factors = _Factors(lu, order)
        self.factorizations += 1
        if order is not None:
            fill = lu.nnz
            if fresh:
                self._ordered_fill = fill
            elif fill > _REORDER_FILL * self._ordered_fill:
                self._order = None  # order the next Jacobian anew

    def _refine(
        self, jacobian, rhs: np.ndarray, tolerance: float, final: bool = False
    ) -> np.ndarray | None:
        """GMRES-based iterative refinement with the current factors M: GMRES on the scaled
        system D^-1 J M^-1 D y = D^-1 rhs (D the residual scale), x = M^-1 D y, at most
        `refinement` iterations (Givens rotations on the Hessenberg matrix). None if the
        linear residual does not reach `tolerance` times that of rhs (scaled max-norms; given
        up early when the iterations' contraction cannot make it), unless `final`: then the
        last iterate."""
        limit = self.options.refinement
        scale = np.broadcast_to(self.residual_scale, rhs.shape)
        scaled = rhs / scale
        size = float(np.abs(scaled).max()) if scaled.size else 0.0
        if size == 0.0:
            return np.zeros_like(rhs)
        target = tolerance * size
        beta = float(np.linalg.norm(scaled))
        basis = np.empty((limit + 1, rhs.size))  # orthonormal Krylov basis (scaled space)
        directions = np.empty((limit, rhs.size))  # M^-1 D of the basis vectors
        triangle = np.zeros((limit + 1, limit))  # the Hessenberg matrix, rotated
        rotations = np.zeros((limit, 2))  # cosine and sine of each Givens rotation
        projected = np.zeros(limit + 1)  # the rotated beta e1
        projected[0] = beta
        basis[0] = scaled / beta
        solution = None
        for j in range(limit):
            directions[j] = self._factors.apply(basis[j] * scale)
            vector = (jacobian @ directions[j]) / scale
            column = np.zeros(j + 2)
            for _ in range(2):  # classical Gram-Schmidt, twice
                projection = basis[: j + 1] @ vector
                vector -= projection @ basis[: j + 1]
                column[: j + 1] += projection
            column[j + 1] = np.linalg.norm(vector)
            breakdown = not column[j + 1] > 1e-14 * beta  # (also NaN)
            if not breakdown:
                basis[j + 1] = vector / column[j + 1]
            for i in range(j):
                c, s = rotations[i]
                column[i], column[i + 1] = (
                    c * column[i] + s * column[i + 1],
                    (-s * column[i] + c * column[i + 1]),
                )
            radius = np.hypot(column[j], column[j + 1])
            if not radius > 0.0:
                break
            c, s = column[j] / radius, column[j + 1] / radius
            rotations[j] = c, s
            column[j], column[j + 1] = radius, 0.0
            triangle[: j + 2, j] = column
            projected[j], projected[j + 1] = c * projected[j], -s * projected[j]
            estimate = abs(projected[j + 1])  # the scaled linear residual's 2-norm
            last = estimate <= target or breakdown or j == limit - 1
            hopeless = estimate > _HOPELESS * beta * (target / beta) ** ((j + 1) / limit)
            if last or hopeless or not np.isfinite(estimate):
                coefficients = scipy.linalg.solve_triangular(
                    triangle[: j + 1, : j + 1], projected[: j + 1]
                )
                solution = coefficients @ directions[: j + 1]
                break
        if solution is None:  # J M^-1 annihilates the right-hand side: J is singular
            return self._factors.apply(rhs) if final else None
        if final:
            return solution
        if _scaled_norm(rhs - jacobian @ solution, scale) <= target:
            return solution
        return None


def newton_solve(
    problem: NonlinearProblem,
    state: np.ndarray,
    load_factor: float,
    options: NewtonOptions = NewtonOptions(),
    *,
    solver: LinearSolver | None = None,
) -> NewtonResult:
    """Newton iterations on R(u, t) = 0 at fixed t from the initial guess `state`.

    `solver` carries LU factors from earlier solves (`solve_path` passes one along the path);
    None starts a new one.
    """
    if solver is None:
        solver = LinearSolver(options, problem.nodes, problem.residual_scale)
    state = np.array(state, dtype=float)
    residual, jacobian = problem.evaluate(state, load_factor)
    residual_norms = [_scaled_norm(residual, problem.residual_scale)]
    increment_norms: list[float] = []
    first = max(residual_norms[0], 1.0)
    reason = "max iterations"
    for iteration in range(1, options.max_iterations + 1):
        if not np.all(np.isfinite(residual)):
            reason = "not finite"
            break
        try:
            increment = solver.solve(jacobian, -residual, _forcing(options, residual_norms[-1]))
        except RuntimeError:  # SuperLU: "Factor is exactly singular"
            reason = "singular"
            break
        increment_norms.append(_scaled_norm(increment, problem.state_scale))
        if not np.isfinite(increment_norms[-1]):
            reason = "not finite"
            break
        at_floor = increment_norms[-1] > options.increment_tolerance and _at_round_off(
            residual_norms, options
        )
        if at_floor:
            logger.debug(
                "t=%.6g: residual %.3e at round-off for %d iterates, correction %.3e: accepted",
                load_factor,
                residual_norms[-1],
                ROUND_OFF_ITERATES,
                increment_norms[-1],
            )
        if at_floor or (
            residual_norms[-1] <= options.residual_tolerance
            and increment_norms[-1] <= options.increment_tolerance
        ):
            return NewtonResult(
                state,
                load_factor,
                True,
                iteration,
                tuple(residual_norms),
                tuple(increment_norms),
                "converged",
            )
        merit = _mean_square(residual, problem.residual_scale)
        trial = state + increment
        if (
            problem.residual is not None
            and iteration < options.max_iterations  # the correction there is one more
            and _expect_convergence(residual_norms, options)
        ):
            found = problem.residual(trial, load_factor)
            size = _scaled_norm(found, problem.residual_scale)
            if size <= options.residual_tolerance and np.all(np.isfinite(found)):
                correction = solver.solve(jacobian, -found, _forcing(options, size))
                norm = _scaled_norm(correction, problem.state_scale)
                if norm <= options.increment_tolerance:
                    return NewtonResult(
                        trial,
                        load_factor,
                        True,
                        iteration + 1,
                        (*residual_norms, size),
                        (*increment_norms, norm),
                        "converged",
                    )
        residual, jacobian = problem.evaluate(trial, load_factor)
        for _ in range(options.line_search):
            if (
                _scaled_norm(residual, problem.residual_scale) <= options.residual_tolerance
                or _mean_square(residual, problem.residual_scale) < merit
            ):
                break
            increment = 0.5 * increment
            trial = state + increment
            residual, jacobian = problem.evaluate(trial, load_factor)
        state = trial
        residual_norms.append(_scaled_norm(residual, problem.residual_scale))
        increment_norms[-1] = _scaled_norm(increment, problem.state_scale)
        logger.debug(
            "t=%.6g iteration %d: residual %.3e, increment %.3e",
            load_factor,
            iteration,
            residual_norms[-1],
            increment_norms[-1],
        )
        if not np.isfinite(residual_norms[-1]):
            reason = "not finite"
            break
        if residual_norms[-1] > options.divergence_factor * first:
            reason = "diverged"
            break
    return NewtonResult(
        state,
        load_factor,
        False,
        len(increment_norms),
        tuple(residual_norms),
        tuple(increment_norms),
        reason,
    )


def solve_path(
    problem: NonlinearProblem,
    initial_state: np.ndarray,
    load_factors: Sequence[float],
    *,
    stepping: SteppingOptions = SteppingOptions(),
    newton: NewtonOptions = NewtonOptions(),
    start: float = 0.0,
) -> PathResult:
    """Follow the load path from t = `start` through every value of `load_factors`.

    `initial_state` must be an equilibrium at t = `start` (e.g. the unloaded reference state);
    it is recorded as the first step. Between requested load factors the increment adapts
    (`rve_rod.stepping.StepController`: cutback on failure or on a converged state
    `problem.admissible` refuses, growth after easy steps). One `LinearSolver` serves the
    whole path, so that LU factors can be reused across steps (`NewtonOptions.refinement`).

    Raises:
        ConvergenceError: when the increment would fall below `min_increment` or more than
            `max_cutbacks` consecutive halvings fail (or are refused); `last_converged` is the
            last accepted StepRecord (possibly a substep) and `history` the PathResult up to there.
    """
    controller = StepController(load_factors, stepping, start)
    solver = LinearSolver(newton, problem.nodes, problem.residual_scale)
    state = np.array(initial_state, dtype=float)
    result = PathResult(steps=[StepRecord(float(start), state.copy(), 0, ())])
    previous_state = None  # the accepted state before the current one
    last = None  # the last accepted Newton solve on the way to the current target
    while not controller.finished:
        raise_pending_interrupt()  # a Ctrl-C Python lost in a callback stops the path here
        t, target = controller.load_factor, controller.target
        trial = controller.trial()
        guess = state
        if stepping.extrapolate and previous_state is not None:
            guess = state + (trial - t) / (t - controller.previous) * (state - previous_state)
        attempt = newton_solve(problem, guess, trial, newton, solver=solver)
        result.newton_iterations += attempt.iterations
        reason = attempt.reason
        if attempt.converged and problem.admissible is not None:
            reason = problem.admissible(attempt.state, trial) or reason
        if reason == "converged":
            previous_state, state, last = state, attempt.state, attempt
            if problem.commit is not None:
                problem.commit(state, trial)
            count = controller.accept(trial, attempt.iterations)
            if count.reached:
                result.steps.append(
                    StepRecord(
                        trial,
                        state.copy(),
                        last.iterations,
                        last.residual_norms,
                        count.substeps,
                        count.cutbacks,
                    )
                )
                logger.info(
                    "t=%.6g converged: %d substeps, %d cutbacks, %d iterations in the last",
                    trial,
                    count.substeps,
                    count.cutbacks,
                    last.iterations,
                )
                last = None
            continue
        stop = controller.reject(trial)
        result.cutbacks = controller.total_cutbacks
        logger.info(  # a solver detail (-v); the caller reports a stop once
            "t=%.6g not reached from t=%.6g (%s after %d iterations); increment cut to %.3g",
            trial,
            t,
            reason,
            attempt.iterations,
            controller.increment,
        )
        if stop:
            last_record = StepRecord(
                t,
                state.copy(),
                0 if last is None else last.iterations,
                () if last is None else last.residual_norms,
                controller.substeps,
                controller.cutbacks,
            )
            raise ConvergenceError(
                f"no accepted state beyond load factor t={t:.6g} on the way to {target:.6g}: "
                f"{reason} (increment {controller.increment:.3g}, "
                f"{controller.consecutive} cutbacks)",
                last_converged=last_record,
                history=result,
            )
    return result
