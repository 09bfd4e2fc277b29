"""Fitting response surfaces to (E, S) samples: regularized, constrained least squares on B-splines.

Stress fit (the paper's, kind "stress"): tensor-product splines S11(E11, E22), S22(E11, E22) of
degree p >= 2 (C1 with simple knots) and an odd curve S12(E12), each by

    min_c |A c - s|^2 + lambda |J c|^2   subject to   S(0) = 0   (and D c >= 0),

where A evaluates the spline at the sample strains, s holds the sampled stresses and J the jumps
of the p-th derivative across every interior knot (in each direction of the tensor product).
That penalty vanishes exactly on the polynomials of degree p in each input, so a law in that
space is reproduced exactly whatever lambda is, while regions without samples (between the
rays of star-shaped data, box corners) are filled by the smoothest continuation. lambda is
`regularization` times |A|_F^2 / |J|_F^2, i.e. relative and independent of units and sizes.
With `monotone` (default), S11 is made nondecreasing in E11 and S22 in E22 everywhere: the
differences of consecutive coefficients along that input, D c, are held >= 0 (a sufficient
condition: the derivative spline's coefficients are those differences times positive
factors), solved as a bounded least-squares problem in the coefficients' partial sums. A
negative dS11/dE11 or dS22/dE22 is a material that softens, where the membrane has no unique
equilibrium; the knit's data near E = 0 have a kink (almost no lateral stress in
compression, stiffening in tension) across which the unconstrained fit undershoots.
The knots are uniform on each side of E = 0 over the range of the data (a knot at 0 lets the
compression and tension branches differ); S12 uses knots symmetric about 0 and an odd
coefficient pattern (c_{n-1-i} = -c_i), so it is odd by construction.

Energy fit (kind "energy"): a potential psi(E11, E22) of degree q >= 3 and an even
psi_shear(E12), fitted so that their gradients match the same samples, with psi(0) = 0,
grad psi(0) = 0 and psi_shear(0) = 0; the stored stresses are their exact derivative splines
(docs/surface-format.md), so the tangent is symmetric everywhere.
"""

import math
from dataclasses import asdict, dataclass
from typing import NamedTuple

import numpy as np
import scipy.linalg
import scipy.optimize

from rve_rod.errors import InputError, check_integer, check_range
from rve_rod.geometry.bspline import basis_matrix
from rve_rod.homogenize.samples import SurfaceSamples
from rve_rod.surface import (
    FitSamples,
    ResidualStats,
    ResponseSurface,
    Spline1D,
    Spline2D,
    energy_surface,
    tangent_asymmetry,
)

__all__ = [
    "FitOptions",
    "FitReport",
    "fit_energy_surface",
    "fit_report",
    "fit_stress_surface",
    "knot_vector",
]


@dataclass(frozen=True)
class FitOptions:
    """Settings of the response-surface fits.

    Attributes:
        degree: degree of the stress splines of a stress fit (>= 2 for C1; default 2 as the
            paper).
        energy_degree: degree of the potentials of an energy fit (>= 3, so the stresses are
            C1; default 3).
        spans: knot spans per input of the (E11, E22) splines; None: from the number of
            samples m, round(sqrt(m) / 1.5) clipped to [2, 12] (8 for the default plan).
        shear_spans: knot spans of the S12 curve over [-max E12, max E12] (even, so 0 is a
            knot); None: twice round(k / 3) clipped to [1, 8], k shear samples.
        regularization: relative weight of the smoothness penalty (>= 0; default 1e-3, see
            benchmarks/bench_surface_fit.py: it barely changes the residuals at the samples
            but keeps the surface sane between the rays).
        monotone: stress fit with S11 nondecreasing in E11 and S22 in E22 (default True;
            module docstring); the energy fit ignores it.
        stiffness_floor: with `monotone`, the smallest dS11/dE11 (dS22/dE22) as a fraction
            of the data's mean slope (S range over E range of that component; default 0.01,
            0 for a plain monotone fit): a membrane made of a material with zero stiffness
            has no unique equilibrium.
    """

    degree: int = 2
    energy_degree: int = 3
    spans: int | None = None
    shear_spans: int | None = None
    regularization: float = 1e-3
    monotone: bool = True
    stiffness_floor: float = 0.01

    def __post_init__(self):
        check_integer("degree", self.degree, 2, 5)
        check_integer("energy_degree", self.energy_degree, 3, 6)
        if self.spans is not None:
            check_integer("spans", self.spans, 1, 64)
        if self.shear_spans is not None:
            check_integer("shear_spans", self.shear_spans, 2, 64)
            if self.shear_spans % 2:
                raise InputError(f"shear_spans={self.shear_spans} must be even (0 is a knot)")
        check_range("regularization", self.regularization, 0.0, 1.0)
        check_range("stiffness_floor", self.stiffness_floor, 0.0, 1.0)


class FitReport(NamedTuple):
    """Quality of a fitted surface.

    Attributes:
        kind: "stress" or "energy".
        residuals: ResidualStats per stress group ("S11", "S22", "S12").
        tangent_asymmetry: max |dS11/dE22 - dS22/dE11| / max |dS/dE|_F over the domain.
    """

    kind: str
    residuals: dict[str, ResidualStats]
    tangent_asymmetry: float


def fit_report(surface: ResponseSurface) -> FitReport:
    """Residuals and tangent asymmetry of a fitted surface."""
    return FitReport(surface.kind, surface.residual_stats(), tangent_asymmetry(surface))


def knot_vector(values: np.ndarray, degree: int, spans: int) -> np.ndarray:
    """Open knot vector over [min(values, 0), max(values, 0)], uniform on each side of 0.

    When the range straddles 0, 0 is a knot and each side gets spans in proportion to its
    length (at least one).
    """
    low, high = min(float(np.min(values)), 0.0), max(float(np.max(values)), 0.0)
    if not high > low:
        raise InputError(f"samples span no range ([{low}, {high}]): cannot place knots")
    if low < 0.0 < high and spans >= 2:
        below = min(max(round(spans * -low / (high - low)), 1), spans - 1)
        breaks = np.concatenate(
            [np.linspace(low, 0.0, below + 1)[:-1], np.linspace(0.0, high, spans - below + 1)]
        )
    else:
        breaks = np.linspace(low, high, spans + 1)
    return np.concatenate([np.full(degree, low), breaks, np.full(degree, high)])


def symmetric_knot_vector(extent: float, degree: int, spans: int) -> np.ndarray:
    """Open uniform knot vector over [-extent, extent] with an even number of spans."""
    breaks = np.linspace(-extent, extent, spans + 1)
    return np.concatenate([np.full(degree, -extent), breaks, np.full(degree, extent)])


def _default_spans(samples: int) -> int:
    return int(np.clip(round(math.sqrt(samples) / 1.5), 2, 12))


def _default_shear_spans(samples: int) -> int:
    return 2 * int(np.clip(round(samples / 3), 1, 8))


def _basis(knots: np.ndarray, degree: int, x: np.ndarray, derivative: int = 0) -> np.ndarray:
    return basis_matrix(knots, degree, x, derivative).toarray()


def _jump_matrix(knots: np.ndarray, degree: int) -> np.ndarray:
    """(breaks - 2, n): jumps of the degree-th derivative across the interior breakpoints."""
    breaks = np.unique(knots)
    middles = 0.5 * (breaks[:-1] + breaks[1:])
    highest = _basis(knots, degree, middles, degree)
    return highest[1:] - highest[:-1]


def _tensor_rows(left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Row-wise Kronecker product: (m, n1) x (m, n2) -> (m, n1 n2), index i n2 + j."""
    return (left[:, :, None] * right[:, None, :]).reshape(left.shape[0], -1)


def _tensor_penalty(knots: tuple, degrees: tuple) -> np.ndarray:
    jumps = [_jump_matrix(t, p) for t, p in zip(knots, degrees, strict=True)]
    sizes = [t.size - p - 1 for t, p in zip(knots, degrees, strict=True)]
    return np.vstack([np.kron(jumps[0], np.eye(sizes[1])), np.kron(np.eye(sizes[0]), jumps[1])])


def _parity_map(n: int, sign: float) -> np.ndarray:
    """(n, r) map T of free parameters to coefficients with c_{n-1-i} = sign c_i."""
    columns = []
    for i in range(n // 2):
        column = np.zeros(n)
        column[i], column[n - 1 - i] = 1.0, sign
        columns.append(column)
    if n % 2 and sign > 0:
        column = np.zeros(n)
        column[n // 2] = 1.0
        columns.append(column)
    return np.array(columns).T


def constrained_least_squares(
    matrix: np.ndarray,
    rhs: np.ndarray,
    penalty: np.ndarray,
    regularization: float,
    constraints: np.ndarray | None = None,
) -> np.ndarray:
    """argmin |M c - b|^2 + lambda |P c|^2 subject to C c = 0, lambda relative (module doc).

    Solved in the null space of C by an SVD-based least-squares solve (robust to directions
    that neither samples nor penalty determine: those get the minimum-norm solution).
    """
    basis = (
        scipy.linalg.null_space(constraints) if constraints is not None else np.eye(matrix.shape[1])
    )
    system, right = _regularized_system(matrix, rhs, penalty, regularization)
    reduced = np.linalg.lstsq(system @ basis, right, rcond=None)[0]
    return basis @ reduced


def _regularized_system(
    matrix: np.ndarray, rhs: np.ndarray, penalty: np.ndarray, regularization: float
) -> tuple[np.ndarray, np.ndarray]:
    """The stacked least-squares system [M; sqrt(lambda) P], [b; 0], lambda relative."""
    penalty_norm = np.linalg.norm(penalty)
    weight = regularization * np.linalg.norm(matrix) ** 2 / penalty_norm**2 if penalty_norm else 0
    system = np.vstack([matrix, math.sqrt(weight) * penalty])
    return system, np.concatenate([rhs, np.zeros(penalty.shape[0])])


def monotone_least_squares(
    matrix: np.ndarray,
    rhs: np.ndarray,
    penalty: np.ndarray,
    regularization: float,
    constraint: np.ndarray,
    *,
    shape: tuple[int, int],
    axis: int,
    min_increments: np.ndarray,
) -> np.ndarray:
    """`constrained_least_squares` with one equality row `constraint` (1, n) and the tensor
    coefficients (shape, raveled C-order) increasing along `axis` by at least
    `min_increments` (shape[axis] - 1,) from one to the next.

    The unknowns become the partial sums' terms d along `axis` (c = T d, T the cumulative
    sum): the first of each line is free, the others (the differences) are bounded below. The
    equality is solved for the free unknown with the largest coefficient in it, and the
    remaining bounded least-squares problem is `_bounded_least_squares`. With no bound active
    the result is that of `constrained_least_squares`.
    """
    cumulative = np.tril(np.ones((shape[axis], shape[axis])))
    eye = np.eye(shape[1 - axis])
    transform = np.kron(cumulative, eye) if axis == 0 else np.kron(eye, cumulative)
    free = (np.indices(shape)[axis] == 0).ravel()
    system, right = _regularized_system(matrix, rhs, penalty, regularization)
    system = system @ transform
    equality = (constraint @ transform).ravel()
    pivot = int(np.flatnonzero(free)[np.argmax(np.abs(equality[free]))])
    rest = np.arange(equality.size) != pivot
    # d[pivot] = -equality[rest] . d[rest] / equality[pivot]
    eliminated = system[:, rest] - np.outer(system[:, pivot], equality[rest] / equality[pivot])
    increments = np.concatenate([[-np.inf], min_increments])
    lower = np.broadcast_to(np.expand_dims(increments, 1 - axis), shape).ravel()[rest]
    solution = _bounded_least_squares(eliminated, right, lower)
    terms = np.empty(equality.size)
    terms[rest] = solution
    terms[pivot] = -equality[rest] @ solution / equality[pivot]
    return transform @ terms


def _bounded_least_squares(matrix: np.ndarray, rhs: np.ndarray, lower: np.ndarray) -> np.ndarray:
    """argmin |M x - b| subject to x >= lower (entries of `lower` may be -inf: free).

    The free unknowns x_F are eliminated (for given bounded ones they are the least-squares
    solution), x_B = lower_B + y leaves a nonnegative least-squares problem in y for the
    projection of M_B onto the complement of range(M_F), solved by Lawson-Hanson
    (scipy.optimize.nnls: an active-set method whose steps are least-squares solves of the
    passive set; far faster than BVLS in Python once hundreds of bounds are active).
    """
    free = np.isneginf(lower)
    bounded = ~free
    shift = rhs - matrix[:, bounded] @ lower[bounded]
    basis = scipy.linalg.orth(matrix[:, free])  # orthonormal basis of range(M_F)
    projected = matrix[:, bounded] - basis @ (basis.T @ matrix[:, bounded])
    y = scipy.optimize.nnls(projected, shift - basis @ (basis.T @ shift), maxiter=50 * lower.size)[
        0
    ]
    x = np.empty(lower.size)
    x[bounded] = lower[bounded] + y
    x[free] = np.linalg.lstsq(matrix[:, free], shift - matrix[:, bounded] @ y, rcond=None)[0]
    return x


def _slope_increments(knots: np.ndarray, degree: int, slope: float) -> np.ndarray:
    """Smallest increments c_k - c_(k-1) (k = 1..n-1) of a spline's coefficients for which
    its derivative is >= slope: that derivative's coefficients are
    degree (c_k - c_(k-1)) / (t_(k+degree) - t_k)."""
    n = knots.size - degree - 1
    k = np.arange(1, n)
    return slope * (knots[k + degree] - knots[k]) / degree


def _check_samples(samples: SurfaceSamples) -> None:
    if samples.biaxial_strain.shape[0] == 0:
        raise InputError("no biaxial samples: every ray failed or none was run")
    if samples.shear_strain.shape[0] == 0:
        raise InputError("no shear samples: the shear run failed or was not run")
    if np.max(np.abs(samples.shear_strain[:, 2])) == 0.0:
        raise InputError("the shear samples have E12 = 0 only")


def _normal_knots(samples: SurfaceSamples, degree: int, options: FitOptions) -> tuple:
    spans = options.spans or _default_spans(samples.biaxial_strain.shape[0])
    return tuple(knot_vector(samples.biaxial_strain[:, a], degree, spans) for a in (0, 1))


def _shear_knots(samples: SurfaceSamples, degree: int, options: FitOptions) -> np.ndarray:
    spans = options.shear_spans or _default_shear_spans(samples.shear_strain.shape[0])
    extent = float(np.max(np.abs(samples.shear_strain[:, 2])))
    return symmetric_knot_vector(extent, degree, spans)


def _residual_samples(samples: SurfaceSamples, s11, s22, s12) -> dict[str, FitSamples]:
    """The samples of each stress group with the residuals of the fitted splines."""
    normal = samples.biaxial_strain[:, :2]
    shear = samples.shear_strain[:, 2:]
    fitted = {
        "S11": (normal, samples.biaxial_stress[:, 0], s11(normal[:, 0], normal[:, 1])),
        "S22": (normal, samples.biaxial_stress[:, 1], s22(normal[:, 0], normal[:, 1])),
        "S12": (shear, samples.shear_stress[:, 2], s12(shear[:, 0])),
    }
    return {
        name: FitSamples(inputs=inputs, values=values, residuals=fit - values)
        for name, (inputs, values, fit) in fitted.items()
    }


def _parameters(options: FitOptions, kind: str) -> dict:
    return {"fit": {"kind": kind, **asdict(options)}}


def fit_stress_surface(
    samples: SurfaceSamples, options: FitOptions = FitOptions()
) -> ResponseSurface:
    """The paper's stress fit (kind "stress"): S11, S22 over (E11, E22) and odd S12(E12)."""
    _check_samples(samples)
    p = options.degree
    knots = _normal_knots(samples, p, options)
    E, S = samples.biaxial_strain, samples.biaxial_stress
    rows = _tensor_rows(_basis(knots[0], p, E[:, 0]), _basis(knots[1], p, E[:, 1]))
    penalty = _tensor_penalty(knots, (p, p))
    origin = _tensor_rows(_basis(knots[0], p, [0.0]), _basis(knots[1], p, [0.0]))
    shape = tuple(t.size - p - 1 for t in knots)
    splines = {}
    for column, name in enumerate(("S11", "S22")):
        if options.monotone:
            slope = np.ptp(S[:, column]) / np.ptp(E[:, column])
            coefficients = monotone_least_squares(
                rows,
                S[:, column],
                penalty,
                options.regularization,
                origin,
                shape=shape,
                axis=column,
                min_increments=_slope_increments(knots[column], p, options.stiffness_floor * slope),
            )
        else:
            coefficients = constrained_least_squares(
                rows, S[:, column], penalty, options.regularization, origin
            )
        splines[name] = Spline2D((p, p), knots, coefficients.reshape(shape))

    shear_knots = _shear_knots(samples, p, options)
    n = shear_knots.size - p - 1
    odd = _parity_map(n, -1.0)
    shear_rows = _basis(shear_knots, p, samples.shear_strain[:, 2])
    shear_penalty = _jump_matrix(shear_knots, p)
    free = constrained_least_squares(
        shear_rows @ odd, samples.shear_stress[:, 2], shear_penalty @ odd, options.regularization
    )
    splines["S12"] = Spline1D(p, shear_knots, odd @ free)
    return ResponseSurface(
        kind="stress",
        s11=splines["S11"],
        s22=splines["S22"],
        s12=splines["S12"],
        samples=_residual_samples(samples, splines["S11"], splines["S22"], splines["S12"]),
        parameters=_parameters(options, "stress"),
    )


def fit_energy_surface(
    samples: SurfaceSamples, options: FitOptions = FitOptions()
) -> ResponseSurface:
    """The energy fit (kind "energy"): potentials whose gradients fit the samples."""
    _check_samples(samples)
    q = options.energy_degree
    knots = _normal_knots(samples, q, options)
    E, S = samples.biaxial_strain, samples.biaxial_stress
    values = [_basis(t, q, E[:, a]) for a, t in enumerate(knots)]
    slopes = [_basis(t, q, E[:, a], 1) for a, t in enumerate(knots)]
    rows = np.vstack([_tensor_rows(slopes[0], values[1]), _tensor_rows(values[0], slopes[1])])
    at_zero = [[_basis(t, q, [0.0], r) for r in (0, 1)] for t in knots]
    constraints = np.vstack(
        [
            _tensor_rows(at_zero[0][0], at_zero[1][0]),
            _tensor_rows(at_zero[0][1], at_zero[1][0]),
            _tensor_rows(at_zero[0][0], at_zero[1][1]),
        ]
    )
    coefficients = constrained_least_squares(
        rows,
        np.concatenate([S[:, 0], S[:, 1]]),
        _tensor_penalty(knots, (q, q)),
        options.regularization,
        constraints,
    )
    shape = tuple(t.size - q - 1 for t in knots)
    psi = Spline2D((q, q), knots, coefficients.reshape(shape), (2, 2))

    shear_knots = _shear_knots(samples, q, options)
    even = _parity_map(shear_knots.size - q - 1, 1.0)
    free = constrained_least_squares(
        _basis(shear_knots, q, samples.shear_strain[:, 2], 1) @ even,
        samples.shear_stress[:, 2],
        _jump_matrix(shear_knots, q) @ even,
        options.regularization,
        _basis(shear_knots, q, [0.0]) @ even,
    )
    psi_shear = Spline1D(q, shear_knots, even @ free, 2)

    surface = energy_surface(psi, psi_shear)
    residuals = _residual_samples(samples, surface.s11, surface.s22, surface.s12)
    return energy_surface(psi, psi_shear, residuals, _parameters(options, "energy"))
