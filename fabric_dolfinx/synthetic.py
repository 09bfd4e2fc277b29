"""A synthetic response surface from an analytic stiffening law, until RVE surfaces exist.

Knitted fabrics stiffen sharply in tension (yarns straighten and jam) and barely resist
compression (loops buckle). `StiffeningLaw` is the simplest hyperelastic law with that shape,

    S11 = a1 (exp(b1 E11) - 1) + c E22,   S22 = c E11 + a2 (exp(b2 E22) - 1),
    S12 = g E12 + h E12^3                                      (N/mm),

the derivatives of W = psi(E11, E22) + 2 psi_shear(E12) with
psi = a1 ((exp(b1 E11) - 1) / b1 - E11) + a2 ((exp(b2 E22) - 1) / b2 - E22) + c E11 E22 and
psi_shear = g E12^2 / 2 + h E12^4 / 4. `synthetic_surface` interpolates it by B-splines at
the Greville points and returns an `rve_rod.surface.ResponseSurface` of kind `stress` (the
three stress splines) or `energy` (the two potentials); `write_surface` stores it.
"""

from dataclasses import asdict, dataclass

import numpy as np
import scipy.interpolate

from rve_rod.errors import InputError, check_integer, check_positive
from rve_rod.surface import ResponseSurface, Spline1D, Spline2D, energy_surface


@dataclass(frozen=True)
class StiffeningLaw:
    """Analytic orthotropic stiffening membrane law (docs: module docstring), N/mm.

    The defaults give about 130 gf/cm course-wise and 160 gf/cm wale-wise at E = 0.22
    (20 % engineering strain), the order of the cotton single jersey of the reference data.

    Attributes:
        course_scale: a1 (N/mm); the initial course-wise stiffness is a1 b1.
        course_rate: b1 (-), how fast the course-wise response stiffens.
        wale_scale: a2 (N/mm); the initial wale-wise stiffness is a2 b2.
        wale_rate: b2 (-).
        coupling: c (N/mm), the biaxial coupling dS11/dE22 = dS22/dE11.
        shear_stiffness: g (N/mm), initial dS12/dE12.
        shear_stiffening: h (N/mm), cubic shear term.
    """

    course_scale: float = 0.01
    course_rate: float = 12.0
    wale_scale: float = 0.02
    wale_rate: float = 10.0
    coupling: float = 0.02
    shear_stiffness: float = 0.05
    shear_stiffening: float = 1.0

    def __post_init__(self):
        for name, value in asdict(self).items():
            if name != "coupling":
                check_positive(name, value)
        limit = np.sqrt(self.course_scale * self.course_rate * self.wale_scale * self.wale_rate)
        if not abs(self.coupling) < limit:
            raise InputError(
                f"coupling={self.coupling:.6g} N/mm must satisfy |c| < sqrt(a1 b1 a2 b2) = "
                f"{limit:.6g} N/mm (positive definite at E = 0)"
            )

    def stress(self, E: np.ndarray) -> np.ndarray:
        """(S11, S22, S12) N/mm at E (m, 3) = (E11, E22, E12 tensor shear)."""
        E11, E22, E12 = np.atleast_2d(E).T
        S11 = self.course_scale * np.expm1(self.course_rate * E11) + self.coupling * E22
        S22 = self.coupling * E11 + self.wale_scale * np.expm1(self.wale_rate * E22)
        S12 = self.shear_stiffness * E12 + self.shear_stiffening * E12**3
        return np.stack([S11, S22, S12], axis=1)

    def potential(self, E11: np.ndarray, E22: np.ndarray) -> np.ndarray:
        """psi(E11, E22) N/mm, with dpsi/dE11 = S11 and dpsi/dE22 = S22."""
        a1, b1, a2, b2 = self.course_scale, self.course_rate, self.wale_scale, self.wale_rate
        return (
            a1 * (np.expm1(b1 * E11) / b1 - E11)
            + a2 * (np.expm1(b2 * E22) / b2 - E22)
            + self.coupling * E11 * E22
        )

    def shear_potential(self, E12: np.ndarray) -> np.ndarray:
        """psi_shear(E12) N/mm, with dpsi_shear/dE12 = S12."""
        return self.shear_stiffness * E12**2 / 2 + self.shear_stiffening * E12**4 / 4


def _knots(degree: int, spans: int, low: float, high: float) -> np.ndarray:
    interior = np.linspace(low, high, spans + 1)[1:-1]
    return np.concatenate([np.full(degree + 1, low), interior, np.full(degree + 1, high)])


def _greville(knots: np.ndarray, degree: int) -> np.ndarray:
    n = knots.size - degree - 1
    points = np.array([knots[i + 1 : i + degree + 1].mean() for i in range(n)])
    return np.clip(points, knots[degree], knots[n])  # the mean of equal knots may round off


def _interpolate_1d(function, knots: np.ndarray, degree: int) -> np.ndarray:
    """Coefficients of the spline interpolating `function` at the Greville points."""
    points = _greville(knots, degree)
    matrix = scipy.interpolate.BSpline.design_matrix(points, knots, degree).toarray()
    return np.linalg.solve(matrix, function(points))


def _interpolate_2d(function, knots: np.ndarray, degree: int) -> np.ndarray:
    """Coefficients C (n, n) of the tensor-product interpolant: B C B^T = f(g_i, g_j)."""
    points = _greville(knots, degree)
    matrix = scipy.interpolate.BSpline.design_matrix(points, knots, degree).toarray()
    values = function(points[:, None], points[None, :])
    return np.linalg.solve(matrix, np.linalg.solve(matrix, values).T).T


def synthetic_surface(
    law: StiffeningLaw = StiffeningLaw(),
    kind: str = "stress",
    *,
    degree: int = 2,
    spans: int = 8,
    normal_domain: tuple[float, float] = (-0.1, 0.3),
    shear_limit: float = 0.2,
) -> ResponseSurface:
    """The B-spline interpolant of `law` as a response surface (no samples).

    Args:
        kind: "stress" (S11, S22 degree `degree`, S12 degree max(degree, 3)) or "energy"
            (psi, psi_shear of degree `degree` + 1, S the exact derivative splines).
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
        knots = _knots(degree, spans, low, high)
        shear_degree = max(degree, 3)
        shear_knots = _knots(shear_degree, 2 * spans, -shear_limit, shear_limit)

        def component(index):
            def function(x, y):
                x, y = np.broadcast_arrays(x, y)
                E = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
                return law.stress(E)[:, index].reshape(x.shape)

            return function

        splines = []
        for index in (0, 1):
            coefficients = _interpolate_2d(component(index), knots, degree)
            at_zero = Spline2D((degree, degree), (knots, knots), coefficients)(0.0, 0.0)[0]
            splines.append(Spline2D((degree, degree), (knots, knots), coefficients - at_zero))
        shear = _interpolate_1d(
            lambda x: law.stress(np.stack([0 * x, 0 * x, x], axis=1))[:, 2],
            shear_knots,
            shear_degree,
        )
        return ResponseSurface(
            kind="stress",
            s11=splines[0],
            s22=splines[1],
            s12=Spline1D(shear_degree, shear_knots, shear),
            parameters=parameters,
        )
    if kind == "energy":
        energy_degree = degree + 1
        knots = _knots(energy_degree, spans, low, high)
        greville = _greville(knots, energy_degree)
        coefficients = _interpolate_2d(law.potential, knots, energy_degree)
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
        shear_knots = _knots(shear_degree, 2 * spans, -shear_limit, shear_limit)
        shear = _interpolate_1d(law.shear_potential, shear_knots, shear_degree)
        shear = shear - Spline1D(shear_degree, shear_knots, shear, 2)(0.0)[0]
        psi_shear = Spline1D(shear_degree, shear_knots, shear, 2)
        return energy_surface(psi, psi_shear, parameters=parameters)
    raise InputError(f"kind={kind!r} must be 'stress' or 'energy'")
