"""The specification of the patch tension test, without DOLFINx (the pipeline plans with it).

`fabric_dolfinx.part.tension` runs it; `knitmech` builds and caches it without importing DOLFINx.
"""

from dataclasses import dataclass

from rve_rod import limits
from rve_rod.errors import InputError, check_integer, check_positive, check_range
from rve_rod.limits import check_count

__all__ = ["DIRECTIONS", "TensionTest"]

DIRECTIONS = {"course": ("left", "right", 0), "wale": ("bottom", "top", 1)}
"""Load direction -> (clamped boundary, moving boundary, displaced component)."""


@dataclass(frozen=True)
class TensionTest:
    """A uniaxial tension test of a square patch.

    Attributes:
        direction: "course" (along x) or "wale" (along y).
        size: side of the square patch (mm); the paper uses 50.
        elements: elements per side; the paper uses 10.
        max_strain: nominal strain at the end of the load path (-).
        angle: course direction of the material against the x axis (degrees).
        element_degree: Lagrange degree of the displacement (1 or 2).
        quadrature_degree: Gauss rule exactness; None: twice the element degree.
    """

    direction: str = "course"
    size: float = 50.0
    elements: int = 10
    max_strain: float = 0.2
    angle: float = 0.0
    element_degree: int = 1
    quadrature_degree: int | None = None

    def __post_init__(self):
        if self.direction not in DIRECTIONS:
            raise InputError(f"direction={self.direction!r} is not one of {', '.join(DIRECTIONS)}")
        check_positive("size", self.size, "mm")
        check_count("elements", self.elements, limits.ELEMENTS)
        check_range("max_strain", self.max_strain, 0.0, 1.0, closed=False)
        check_range("angle", self.angle, -360.0, 360.0, "degrees")
        check_integer("element_degree", self.element_degree, 1, 2)
        if self.quadrature_degree is not None:
            check_integer("quadrature_degree", self.quadrature_degree, 1, 12)
