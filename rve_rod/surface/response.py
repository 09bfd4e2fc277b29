"""The homogenized membrane law of a knit: `ResponseSurface`, S(E) from three B-splines.

S11(E11, E22), S22(E11, E22) and S12(E12) in N/mm, fitted directly (kind "stress") or derived
from a potential (kind "energy"), with the samples they were fitted to and their residuals.
Strains are Green-Lagrange in Voigt order (E11, E22, E12) with the tensor shear component E12
(not 2 E12); stresses are second Piola-Kirchhoff membrane stresses per unit undeformed width.
"""

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from rve_rod.errors import InputError
from rve_rod.surface.splines import Spline1D, Spline2D, extension_orders, float_array, knot_list

__all__ = [
    "EXTENSION_ORDERS",
    "GROUP_INPUTS",
    "STRESS_GROUPS",
    "FitSamples",
    "ResidualStats",
    "ResponseSurface",
    "StressResult",
    "energy_surface",
]

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
        inputs = float_array(self.inputs)
        values = float_array(self.values)
        residuals = float_array(self.residuals)
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
            orders = extension_orders(spline)
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
                for a, b in zip(knot_list(stored), knot_list(derived), strict=True)
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
