"""B-spline toolkit: knot vectors, basis functions with derivatives, curves, refinement.

Everything the geometry, the collocation rod engine and the surface fits stand on. Algorithms
follow Piegl & Tiller, The NURBS Book (2nd ed., 1997), cited by algorithm number. Basis
evaluation is vectorized over many parameters at once (loops run over the degree only).

Conventions: degree p, n control points, knot vector of length n + p + 1, open (clamped)
unless stated. Control points have shape (n, dim). Parameters are 1D arrays of shape (m,).
"""

import bisect
import itertools
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.linalg
import scipy.sparse

from rve_rod.errors import InputError, check_integer

__all__ = [
    "BSplineCurve",
    "BasisValues",
    "SplitCurve",
    "basis_functions",
    "basis_matrix",
    "check_knot_vector",
    "collocation_solve",
    "find_spans",
    "greville_abscissae",
    "interpolate",
    "join",
    "open_knot_vector",
]


class BasisValues(NamedTuple):
    """The nonzero basis functions at m parameters.

    Attributes:
        spans: (m,) knot-span index i of each parameter; the nonzero functions are
            N_{i-p}, ..., N_{i}, i.e. control points i-p ... i.
        values: (d+1, m, p+1) values[k, j, a] = k-th derivative of N_{spans[j]-p+a} at u_j.
    """

    spans: np.ndarray
    values: np.ndarray


def open_knot_vector(
    degree: int, n_control_points: int, domain: tuple[float, float] = (0.0, 1.0)
) -> np.ndarray:
    """Open uniform knot vector: p+1 repeated end knots and uniform interior knots.

    Returns an array of length n_control_points + degree + 1.
    """
    check_integer("degree", degree, 1)
    check_integer("n_control_points", n_control_points, degree + 1)
    start, end = float(domain[0]), float(domain[1])
    if not end > start:
        raise InputError(f"domain={domain} must satisfy start < end")
    n_spans = n_control_points - degree
    interior = np.linspace(start, end, n_spans + 1)[1:-1]
    return np.concatenate([np.full(degree + 1, start), interior, np.full(degree + 1, end)])


def check_knot_vector(knots: np.ndarray, degree: int, n_control_points: int) -> np.ndarray:
    """Return `knots` as a float array after checking length, order and multiplicities."""
    knots = np.asarray(knots, dtype=float)
    if knots.ndim != 1 or knots.size != n_control_points + degree + 1:
        raise InputError(
            f"knot vector has {knots.size} entries; degree {degree} with "
            f"{n_control_points} control points needs {n_control_points + degree + 1}"
        )
    if np.any(np.diff(knots) < 0) or not np.all(np.isfinite(knots)):
        raise InputError("knot vector must be finite and non-decreasing")
    if knots[degree] >= knots[-degree - 1]:
        raise InputError("knot vector has an empty parameter domain")
    interior = knots[degree + 1 : -degree - 1]  # sorted: a run of degree + 1 equal knots
    if interior.size > degree and np.any(interior[degree:] == interior[: interior.size - degree]):
        raise InputError(f"an interior knot repeats more than degree={degree} times")
    return knots


def find_spans(knots: np.ndarray, degree: int, params: np.ndarray) -> np.ndarray:
    """Knot-span index i with knots[i] <= u < knots[i+1] for each u (A2.1, vectorized).

    The right end of the domain belongs to the last non-empty span. Parameters outside the
    domain raise InputError.
    """
    params = np.atleast_1d(np.asarray(params, dtype=float))
    n = knots.size - degree - 1
    low, high = knots[degree], knots[n]
    tolerance = 1e-12 * max(1.0, abs(high - low))
    if params.size and (params.min() < low - tolerance or params.max() > high + tolerance):
        raise InputError(
            f"parameter outside the curve domain [{low:.6g}, {high:.6g}]: "
            f"min {params.min():.6g}, max {params.max():.6g}"
        )
    spans = np.searchsorted(knots, params, side="right") - 1
    return np.clip(spans, degree, n - 1)


def basis_functions(
    knots: np.ndarray, degree: int, params: np.ndarray, derivatives: int = 0
) -> BasisValues:
    """Nonzero basis functions and their derivatives up to `derivatives` (A2.3, vectorized).

    Returns BasisValues with values of shape (derivatives+1, m, degree+1).
    """
    p = degree
    params = np.atleast_1d(np.asarray(params, dtype=float))
    spans = find_spans(knots, p, params)
    m = params.size
    # ndu[:, j, r] for r >= j holds basis values N_{r,j} (upper triangle, A2.2) and for r < j
    # the knot differences used by the derivative recursion (lower triangle).
    ndu = np.empty((m, p + 1, p + 1))
    ndu[:, 0, 0] = 1.0
    left = np.empty((m, p + 1))
    right = np.empty((m, p + 1))
    for j in range(1, p + 1):
        left[:, j] = params - knots[spans + 1 - j]
        right[:, j] = knots[spans + j] - params
        saved = np.zeros(m)
        for r in range(j):
            ndu[:, j, r] = right[:, r + 1] + left[:, j - r]
            temp = ndu[:, r, j - 1] / ndu[:, j, r]
            ndu[:, r, j] = saved + right[:, r + 1] * temp
            saved = left[:, j - r] * temp
        ndu[:, j, j] = saved
    values = np.zeros((derivatives + 1, m, p + 1))
    values[0] = ndu[:, :, p]
    a = np.empty((2, m, p + 1))
    for r in range(p + 1):
        s1, s2 = 0, 1
        a[0, :, 0] = 1.0
        for k in range(1, min(derivatives, p) + 1):
            d = np.zeros(m)
            rk, pk = r - k, p - k
            if r >= k:
                a[s2, :, 0] = a[s1, :, 0] / ndu[:, pk + 1, rk]
                d = a[s2, :, 0] * ndu[:, rk, pk]
            j1 = 1 if rk >= -1 else -rk
            j2 = k - 1 if r - 1 <= pk else p - r
            for j in range(j1, j2 + 1):
                a[s2, :, j] = (a[s1, :, j] - a[s1, :, j - 1]) / ndu[:, pk + 1, rk + j]
                d = d + a[s2, :, j] * ndu[:, rk + j, pk]
            if r <= pk:
                a[s2, :, k] = -a[s1, :, k - 1] / ndu[:, pk + 1, r]
                d = d + a[s2, :, k] * ndu[:, r, pk]
            values[k, :, r] = d
            s1, s2 = s2, s1
    factor = float(p)
    for k in range(1, min(derivatives, p) + 1):
        values[k] *= factor
        factor *= p - k
    return BasisValues(spans=spans, values=values)


def basis_matrix(
    knots: np.ndarray, degree: int, params: np.ndarray, derivative: int = 0
) -> scipy.sparse.csr_matrix:
    """Sparse (m, n) matrix B[j, i] = d^k N_i / du^k (u_j) with k = `derivative`."""
    basis = basis_functions(knots, degree, params, derivative)
    n = knots.size - degree - 1
    m = basis.spans.size
    columns = basis.spans[:, None] - degree + np.arange(degree + 1)[None, :]
    rows = np.repeat(np.arange(m), degree + 1)
    return scipy.sparse.csr_matrix(
        (basis.values[derivative].ravel(), (rows, columns.ravel())), shape=(m, n)
    )


def collocation_solve(
    knots: np.ndarray, degree: int, params: np.ndarray, rhs: np.ndarray, transpose: bool = False
) -> np.ndarray:
    """The solution x of B x = rhs (or B^T x = rhs with `transpose`), B = basis_matrix(knots,
    degree, params) square (one parameter per basis function, increasing): B is banded (row j
    holds the p+1 functions acting at u_j), so LAPACK's banded LU solves it in O(n p^2), not
    the O(n^3) of a dense solve (263 unknowns: about 0.1 instead of 3 ms).

    Args:
        rhs: (n,) or (n, k) right-hand side(s).

    Raises:
        InputError: B is singular (the Schoenberg-Whitney condition fails).
    """
    basis = basis_functions(knots, degree, params)
    n = knots.size - degree - 1
    if basis.spans.size != n:
        raise InputError(f"{basis.spans.size} parameters for {n} basis functions: not square")
    # Schoenberg-Whitney: B of increasing parameters is regular iff every B_j(u_j) != 0
    # (checked exactly: LU of a singular B may meet a round-off pivot instead of a zero one)
    position = np.arange(n) - (basis.spans - degree)
    within = (position >= 0) & (position <= degree)
    diagonal = basis.values[0][np.flatnonzero(within), position[within]]
    if np.any(np.diff(params) <= 0.0) or not within.all() or np.any(diagonal == 0.0):
        raise InputError("collocation system is singular (Schoenberg-Whitney condition violated)")
    rows = np.repeat(np.arange(n), degree + 1)
    columns = (basis.spans[:, None] - degree + np.arange(degree + 1)[None, :]).ravel()
    if transpose:
        rows, columns = columns, rows
    lower = int(max(np.max(rows - columns), 0))
    upper = int(max(np.max(columns - rows), 0))
    banded = np.zeros((lower + upper + 1, n))
    banded[upper + rows - columns, columns] = basis.values[0].ravel()
    try:
        return scipy.linalg.solve_banded((lower, upper), banded, rhs)
    except np.linalg.LinAlgError:
        raise InputError(
            "collocation system is singular (Schoenberg-Whitney condition violated)"
        ) from None


def greville_abscissae(knots: np.ndarray, degree: int) -> np.ndarray:
    """Greville points g_i = (t_{i+1} + ... + t_{i+p}) / p, shape (n,)."""
    n = knots.size - degree - 1
    window = np.lib.stride_tricks.sliding_window_view(knots[1:-1], degree)
    return window[:n].mean(axis=1)


def knot_multiplicity(knots: np.ndarray, value: float, tolerance: float = 1e-14) -> int:
    """How many times `value` occurs in the knot vector."""
    return int(np.count_nonzero(np.abs(knots - value) <= tolerance))


def insert_knot(
    knots: np.ndarray, degree: int, control_points: np.ndarray, value: float, times: int = 1
) -> tuple[np.ndarray, np.ndarray]:
    """Insert `value` `times` times (Boehm's algorithm, A5.1); the curve is unchanged.

    Returns (new knots, new control points (n + times, dim)).
    """
    points = np.asarray(control_points, dtype=float)
    if points.ndim == 1:
        points = points[:, None]
    knots = np.asarray(knots, dtype=float)
    find_spans(knots, degree, np.array([value]))  # inside the domain
    knot_list, point_list = knots.tolist(), points.tolist()
    _insert_knot(knot_list, degree, point_list, float(value), times)
    return np.array(knot_list), np.array(point_list).reshape(-1, points.shape[1])


def _insert_knot(knots: list, p: int, points: list, value: float, times: int) -> None:
    """Boehm's algorithm (A5.1) in place on plain lists: the knots (floats) and the control
    points (lists of coordinates); `value` must lie in the domain. Python floats do the
    arithmetic of NumPy's float64 operation by operation, at a fraction of the cost per call
    on the few coordinates of a control point (`BSplineCurve.refine` inserts hundreds)."""
    n = len(knots) - p - 1
    span = min(max(bisect.bisect_right(knots, value) - 1, p), n - 1)  # as find_spans
    # knots within 1e-14 of value (as knot_multiplicity) lie next to the span (sorted knots)
    s = sum(abs(knot - value) <= 1e-14 for knot in knots[max(span - p - 1, 0) : span + p + 2])
    if times < 1 or times + s > p:
        raise InputError(
            f"cannot insert knot {value} {times} times: multiplicity {s} + {times} "
            f"would exceed degree {p}"
        )
    r = times
    new_points = points[: span - p + 1] + [None] * (p - 1 - s + r) + points[span - s :]
    temp = points[span - p : span - s + 1]
    last = span - p
    for j in range(1, r + 1):
        last = span - p + j
        for i in range(p - j - s + 1):
            alpha = (value - knots[last + i]) / (knots[i + span + 1] - knots[last + i])
            temp[i] = [
                alpha * a + (1.0 - alpha) * b for a, b in zip(temp[i + 1], temp[i], strict=True)
            ]
        new_points[last] = temp[0]
        new_points[span + r - j - s] = temp[p - j - s]
    for i in range(last + 1, span - s):
        new_points[i] = temp[i - last]
    points[:] = new_points
    knots[span + 1 : span + 1] = [value] * r


class SplitCurve(NamedTuple):
    """The two pieces of a curve split at a parameter (`BSplineCurve.split`)."""

    left: "BSplineCurve"
    right: "BSplineCurve"


@dataclass(frozen=True, eq=False)
class BSplineCurve:
    """A B-spline curve C(u) = sum_i N_{i,p}(u) P_i.

    Attributes:
        degree: polynomial degree p >= 1.
        knots: (n + p + 1,) non-decreasing knot vector.
        control_points: (n, dim) control points (mm for geometry).
    """

    degree: int
    knots: np.ndarray
    control_points: np.ndarray

    def __post_init__(self):
        check_integer("degree", self.degree, 1)
        points = np.asarray(self.control_points, dtype=float)
        if points.ndim == 1:
            points = points[:, None]
        object.__setattr__(self, "control_points", points)
        knots = check_knot_vector(self.knots, self.degree, points.shape[0])
        object.__setattr__(self, "knots", knots)

    @property
    def n_control_points(self) -> int:
        return self.control_points.shape[0]

    @property
    def dim(self) -> int:
        return self.control_points.shape[1]

    @property
    def domain(self) -> tuple[float, float]:
        return float(self.knots[self.degree]), float(self.knots[-self.degree - 1])

    def breakpoints(self) -> np.ndarray:
        """The distinct knots of the domain (span boundaries), shape (n_spans + 1,)."""
        low, high = self.domain
        unique = np.unique(self.knots)
        return unique[(unique >= low) & (unique <= high)]

    def derivatives(self, params: np.ndarray, order: int = 0) -> np.ndarray:
        """Curve and its derivatives, shape (order+1, m, dim); [k] is d^k C / du^k."""
        basis = basis_functions(self.knots, self.degree, params, order)
        index = basis.spans[:, None] - self.degree + np.arange(self.degree + 1)[None, :]
        local = self.control_points[index]  # (m, p+1, dim)
        return np.einsum("kma,mad->kmd", basis.values, local)

    def __call__(self, params: np.ndarray, derivative: int = 0) -> np.ndarray:
        """Points (or the `derivative`-th derivative) at `params`, shape (m, dim)."""
        return self.derivatives(params, derivative)[derivative]

    def greville(self) -> np.ndarray:
        """Greville abscissae, shape (n,)."""
        return greville_abscissae(self.knots, self.degree)

    def insert_knot(self, value: float, times: int = 1) -> "BSplineCurve":
        """The same curve with `value` inserted `times` times into the knot vector."""
        knots, points = insert_knot(self.knots, self.degree, self.control_points, value, times)
        return BSplineCurve(self.degree, knots, points)

    def refine(self, new_knots) -> "BSplineCurve":
        """The same curve with every value of `new_knots` inserted once (h-refinement)."""
        values = np.sort(np.asarray(new_knots, dtype=float))
        find_spans(self.knots, self.degree, values)  # inside the domain
        knots, points = self.knots.tolist(), self.control_points.tolist()
        for value in values.tolist():
            _insert_knot(knots, self.degree, points, value, 1)
        return BSplineCurve(self.degree, np.array(knots), np.array(points))

    def subdivide(self, parts: int) -> "BSplineCurve":
        """Uniform h-refinement: split every non-empty knot span into `parts` equal spans.

        A degree-p curve with s spans gets s * parts spans and s * parts + p control points;
        e.g. the quarter loop (p = 4, 12 points, 8 spans) with parts=8 has 68 control points.
        """
        check_integer("parts", parts, 1)
        edges = self.breakpoints()
        fractions = np.arange(1, parts) / parts
        inner = (edges[:-1, None] + np.diff(edges)[:, None] * fractions[None, :]).ravel()
        return self.refine(inner)

    def refined_to(self, n_control_points: int) -> "BSplineCurve":
        """The same curve h-refined to `n_control_points` by inserting simple knots.

        The new knots split every non-empty span into equal parts; the number of parts per
        span is proportional to its parameter length (largest remainders, at least one), so
        a uniform curve is refined uniformly (`subdivide`) whenever the count allows.
        """
        extra = check_integer("n_control_points", n_control_points, self.n_control_points)
        extra -= self.n_control_points
        edges = self.breakpoints()
        lengths = np.diff(edges)
        target = lengths.size + extra
        ideal = target * lengths / lengths.sum()
        parts = np.maximum(np.floor(ideal).astype(int), 1)
        while parts.sum() > target:  # the minimum of one part overshot: take from the largest
            parts[np.argmax(parts - ideal)] -= 1
        order = np.argsort(-(ideal - parts), kind="stable")
        parts[order[: target - parts.sum()]] += 1
        inner = [
            edges[i] + lengths[i] * np.arange(1, parts[i]) / parts[i] for i in range(lengths.size)
        ]
        return self.refine(np.concatenate(inner))

    def split(self, parameter: float) -> "SplitCurve":
        """The pieces left and right of an interior `parameter` (knot insertion up to
        multiplicity p, A5.1); each keeps its part of the parameter domain, and together they
        are the same curve."""
        low, high = self.domain
        u = float(parameter)
        if not low < u < high:
            raise InputError(
                f"split parameter={u:.6g} is outside the open curve domain ({low:.6g}, {high:.6g})"
            )
        p = self.degree
        curve = self
        existing = knot_multiplicity(self.knots, u)
        if existing < p:
            curve = self.insert_knot(u, p - existing)
        knots, points = curve.knots, curve.control_points
        first = int(np.flatnonzero(np.abs(knots - u) <= 1e-14)[0])  # u occupies first..first+p-1
        left = BSplineCurve(p, np.concatenate([knots[: first + p], [u]]), points[:first])
        right = BSplineCurve(p, np.concatenate([[u], knots[first:]]), points[first - 1 :])
        return SplitCurve(left, right)

    def translated(self, offset) -> "BSplineCurve":
        """The curve moved by `offset` (dim,) (mm), same parametrization."""
        return BSplineCurve(
            self.degree, self.knots, self.control_points + np.asarray(offset, dtype=float)
        )

    def reparametrized(self, start: float) -> "BSplineCurve":
        """The same curve with its parameter domain shifted to begin at `start`."""
        return BSplineCurve(
            self.degree, self.knots - self.domain[0] + float(start), self.control_points
        )

    def arc_length(self, points_per_span: int = 12) -> float:
        """Length of the curve over its domain by Gauss-Legendre quadrature per span (mm)."""
        return float(self.arc_length_function(points_per_span)[1][-1])

    def arc_length_function(self, points_per_span: int = 12) -> tuple[np.ndarray, np.ndarray]:
        """Cumulative arc length at the breakpoints: (breakpoints (s+1,), length (s+1,))."""
        params, half, weights = self.span_quadrature(points_per_span)
        speed = np.linalg.norm(self(params, 1), axis=1).reshape(half.size, points_per_span)
        per_span = half * (speed @ weights)
        return self.breakpoints(), np.concatenate([[0.0], np.cumsum(per_span)])

    def span_quadrature(
        self, points_per_span: int = 12
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Gauss-Legendre points per knot span: (params (s p,), span after span; half of each
        span's length in the parameter (s,); the rule's weights on [-1, 1] (p,)), so that
        int f du = sum over spans of half * (f(params).reshape(s, p) @ weights)."""
        edges = self.breakpoints()
        nodes, weights = np.polynomial.legendre.leggauss(points_per_span)
        half = 0.5 * np.diff(edges)
        params = (edges[:-1, None] + half[:, None] * (nodes[None, :] + 1.0)).ravel()
        return params, half, weights


def averaged_knots(params: np.ndarray, degree: int) -> np.ndarray:
    """Knots by averaging the interpolation parameters (NURBS Book eq. 9.8); open ends."""
    params = np.asarray(params, dtype=float)
    n = params.size
    interior = np.array([params[j : j + degree].mean() for j in range(1, n - degree)])
    return np.concatenate(
        [np.full(degree + 1, params[0]), interior, np.full(degree + 1, params[-1])]
    )


def chord_length_parameters(points: np.ndarray) -> np.ndarray:
    """Parameters in [0, 1] proportional to the cumulative chord length (eq. 9.4)."""
    points = np.asarray(points, dtype=float)
    chords = np.linalg.norm(np.diff(points, axis=0), axis=1)
    if np.any(chords <= 0):
        raise InputError("interpolation points must be distinct consecutive points")
    cumulative = np.concatenate([[0.0], np.cumsum(chords)])
    return cumulative / cumulative[-1]


def interpolate(
    points: np.ndarray, degree: int, params: np.ndarray | None = None, knots=None
) -> BSplineCurve:
    """The B-spline curve through `points` (n, dim) at `params` (global interpolation, A9.1).

    Defaults: chord-length parameters and averaged knots. With explicit knots the system
    N(params) P = points must be nonsingular (Schoenberg-Whitney condition).
    """
    points = np.asarray(points, dtype=float)
    if points.ndim == 1:
        points = points[:, None]
    n = points.shape[0]
    check_integer("number of interpolation points", n, degree + 1)
    params = chord_length_parameters(points) if params is None else np.asarray(params, float)
    if params.shape != (n,) or np.any(np.diff(params) <= 0):
        raise InputError("interpolation parameters must be strictly increasing, one per point")
    knots = averaged_knots(params, degree) if knots is None else np.asarray(knots, float)
    knots = check_knot_vector(knots, degree, n)
    return BSplineCurve(degree, knots, collocation_solve(knots, degree, params, points))


def join(curves, continuity: int, tolerance: float = 1e-9) -> BSplineCurve:
    """One curve through consecutive curves of one degree, C^continuity at the joins.

    Each curve's parameter domain is laid after the previous one's (domains keep their
    lengths, the first keeps its start); the joins become interior knots of multiplicity
    p - continuity. The result is exact (the curves must meet with equal derivatives up to
    order `continuity`, in their own parametrizations): the curves are first concatenated
    with C0 joins (knots of multiplicity p, control points shared at the joins), which
    represents them exactly, and that curve is then interpolated at the Greville points of
    the smoother knot vector, which contains it.

    Raises InputError when a derivative of order <= continuity jumps at a join by more than
    `tolerance` times its size (or the curves do not meet).
    """
    curves = list(curves)
    if not curves:
        raise InputError("join needs at least one curve")
    p = curves[0].degree
    if any(curve.degree != p for curve in curves):
        raise InputError(f"join needs curves of one degree, got {[c.degree for c in curves]}")
    continuity = check_integer("continuity", continuity, 0, p - 1)
    pieces = [curves[0]]
    for curve in curves[1:]:
        pieces.append(curve.reparametrized(pieces[-1].domain[1]))
    for k, (before, after) in enumerate(itertools.pairwise(pieces)):
        at = before.domain[1]
        left = before.derivatives(np.array([at]), continuity)[:, 0]
        right = after.derivatives(np.array([at]), continuity)[:, 0]
        # a derivative that vanishes at the join is compared with the curve's own scale,
        # its extent over its parameter length to the derivative's order
        extent = np.ptp(before.control_points, axis=0).max()
        span = before.domain[1] - before.domain[0]
        for order in range(continuity + 1):
            size = max(np.abs(left[order]).max(), np.abs(right[order]).max(), 1e-300)
            jump = np.abs(left[order] - right[order]).max()
            size = max(size, extent / span**order)
            if order == 0:
                size = max(size, np.abs(before.control_points).max())
            if jump > tolerance * size:
                raise InputError(
                    f"curves {k} and {k + 1} differ in derivative {order} at their join by "
                    f"{jump:.3g} (relative {jump / size:.3g} > tolerance {tolerance:g}); "
                    f"they are not C{continuity}-continuous"
                )
    knots = [pieces[0].knots[:-1]]
    points = [pieces[0].control_points]
    for piece in pieces[1:]:
        knots.append(piece.knots[p + 1 : -1])
        points.append(piece.control_points[1:])
    knots.append(pieces[-1].knots[-1:])
    chained = BSplineCurve(p, np.concatenate(knots), np.concatenate(points))
    if continuity == 0:
        return chained
    joins = np.array([piece.domain[0] for piece in pieces[1:]])
    smooth = chained.knots
    for value in joins:
        position = int(np.flatnonzero(np.abs(smooth - value) <= 1e-14)[0])
        smooth = np.delete(smooth, np.arange(position, position + continuity))
    greville = greville_abscissae(smooth, p)
    return BSplineCurve(p, smooth, collocation_solve(smooth, p, greville, chained(greville)))
