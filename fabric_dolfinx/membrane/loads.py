"""Loads of a membrane in space: the follower pressure and rigid indenters.

The membrane itself (frames, kinematics, stresses, forms) is `fabric_dolfinx.membrane.forms`, the
same for plane parts and parts in space; this module adds the loads that need a third
component (lengths mm):

    R(u; v) = int P : (grad v T) dA - int p (g_1 x g_2) . v dA - contact = 0,

the contact of a rigid sphere, plane or body of revolution (frictionless penalty,
`penalty_pressure`). The pressure p (N/mm^2) acts on the deformed surface (g_1 x g_2 dA is
the deformed area times its normal): a follower load. The load terms are differentiated by
`ufl.derivative`.

An indenter moves with the load factor t: its state q(t) = start + t change (`motion`; a
sphere's centre, a plane's point, a body of revolution's translation and radius scale, then
the numbers that stay: a sphere's radius, a plane's unit normal, and last the penalty) is a
`LoadConstants` constant, and `gap(x, q)` gives the gap and contact direction at a deformed
point x. Its numbers being a Constant's, the forms of every sphere (every plane) and penalty
are one compiled form each (a body of revolution's profile stays in its forms).
"""

from dataclasses import dataclass

import numpy as np
import ufl

from fabric_dolfinx.membrane.forms import MaterialFrame, deformation_gradient
from fabric_dolfinx.spec.revolution import RadiusProfile
from rve_rod.errors import InputError, check_positive, check_range

__all__ = [
    "Indenter",
    "PlaneIndenter",
    "RevolutionIndenter",
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


def penalty_pressure(gap, penalty):
    """The contact pressure k <-gap> (N/mm^2 per undeformed area) of a penalty `penalty` k
    (N/mm^3, a number or UFL scalar) at `gap` (mm, negative when the fabric is inside the
    indenter): the one law of every indenter."""
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

    def motion(self) -> tuple[np.ndarray, np.ndarray]:
        """(start, change) of its state q(t) = start + t change: the centre (mm), then the
        radius (mm) and the penalty."""
        start = [*self.centre, self.radius, self.penalty]
        return np.asarray(start, dtype=float), np.array([*self.travel, 0.0, 0.0], dtype=float)

    def gap(self, position, state):
        """(gap |x - c| - R mm, unit vector from the centre c to x) at the deformed position x
        (UFL), for the state q = (c, R, k) (a Constant (5,))."""
        offset = position - ufl.as_vector([state[0], state[1], state[2]])
        distance = ufl.sqrt(ufl.dot(offset, offset))
        return distance - state[3], offset / distance

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

    def motion(self) -> tuple[np.ndarray, np.ndarray]:
        """(start, change) of its state q(t) = start + t change: the plane's point (mm), then
        its unit normal and the penalty."""
        start = [*self.point, *self._unit(), self.penalty]
        return np.asarray(start, dtype=float), np.array([*self.travel, 0, 0, 0, 0], dtype=float)

    def _unit(self) -> np.ndarray:
        normal = np.asarray(self.normal, dtype=float)
        return normal / np.linalg.norm(normal)

    def gap(self, position, state):
        """(gap (x - p) . n mm, the unit normal n) at the deformed position x (UFL), for the
        state q = (p, n, k) (a Constant (7,))."""
        point = ufl.as_vector([state[0], state[1], state[2]])
        normal = ufl.as_vector([state[3], state[4], state[5]])
        return ufl.dot(position - point, normal), normal

    def start_gaps(self, points: np.ndarray) -> np.ndarray:
        """The gaps (mm) of reference points (n, 3) at load factor 0."""
        return (points - np.asarray(self.point)) @ self._unit()

    def describe(self) -> str:
        return f"plane point={tuple(self.point)} mm, normal={tuple(self.normal)}"


def profile_radius(profile: RadiusProfile, z) -> tuple:
    """(r(z), dr/dz) of `profile` at the UFL scalar z (mm): its polynomial pieces
    (`RadiusProfile.pieces`) chosen by conditionals, linear beyond its ends."""
    knots, pieces = profile.z, profile.pieces()
    start, end = profile.end_slopes()
    radius = profile.r[0] + start * (z - knots[0])
    slope = ufl.as_ufl(start)
    for knot, (a0, a1, a2, a3) in zip(knots[:-1], pieces, strict=True):
        t = z - knot
        inside = ufl.ge(z, knot)
        radius = ufl.conditional(inside, a0 + t * (a1 + t * (a2 + t * a3)), radius)
        slope = ufl.conditional(inside, a1 + t * (2 * a2 + t * 3 * a3), slope)
    beyond = ufl.gt(z, knots[-1])
    radius = ufl.conditional(beyond, profile.r[-1] + end * (z - knots[-1]), radius)
    return radius, ufl.conditional(beyond, end, slope)


@dataclass(frozen=True)
class RevolutionIndenter:
    """A rigid body of revolution about the z axis, r(z) from a profile, that grows from
    `start_scale` r(z) to r(z) (an expanding mandrel) while it moves by t * travel, in
    frictionless penalty contact with the fabric from inside or outside.

    The gap at a deformed point x (the body translated by d, scaled by sigma; rho the
    distance of x - d from the axis, z its axial coordinate) is the distance to the body
    along its outward normal to first order in the surface's curvature,

        gap = (rho - sigma r(z)) / sqrt(1 + (sigma r'(z))^2),
        n = (e_rho - sigma r'(z) e_z) / sqrt(1 + (sigma r'(z))^2),

    exact for a cylinder and a cone. Positive outside the body: the fabric is pushed out
    along n (a tube drawn over a limb).

    Attributes:
        profile: the body's radius profile r(z) (mm).
        start_scale: sigma at load factor 0, in (0, 1]; sigma = 1 at load factor 1.
        travel: (dx, dy, dz) of the body at load factor 1 (mm).
        penalty: contact stiffness k (N/mm^3), the law of the sphere (`penalty_pressure`).
    """

    profile: RadiusProfile
    start_scale: float
    travel: tuple[float, float, float]
    penalty: float

    def __post_init__(self):
        check_positive("penalty", self.penalty, "N/mm^3")
        check_range("start_scale", self.start_scale, 0.0, 1.0, closed=True)
        check_positive("start_scale", self.start_scale)
        _check_vectors(travel=self.travel)

    def motion(self) -> tuple[np.ndarray, np.ndarray]:
        """(start, change) of its state q(t) = start + t change: (dx, dy, dz mm, sigma), then
        the penalty."""
        start = np.array([0.0, 0.0, 0.0, self.start_scale, self.penalty])
        return start, np.array([*self.travel, 1.0 - self.start_scale, 0.0])

    def gap(self, position, state):
        """(gap mm, unit normal n of the body) at the deformed position x (UFL), the body's
        state q = (dx, dy, dz, sigma, k) (a Constant (5,))."""
        offset = position - ufl.as_vector([state[0], state[1], state[2]])
        rho = ufl.sqrt(offset[0] ** 2 + offset[1] ** 2)
        radius, slope = profile_radius(self.profile, offset[2])
        scale = state[3]
        norm = ufl.sqrt(1.0 + (scale * slope) ** 2)
        normal = ufl.as_vector([offset[0] / rho, offset[1] / rho, -scale * slope]) / norm
        return (rho - scale * radius) / norm, normal

    def start_gaps(self, points: np.ndarray) -> np.ndarray:
        """The gaps (mm) of reference points (n, 3) at load factor 0."""
        rho = np.hypot(points[:, 0], points[:, 1])
        slope = self.start_scale * self.profile.slope(points[:, 2])
        radius = self.start_scale * self.profile.radius(points[:, 2])
        return (rho - radius) / np.sqrt(1.0 + slope**2)

    def describe(self) -> str:
        first, last = self.profile.extent
        return (
            f"body of revolution r(z) over z = {first:g} ... {last:g} mm, scaled by "
            f"{self.start_scale:g} at the start"
        )


Indenter = SphereIndenter | PlaneIndenter | RevolutionIndenter
"""A rigid indenter: its state follows the load factor (`motion`) and it gives the gap and
the contact direction at a point (`gap`)."""


def contact_pressure(u, indenter: Indenter, state, frame: MaterialFrame):
    """(contact pressure k <-gap> N/mm^2 per undeformed area, its unit direction on the
    fabric) at u, for the indenter in `state` (a Constant, `Indenter.motion`; the penalty k
    its last entry)."""
    gap, direction = indenter.gap(frame.position + u, state)
    return penalty_pressure(gap, state[ufl.shape(state)[0] - 1]), direction


def contact_residual(u, indenter: Indenter, state, frame: MaterialFrame, dx: ufl.Measure):
    """The contact force's virtual work int k <-gap> n . v dA (N; subtract it from R)."""
    v = ufl.TestFunction(u.function_space)
    pressure, direction = contact_pressure(u, indenter, state, frame)
    return pressure * ufl.dot(direction, v) * dx
