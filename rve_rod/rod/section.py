"""Section stiffness of a Cosserat rod: the diagonal matrices A (shear, shear, axial) and C
(bending, bending, torsion) of the linear law n = R A eps, m = R C kappa.

Material axes: d1, d2 span the cross-section, d3 is the (reference) tangent. The yarn model of
Weeger et al. uses separate moduli for A (E_A = E0) and C (E_C = 0.5 E0) and scales A by
(r0/r)^4 and C by (r0/r)^6; `SectionStiffness.circular(...).scaled(...)` expresses exactly that.
"""

import math
from dataclasses import dataclass, replace

import numpy as np

from rve_rod.errors import InputError, check_positive, check_range

__all__ = [
    "PAPER_CIRCLE",
    "SOLID_CIRCLE",
    "SectionStiffness",
    "free_fibre_rigidity",
]

SOLID_CIRCLE = "solid"
"""Second moment of area of a solid circle, I = pi r^4 / 4 (the default)."""

PAPER_CIRCLE = "paper"
"""The value printed in Weeger et al.'s knit paper, I = pi r^4 / 12 (see design.md)."""

_SECOND_MOMENT_FACTORS = {SOLID_CIRCLE: 0.25, PAPER_CIRCLE: 1.0 / 12.0}


def free_fibre_rigidity(
    specific_rigidity: float, fibre_linear_density: float, yarn_linear_density: float
) -> float:
    """Bending (or twisting) rigidity of a spun yarn whose fibres bend each about its own axis
    (N mm^2): the sum over its n = T / T_f fibres of R T_f^2 each, R T_f T.

    The lower bound of a yarn's rigidity, reached when the fibres slip freely past each other
    (Platt, Klein & Hamburger 1959; Owen 1965: staple yarns bend close to it); the solid rod,
    E I of the whole section, is the upper one.

    Args:
        specific_rigidity: R, a fibre's rigidity / T_f^2 (mN mm^2 / tex^2).
        fibre_linear_density: T_f (tex).
        yarn_linear_density: T (tex).
    """
    r = check_positive("specific_rigidity", specific_rigidity, "mN mm^2/tex^2")
    t_f = check_positive("fibre_linear_density", fibre_linear_density, "tex")
    t = check_positive("yarn_linear_density", yarn_linear_density, "tex")
    return 1e-3 * r * t_f * t


def cowper_shear_correction(poissons_ratio: float) -> float:
    """Cowper's (1966) shear correction factor of a solid circle, 6(1+nu)/(7+6nu)."""
    nu = check_range("poissons_ratio", poissons_ratio, 0.0, 0.5, closed=True)
    return 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)


@dataclass(frozen=True)
class SectionStiffness:
    """Diagonal section stiffness of a rod; all entries > 0.

    Attributes:
        shear_1: k G A for shear along d1 (N).
        shear_2: k G A for shear along d2 (N).
        axial: E A for stretching along d3 (N).
        bending_1: E I1 for bending about d1 (N mm^2).
        bending_2: E I2 for bending about d2 (N mm^2).
        torsion: G J for twisting about d3 (N mm^2).
    """

    shear_1: float
    shear_2: float
    axial: float
    bending_1: float
    bending_2: float
    torsion: float

    def __post_init__(self):
        units = ("N", "N", "N", "N mm^2", "N mm^2", "N mm^2")
        for (name, value), unit in zip(self.__dict__.items(), units, strict=True):
            object.__setattr__(self, name, check_positive(f"{name} stiffness", value, unit))

    @property
    def translational(self) -> np.ndarray:
        """diag(A) = (k G A, k G A, E A), shape (3,) (N)."""
        return np.array([self.shear_1, self.shear_2, self.axial])

    @property
    def rotational(self) -> np.ndarray:
        """diag(C) = (E I1, E I2, G J), shape (3,) (N mm^2)."""
        return np.array([self.bending_1, self.bending_2, self.torsion])

    def scaled(self, translational: float = 1.0, rotational: float = 1.0) -> "SectionStiffness":
        """The same section with A multiplied by `translational` and C by `rotational`.

        The knit model uses translational = (r0/r)^4 and rotational = (r0/r)^6.
        """
        a = check_positive("translational scale", translational)
        c = check_positive("rotational scale", rotational)
        return replace(
            self,
            shear_1=a * self.shear_1,
            shear_2=a * self.shear_2,
            axial=a * self.axial,
            bending_1=c * self.bending_1,
            bending_2=c * self.bending_2,
            torsion=c * self.torsion,
        )

    @classmethod
    def circular(
        cls,
        radius: float,
        youngs_modulus: float,
        *,
        rotational_modulus: float | None = None,
        poissons_ratio: float = 0.3,
        shear_correction: float | None = None,
        second_moment: str = SOLID_CIRCLE,
    ) -> "SectionStiffness":
        """Stiffness of a circular section of `radius` r (mm).

        Args:
            radius: r (mm).
            youngs_modulus: E_A, the modulus of the translational stiffness A (MPa).
            rotational_modulus: E_C, the modulus of the rotational stiffness C (MPa);
                defaults to E_A (the knit model uses 0.5 E0).
            poissons_ratio: nu, gives G = E / (2 (1 + nu)) for both A and C.
            shear_correction: k of k G A; defaults to Cowper's 6(1+nu)/(7+6nu).
            second_moment: "solid" (I = pi r^4/4, default) or "paper" (I = pi r^4/12);
                the polar moment is J = 2 I either way.
        """
        r = check_positive("radius", radius, "mm")
        e_a = check_positive("youngs_modulus", youngs_modulus, "MPa")
        e_c = e_a if rotational_modulus is None else rotational_modulus
        e_c = check_positive("rotational_modulus", e_c, "MPa")
        nu = check_range("poissons_ratio", poissons_ratio, 0.0, 0.5, closed=True)
        k = cowper_shear_correction(nu) if shear_correction is None else shear_correction
        k = check_range("shear_correction", k, 0.0, 1.0, closed=True)
        if k == 0.0:
            raise InputError("shear_correction=0 is outside the valid range (0, 1]")
        if second_moment not in _SECOND_MOMENT_FACTORS:
            raise InputError(
                f"second_moment={second_moment!r} is unknown; valid: "
                f"{', '.join(_SECOND_MOMENT_FACTORS)}"
            )
        area = math.pi * r**2
        inertia = _SECOND_MOMENT_FACTORS[second_moment] * math.pi * r**4
        shear_a = e_a / (2.0 * (1.0 + nu))
        shear_c = e_c / (2.0 * (1.0 + nu))
        return cls(
            shear_1=k * shear_a * area,
            shear_2=k * shear_a * area,
            axial=e_a * area,
            bending_1=e_c * inertia,
            bending_2=e_c * inertia,
            torsion=shear_c * 2.0 * inertia,
        )
