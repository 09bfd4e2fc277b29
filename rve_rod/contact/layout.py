"""What the contact module knows of the yarns: B-spline patches, yarn chains, periodic lattice.

The caller (the rod RVE, or a test) describes the yarn centrelines by their patches (degree,
knots, collocation parameters), how the patches chain into yarns, and the lattice of the
periodic cell; `ContactLayout` turns this once into per-knot-span data: each span's basis as a
polynomial in the local parameter tau in [0, 1] (so a span's curve is a (3, p+1) coefficient
block and every evaluation is a polynomial), its reference arc length, and where each
collocation point sits. Global numbering: control points and collocation points of the patches
are concatenated in patch order; spans likewise.
"""

import functools
import math
from dataclasses import dataclass

import numpy as np

from rve_rod.contact import _kernels
from rve_rod.errors import InputError, check_integer
from rve_rod.geometry.bspline import (
    basis_functions,
    basis_matrix,
    check_knot_vector,
    collocation_solve,
    find_spans,
    greville_abscissae,
)

__all__ = [
    "ContactLayout",
    "Patch",
    "PeriodicLattice",
    "YarnChain",
    "build_layout",
]

_GAUSS_POINTS = 8
_IMAGE_BITS = 10  # image offsets |i|, |j| < 2^9 in strand keys


@dataclass(frozen=True, eq=False)
class Patch:
    """One B-spline patch of a yarn centreline.

    Attributes:
        degree: p >= 1 (all patches of a layout share it).
        knots: (n + p + 1,) knot vector of the patch's n control points.
        collocation_parameters: (m,) parameters of the collocation points (slave points of
            contact); None means the Greville abscissae (m = n).
    """

    degree: int
    knots: np.ndarray
    collocation_parameters: np.ndarray | None = None

    def __post_init__(self):
        check_integer("degree", self.degree, 1)
        knots = np.asarray(self.knots, dtype=float)
        n = knots.size - self.degree - 1
        check_integer("number of control points", n, self.degree + 1)
        knots = check_knot_vector(knots, self.degree, n)
        object.__setattr__(self, "knots", knots)
        if self.collocation_parameters is None:
            params = greville_abscissae(knots, self.degree)
        else:
            params = np.atleast_1d(np.asarray(self.collocation_parameters, dtype=float))
            find_spans(knots, self.degree, params)  # raises InputError outside the domain
        object.__setattr__(self, "collocation_parameters", params)

    @property
    def n_control_points(self) -> int:
        return self.knots.size - self.degree - 1


@dataclass(frozen=True)
class YarnChain:
    """Patches that join end to start into one yarn.

    Attributes:
        patches: indices of the patches in order along the yarn.
        period: the lattice image (i, j) in which the yarn continues after its last patch
            (the knit loop: (1, 0), the next wale), one of (+-1, 0), (0, +-1); None for a yarn
            with two free ends.
    """

    patches: tuple[int, ...]
    period: tuple[int, int] | None = None

    def __post_init__(self):
        object.__setattr__(self, "patches", tuple(int(k) for k in self.patches))
        if not self.patches:
            raise InputError("a yarn chain needs at least one patch")
        if self.period is not None:
            period = (int(self.period[0]), int(self.period[1]))
            if abs(period[0]) + abs(period[1]) != 1:
                raise InputError(
                    f"yarn period={self.period} must be one of (1, 0), (-1, 0), (0, 1), (0, -1)"
                )
            object.__setattr__(self, "period", period)


@dataclass(frozen=True, eq=False)
class PeriodicLattice:
    """The lattice of the periodic cell: image (i, j) is the cell translated by F (i a1 + j a2).

    Attributes:
        vectors: (2, 3) lattice vectors a1 = (w, 0, 0) and a2 = (0, c, 0) in the reference
            configuration (mm); both must lie in the x-y plane.
    """

    vectors: np.ndarray

    def __post_init__(self):
        vectors = np.asarray(self.vectors, dtype=float)
        if vectors.shape != (2, 3) or not np.all(np.isfinite(vectors)):
            raise InputError(f"lattice vectors must be a finite (2, 3) array, got {vectors.shape}")
        if np.any(vectors[:, 2] != 0.0):
            raise InputError(f"lattice vectors must lie in the x-y plane, got z={vectors[:, 2]}")
        if abs(np.linalg.det(vectors[:, :2])) <= 1e-12 * np.abs(vectors).max() ** 2:
            raise InputError("lattice vectors a1, a2 are parallel")
        object.__setattr__(self, "vectors", vectors)

    @classmethod
    def rectangular(cls, wale_width: float, course_height: float) -> "PeriodicLattice":
        """a1 = (w, 0, 0), a2 = (0, c, 0) (mm)."""
        return cls(np.array([[wale_width, 0.0, 0.0], [0.0, course_height, 0.0]]))

    def shifts(self, images: np.ndarray) -> np.ndarray:
        """Reference lattice shifts L = i a1 + j a2 of images (k, 2): shape (k, 3) (mm)."""
        return np.asarray(images, dtype=float) @ self.vectors


@dataclass(frozen=True, eq=False)
class ContactLayout:
    """Per-span and per-collocation-point data of the yarns (built once by `build_layout`).

    Span arrays have length S (all knot spans of all patches), point arrays length m (all
    collocation points). tau in [0, 1] is the local span parameter, u = start + length * tau.

    Attributes:
        degree: p.
        n_control_points: total number of control points.
        span_first: (S,) global index of the first of the span's p+1 control points.
        span_patch: (S,) patch of each span.
        span_start, span_length: (S,) parameter interval of each span (patch parameter).
        span_basis: (S, p+1, p+1) N_a(tau) = sum_k span_basis[s, a, k] tau^k.
        span_yarn: (S,) yarn of each span.
        span_arc_start, span_arc_length: (S,) reference arc coordinate along the yarn (mm).
        span_closed_end: (S,) True for the last span of an open yarn (owns its end point).
        span_next: (S,) the next span of the same patch, -1 for a patch's last span.
        point_span: (m,) span of each collocation point.
        point_basis: (m, p+1) basis values of the span's control points at the point.
        point_arc: (m,) reference arc coordinate of each point along its yarn (mm).
        yarn_length: (Y,) reference length of each yarn (one period for periodic yarns, mm).
        yarn_period: (Y, 2) lattice period of each yarn ((0, 0) for open yarns).
        collocation_weights: (m,) reference arc length represented by each collocation point
            (mm): sum_j w_j f_j integrates the spline interpolant of a line load f.
    """

    degree: int
    n_control_points: int
    span_first: np.ndarray
    span_patch: np.ndarray
    span_start: np.ndarray
    span_length: np.ndarray
    span_basis: np.ndarray
    span_yarn: np.ndarray
    span_arc_start: np.ndarray
    span_arc_length: np.ndarray
    span_closed_end: np.ndarray
    span_next: np.ndarray
    point_span: np.ndarray
    point_basis: np.ndarray
    point_arc: np.ndarray
    yarn_length: np.ndarray
    yarn_period: np.ndarray
    collocation_weights: np.ndarray

    @property
    def n_spans(self) -> int:
        return self.span_first.size

    @property
    def n_points(self) -> int:
        return self.point_span.size

    @functools.cached_property
    def span_control_points(self) -> np.ndarray:
        """(S, p+1) global index of the control points acting on each span."""
        return self.span_first[:, None] + np.arange(self.degree + 1)[None, :]

    def coefficients(self, positions: np.ndarray) -> np.ndarray:
        """Power-basis coefficients of every span, (3, p+1, S): C(tau) = sum_k c[:, k] tau^k."""
        out = np.empty((3, self.degree + 1, self.n_spans))
        _kernels.span_coefficients(positions, self.span_control_points, self.span_basis, out)
        return out

    @functools.cached_property
    def _point_first(self) -> np.ndarray:
        """(m,) the first control point acting at each collocation point."""
        return self.span_first[self.point_span].astype(np.int64)

    def collocation_positions(self, positions: np.ndarray) -> np.ndarray:
        """Centreline positions at the collocation points, shape (3, m) (mm)."""
        out = np.empty((3, self.n_points))
        _kernels.point_positions(positions, self._point_first, self.point_basis, out)
        return out

    def basis(self, spans: np.ndarray, tau: np.ndarray, derivative: int = 0) -> np.ndarray:
        """Basis values (or tau-derivatives) of the spans' control points at tau, (k, p+1)."""
        powers = _monomials(tau, self.degree, derivative)  # (k, p+1)
        return np.einsum("kab,kb->ka", self.span_basis[spans], powers)

    def strands(self, yarns: np.ndarray, images: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Strand key and arc shift of yarn pieces in lattice images.

        Images that differ by multiples of a yarn's period lie on the same endless strand;
        returns (key (k,) int, shift (k,) mm) such that the unwrapped arc coordinate of a point
        on yarn y in image I is its reference arc coordinate plus shift, and two pieces share
        a strand exactly when their keys are equal.
        """
        yarns = np.asarray(yarns)
        images = np.asarray(images, dtype=np.int64).reshape(-1, 2)
        period = self.yarn_period[yarns]
        turns = images[:, 0] * period[:, 0] + images[:, 1] * period[:, 1]
        base = images - turns[:, None] * period
        offset = 1 << (_IMAGE_BITS - 1)
        key = (yarns.astype(np.int64) << (2 * _IMAGE_BITS)) + (
            ((base[:, 0] + offset) << _IMAGE_BITS) + (base[:, 1] + offset)
        )
        return key, turns * self.yarn_length[yarns]


def _next_in_patch(span_patch: np.ndarray) -> np.ndarray:
    """Index of the next span of the same patch, -1 for the last span of each patch."""
    following = np.arange(1, span_patch.size + 1)
    same = np.append(span_patch[1:] == span_patch[:-1], False)
    return np.where(same, following, -1)


def _monomials(tau: np.ndarray, degree: int, derivative: int) -> np.ndarray:
    """d^derivative/dtau^derivative of (1, tau, ..., tau^p), shape (k, p+1)."""
    tau = np.asarray(tau, dtype=float)
    powers = np.zeros((tau.size, degree + 1))
    for k in range(derivative, degree + 1):
        factor = math.factorial(k) // math.factorial(k - derivative)
        powers[:, k] = factor * tau ** (k - derivative)
    return powers


def build_layout(
    patches: list[Patch], yarns: list[YarnChain], reference_positions: np.ndarray
) -> ContactLayout:
    """The contact layout of `patches` chained into `yarns`, measured on the reference positions.

    Args:
        patches: the B-spline patches, all of one degree.
        yarns: how the patches chain into yarns; every patch must belong to exactly one yarn.
        reference_positions: (n_total, 3) control points of the reference configuration (mm),
            for the arc lengths (self-contact exclusion, friction anchors) and the weights.
    """
    if not patches:
        raise InputError("no patches given")
    degree = patches[0].degree
    if any(patch.degree != degree for patch in patches):
        raise InputError(f"all patches must have one degree, got {[p.degree for p in patches]}")
    listed = sorted(k for yarn in yarns for k in yarn.patches)
    if listed != list(range(len(patches))):
        raise InputError(
            f"every patch must belong to exactly one yarn chain; chains list patches {listed} "
            f"for {len(patches)} patches"
        )
    counts = np.array([patch.n_control_points for patch in patches])
    cp_offset = np.concatenate([[0], np.cumsum(counts)])
    n_total = int(cp_offset[-1])
    reference = np.asarray(reference_positions, dtype=float)
    if reference.shape != (n_total, 3) or not np.all(np.isfinite(reference)):
        raise InputError(
            f"reference positions must be a finite ({n_total}, 3) array, got {reference.shape}"
        )

    spans = [_patch_spans(patch, cp_offset[k]) for k, patch in enumerate(patches)]
    span_offset = np.concatenate([[0], np.cumsum([len(s["first"]) for s in spans])])
    span_first = np.concatenate([s["first"] for s in spans])
    span_basis = np.concatenate([s["basis"] for s in spans])
    span_start = np.concatenate([s["start"] for s in spans])
    span_length = np.concatenate([s["length"] for s in spans])
    span_patch = np.concatenate([np.full(len(s["first"]), k) for k, s in enumerate(spans)])
    n_spans = span_first.size

    # Reference arc length of every span by Gauss quadrature of |dC/dtau|.
    nodes, weights = np.polynomial.legendre.leggauss(_GAUSS_POINTS)
    tau_q = 0.5 * (nodes + 1.0)
    local = reference[span_first[:, None] + np.arange(degree + 1)]  # (S, p+1, 3)
    d_basis = np.einsum("sab,qb->sqa", span_basis, _monomials(tau_q, degree, 1))
    speed = np.linalg.norm(np.einsum("sqa,sac->sqc", d_basis, local), axis=2)  # (S, q)
    span_arc_length = 0.5 * speed @ weights

    span_yarn = np.empty(n_spans, dtype=np.int64)
    span_arc_start = np.empty(n_spans)
    span_closed_end = np.zeros(n_spans, dtype=bool)
    yarn_length = np.empty(len(yarns))
    yarn_period = np.zeros((len(yarns), 2), dtype=np.int64)
    for y, yarn in enumerate(yarns):
        order = np.concatenate(
            [np.arange(span_offset[k], span_offset[k + 1]) for k in yarn.patches]
        )
        span_yarn[order] = y
        span_arc_start[order] = np.concatenate([[0.0], np.cumsum(span_arc_length[order])[:-1]])
        yarn_length[y] = span_arc_length[order].sum()
        if yarn.period is None:
            span_closed_end[order[-1]] = True
        else:
            yarn_period[y] = yarn.period

    # Collocation points: span, local parameter, basis values, arc coordinate.
    point_span, point_tau = [], []
    for k, patch in enumerate(patches):
        params = patch.collocation_parameters
        local_span = find_spans(patch.knots, degree, params)
        lookup = {int(i): span_offset[k] + a for a, i in enumerate(spans[k]["index"])}
        global_span = np.array([lookup[int(i)] for i in local_span], dtype=np.int64)
        point_span.append(global_span)
        point_tau.append((params - span_start[global_span]) / span_length[global_span])
    point_span = np.concatenate(point_span)
    point_tau = np.clip(np.concatenate(point_tau), 0.0, 1.0)
    powers = _monomials(point_tau, degree, 0)
    point_basis = np.einsum("mab,mb->ma", span_basis[point_span], powers)
    point_arc = span_arc_start[point_span] + point_tau * span_arc_length[point_span]

    weights_per_point = _collocation_weights(patches, cp_offset, span_first, span_basis, speed)
    return ContactLayout(
        degree=degree,
        n_control_points=n_total,
        span_first=span_first,
        span_patch=span_patch,
        span_start=span_start,
        span_length=span_length,
        span_basis=span_basis,
        span_yarn=span_yarn,
        span_arc_start=span_arc_start,
        span_arc_length=span_arc_length,
        span_closed_end=span_closed_end,
        span_next=_next_in_patch(span_patch),
        point_span=point_span,
        point_basis=point_basis,
        point_arc=point_arc,
        yarn_length=yarn_length,
        yarn_period=yarn_period,
        collocation_weights=weights_per_point,
    )


def _patch_spans(patch: Patch, cp_offset: int) -> dict:
    """Non-empty knot spans of a patch and their basis as polynomials in tau (Taylor at start)."""
    p, knots = patch.degree, patch.knots
    n = patch.n_control_points
    index = np.array([i for i in range(p, n) if knots[i + 1] > knots[i]], dtype=np.int64)
    start = knots[index]
    length = knots[index + 1] - start
    values = basis_functions(knots, p, start, derivatives=p).values  # (p+1, S, p+1)
    factor = np.array([length**k / math.factorial(k) for k in range(p + 1)])  # (p+1, S)
    basis = np.einsum("ksa,ks->sak", values, factor)
    return {
        "index": index,
        "first": cp_offset + index - p,
        "start": start,
        "length": length,
        "basis": basis,
    }


def _collocation_weights(patches, cp_offset, span_first, span_basis, speed):
    """Weights w = (B^+)^T int N ds per patch, B the basis matrix at the collocation points
    (the minimum-norm least-squares solution of B^T w = int N ds; B is square and regular at the
    Greville points).

    speed: (S, q) |dC/dtau| at the Gauss points of every span (reference configuration).
    """
    degree = patches[0].degree
    nodes, weights = np.polynomial.legendre.leggauss(_GAUSS_POINTS)
    powers = _monomials(0.5 * (nodes + 1.0), degree, 0)
    values = np.einsum("sab,qb->sqa", span_basis, powers)  # (S, q, p+1)
    integrals = np.zeros(int(cp_offset[-1]))
    contribution = 0.5 * np.einsum("sqa,sq,q->sa", values, speed, weights)
    np.add.at(integrals, span_first[:, None] + np.arange(degree + 1), contribution)
    result = []
    for k, patch in enumerate(patches):
        parameters = patch.collocation_parameters
        integral = integrals[cp_offset[k] : cp_offset[k + 1]]
        if parameters.size == integral.size:  # collocation at as many points as controls
            result.append(collocation_solve(patch.knots, degree, parameters, integral, True))
        else:
            matrix = basis_matrix(patch.knots, degree, parameters).toarray()
            result.append(np.linalg.lstsq(matrix.T, integral, rcond=None)[0])
    return np.concatenate(result)
