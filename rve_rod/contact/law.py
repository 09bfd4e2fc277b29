"""Contact laws: the compressible-yarn normal penalty law and penalty-regularized Coulomb friction.

The normal law is the one of Weeger et al. (knitted textiles, design.md): a line load (force per
unit length of the loaded yarn, N/mm) that grows with the penetration g = 2r - d of two yarn
surfaces (d: centreline distance, r: yarn radius),

    f_n(g) = k (r/p) (g/r)^p  for g > 0,   0 otherwise,
    k = 0.01 E0 (r0/r)^8,   p = 3 - (r0/r)^3,

so the exponent softens as the yarn radius r is squeezed below its measured radius r0. The law
is used only with p >= 1 (`MINIMUM_EXPONENT`): below p = 1 the slope df_n/dg is infinite at
first touch (no Newton tangent exists there), and as p -> 0 (r0/r -> 3^(1/3) = 1.442) the force
k r/p at any penetration becomes unbounded. p = 1 is the linear penalty f_n = k g.

`CompressibleYarnLaw.load_and_slope` is what a run evaluates: the contact model calls it on the
penetrations of the active contacts and hands f_n, df_n/dg to the load kernel
(`rve_rod.contact.forces.contact_loads`), which has no formula of its own. The formula itself
is one numba function, `_kernels.compressible_yarn_law` (compiled, so that every caller gets the
same bits), which `line_load` and `line_stiffness` share.
"""

from dataclasses import dataclass

import numpy as np

from rve_rod.contact import _kernels
from rve_rod.errors import InputError, check_positive, check_range

__all__ = [
    "DEFAULT_STIFFNESS_FACTOR",
    "MINIMUM_EXPONENT",
    "CompressibleYarnLaw",
    "CoulombFriction",
]

MINIMUM_EXPONENT = 1.0
"""Smallest admissible exponent p: the law stays Lipschitz (finite tangent) at first touch."""

DEFAULT_STIFFNESS_FACTOR = 0.01
"""k = factor * E0 * (r0/r)^8; the reference data's `contact_stiffness_factor`."""


@dataclass(frozen=True)
class CompressibleYarnLaw:
    """Normal line load f_n(g) = k (r/p) (g/r)^p on the penetration g > 0.

    Attributes:
        stiffness: k (MPa = N/mm^2), > 0.
        exponent: p (-), >= MINIMUM_EXPONENT.
        yarn_radius: r (mm), > 0; penetration is g = 2r - d.
    """

    stiffness: float
    exponent: float
    yarn_radius: float

    def __post_init__(self):
        check_positive("contact stiffness", self.stiffness, "MPa")
        check_range("contact exponent", self.exponent, MINIMUM_EXPONENT, np.inf)
        check_positive("yarn_radius", self.yarn_radius, "mm")

    @classmethod
    def from_yarn(
        cls,
        minimal_radius: float,
        yarn_radius: float,
        youngs_modulus: float,
        stiffness_factor: float = DEFAULT_STIFFNESS_FACTOR,
    ) -> "CompressibleYarnLaw":
        """The paper's law for a yarn of radius r0 compressed to r (k, p from design.md).

        Args:
            minimal_radius: r0, measured minimal yarn radius (mm).
            yarn_radius: r = min(r0, w/8), the radius the rods are built with (mm), <= r0.
            youngs_modulus: E0 (MPa).
            stiffness_factor: the 0.01 in k = 0.01 E0 (r0/r)^8.

        Raises InputError when r > r0, or when r is so small that p = 3 - (r0/r)^3 < 1, i.e.
        r < r0 / 2^(1/3) = 0.794 r0 (for r = w/8: wale width below 6.35 r0).
        """
        r0 = check_positive("minimal_radius", minimal_radius, "mm")
        r = check_positive("yarn_radius", yarn_radius, "mm")
        check_range("yarn_radius", r, 0.0, r0, "mm")
        check_positive("youngs_modulus", youngs_modulus, "MPa")
        check_positive("stiffness_factor", stiffness_factor)
        ratio = r0 / r
        exponent = 3.0 - ratio**3
        if exponent < MINIMUM_EXPONENT - 1e-12:
            smallest = r0 / (3.0 - MINIMUM_EXPONENT) ** (1.0 / 3.0)
            raise InputError(
                f"yarn_radius={r:.6g} mm gives r0/r={ratio:.4g} and contact exponent "
                f"p=3-(r0/r)^3={exponent:.4g}; the compressible-yarn law needs p >= "
                f"{MINIMUM_EXPONENT:g}, i.e. yarn_radius in [{smallest:.6g}, {r0:.6g}] mm "
                f"(r >= 0.794 r0; with r = w/8 the wale width must be >= {8 * smallest:.6g} mm)"
            )
        stiffness = stiffness_factor * youngs_modulus * ratio**8
        return cls(stiffness=stiffness, exponent=max(exponent, MINIMUM_EXPONENT), yarn_radius=r)

    def load_and_slope(self, penetration: np.ndarray) -> np.ndarray:
        """f_n(g) (N/mm) and df_n/dg = k (g/r)^(p-1) (N/mm^2) for penetrations g (mm), both
        zero where g <= 0 (the slope is k itself at g = 0+ if p = 1); shape (2, *g.shape).

        The one evaluation of the law, `_kernels.compressible_yarn_law`: the contact loads of a
        run call this method (`rve_rod.contact.forces.contact_loads`).
        """
        g = np.asarray(penetration, dtype=float)
        out = np.empty((2, g.size))
        parameters = np.array([self.stiffness, self.exponent, self.yarn_radius])
        _kernels.compressible_yarn_law(np.ascontiguousarray(g.ravel()), parameters, out)
        return out.reshape((2, *g.shape))

    def line_load(self, penetration: np.ndarray) -> np.ndarray:
        """f_n(g) (N/mm) for penetrations g (mm), zero where g <= 0; same shape as g."""
        return self.load_and_slope(penetration)[0]

    def line_stiffness(self, penetration: np.ndarray) -> np.ndarray:
        """df_n/dg = k (g/r)^(p-1) (N/mm^2), zero where g <= 0 (k itself at g = 0+ if p = 1)."""
        return self.load_and_slope(penetration)[1]

    def line_energy(self, penetration: np.ndarray) -> np.ndarray:
        """Stored energy per unit length, int_0^g f_n = k r^2 (g/r)^(p+1) / (p (p+1)) (N)."""
        g = np.maximum(np.asarray(penetration, dtype=float), 0.0)
        r, p = self.yarn_radius, self.exponent
        return self.stiffness * r**2 * (g / r) ** (p + 1.0) / (p * (p + 1.0))


@dataclass(frozen=True)
class CoulombFriction:
    """Coulomb friction regularized by an elastic stick with a tangential penalty.

    The friction line load is f_t = -k_t g_T while |k_t g_T| <= mu f_n (stick) and mu f_n in
    the direction of -g_T otherwise (slip, return mapping); g_T is the tangential slip since
    the stick anchor. The elastic slip in stick is at most mu f_n / k_t.

    Attributes:
        coefficient: mu (-), >= 0; 0 switches friction off.
        tangential_stiffness: k_t (N/mm^2: line load per mm of slip), > 0.
    """

    coefficient: float
    tangential_stiffness: float

    def __post_init__(self):
        check_range("friction_coefficient", self.coefficient, 0.0, 10.0)
        check_positive("tangential_stiffness", self.tangential_stiffness, "MPa")

    @classmethod
    def for_law(
        cls, law: CompressibleYarnLaw, coefficient: float, stiffness_ratio: float = 1.0
    ) -> "CoulombFriction":
        """Friction with k_t = stiffness_ratio * k of the normal law (default k_t = k)."""
        check_positive("stiffness_ratio", stiffness_ratio)
        return cls(coefficient=coefficient, tangential_stiffness=stiffness_ratio * law.stiffness)
