"""An analytic stand-in for the RVE: a closed-form membrane law followed along the load paths.

It implements the RVE engine interface (`run(case) -> RveRun`) so that sampling, fitting,
caching and parallel generation can be tested and benchmarked before (and independently of)
the rod RVE. It is NOT a model of a knit; its law only mimics the features the fits must
handle: stiffening in tension, softening in compression, biaxial coupling, nonlinear shear.
The same law, interpolated by B-splines, is the membrane's material until RVE surfaces exist
(`tests/support/surface_cases.py`).

    S11 = k1 (exp(b1 E11) - 1) / b1 + c12 E22
    S22 = k2 (exp(b2 E22) - 1) / b2 + c21 E11
    S12 = kg (E12 + 2 E12^3 / eg^2)

(N/mm). With c12 = c21 it derives from the energy
W = k1 (exp(b1 E11) - 1 - b1 E11) / b1^2 + k2 (...) / b2^2 + c E11 E22 + kg (E12^2 + E12^4 / eg^2);
otherwise dS11/dE22 != dS22/dE11 and no energy exists.
"""

import math
from dataclasses import dataclass

import numpy as np

from rve_rod.errors import ConvergenceError, InputError, check_finite, check_positive
from rve_rod.homogenize.samples import RveCase, RveRun
from rve_rod.stress_measures import green_lagrange, voigt

__all__ = [
    "AnalyticRve",
]


@dataclass(frozen=True)
class AnalyticRve:
    """The analytic law above, evaluated along a case's load path (cheap, exact).

    Attributes:
        course_stiffness: k1, initial course-wise stiffness (N/mm).
        course_stiffening: b1, exponential stiffening rate (-).
        wale_stiffness: k2 (N/mm).
        wale_stiffening: b2 (-).
        coupling_11_22: c12 = dS11/dE22 (N/mm).
        coupling_22_11: c21 = dS22/dE11 (N/mm); equal to c12 for a hyperelastic law. The
            tangent at E = 0 must be positive definite: |c12 + c21| / 2 < sqrt(k1 k2).
        shear_stiffness: kg (N/mm).
        shear_stiffening_strain: eg, strain scale of the cubic shear stiffening (-): the shear
            tangent is kg (1 + 6 E12^2 / eg^2).
        compression_limit: if set, the "cell" stops (ConvergenceError with the converged steps)
            once an engineering strain component falls below -compression_limit, to emulate
            an RVE that cannot follow a path to its end.
    """

    course_stiffness: float = 0.2
    course_stiffening: float = 8.0
    wale_stiffness: float = 0.5
    wale_stiffening: float = 10.0
    coupling_11_22: float = 0.05
    coupling_22_11: float = 0.05
    shear_stiffness: float = 0.05
    shear_stiffening_strain: float = 0.2
    compression_limit: float | None = None

    def __post_init__(self):
        positive = (
            "course_stiffness",
            "course_stiffening",
            "wale_stiffness",
            "wale_stiffening",
            "shear_stiffness",
            "shear_stiffening_strain",
        )
        for name in positive:
            check_positive(name, getattr(self, name))
        check_finite("coupling_11_22", self.coupling_11_22)
        check_finite("coupling_22_11", self.coupling_22_11)
        coupling = 0.5 * (self.coupling_11_22 + self.coupling_22_11)
        limit = math.sqrt(self.course_stiffness * self.wale_stiffness)
        if not abs(coupling) < limit:
            raise InputError(
                f"coupling (c12 + c21)/2={coupling:.6g} N/mm must satisfy |.| < sqrt(k1 k2) = "
                f"{limit:.6g} N/mm (a positive definite tangent at E = 0)"
            )
        if self.compression_limit is not None:
            check_positive("compression_limit", self.compression_limit)

    def stress(self, E: np.ndarray) -> np.ndarray:
        """S (m, 3) in N/mm at Green-Lagrange strains E (m, 3), Voigt with tensor shear."""
        E11, E22, E12 = np.asarray(E, dtype=float).T
        k1, b1 = self.course_stiffness, self.course_stiffening
        k2, b2 = self.wale_stiffness, self.wale_stiffening
        S11 = k1 * np.expm1(b1 * E11) / b1 + self.coupling_11_22 * E22
        S22 = k2 * np.expm1(b2 * E22) / b2 + self.coupling_22_11 * E11
        S12 = self.shear_stiffness * (E12 + 2.0 * E12**3 / self.shear_stiffening_strain**2)
        return np.stack([S11, S22, S12], axis=1)

    def energy(self, E: np.ndarray) -> np.ndarray:
        """W (m,) in N/mm at E (m, 3); only a potential of `stress` when coupling_11_22 ==
        coupling_22_11: then dW/dE11 = S11, dW/dE22 = S22 and dW/dE12 = 2 S12 (tensor shear)."""
        E11, E22, E12 = np.asarray(E, dtype=float).T
        k1, b1 = self.course_stiffness, self.course_stiffening
        k2, b2 = self.wale_stiffness, self.wale_stiffening
        return (
            k1 * (np.expm1(b1 * E11) - b1 * E11) / b1**2
            + k2 * (np.expm1(b2 * E22) - b2 * E22) / b2**2
            + self.coupling_11_22 * E11 * E22
            + self.shear_stiffness * (E12**2 + E12**4 / self.shear_stiffening_strain**2)
        )

    def __call__(self, case: RveCase) -> RveRun:
        """Follow the load path of `case`: F prescribed (a uniaxial path's stretch across from
        S = 0 across), P = F S(E)."""
        F = case.load.deformation_gradients()
        if case.load.kind == "uniaxial":
            F = self._free_across(F, 0 if case.load.angle_deg == 0.0 else 1)
        S = self.stress(voigt(green_lagrange(F)))
        S_tensor = np.stack([S[:, [0, 2]], S[:, [2, 1]]], axis=1)
        run = RveRun(F, F @ S_tensor)
        if self.compression_limit is None:
            return run
        supported = np.all(np.diagonal(F, axis1=1, axis2=2) - 1.0 >= -self.compression_limit, 1)
        if supported.all():
            return run
        converged = int(np.argmin(supported))
        partial = RveRun(F[:converged], run.first_piola[:converged], complete=False)
        raise ConvergenceError(
            f"analytic cell stops below {-self.compression_limit} compression", history=partial
        )

    def _free_across(self, F: np.ndarray, along: int) -> np.ndarray:
        """F (k, 2, 2) with the stretch across `along` that makes the stress across vanish:
        k (exp(b E) - 1) / b + c E_along = 0, E = ln(1 - b c E_along / k) / b; raises
        ConvergenceError (with the states before) where no stretch does (the lateral
        compression branch saturates at -k / b)."""
        across = 1 - along
        k, b = (
            (self.wale_stiffness, self.wale_stiffening)
            if across == 1
            else (self.course_stiffness, self.course_stiffening)
        )
        c = self.coupling_22_11 if across == 1 else self.coupling_11_22
        E_along = (F[:, along, along] ** 2 - 1.0) / 2.0
        argument = 1.0 - b * c * E_along / k
        free = F.copy()
        reachable = argument > 0.0
        E_across = np.log(np.where(reachable, argument, 1.0)) / b
        free[:, across, across] = np.sqrt(1.0 + 2.0 * E_across)
        if reachable.all():
            return free
        converged = int(np.argmin(reachable))
        S = self.stress(voigt(green_lagrange(free[:converged])))
        S_tensor = np.stack([S[:, [0, 2]], S[:, [2, 1]]], axis=1)
        raise ConvergenceError(
            "analytic cell: no stretch across frees the stress beyond this strain",
            history=RveRun(free[:converged], free[:converged] @ S_tensor, complete=False),
        )
