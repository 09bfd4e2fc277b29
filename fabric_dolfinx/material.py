"""Membrane material laws, evaluated with NumPy at the strains of the quadrature points.

Two laws, each a function (E, stitch) -> (S, dS/dE) over m points in the material frame
(axis 1 course-wise, axis 2 wale-wise): the response-surface law of `docs/surface-format.md`
(`rve_rod.surface.ResponseSurface.stress`: the B-splines and their derivatives, extended
outside the sampled domain by their Taylor polynomials) and an orthotropic Saint
Venant-Kirchhoff law for tests and comparisons; `fabric_dolfinx.graded` blends a family of
laws in the stitch value. `fabric_dolfinx.membrane.quadrature` evaluates a part's laws at its
quadrature points before every assembly and gives the membrane forms S and its tangent as
Functions, so the forms hold no number of the law (one FFCx compilation for every surface).

Shapes and units: strains E (m, 3) = (E11, E22, E12), dimensionless, tensor shear E12;
stresses S (m, 3) = (S11, S22, S12) in N/mm (force per unit undeformed width); the tangent
(m, 3, 3) dS_a/dE_b in N/mm (`rve_rod.surface.StressResult`).
"""

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rve_rod.errors import check_positive, check_range
from rve_rod.surface import ResponseSurface, StressResult

__all__ = [
    "Material",
    "OrthotropicSVK",
    "PointLaw",
    "surface_material",
    "svk_material",
]

PointLaw = Callable[[np.ndarray, np.ndarray], StressResult]
"""A material law at m points: (E (m, 3), stitch value (m,) mm) -> StressResult (S (m, 3) N/mm,
tangent (m, 3, 3) N/mm, outside (m,)). Only a graded law reads the stitch value."""


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

    def stress(self, E: np.ndarray) -> StressResult:
        """S = C E (m, 3), the constant tangent C (m, 3, 3) and `outside` (all False: the law
        holds everywhere) at strains E (m, 3)."""
        C = self.plane_stress_matrix()
        E = np.asarray(E, dtype=float).reshape(-1, 3)
        tangent = np.broadcast_to(C, (E.shape[0], 3, 3))
        return StressResult(S=E @ C.T, tangent=tangent, outside=np.zeros(E.shape[0], bool))


class Material(NamedTuple):
    """A membrane material ready for the solvers.

    Attributes:
        law: the stress law (E, stitch) -> S, dS/dE at m points, material frame (`PointLaw`).
        domain: (3, 2) [min, max] of E11, E22, E12 where the law rests on data (a response
            surface's sampled domain; outside it the extension applies), or None.
        name: a label for output.
    """

    law: PointLaw
    domain: np.ndarray | None
    name: str


def surface_material(surface: ResponseSurface, name: str = "response surface") -> Material:
    """The response-surface law of `surface` with its domain."""
    return Material(lambda E, stitch: surface.stress(E), surface.domain, name)


def svk_material(material: OrthotropicSVK, name: str = "orthotropic SVK") -> Material:
    """The orthotropic Saint Venant-Kirchhoff law (valid everywhere: no domain)."""
    return Material(lambda E, stitch: material.stress(E), None, name)
