"""The specification of the membrane in space, without DOLFINx (the scene reader checks it).

`SpaceSpec` holds what a part in space adds to the plane part: the follower pressure, a
sphere indenter, the normal stabilization and, for a gmsh surface in space, the course
direction field (around or along an axis). `fabric_dolfinx.membrane3d_solve` runs it.
"""

import math
from dataclasses import dataclass

import numpy as np

from rve_rod.errors import InputError, check_positive

__all__ = [
    "COURSE_KINDS",
    "IndenterSpec",
    "SpaceSpec",
]

COURSE_KINDS = ("around", "along")
"""Course fields of a surface in space: around an axis (a tube's circumference) or along it
(projected onto the surface)."""


def _vector(name: str, value, length: int = 3) -> tuple[float, ...]:
    if len(value) != length or not all(math.isfinite(float(v)) for v in value):
        raise InputError(f"{name}={tuple(value)!r} needs {length} finite numbers")
    return tuple(float(v) for v in value)


@dataclass(frozen=True)
class IndenterSpec:
    """A rigid sphere moving along a line (`membrane3d.SphereIndenter`).

    Attributes:
        radius: mm; centre: (x, y, z) mm at t = 0 (outside the fabric); travel: (dx, dy, dz)
        mm of the centre at t = 1; penalty: contact stiffness N/mm^3.
    """

    radius: float
    centre: tuple[float, float, float]
    travel: tuple[float, float, float]
    penalty: float = 100.0

    def __post_init__(self):
        check_positive("indenter.radius", self.radius, "mm")
        check_positive("indenter.penalty", self.penalty, "N/mm^3")
        _vector("indenter.centre", self.centre)
        _vector("indenter.travel", self.travel)
        if not np.any(self.travel):
            raise InputError("indenter.travel=(0, 0, 0): the indenter must move")


@dataclass(frozen=True)
class SpaceSpec:
    """The membrane in space of a part.

    Attributes:
        pressure: follower pressure at t = 1 (N/mm^2 = MPa) towards the normal's side (+z
            for a flat part, outwards for a tube); 0: none.
        indenter: a sphere, or None.
        stabilization: normal stabilization c (N/mm^3), 0: none (`membrane3d_solve`).
        course: for a gmsh surface in space, "around" or "along" the axis; None for flat
            parts and built-in shapes (a tube's course runs around its axis).
        axis: (3,) the axis direction of the course field and of the normal's side (the
            normal points away from the axis).
        axis_point: (3,) a point of the axis (mm).
    """

    pressure: float = 0.0
    indenter: IndenterSpec | None = None
    stabilization: float = 0.0
    course: str | None = None
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    axis_point: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self):
        if not math.isfinite(self.pressure):
            raise InputError(f"pressure={self.pressure!r} must be a finite number (N/mm^2)")
        if not (math.isfinite(self.stabilization) and self.stabilization >= 0.0):
            raise InputError(f"stabilization={self.stabilization!r} must be >= 0 (N/mm^3)")
        if self.course is not None and self.course not in COURSE_KINDS:
            raise InputError(f"course={self.course!r} is not one of {', '.join(COURSE_KINDS)}")
        if not np.any(_vector("axis", self.axis)):
            raise InputError("axis=(0, 0, 0) has no direction")
        _vector("axis_point", self.axis_point)
