"""Membrane material laws as UFL expressions of the Green-Lagrange strain.

Two laws, each a plain function `E -> S` in the material frame (axis 1 course-wise, axis 2
wale-wise): the response-surface law of `docs/surface-format.md` (B-spline factors written as
piecewise polynomials with `ufl.conditional`, extended outside the sampled domain by their
Taylor polynomials) and an orthotropic Saint Venant-Kirchhoff law for tests and comparisons.
The membrane (`fabric_dolfinx.membrane.forms`) gives a law the strain in the material frame.
Strains are dimensionless (tensor shear E12), stresses N/mm (force per unit undeformed
width). No tangent is written here: the membrane derives it with `ufl.diff`.
"""

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.interpolate
import ufl

from rve_rod.errors import check_integer, check_positive, check_range
from rve_rod.surface import ResponseSurface, Spline1D, Spline2D

__all__ = [
    "Material",
    "OrthotropicSVK",
    "PiecewiseBasis",
    "StressLaw",
    "piecewise_basis",
    "spline_1d",
    "spline_2d",
    "surface_material",
    "surface_stress",
    "svk_material",
    "svk_stress",
]

StressLaw = Callable[[ufl.core.expr.Expr], ufl.core.expr.Expr]
"""A material law: Green-Lagrange strain (2, 2) -> second Piola-Kirchhoff stress (2, 2) N/mm,
both UFL expressions in the material frame."""


@dataclass(frozen=True)
class OrthotropicSVK:
    """Orthotropic Saint Venant-Kirchhoff membrane: S = C : E in the material frame.

    Plane stress: S11 = Q11 E11 + Q12 E22, S22 = Q12 E11 + Q22 E22, S12 = 2 G12 E12 with
    Q11 = E1 / (1 - nu12 nu21), Q22 = E2 / (1 - nu12 nu21), Q12 = nu12 Q22 and
    nu21 = nu12 E2 / E1 (Maxwell-Betti symmetry).

    Attributes:
        course_stiffness: E1, membrane Young's modulus along axis 1 (course-wise), N/mm.
        wale_stiffness: E2, membrane Young's modulus along axis 2 (wale-wise), N/mm.
        poissons_ratio: nu12, contraction along 2 under tension along 1 (-), nu12^2 < E1/E2.
        shear_stiffness: G12, membrane shear modulus, N/mm.
    """

    course_stiffness: float = 1.0
    wale_stiffness: float = 0.5
    poissons_ratio: float = 0.3
    shear_stiffness: float = 0.2

    def __post_init__(self):
        check_positive("course_stiffness", self.course_stiffness, "N/mm")
        check_positive("wale_stiffness", self.wale_stiffness, "N/mm")
        check_positive("shear_stiffness", self.shear_stiffness, "N/mm")
        limit = float(np.sqrt(self.course_stiffness / self.wale_stiffness))
        check_range("poissons_ratio", self.poissons_ratio, -limit, limit, closed=False)

    def plane_stress_matrix(self) -> np.ndarray:
        """The (3, 3) matrix C with (S11, S22, S12) = C (E11, E22, E12), N/mm (tensor shear)."""
        nu21 = self.poissons_ratio * self.wale_stiffness / self.course_stiffness
        denominator = 1.0 - self.poissons_ratio * nu21
        q11 = self.course_stiffness / denominator
        q22 = self.wale_stiffness / denominator
        q12 = self.poissons_ratio * q22
        return np.array([[q11, q12, 0.0], [q12, q22, 0.0], [0.0, 0.0, 2.0 * self.shear_stiffness]])


def svk_stress(E: ufl.core.expr.Expr, material: OrthotropicSVK) -> ufl.core.expr.Expr:
    """S (2, 2) N/mm of the orthotropic Saint Venant-Kirchhoff law at E (2, 2), material frame."""
    C = material.plane_stress_matrix()
    S11 = C[0, 0] * E[0, 0] + C[0, 1] * E[1, 1]
    S22 = C[1, 0] * E[0, 0] + C[1, 1] * E[1, 1]
    S12 = C[2, 2] * E[0, 1]
    return ufl.as_matrix([[S11, S12], [S12, S22]])


class PiecewiseBasis(NamedTuple):
    """The extended B-spline basis of one input direction as piecewise polynomials.

    Piece 0 is (-inf, breakpoints[0]) (the extension below the domain), piece j is
    [breakpoints[j-1], breakpoints[j]) and the last piece [breakpoints[-1], inf) (the extension
    above). On piece j, basis function i is sum_m coefficients[i, j, m] (x - origins[j])^m.

    Attributes:
        breakpoints: (s - 1,) distinct knots of the domain [a, ..., b].
        origins: (s,) expansion point of each piece (a for the lower extension).
        coefficients: (n, s, p + 1) power-basis coefficients of the n basis functions.
    """

    breakpoints: np.ndarray
    origins: np.ndarray
    coefficients: np.ndarray


def piecewise_basis(knots: np.ndarray, degree: int, extension_order: int) -> PiecewiseBasis:
    """Power-basis form of the extended basis N_i^ext of `docs/surface-format.md`.

    Inside a knot span the coefficients are the Taylor coefficients N_i^(m)(t_j+) / m! at the
    span's left knot (exact: N_i is a polynomial of degree p there). Outside [a, b] they are
    the Taylor coefficients at the nearest end, truncated after order `extension_order`.
    """
    knots = np.asarray(knots, dtype=float)
    check_integer("extension_order", extension_order, 0, 2)
    n = knots.size - degree - 1
    low, high = knots[degree], knots[n]
    distinct = np.unique(knots)
    breakpoints = distinct[(distinct >= low) & (distinct <= high)]
    # scipy's BSpline evaluates at a knot from the span to its right (and at b from the last
    # span), which is exactly the one-sided limit each piece needs.
    basis = scipy.interpolate.BSpline(knots, np.eye(n), degree, extrapolate=False)
    origins = np.concatenate([[low], breakpoints[:-1], [high]])
    orders = [extension_order] + [degree] * (breakpoints.size - 1) + [extension_order]
    coefficients = np.zeros((n, origins.size, degree + 1))
    factorial = 1.0
    for m in range(degree + 1):
        factorial *= max(m, 1)
        values = np.stack([basis(x, nu=m) for x in origins], axis=1) / factorial
        for piece, order in enumerate(orders):
            if m <= order:
                coefficients[:, piece, m] = values[:, piece]
    return PiecewiseBasis(breakpoints=breakpoints, origins=origins, coefficients=coefficients)


def _polynomial(coefficients: np.ndarray, offset: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
    """Horner evaluation of sum_m coefficients[m] offset^m (trailing zeros dropped)."""
    nonzero = np.flatnonzero(coefficients)
    if nonzero.size == 0:
        return ufl.as_ufl(0.0)
    result = ufl.as_ufl(float(coefficients[nonzero[-1]]))
    for m in range(nonzero[-1] - 1, -1, -1):
        result = result * offset + float(coefficients[m]) if coefficients[m] else result * offset
    return result


def _piecewise(basis: PiecewiseBasis, index: int, x: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
    """Basis function `index` of `basis` at x: nested conditionals over its nonzero pieces."""
    pieces = basis.coefficients[index]
    nonzero = np.flatnonzero(np.any(pieces != 0.0, axis=1))
    first, last = nonzero[0], nonzero[-1]
    result = _polynomial(pieces[last], x - basis.origins[last])
    for piece in range(last - 1, first - 1, -1):
        value = _polynomial(pieces[piece], x - basis.origins[piece])
        result = ufl.conditional(ufl.lt(x, basis.breakpoints[piece]), value, result)
    if first > 0:
        result = ufl.conditional(ufl.lt(x, basis.breakpoints[first - 1]), 0.0, result)
    if last < pieces.shape[0] - 1:
        result = ufl.conditional(ufl.lt(x, basis.breakpoints[last]), result, 0.0)
    return result


def spline_1d(spline: Spline1D, x: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
    """f(x) = sum_i c_i N_i^ext(x) of a `Spline1D` as a UFL expression of the scalar x."""
    basis = piecewise_basis(spline.knots, spline.degree, spline.extension_order)
    terms = [
        float(c) * _piecewise(basis, i, x) for i, c in enumerate(spline.coefficients) if c != 0.0
    ]
    return sum(terms[1:], terms[0]) if terms else ufl.as_ufl(0.0)


def spline_2d(spline: Spline2D, x: ufl.core.expr.Expr, y: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
    """f(x, y) = sum_ij c_ij N_i^ext(x) M_j^ext(y) of a `Spline2D` as a UFL expression.

    Evaluated as sum_i N_i(x) (sum_j c_ij M_j(y)): n_x + n_y piecewise basis functions and
    n_x n_y products, instead of one bivariate polynomial per pair of knot spans.
    """
    basis_x = piecewise_basis(spline.knots[0], spline.degrees[0], spline.extension_orders[0])
    basis_y = piecewise_basis(spline.knots[1], spline.degrees[1], spline.extension_orders[1])
    columns = [_piecewise(basis_y, j, y) for j in range(spline.coefficients.shape[1])]
    terms = []
    for i, row in enumerate(spline.coefficients):
        inner = [float(c) * columns[j] for j, c in enumerate(row) if c != 0.0]
        if inner:
            terms.append(_piecewise(basis_x, i, x) * sum(inner[1:], inner[0]))
    return sum(terms[1:], terms[0]) if terms else ufl.as_ufl(0.0)


def surface_stress(E: ufl.core.expr.Expr, surface: ResponseSurface) -> ufl.core.expr.Expr:
    """S (2, 2) N/mm of the response-surface law at E (2, 2), material frame.

    S11 = f_S11(E11, E22), S22 = f_S22(E11, E22), S12 = f_S12(E12) (docs/surface-format.md);
    `stress` and `energy` surfaces alike (an energy surface stores its S groups).
    """
    S11 = spline_2d(surface.s11, E[0, 0], E[1, 1])
    S22 = spline_2d(surface.s22, E[0, 0], E[1, 1])
    S12 = spline_1d(surface.s12, E[0, 1])
    return ufl.as_matrix([[S11, S12], [S12, S22]])


class Material(NamedTuple):
    """A membrane material ready for the solvers.

    Attributes:
        law: the stress law E -> S in the material frame (UFL).
        domain: (3, 2) [min, max] of E11, E22, E12 where the law rests on data (a response
            surface's sampled domain; outside it the extension applies), or None.
        name: a label for output.
    """

    law: StressLaw
    domain: np.ndarray | None
    name: str


def surface_material(surface: ResponseSurface, name: str = "response surface") -> Material:
    """The response-surface law of `surface` with its domain."""
    return Material(lambda E: surface_stress(E, surface), surface.domain, name)


def svk_material(material: OrthotropicSVK, name: str = "orthotropic SVK") -> Material:
    """The orthotropic Saint Venant-Kirchhoff law (valid everywhere: no domain)."""
    return Material(lambda E: svk_stress(E, material), None, name)
