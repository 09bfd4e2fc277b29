"""B-splines of the response surface with the C1 (Taylor) extension of each univariate basis.

`Spline1D` and `Spline2D` evaluate a clamped B-spline and its derivatives; outside the spline's
domain each basis function continues as its Taylor polynomial of the group's extension order
at the nearest end (docs/surface-format.md), so a surface never returns NaN for finite strains.
"""

from dataclasses import dataclass

import numpy as np

from rve_rod.errors import InputError, check_integer
from rve_rod.geometry.bspline import basis_functions, check_knot_vector

__all__ = [
    "Spline1D",
    "Spline2D",
    "degree_list",
    "extension_orders",
    "float_array",
    "knot_list",
]


def float_array(array: np.ndarray) -> np.ndarray:
    return np.array(array, dtype=float)


def _check_open_knots(knots: np.ndarray, degree: int, n: int, name: str) -> np.ndarray:
    knots = check_knot_vector(knots, degree, n)
    if np.any(knots[: degree + 1] != knots[0]) or np.any(knots[-degree - 1 :] != knots[-1]):
        raise InputError(
            f"{name}: knot vector must be open (first and last knot repeated degree+1 = "
            f"{degree + 1} times)"
        )
    return knots


def _check_extension_order(name: str, order: int) -> int:
    return check_integer(f"{name} extension order", order, 0, 2)


def _extended_basis(
    knots: np.ndarray, degree: int, extension_order: int, x: np.ndarray, order: int
) -> tuple[np.ndarray, np.ndarray]:
    """Extended basis functions N_i^ext and their derivatives at x (docs/surface-format.md).

    Returns (spans (m,), values (order+1, m, degree+1)) where values[r, j, a] is the r-th
    derivative of N^ext_{spans[j]-degree+a} at x_j. Outside [t_p, t_n] each function is its
    Taylor polynomial of order k = `extension_order` at the nearest end, so derivatives above k
    vanish there.
    """
    low, high = knots[degree], knots[-degree - 1]
    clamped = np.clip(x, low, high)
    step = x - clamped
    outside = step != 0.0
    k = extension_order
    basis = basis_functions(knots, degree, clamped, max(order, k))
    values = np.empty((order + 1, x.size, degree + 1))
    for r in range(order + 1):
        if r > k:
            values[r] = np.where(outside[:, None], 0.0, basis.values[r])
            continue
        # sum_{j=r..k} N^(j)(c) d^(j-r) / (j-r)!, exact also inside where d = 0
        taylor = basis.values[k].copy()
        for j in range(k - 1, r - 1, -1):
            taylor = basis.values[j] + taylor * (step[:, None] / (j - r + 1))
        values[r] = taylor
    return basis.spans, values


def _derivative_coefficients(knots: np.ndarray, degree: int, coefficients: np.ndarray, axis: int):
    """Coefficients of the derivative spline along `axis` (degree p-1 on knots[1:-1])."""
    n = knots.size - degree - 1
    width = knots[degree + 1 : n + degree] - knots[1:n]
    factor = np.divide(degree, width, out=np.zeros_like(width), where=width > 0)
    difference = np.diff(coefficients, axis=axis)
    shape = [1] * coefficients.ndim
    shape[axis] = n - 1
    return difference * factor.reshape(shape)


@dataclass(frozen=True, eq=False)
class Spline1D:
    """A univariate B-spline f(x) = sum_i c_i N_i^ext(x) with Taylor extension outside.

    Attributes:
        degree: p >= 1.
        knots: (n + p + 1,) open knot vector; the domain is [t_p, t_n].
        coefficients: (n,) coefficients c_i (N/mm for stresses and potentials).
        extension_order: k in {0, 1, 2}, order of the Taylor extension of every basis function
            at the nearest domain end (the file uses 1 or 2; 0 arises for derivatives of k = 1).
    """

    degree: int
    knots: np.ndarray
    coefficients: np.ndarray
    extension_order: int = 1

    def __post_init__(self):
        check_integer("degree", self.degree, 1)
        coefficients = float_array(self.coefficients)
        if coefficients.ndim != 1 or not np.all(np.isfinite(coefficients)):
            raise InputError(f"coefficients must be a finite 1D array, got {coefficients.shape}")
        knots = _check_open_knots(self.knots, self.degree, coefficients.size, "Spline1D")
        object.__setattr__(self, "knots", float_array(knots))
        object.__setattr__(self, "coefficients", coefficients)
        _check_extension_order("Spline1D", self.extension_order)

    @property
    def domain(self) -> np.ndarray:
        """[t_p, t_n], shape (2,)."""
        return np.array([self.knots[self.degree], self.knots[-self.degree - 1]])

    def outside(self, x: np.ndarray) -> np.ndarray:
        """(m,) bool: x lies strictly outside the domain."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        low, high = self.domain
        return (x < low) | (x > high)

    def derivatives(self, x: np.ndarray, order: int = 1) -> np.ndarray:
        """f and its derivatives at x (m,): shape (order+1, m), [r] = d^r f / dx^r."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        spans, values = _extended_basis(self.knots, self.degree, self.extension_order, x, order)
        index = spans[:, None] - self.degree + np.arange(self.degree + 1)
        return np.einsum("rma,ma->rm", values, self.coefficients[index])

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """f(x), shape (m,)."""
        return self.derivatives(x, 0)[0]

    def derivative(self) -> "Spline1D":
        """The exact derivative f' (degree p-1, knots t[1:-1], extension order k-1)."""
        check_integer("degree of the spline to differentiate", self.degree, 2)
        coefficients = _derivative_coefficients(self.knots, self.degree, self.coefficients, 0)
        return Spline1D(
            self.degree - 1, self.knots[1:-1], coefficients, max(self.extension_order - 1, 0)
        )


@dataclass(frozen=True, eq=False)
class Spline2D:
    """A tensor-product B-spline f(x, y) = sum_ij c_ij N_i^ext(x) M_j^ext(y).

    Attributes:
        degrees: (p1, p2), degree per input.
        knots: (knots along x, knots along y), each an open knot vector.
        coefficients: (n1, n2) coefficients c_ij (N/mm).
        extension_orders: (k1, k2), Taylor extension order per input (see Spline1D).
    """

    degrees: tuple[int, int]
    knots: tuple[np.ndarray, np.ndarray]
    coefficients: np.ndarray
    extension_orders: tuple[int, int] = (1, 1)

    def __post_init__(self):
        if len(self.degrees) != 2 or len(self.knots) != 2 or len(self.extension_orders) != 2:
            raise InputError("Spline2D needs two degrees, two knot vectors, two extension orders")
        degrees = tuple(check_integer("degree", p, 1) for p in self.degrees)
        coefficients = float_array(self.coefficients)
        if coefficients.ndim != 2 or not np.all(np.isfinite(coefficients)):
            raise InputError(f"coefficients must be a finite 2D array, got {coefficients.shape}")
        knots = tuple(
            float_array(_check_open_knots(t, p, n, f"Spline2D input {axis + 1}"))
            for axis, (t, p, n) in enumerate(
                zip(self.knots, degrees, coefficients.shape, strict=True)
            )
        )
        orders = tuple(_check_extension_order("Spline2D", k) for k in self.extension_orders)
        object.__setattr__(self, "degrees", degrees)
        object.__setattr__(self, "knots", knots)
        object.__setattr__(self, "coefficients", coefficients)
        object.__setattr__(self, "extension_orders", orders)

    @property
    def domain(self) -> np.ndarray:
        """[[x_min, x_max], [y_min, y_max]], shape (2, 2)."""
        return np.array([[t[p], t[-p - 1]] for t, p in zip(self.knots, self.degrees, strict=True)])

    def outside(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """(m,) bool: x or y lies strictly outside its domain."""
        (x_low, x_high), (y_low, y_high) = self.domain
        x = np.atleast_1d(np.asarray(x, dtype=float))
        y = np.atleast_1d(np.asarray(y, dtype=float))
        return (x < x_low) | (x > x_high) | (y < y_low) | (y > y_high)

    def derivatives(self, x: np.ndarray, y: np.ndarray, order: int = 1) -> np.ndarray:
        """f and its partial derivatives at m points: shape (order+1, order+1, m).

        [i, j] = d^(i+j) f / dx^i dy^j (all i, j <= order, including mixed ones).
        """
        x = np.atleast_1d(np.asarray(x, dtype=float))
        y = np.atleast_1d(np.asarray(y, dtype=float))
        if x.shape != y.shape or x.ndim != 1:
            raise InputError(f"x and y must be 1D of equal length, got {x.shape} and {y.shape}")
        (p, q), (k1, k2) = self.degrees, self.extension_orders
        spans_x, basis_x = _extended_basis(self.knots[0], p, k1, x, order)
        spans_y, basis_y = _extended_basis(self.knots[1], q, k2, y, order)
        rows = spans_x[:, None] - p + np.arange(p + 1)
        columns = spans_y[:, None] - q + np.arange(q + 1)
        local = self.coefficients[rows[:, :, None], columns[:, None, :]]  # (m, p+1, q+1)
        return np.einsum("ima,mab,jmb->ijm", basis_x, local, basis_y)

    def __call__(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """f(x, y), shape (m,)."""
        return self.derivatives(x, y, 0)[0, 0]

    def derivative(self, axis: int) -> "Spline2D":
        """The exact partial derivative along `axis` (0: x, 1: y) as a Spline2D."""
        check_integer("axis", axis, 0, 1)
        check_integer("degree of the spline to differentiate", self.degrees[axis], 2)
        coefficients = _derivative_coefficients(
            self.knots[axis], self.degrees[axis], self.coefficients, axis
        )
        degrees, knots, orders = list(self.degrees), list(self.knots), list(self.extension_orders)
        degrees[axis] -= 1
        knots[axis] = knots[axis][1:-1]
        orders[axis] = max(orders[axis] - 1, 0)
        return Spline2D(tuple(degrees), tuple(knots), coefficients, tuple(orders))


def knot_list(spline) -> list:
    return [spline.knots] if isinstance(spline, Spline1D) else list(spline.knots)


def degree_list(spline) -> list:
    return [spline.degree] if isinstance(spline, Spline1D) else list(spline.degrees)


def extension_orders(spline) -> tuple:
    if isinstance(spline, Spline1D):
        return (spline.extension_order,)
    return tuple(spline.extension_orders)
