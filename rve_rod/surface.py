"""Response surfaces: B-spline stress laws of the knit, their evaluation and the HDF5 surface file.

This module implements `docs/surface-format.md` (the normative contract between the scales):
`Spline1D` and `Spline2D` with the Taylor extension of each univariate basis outside the
spline's domain, `ResponseSurface` (S11(E11, E22), S22(E11, E22), S12(E12) in N/mm, optionally
derived from a potential), the atomic writer `write_surface` and the checking reader
`read_surface`. It needs only numpy, scipy and h5py (`fabric_dolfinx` imports it): no numba,
no matplotlib, no dolfinx.

Strains are Green-Lagrange in Voigt order (E11, E22, E12) with the tensor shear component E12
(not 2 E12); stresses are second Piola-Kirchhoff membrane stresses per unit undeformed width.
"""

import datetime
import json
import logging
import math
import os
import subprocess
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import h5py
import numpy as np

from rve_rod import __version__
from rve_rod.atomic import atomic_write
from rve_rod.errors import InputError, check_integer
from rve_rod.geometry.bspline import basis_functions, check_knot_vector

logger = logging.getLogger(__name__)

FORMAT = "knit-response-surface"
"""Value of the root attribute `format`."""
VERSION = 1
"""The file version this module writes and reads."""
UNITS = "E: 1 (Green-Lagrange); S: N/mm (per unit undeformed width)"
"""Value of the root attribute `units`."""
STRESS_GROUPS = ("S11", "S22", "S12")
"""The stress groups of every file, in Voigt order."""
EXTENSION_ORDERS = {
    "stress": {"S11": (1, 1), "S22": (1, 1), "S12": (1,)},
    "energy": {"S11": (1, 2), "S22": (2, 1), "S12": (1,), "psi": (2, 2), "psi_shear": (2,)},
}
"""Extension order per input of every group, by fit kind (docs/surface-format.md)."""
GROUP_INPUTS = {
    "S11": ("E11", "E22"),
    "S22": ("E11", "E22"),
    "S12": ("E12",),
    "psi": ("E11", "E22"),
    "psi_shear": ("E12",),
}
"""The strain components each group is a function of."""


class SurfaceFileError(InputError):
    """A surface file cannot be used; the message names the file and the problem."""


def _float_array(array: np.ndarray) -> np.ndarray:
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
        coefficients = _float_array(self.coefficients)
        if coefficients.ndim != 1 or not np.all(np.isfinite(coefficients)):
            raise InputError(f"coefficients must be a finite 1D array, got {coefficients.shape}")
        knots = _check_open_knots(self.knots, self.degree, coefficients.size, "Spline1D")
        object.__setattr__(self, "knots", _float_array(knots))
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
        coefficients = _float_array(self.coefficients)
        if coefficients.ndim != 2 or not np.all(np.isfinite(coefficients)):
            raise InputError(f"coefficients must be a finite 2D array, got {coefficients.shape}")
        knots = tuple(
            _float_array(_check_open_knots(t, p, n, f"Spline2D input {axis + 1}"))
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


class ResidualStats(NamedTuple):
    """Fit quality of one stress group (N/mm, and relative to the largest |sample|).

    Relative values divide by max |sample value| of the group (not point by point, which
    would blow up near the stress-free state).
    """

    max_abs: float
    rms_abs: float
    max_rel: float
    rms_rel: float


@dataclass(frozen=True, eq=False)
class FitSamples:
    """The samples a stress group was fitted to.

    Attributes:
        inputs: (m, d) strains (E11, E22) or (E12,) of each sample.
        values: (m,) sampled stress (N/mm).
        residuals: (m,) fit minus sample (N/mm).
    """

    inputs: np.ndarray
    values: np.ndarray
    residuals: np.ndarray

    def __post_init__(self):
        inputs = _float_array(self.inputs)
        values = _float_array(self.values)
        residuals = _float_array(self.residuals)
        if (
            inputs.ndim != 2
            or values.shape != (inputs.shape[0],)
            or residuals.shape != values.shape
        ):
            raise InputError(
                f"samples need inputs (m, d), values (m,), residuals (m,); got {inputs.shape}, "
                f"{values.shape}, {residuals.shape}"
            )
        object.__setattr__(self, "inputs", inputs)
        object.__setattr__(self, "values", values)
        object.__setattr__(self, "residuals", residuals)

    def stats(self) -> ResidualStats:
        """Max and RMS of the residuals, absolute and relative; NaN without samples."""
        if self.values.size == 0:
            return ResidualStats(math.nan, math.nan, math.nan, math.nan)
        absolute = np.abs(self.residuals)
        scale = float(np.abs(self.values).max())
        max_abs = float(absolute.max())
        rms_abs = float(np.sqrt(np.mean(absolute**2)))
        if scale == 0.0:
            return ResidualStats(max_abs, rms_abs, math.nan, math.nan)
        return ResidualStats(max_abs, rms_abs, max_abs / scale, rms_abs / scale)


class StressResult(NamedTuple):
    """Stress and tangent of a response surface at m strains.

    Attributes:
        S: (m, 3) second Piola-Kirchhoff stress (S11, S22, S12), N/mm.
        tangent: (m, 3, 3) partial derivatives dS_a/dE_b with E = (E11, E22, E12), E12 the
            tensor shear component (N/mm).
        outside: (m,) True where a strain component lies strictly outside the sampled domain
            (the value then comes from the extension).
    """

    S: np.ndarray
    tangent: np.ndarray
    outside: np.ndarray


@dataclass(frozen=True, eq=False)
class ResponseSurface:
    """The homogenized membrane law of a knit: S11(E11, E22), S22(E11, E22), S12(E12).

    Attributes:
        kind: "stress" (each component fitted directly, as the paper) or "energy" (S11, S22
            derived from a potential psi(E11, E22) and S12 from psi_shear(E12)).
        s11, s22: Spline2D over (E11, E22) sharing one domain, N/mm.
        s12: Spline1D over E12, odd, N/mm.
        psi: Spline2D potential (N/mm) for kind "energy", else None.
        psi_shear: Spline1D shear potential (N/mm) for kind "energy", else None; the strain
            energy per undeformed area is W = psi(E11, E22) + 2 psi_shear(E12).
        samples: the data each stress group was fitted to, by group name ("S11", "S22",
            "S12"); groups without samples are written with zero samples.
        parameters: JSON-serializable settings that regenerate the surface (yarn, knit, model,
            sampling, fit).
        created: ISO 8601 time (UTC); empty until written.
        generator: package name, version and git revision; empty until written.
    """

    kind: str
    s11: Spline2D
    s22: Spline2D
    s12: Spline1D
    psi: Spline2D | None = None
    psi_shear: Spline1D | None = None
    samples: Mapping[str, FitSamples] = field(default_factory=dict)
    parameters: Mapping = field(default_factory=dict)
    created: str = ""
    generator: Mapping = field(default_factory=dict)

    def __post_init__(self):
        if self.kind not in EXTENSION_ORDERS:
            raise InputError(f"kind={self.kind!r} must be one of {sorted(EXTENSION_ORDERS)}")
        if (self.psi is None) != (self.kind == "stress") or (
            (self.psi_shear is None) != (self.kind == "stress")
        ):
            raise InputError(f"kind={self.kind!r}: psi and psi_shear are given iff kind is energy")
        for name, spline in self.groups().items():
            expected = EXTENSION_ORDERS[self.kind][name]
            orders = _extension_orders(spline)
            if orders != expected:
                raise InputError(
                    f"group {name}: extension orders {orders}, kind {self.kind} needs {expected}"
                )
        if not np.array_equal(self.s11.domain, self.s22.domain):
            raise InputError(
                f"S11 and S22 must share one domain: {self.s11.domain.tolist()} vs "
                f"{self.s22.domain.tolist()}"
            )
        unknown = set(self.samples) - set(STRESS_GROUPS)
        if unknown:
            raise InputError(f"samples for unknown groups {sorted(unknown)}")
        for name, samples in self.samples.items():
            width = len(GROUP_INPUTS[name])
            if samples.inputs.shape[1] != width:
                raise InputError(f"samples of {name} need {width} input columns")
        if self.kind == "energy":
            self._check_derived()

    def _check_derived(self) -> None:
        """S11, S22, S12 of an energy surface must be the derivatives of psi, psi_shear."""
        pairs = {
            "S11": (self.s11, self.psi.derivative(0)),
            "S22": (self.s22, self.psi.derivative(1)),
            "S12": (self.s12, self.psi_shear.derivative()),
        }
        for name, (stored, derived) in pairs.items():
            scale = max(float(np.abs(derived.coefficients).max()), 1e-300)
            same_knots = all(
                a.shape == b.shape and np.allclose(a, b, rtol=0.0, atol=1e-14)
                for a, b in zip(_knot_list(stored), _knot_list(derived), strict=True)
            )
            if (
                not same_knots
                or stored.coefficients.shape != derived.coefficients.shape
                or np.abs(stored.coefficients - derived.coefficients).max() > 1e-10 * scale
            ):
                raise InputError(f"group {name} is not the derivative of the potential")

    def groups(self) -> dict:
        """The splines by file group name: S11, S22, S12 (and psi, psi_shear for energy)."""
        groups = {"S11": self.s11, "S22": self.s22, "S12": self.s12}
        if self.kind == "energy":
            groups.update(psi=self.psi, psi_shear=self.psi_shear)
        return groups

    @property
    def domain(self) -> np.ndarray:
        """[[E11 min, max], [E22 min, max], [E12 min, max]], shape (3, 2)."""
        return np.vstack([self.s11.domain, self.s12.domain[None, :]])

    def __repr__(self) -> str:
        """A few lines: kind, domain, samples, largest relative residuals, checks (the arrays
        are in the attributes; `rve-rod surface-info` prints everything)."""
        domain = ", ".join(
            f"{label} [{low:.3g}, {high:.3g}]"
            for label, (low, high) in zip(("E11", "E22", "E12"), self.domain, strict=True)
        )
        stats = self.residual_stats()
        samples = sum(self.samples[name].values.size for name in self.samples)
        residuals = ", ".join(f"{name} {stats[name].max_rel:.2g}" for name in STRESS_GROUPS)
        checks = self.parameters.get("checks")
        verdict = "not recorded" if checks is None else "; ".join(checks) or "passed"
        return (
            f"ResponseSurface(kind={self.kind!r}, domain {domain}, {samples} samples, "
            f"max relative residual {residuals}, checks {verdict})"
        )

    def residual_stats(self) -> dict[str, ResidualStats]:
        """ResidualStats per stress group (NaN for groups without samples)."""
        empty = FitSamples(np.zeros((0, 1)), np.zeros(0), np.zeros(0))
        return {name: self.samples.get(name, empty).stats() for name in STRESS_GROUPS}

    def stress(self, E: np.ndarray) -> StressResult:
        """S, dS/dE and the outside flag at Green-Lagrange strains E, shape (m, 3) or (3,).

        Never NaN for finite E: outside the domain the C1 extension applies (flagged).
        """
        E = _check_strains(E)
        E11, E22, E12 = E.T
        d11 = self.s11.derivatives(E11, E22, 1)
        d22 = self.s22.derivatives(E11, E22, 1)
        d12 = self.s12.derivatives(E12, 1)
        S = np.stack([d11[0, 0], d22[0, 0], d12[0]], axis=1)
        tangent = np.zeros((E.shape[0], 3, 3))
        tangent[:, 0, 0], tangent[:, 0, 1] = d11[1, 0], d11[0, 1]
        tangent[:, 1, 0], tangent[:, 1, 1] = d22[1, 0], d22[0, 1]
        tangent[:, 2, 2] = d12[1]
        outside = self.s11.outside(E11, E22) | self.s12.outside(E12)
        return StressResult(S=S, tangent=tangent, outside=outside)

    def energy(self, E: np.ndarray) -> np.ndarray:
        """W = psi(E11, E22) + 2 psi_shear(E12) (N/mm) at E (m, 3); kind "energy" only.

        With this W, S = dW/dE for the symmetric strain tensor (S12 = psi_shear'(E12)).
        """
        if self.kind != "energy":
            raise InputError("energy() needs a surface of kind 'energy'; this one is 'stress'")
        E = _check_strains(E)
        return self.psi(E[:, 0], E[:, 1]) + 2.0 * self.psi_shear(E[:, 2])

    def tangent_asymmetry(self, points_per_axis: int = 41) -> float:
        """max |dS11/dE22 - dS22/dE11| / max ||dS/dE (normal block)||_F on a grid over the domain.

        Zero (to round-off) for energy surfaces; for stress fits it measures how far the
        material is from hyperelastic.
        """
        check_integer("points_per_axis", points_per_axis, 2)
        (x_low, x_high), (y_low, y_high) = self.s11.domain
        x, y = np.meshgrid(
            np.linspace(x_low, x_high, points_per_axis), np.linspace(y_low, y_high, points_per_axis)
        )
        E = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
        tangent = self.stress(E).tangent[:, :2, :2]
        norm = float(np.sqrt((tangent**2).sum(axis=(1, 2))).max())
        if norm == 0.0:
            return 0.0
        return float(np.abs(tangent[:, 0, 1] - tangent[:, 1, 0]).max()) / norm


def energy_surface(
    psi: Spline2D,
    psi_shear: Spline1D,
    samples: Mapping[str, FitSamples] | None = None,
    parameters: Mapping | None = None,
) -> ResponseSurface:
    """The `energy` surface of the potentials psi(E11, E22) and psi_shear(E12) (N/mm).

    psi needs extension orders (2, 2) and psi_shear 2, degrees >= 2 (>= 3 for a C1 stress);
    S11, S22, S12 become their exact derivative splines.
    """
    return ResponseSurface(
        kind="energy",
        s11=psi.derivative(0),
        s22=psi.derivative(1),
        s12=psi_shear.derivative(),
        psi=psi,
        psi_shear=psi_shear,
        samples=dict(samples or {}),
        parameters=dict(parameters or {}),
    )


def _check_strains(E: np.ndarray) -> np.ndarray:
    E = np.asarray(E, dtype=float)
    if E.ndim == 1:
        E = E[None, :]
    if E.ndim != 2 or E.shape[1] != 3:
        raise InputError(f"strains E must have shape (m, 3) or (3,), got {E.shape}")
    if not np.all(np.isfinite(E)):
        raise InputError("strains E must be finite numbers")
    return E


def _knot_list(spline) -> list:
    return [spline.knots] if isinstance(spline, Spline1D) else list(spline.knots)


def _degree_list(spline) -> list:
    return [spline.degree] if isinstance(spline, Spline1D) else list(spline.degrees)


def _extension_orders(spline) -> tuple:
    if isinstance(spline, Spline1D):
        return (spline.extension_order,)
    return tuple(spline.extension_orders)


def generator_info() -> dict:
    """Package name, version and git revision of the source tree (None if not a checkout)."""
    try:
        revision = subprocess.run(
            ["git", "rev-parse", "HEAD"],
            cwd=Path(__file__).parent,
            capture_output=True,
            text=True,
            timeout=5,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        revision = None
    return {"package": "knitmech", "version": __version__, "git_revision": revision or None}


def write_surface(path: str | os.PathLike, surface: ResponseSurface) -> Path:
    """Write `surface` to `path` atomically (temporary file in the same folder, then rename).

    `created` and `generator` are filled in when empty. Returns the final path.
    """
    path = Path(path)
    created = surface.created or datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")
    generator = dict(surface.generator) or generator_info()
    try:
        parameters = json.dumps(surface.parameters, sort_keys=True, allow_nan=False)
    except (TypeError, ValueError) as error:
        raise InputError(f"surface parameters are not JSON-serializable: {error}") from None
    with atomic_write(path) as temporary, h5py.File(temporary, "w") as h5:
        h5.attrs["format"] = FORMAT
        h5.attrs["version"] = VERSION
        h5.attrs["kind"] = surface.kind
        h5.attrs["units"] = UNITS
        h5.attrs["created"] = created
        h5.attrs["generator"] = json.dumps(generator, sort_keys=True)
        h5.attrs["parameters"] = parameters
        for name, spline in surface.groups().items():
            _write_group(h5.create_group(name), name, spline, surface.samples.get(name))
    logger.info("wrote response surface %s (kind %s)", path, surface.kind)
    return path


def _write_group(group: h5py.Group, name: str, spline, samples: FitSamples | None) -> None:
    inputs = GROUP_INPUTS[name]
    group.attrs["inputs"] = list(inputs)
    group.attrs["degree"] = np.array(_degree_list(spline), dtype=np.int64)
    group.attrs["extension_order"] = np.array(_extension_orders(spline), dtype=np.int64)
    for label, knots in zip(inputs, _knot_list(spline), strict=True):
        group.create_dataset(f"knots_{label}", data=knots)
    group.create_dataset("coefficients", data=spline.coefficients)
    domain = spline.domain.reshape(len(inputs), 2)
    group.create_dataset("domain", data=domain)
    if name not in STRESS_GROUPS:
        return
    if samples is None:
        samples = FitSamples(np.zeros((0, len(inputs))), np.zeros(0), np.zeros(0))
    sample_group = group.create_group("samples")
    sample_group.create_dataset("inputs", data=samples.inputs)
    sample_group.create_dataset("values", data=samples.values)
    sample_group.create_dataset("residuals", data=samples.residuals)
    for key, value in samples.stats()._asdict().items():
        group.attrs[f"residual_{key}"] = value


def softest_normal_tangents(surface, points_per_axis: int = 41) -> dict:
    """The smallest dS11/dE11 and dS22/dE22 (N/mm) on a grid over the (E11, E22) domain,
    the strain (E11, E22) where each occurs and the largest of each (`largest`): a negative
    value means the fitted material softens there, where a membrane has no unique
    equilibrium."""
    (x_low, x_high), (y_low, y_high) = surface.domain[:2]
    x, y = np.meshgrid(
        np.linspace(x_low, x_high, points_per_axis), np.linspace(y_low, y_high, points_per_axis)
    )
    strain = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    tangent = surface.stress(strain).tangent
    softest = {}
    for index, name in enumerate(("dS11/dE11", "dS22/dE22")):
        values = tangent[:, index, index]
        at = int(np.argmin(values))
        softest[name] = {
            "value": values[at],
            "strain": strain[at, :2],
            "largest": float(values.max()),
        }
    return softest


def read_surface(path: str | os.PathLike) -> ResponseSurface:
    """Read and check a surface file; SurfaceFileError names the file and the problem.

    Checked: HDF5 and readable (not truncated), format, version, kind, the groups of the kind,
    every member, shapes, knot vectors, extension orders, domains, and for `energy` files that
    the stress groups are the derivatives of the potentials.
    """
    path = Path(path)
    if not path.is_file():
        raise SurfaceFileError(f"{path}: no such file")
    if not h5py.is_hdf5(path):
        raise SurfaceFileError(f"{path}: not an HDF5 file (wrong format or damaged header)")
    try:
        with h5py.File(path, "r") as h5:
            return _read_file(h5, path)
    except SurfaceFileError:
        raise
    except InputError as error:
        raise SurfaceFileError(f"{path}: {error}") from None
    except (OSError, KeyError, ValueError, TypeError, RuntimeError) as error:
        raise SurfaceFileError(
            f"{path}: cannot be read as HDF5 (truncated or corrupt file): {error}"
        ) from None


def _read_file(h5: h5py.File, path: Path) -> ResponseSurface:
    def fail(problem: str):
        raise SurfaceFileError(f"{path}: {problem}")

    if "format" not in h5.attrs:
        fail(f"not a response-surface file (no 'format' attribute; expected {FORMAT!r})")
    file_format = _attribute(h5, "format", path)
    if file_format != FORMAT:
        fail(f"not a response-surface file (format={file_format!r}, expected {FORMAT!r})")
    version = _attribute(h5, "version", path)
    if not isinstance(version, int | np.integer) or int(version) != VERSION:
        fail(f"file version {version!r} is not supported (this reader reads version {VERSION})")
    units = _attribute(h5, "units", path)
    if units != UNITS:
        fail(f"units={units!r}: this reader reads {UNITS!r} only (convert the stresses)")
    kind = _attribute(h5, "kind", path)
    if kind not in EXTENSION_ORDERS:
        fail(f"kind={kind!r} is unknown (expected one of {sorted(EXTENSION_ORDERS)})")
    try:
        parameters = json.loads(_attribute(h5, "parameters", path))
        generator = json.loads(_attribute(h5, "generator", path))
    except (TypeError, json.JSONDecodeError) as error:
        fail(f"attribute parameters or generator is not valid JSON: {error}")
    if not isinstance(parameters, dict) or not isinstance(generator, dict):
        fail("attributes parameters and generator must hold JSON objects")
    created = str(_attribute(h5, "created", path))
    splines, samples = {}, {}
    for name in EXTENSION_ORDERS[kind]:
        if name not in h5 or not isinstance(h5[name], h5py.Group):
            fail(f"missing group {name!r} (required for kind {kind!r})")
        try:
            splines[name], group_samples = _read_group(h5[name], name)
        except InputError as error:
            fail(f"group {name}: {error}")
        if group_samples is not None:
            samples[name] = group_samples
    return ResponseSurface(
        kind=kind,
        s11=splines["S11"],
        s22=splines["S22"],
        s12=splines["S12"],
        psi=splines.get("psi"),
        psi_shear=splines.get("psi_shear"),
        samples=samples,
        parameters=parameters,
        created=created,
        generator=generator,
    )


def _attribute(node, name: str, path: Path):
    if name not in node.attrs:
        where = "root" if node.name == "/" else f"group {node.name.lstrip('/')}"
        raise SurfaceFileError(f"{path}: missing attribute {name!r} of {where}")
    value = node.attrs[name]
    return value.decode() if isinstance(value, bytes) else value


def _member(group: h5py.Group, name: str) -> np.ndarray:
    if name not in group or not isinstance(group[name], h5py.Dataset):
        raise InputError(f"missing member {name!r}")
    return np.asarray(group[name][()], dtype=float)


def _group_attribute(group: h5py.Group, name: str) -> np.ndarray:
    if name not in group.attrs:
        raise InputError(f"missing attribute {name!r}")
    return np.atleast_1d(group.attrs[name])


def _read_group(group: h5py.Group, name: str):
    expected_inputs = GROUP_INPUTS[name]
    inputs = tuple(
        value.decode() if isinstance(value, bytes) else str(value)
        for value in _group_attribute(group, "inputs")
    )
    if inputs != expected_inputs:
        raise InputError(f"inputs {list(inputs)}, expected {list(expected_inputs)}")
    dimension = len(inputs)
    degrees = [int(p) for p in _group_attribute(group, "degree")]
    orders = [int(k) for k in _group_attribute(group, "extension_order")]
    if len(degrees) != dimension or len(orders) != dimension:
        raise InputError(f"degree and extension_order need {dimension} entries")
    knots = [_member(group, f"knots_{label}") for label in inputs]
    coefficients = _member(group, "coefficients")
    shape = tuple(t.size - p - 1 for t, p in zip(knots, degrees, strict=True))
    if coefficients.shape != shape:
        raise InputError(
            f"coefficients have shape {coefficients.shape}; the knot vectors and degrees "
            f"{degrees} need {shape}"
        )
    if dimension == 1:
        spline = Spline1D(degrees[0], knots[0], coefficients, orders[0])
    else:
        spline = Spline2D(tuple(degrees), tuple(knots), coefficients, tuple(orders))
    domain = _member(group, "domain")
    if domain.shape != (dimension, 2) or not np.allclose(
        domain, spline.domain.reshape(dimension, 2), rtol=0.0, atol=1e-14
    ):
        raise InputError(f"domain {domain.tolist()} does not match the knot vectors")
    if name not in STRESS_GROUPS:
        return spline, None
    if "samples" not in group:
        raise InputError("missing member 'samples'")
    sample_group = group["samples"]
    sample_inputs = _member(sample_group, "inputs")
    if sample_inputs.ndim != 2 or sample_inputs.shape[1] != dimension:
        raise InputError(
            f"samples/inputs has shape {sample_inputs.shape}, expected (m, {dimension})"
        )
    samples = FitSamples(
        inputs=sample_inputs,
        values=_member(sample_group, "values"),
        residuals=_member(sample_group, "residuals"),
    )
    for key in ResidualStats._fields:
        _group_attribute(group, f"residual_{key}")
    return spline, (samples if samples.values.size else None)
