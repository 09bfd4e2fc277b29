"""Test fixture: a synthetic response surface, the analytic membrane law as B-splines.

Knitted fabrics stiffen sharply in tension (yarns straighten and jam) and barely resist
compression (loops buckle). The closed-form law of `rve_rod.homogenize.analytic.AnalyticRve`
has that shape; `synthetic_surface` interpolates it by B-splines at the Greville points and
returns an `rve_rod.surface.ResponseSurface` of kind `stress` (the three stress splines) or
`energy` (the two potentials); `write_surface` stores it. `COTTON_LIKE_LAW` is the parameter
set the membrane's tests and benchmarks use (`benchmarks/bench_membrane.py` imports this file
from tests/). It lives with the tests: it reads `rve_rod` beyond the surface file, which the
library `fabric_dolfinx` must not.
"""

import math
from dataclasses import asdict

import numpy as np

from rve_rod.errors import InputError, check_integer, check_positive
from rve_rod.geometry.bspline import basis_matrix, greville_abscissae, open_knot_vector
from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.surface import ResponseSurface, Spline1D, Spline2D, energy_surface

COTTON_LIKE_LAW = AnalyticRve(
    course_stiffness=0.12,
    course_stiffening=12.0,
    wale_stiffness=0.2,
    wale_stiffening=10.0,
    coupling_11_22=0.02,
    coupling_22_11=0.02,
    shear_stiffness=0.05,
    shear_stiffening_strain=math.sqrt(0.1),
)
"""About 130 gf/cm course-wise and 160 gf/cm wale-wise at E = 0.22 (20 % engineering strain),
the order of the cotton single jersey of the reference data; hyperelastic (equal couplings)."""


def _greville(knots: np.ndarray, degree: int) -> np.ndarray:
    """Greville points clipped to the domain (the mean of equal end knots may round off)."""
    return np.clip(greville_abscissae(knots, degree), knots[0], knots[-1])


def _interpolate_normal(function, knots: np.ndarray, degree: int) -> np.ndarray:
    """Coefficients C (n, n) of the tensor-product interpolant over (E11, E22) of
    `function(E) -> (m,)` at strains E (m, 3) with E12 = 0: B C B^T = f(g_i, g_j)."""
    points = _greville(knots, degree)
    matrix = basis_matrix(knots, degree, points).toarray()
    E11, E22 = np.meshgrid(points, points, indexing="ij")
    strains = np.stack([E11.ravel(), E22.ravel(), np.zeros(E11.size)], axis=1)
    values = function(strains).reshape(E11.shape)
    return np.linalg.solve(matrix, np.linalg.solve(matrix, values).T).T


def _interpolate_shear(function, knots: np.ndarray, degree: int) -> np.ndarray:
    """Coefficients of the spline over E12 interpolating `function(E) -> (m,)` at strains
    E (m, 3) with E11 = E22 = 0, at the Greville points."""
    points = _greville(knots, degree)
    matrix = basis_matrix(knots, degree, points).toarray()
    strains = np.stack([np.zeros(points.size), np.zeros(points.size), points], axis=1)
    return np.linalg.solve(matrix, function(strains))


def synthetic_surface(
    law: AnalyticRve = COTTON_LIKE_LAW,
    kind: str = "stress",
    *,
    degree: int = 2,
    spans: int = 8,
    normal_domain: tuple[float, float] = (-0.1, 0.3),
    shear_limit: float = 0.2,
) -> ResponseSurface:
    """The B-spline interpolant of `law` as a response surface (no samples).

    Args:
        law: the analytic law (`AnalyticRve.stress` and, for `energy`, `AnalyticRve.energy`).
        kind: "stress" (S11, S22 degree `degree`, S12 degree max(degree, 3)) or "energy"
            (psi, psi_shear of degree `degree` + 1, S the exact derivative splines; needs a
            hyperelastic law, coupling_11_22 == coupling_22_11).
        degree: degree of the stress splines (the paper uses 2).
        spans: knot spans per input (uniform).
        normal_domain: [min, max] of E11 and of E22, the domain of S11 and S22.
        shear_limit: the S12 domain is [-shear_limit, shear_limit] (symmetric knots keep the
            interpolant odd).

    S(0) = 0 holds to round-off: the interpolant's value at E = 0 (and for `energy` its
    gradient there) is subtracted, which the partition of unity makes exact.
    """
    check_integer("degree", degree, 1, 5)
    check_integer("spans", spans, 1, 64)
    check_positive("shear_limit", shear_limit)
    low, high = float(normal_domain[0]), float(normal_domain[1])
    if not low < 0.0 < high:
        raise InputError(f"normal_domain={normal_domain} must contain E = 0 in its interior")
    parameters = {"synthetic_law": asdict(law), "degree": degree, "spans": spans}
    if kind == "stress":
        knots = open_knot_vector(degree, degree + spans, (low, high))
        shear_degree = max(degree, 3)
        shear_knots = open_knot_vector(
            shear_degree, shear_degree + 2 * spans, (-shear_limit, shear_limit)
        )
        splines = []
        for index in (0, 1):
            coefficients = _interpolate_normal(
                lambda E, index=index: law.stress(E)[:, index], knots, degree
            )
            at_zero = Spline2D((degree, degree), (knots, knots), coefficients)(0.0, 0.0)[0]
            splines.append(Spline2D((degree, degree), (knots, knots), coefficients - at_zero))
        shear = _interpolate_shear(lambda E: law.stress(E)[:, 2], shear_knots, shear_degree)
        return ResponseSurface(
            kind="stress",
            s11=splines[0],
            s22=splines[1],
            s12=Spline1D(shear_degree, shear_knots, shear),
            parameters=parameters,
        )
    if kind == "energy":
        if law.coupling_11_22 != law.coupling_22_11:
            raise InputError(
                f"kind='energy' needs a hyperelastic law: coupling_11_22={law.coupling_11_22:g} "
                f"N/mm must equal coupling_22_11={law.coupling_22_11:g} N/mm"
            )
        energy_degree = degree + 1
        knots = open_knot_vector(energy_degree, energy_degree + spans, (low, high))
        greville = _greville(knots, energy_degree)
        # W = psi(E11, E22) + 2 psi_shear(E12) (tensor shear): dpsi_shear/dE12 = S12.
        coefficients = _interpolate_normal(law.energy, knots, energy_degree)
        psi = Spline2D((energy_degree,) * 2, (knots, knots), coefficients, (2, 2))
        # Remove psi(0) + grad psi(0) . E: linear functions have Greville coefficients.
        value = psi.derivatives(0.0, 0.0, 1)[:, :, 0]
        coefficients = (
            coefficients
            - value[0, 0]
            - value[1, 0] * greville[:, None]
            - value[0, 1] * greville[None, :]
        )
        psi = Spline2D((energy_degree,) * 2, (knots, knots), coefficients, (2, 2))
        shear_degree = max(energy_degree, 4)
        shear_knots = open_knot_vector(
            shear_degree, shear_degree + 2 * spans, (-shear_limit, shear_limit)
        )
        shear = _interpolate_shear(lambda E: 0.5 * law.energy(E), shear_knots, shear_degree)
        shear = shear - Spline1D(shear_degree, shear_knots, shear, 2)(0.0)[0]
        psi_shear = Spline1D(shear_degree, shear_knots, shear, 2)
        return energy_surface(psi, psi_shear, parameters=parameters)
    raise InputError(f"kind={kind!r} must be 'stress' or 'energy'")


DOMAIN = (-0.1, 0.3)
"""The strain domain of `quadratic_in` and `two_quadratics_surface`."""


def quadratic_in(axis, value, slope, curvature):
    """Spline2D of f = value + slope t + curvature t^2 / 2 in input `axis` (t = E11 or E22),
    constant in the other: one Bezier span of degree 2 times degree 1."""
    low, high = DOMAIN
    f = lambda t: value + slope * t + curvature * t**2 / 2  # noqa: E731
    df = slope + curvature * low
    bezier = np.array([f(low), f(low) + df * (high - low) / 2, f(high)])
    coefficients = np.repeat(bezier[:, None], 2, axis=1)
    if axis == 1:
        coefficients = coefficients.T
    knots = {2: np.array([low] * 3 + [high] * 3), 1: np.array([low] * 2 + [high] * 2)}
    degrees = (2, 1) if axis == 0 else (1, 2)
    return Spline2D(degrees, tuple(knots[p] for p in degrees), coefficients, (1, 1))


def two_quadratics_surface(curvature_22):
    """A stress surface with S11 quadratic in E11 (dS11/dE11 = 0.5 + 4 E11), S22 quadratic in
    E22 (dS22/dE22 = 0.2 + curvature_22 E22) and a linear S12: its softest normal stiffness is
    known in closed form."""
    shear = Spline1D(1, np.array([-0.2, -0.2, 0.2, 0.2]), np.array([-0.02, 0.02]), 1)
    return ResponseSurface(
        kind="stress",
        s11=quadratic_in(0, 0.0, 0.5, 4.0),  # dS11/dE11 = 0.5 + 4 E11: softest at E11 = -0.1
        s22=quadratic_in(1, 0.0, 0.2, curvature_22),  # dS22/dE22 = 0.2 + k E22
        s12=shear,
    )
