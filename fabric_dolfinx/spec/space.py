"""The specification of the membrane in space, without DOLFINx (the scene reader checks it).

`SpaceSpec` holds what a part in space adds to the plane part: the follower pressure, a
rigid indenter (sphere, plane or body of revolution), the normal stabilization and, for a
gmsh surface in space, the course direction field (around or along an axis).
`fabric_dolfinx.membrane3d_solve` runs it.
"""

import math
from dataclasses import dataclass

import numpy as np

from fabric_dolfinx.spec.revolution import RadiusProfile
from rve_rod.errors import InputError, check_positive

__all__ = [
    "COURSE_KINDS",
    "INDENTER_SHAPES",
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


INDENTER_SHAPES = {
    "sphere": ("radius", "centre"),
    "plane": ("point", "normal"),
    "revolution": ("profile", "start_scale"),
}
"""The rigid indenters and the keys that place each (`membrane.loads.SphereIndenter`,
`PlaneIndenter`, `RevolutionIndenter`)."""


@dataclass(frozen=True)
class IndenterSpec:
    """A rigid sphere, plane or body of revolution moving along a line.

    Attributes:
        travel: (dx, dy, dz) mm the indenter moves by at t = 1.
        shape: "sphere" (radius mm, centre (x, y, z) mm at t = 0), "plane" (point (x, y, z)
            mm of the plane at t = 0, normal towards the fabric's side) or "revolution"
            (profile ((z, r), ...) mm of a body about the z axis, its radii start_scale r at
            t = 0 growing to r at t = 1: an expanding mandrel); outside the fabric at t = 0.
        penalty: contact stiffness N/mm^3.
    """

    travel: tuple[float, float, float] = (0.0, 0.0, 0.0)
    shape: str = "sphere"
    radius: float | None = None
    centre: tuple[float, float, float] | None = None
    point: tuple[float, float, float] | None = None
    normal: tuple[float, float, float] | None = None
    profile: tuple[tuple[float, float], ...] | None = None
    start_scale: float | None = None
    penalty: float = 100.0

    def __post_init__(self):
        if self.shape not in INDENTER_SHAPES:
            raise InputError(
                f"indenter.shape={self.shape!r} is not one of {', '.join(INDENTER_SHAPES)}"
            )
        needed = INDENTER_SHAPES[self.shape]
        for shape, keys in INDENTER_SHAPES.items():
            for key in keys:
                given = getattr(self, key) is not None
                if key in needed and not given:
                    raise InputError(f"indenter.{key}: a {self.shape} needs it")
                if shape != self.shape and key not in needed and given:
                    raise InputError(f"indenter.{key}: only for a {shape}, not a {self.shape}")
        check_positive("indenter.penalty", self.penalty, "N/mm^3")
        for key in ("centre", "point", "normal"):
            if getattr(self, key) is not None:
                _vector(f"indenter.{key}", getattr(self, key))
        if self.radius is not None:
            check_positive("indenter.radius", self.radius, "mm")
        if self.normal is not None and not np.any(self.normal):
            raise InputError("indenter.normal=(0, 0, 0) has no direction")
        if self.profile is not None:
            pairs = tuple(_vector("indenter.profile point", point, 2) for point in self.profile)
            try:
                RadiusProfile(*zip(*pairs, strict=True))
            except InputError as error:
                raise InputError(f"indenter.profile: {error}") from None
            object.__setattr__(self, "profile", pairs)
        if self.start_scale is not None and not (
            math.isfinite(self.start_scale) and 0.0 < self.start_scale <= 1.0
        ):
            raise InputError(f"indenter.start_scale={self.start_scale!r} is outside (0, 1]")
        _vector("indenter.travel", self.travel)
        if not np.any(self.travel) and (self.shape != "revolution" or self.start_scale == 1.0):
            raise InputError(
                "indenter.travel=(0, 0, 0): the indenter must move (or a body of revolution "
                "grow: start_scale < 1)"
            )


@dataclass(frozen=True)
class SpaceSpec:
    """The membrane in space of a part.

    Attributes:
        pressure: follower pressure at t = 1 (N/mm^2 = MPa) towards the normal's side (+z
            for a flat part, outwards for a tube); 0: none.
        indenter: a sphere or a plane, or None.
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
