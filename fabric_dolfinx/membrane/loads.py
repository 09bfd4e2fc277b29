"""Loads of a membrane in space: the follower pressure and rigid indenters.

The membrane itself (frames, kinematics, stresses, forms) is `fabric_dolfinx.membrane.forms`, the
same for plane parts and parts in space; this module adds the loads that need a third
component (lengths mm):

    R(u; v) = int P : (grad v T) dA - int p (g_1 x g_2) . v dA - contact = 0,

the contact of a rigid sphere or plane (frictionless penalty, `penalty_pressure`). The
pressure p (N/mm^2) acts on the deformed surface (g_1 x g_2 dA is the deformed area times
its normal): a follower load. The load terms are differentiated by `ufl.derivative`.
"""

from dataclasses import dataclass

import numpy as np
import ufl

from fabric_dolfinx.membrane.forms import MaterialFrame, deformation_gradient
from rve_rod.errors import InputError, check_positive

__all__ = [
    "Indenter",
    "PlaneIndenter",
    "SphereIndenter",
    "contact_pressure",
    "contact_residual",
    "penalty_pressure",
    "pressure_residual",
]


def pressure_residual(u, pressure, frame: MaterialFrame, dx: ufl.Measure) -> ufl.Form:
    """The follower pressure's virtual work int p (g1 x g2) . v dA (N; subtract it from R).

    `pressure` (N/mm^2, a Constant scaled by the load factor) pushes towards the reference
    normal's side, on the deformed surface.
    """
    v = ufl.TestFunction(u.function_space)
    F = deformation_gradient(u, frame)
    return pressure * ufl.dot(ufl.cross(F[:, 0], F[:, 1]), v) * dx


def penalty_pressure(gap, penalty: float):
    """The contact pressure k <-gap> (N/mm^2 per undeformed area) of a penalty `penalty` k
    (N/mm^3) at `gap` (mm, negative when the fabric is inside the indenter): the one law
    of both indenters."""
    return penalty * ufl.conditional(ufl.lt(gap, 0.0), -gap, 0.0)


def _check_vectors(**vectors) -> None:
    for name, value in vectors.items():
        if len(value) != 3 or not np.all(np.isfinite(value)):
            raise InputError(f"indenter {name}={value!r} needs 3 finite numbers (mm)")


@dataclass(frozen=True)
class SphereIndenter:
    """A rigid sphere moving along a line, in frictionless penalty contact with the fabric.

    Attributes:
        radius: sphere radius (mm).
        centre: (x, y, z) of its centre at load factor 0 (mm); it must not touch the fabric.
        travel: (dx, dy, dz) displacement of the centre at load factor 1 (mm).
        penalty: contact stiffness k (N/mm^3): contact pressure k <-gap> per undeformed
            area. The reported force converges as k grows (error ~ 1/k); choose it so that
            doubling it changes the force by less than you care (`docs/membrane3d.md`).
    """

    radius: float
    centre: tuple[float, float, float]
    travel: tuple[float, float, float]
    penalty: float

    def __post_init__(self):
        check_positive("radius", self.radius, "mm")
        check_positive("penalty", self.penalty, "N/mm^3")
        _check_vectors(centre=self.centre, travel=self.travel)

    @property
    def origin(self) -> tuple[float, float, float]:
        """The point that moves by t * travel: the centre (mm)."""
        return self.centre

    def gap(self, position, origin):
        """(gap |x - c| - R mm, unit vector from the centre c = `origin` to x) at the deformed
        position x (UFL)."""
        offset = position - origin
        distance = ufl.sqrt(ufl.dot(offset, offset))
        return distance - self.radius, offset / distance

    def start_gaps(self, points: np.ndarray) -> np.ndarray:
        """The gaps (mm) of reference points (n, 3) at load factor 0."""
        return np.linalg.norm(points - np.asarray(self.centre), axis=1) - self.radius

    def describe(self) -> str:
        return f"sphere centre={tuple(self.centre)} mm, radius={self.radius:g} mm"


@dataclass(frozen=True)
class PlaneIndenter:
    """A rigid plane moving along a line, in frictionless penalty contact with the fabric.

    Attributes:
        point: (x, y, z) of a point of the plane at load factor 0 (mm).
        normal: the plane's normal, pointing to the side the fabric stays on (any length);
            no node of the fabric may start behind the plane.
        travel: (dx, dy, dz) displacement of the plane at load factor 1 (mm).
        penalty: contact stiffness k (N/mm^3), the law of the sphere (`penalty_pressure`).
    """

    point: tuple[float, float, float]
    normal: tuple[float, float, float]
    travel: tuple[float, float, float]
    penalty: float

    def __post_init__(self):
        check_positive("penalty", self.penalty, "N/mm^3")
        _check_vectors(point=self.point, normal=self.normal, travel=self.travel)
        if not np.any(self.normal):
            raise InputError("indenter normal=(0, 0, 0) has no direction")

    @property
    def origin(self) -> tuple[float, float, float]:
        """The point that moves by t * travel: the plane's point (mm)."""
        return self.point

    def _unit(self) -> np.ndarray:
        normal = np.asarray(self.normal, dtype=float)
        return normal / np.linalg.norm(normal)

    def gap(self, position, origin):
        """(gap (x - p) . n mm, the unit normal n) at the deformed position x (UFL), p the
        plane's point `origin`."""
        normal = ufl.as_vector(self._unit().tolist())
        return ufl.dot(position - origin, normal), normal

    def start_gaps(self, points: np.ndarray) -> np.ndarray:
        """The gaps (mm) of reference points (n, 3) at load factor 0."""
        return (points - np.asarray(self.point)) @ self._unit()

    def describe(self) -> str:
        return f"plane point={tuple(self.point)} mm, normal={tuple(self.normal)}"


Indenter = SphereIndenter | PlaneIndenter
"""A rigid indenter: it moves its `origin` by t * travel and gives the gap and the contact
direction at a point (`gap`)."""


def contact_pressure(u, indenter: Indenter, origin, frame: MaterialFrame):
    """(contact pressure k <-gap> N/mm^2, its unit direction on the fabric) at u, for the
    indenter whose origin is at `origin` (a Constant (3,), mm)."""
    gap, direction = indenter.gap(frame.position + u, origin)
    return penalty_pressure(gap, indenter.penalty), direction


def contact_residual(u, indenter: Indenter, origin, frame: MaterialFrame, dx: ufl.Measure):
    """The contact force's virtual work int k <-gap> n . v dA (N; subtract it from R)."""
    v = ufl.TestFunction(u.function_space)
    pressure, direction = contact_pressure(u, indenter, origin, frame)
    return pressure * ufl.dot(direction, v) * dx
