"""A membrane in space: kinematics, stresses and forms of a 2D fabric that moves in 3D.

Total Lagrangian on a reference surface (lengths mm): the unknown is the displacement
u in R^3 of every point X of the reference surface, flat (a mesh of the plane membrane, gdim
2) or curved (a gmsh surface in space, gdim 3). At each point the fabric's material axes
a1 (course) and a2 (wale) are orthonormal tangents of the reference surface, the columns of
the frame T (gdim x 2). The surface deformation gradient in the course/wale frame is

    F = (I + grad u) T                    (3 x 2; I the embedding of the reference in R^3)

whose columns g_a = F e_a are the deformed material lines. C = F^T F (2 x 2), E = (C - I)/2
in the material frame, S = law(E) from the same laws as the plane membrane
(`fabric_dolfinx.material`, N/mm per undeformed width), P = F S (3 x 2) and the weak form

    R(u; v) = int P : (grad v T) dA - int p (g_1 x g_2) . v dA - contact = 0,

the contact of a rigid sphere or plane (frictionless penalty, `penalty_pressure`).

The pressure p (N/mm^2) acts on the deformed surface (g_1 x g_2 dA is the deformed area
times its normal): a follower load. On a flat reference the frame is the rotation of the
plane membrane, so in-plane states equal the plane membrane's exactly. The elastic tangent
is split as in `membrane.membrane_forms` (same reason: small kernels for spline laws); the
load terms are differentiated by `ufl.derivative`.
"""

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import ufl

from fabric_dolfinx.material import StressLaw, rotation
from fabric_dolfinx.membrane import MembraneForms, cell_measure
from rve_rod.errors import InputError, check_positive

__all__ = [
    "Indenter",
    "PlaneIndenter",
    "SphereIndenter",
    "SurfaceFrame",
    "SurfaceStress",
    "contact_pressure",
    "contact_residual",
    "curved_frame",
    "flat_frame",
    "membrane3d_forms",
    "penalty_pressure",
    "pressure_residual",
    "surface_deformation_gradient",
    "surface_frame",
    "surface_stress_state",
]

VectorField = Callable[[ufl.core.expr.Expr], ufl.core.expr.Expr]
"""A vector field of the reference position: X (3,) -> UFL vector (3,)."""


class SurfaceFrame(NamedTuple):
    """The material frame of the reference surface at every point.

    Attributes:
        tangents: T (gdim x 2), columns a1 (course) and a2 (wale), orthonormal.
        normal: N = a1 x a2 (3,), the side a positive pressure pushes towards.
        embedding: I (3 x gdim), the reference position in R^3 (the identity when gdim 3).
        position: X (3,), the reference position (mm).
    """

    tangents: ufl.core.expr.Expr
    normal: ufl.core.expr.Expr
    embedding: ufl.core.expr.Expr
    position: ufl.core.expr.Expr


def flat_frame(mesh, angle=0.0) -> SurfaceFrame:
    """The frame of a flat mesh (gdim 2) with the course at `angle` radians from the x axis
    (a number, a Constant or a DG0 field, as for the plane membrane); normal +z."""
    x = ufl.SpatialCoordinate(mesh)
    return SurfaceFrame(
        tangents=rotation(angle),
        normal=ufl.as_vector([0.0, 0.0, 1.0]),
        embedding=ufl.as_matrix([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]),
        position=ufl.as_vector([x[0], x[1], 0.0]),
    )


def curved_frame(mesh, course: VectorField, side: VectorField) -> SurfaceFrame:
    """The frame of a curved surface mesh (gdim 3).

    Args:
        course: X -> a vector along the course direction (any length; its component along
            the surface normal is removed), e.g. X -> (-y, x, 0) around a tube's axis.
        side: X -> a vector on the side the normal N points to (only its sign against the
            cell normal matters: cell orientations of a mesh need not agree), e.g. X ->
            (x, y, 0), outwards from a tube's axis. a2 = N x a1 completes the frame.
    """
    x = ufl.SpatialCoordinate(mesh)
    jacobian = ufl.Jacobian(mesh)
    raw = ufl.cross(jacobian[:, 0], jacobian[:, 1])
    normal = ufl.sign(ufl.dot(raw, side(x))) * raw / ufl.sqrt(ufl.dot(raw, raw))
    c = course(x)
    tangent = c - ufl.dot(c, normal) * normal
    a1 = tangent / ufl.sqrt(ufl.dot(tangent, tangent))
    a2 = ufl.cross(normal, a1)
    tangents = ufl.as_matrix([[a1[i], a2[i]] for i in range(3)])
    return SurfaceFrame(tangents, normal, ufl.Identity(3), ufl.as_vector([x[i] for i in range(3)]))


def surface_frame(mesh, angle=0.0, course=None, side=None) -> SurfaceFrame:
    """`flat_frame(mesh, angle)` for gdim 2, `curved_frame(mesh, course, side)` for gdim 3
    (InputError naming the missing field when a curved mesh has no course or side field)."""
    gdim = mesh.geometry.dim
    if gdim == 2:
        return flat_frame(mesh, angle)
    missing = [name for name, value in (("course", course), ("side", side)) if value is None]
    if missing:
        raise InputError(
            f"a curved surface mesh (gdim {gdim}) needs the {' and '.join(missing)} direction "
            "field: the course direction is a tangent field the scene must give"
        )
    return curved_frame(mesh, course, side)


def surface_deformation_gradient(u, frame: SurfaceFrame) -> ufl.core.expr.Expr:
    """F = (I + grad u) T, shape (3, 2): the deformed course and wale line elements."""
    return (frame.embedding + ufl.grad(u)) * frame.tangents


class SurfaceStress(NamedTuple):
    """UFL expressions of the membrane-in-space state at u.

    Attributes:
        deformation_gradient: F (3, 2).
        strain: Green-Lagrange strain E (2, 2), material frame (course, wale).
        second_piola_kirchhoff: S (2, 2), material frame, N/mm.
        area_ratio: J = |g1 x g2|, deformed over reference area.
        cauchy: sigma = F S F^T / J (3, 3), N/mm per deformed width, in space.
        normal: the deformed unit normal (3,).
    """

    deformation_gradient: ufl.core.expr.Expr
    strain: ufl.core.expr.Expr
    second_piola_kirchhoff: ufl.core.expr.Expr
    area_ratio: ufl.core.expr.Expr
    cauchy: ufl.core.expr.Expr
    normal: ufl.core.expr.Expr


def surface_stress_state(u, law: StressLaw, frame: SurfaceFrame) -> SurfaceStress:
    """The state of the membrane in space for the displacement u and the material law."""
    F = surface_deformation_gradient(u, frame)
    E = 0.5 * (F.T * F - ufl.Identity(2))
    S = law(E)
    area = ufl.cross(F[:, 0], F[:, 1])
    J = ufl.sqrt(ufl.dot(area, area))
    return SurfaceStress(F, E, S, J, F * S * F.T / J, area / J)


def membrane3d_forms(
    u,
    law: StressLaw,
    frame: SurfaceFrame,
    quadrature_degree: int | None = None,
    measure: ufl.Measure | None = None,
) -> MembraneForms:
    """Internal-force residual int P : (grad v T) dA and its consistent Jacobian.

    The Jacobian equals `ufl.derivative(residual, u)` (a test checks it to round-off); it is
    built by the chain rule dP = (grad du T) S + F (dS/dE : dE) with dS/dE from `ufl.diff`
    (see `membrane.membrane_forms`). Arguments as there.
    """
    space = u.function_space
    dx = cell_measure(space, quadrature_degree, measure)
    v, du = ufl.TestFunction(space), ufl.TrialFunction(space)
    T = frame.tangents
    F = surface_deformation_gradient(u, frame)
    strain_value = 0.5 * (F.T * F - ufl.Identity(2))
    strain = ufl.variable(strain_value)
    S = law(strain)
    residual = ufl.inner(F * S, ufl.grad(v) * T) * dx
    tangent = ufl.diff(S, strain)
    strain_increment = ufl.derivative(strain_value, u, du)
    i, j, k, m = ufl.indices(4)
    stress_increment = ufl.as_tensor(tangent[i, j, k, m] * strain_increment[k, m], (i, j))
    increment = ufl.grad(du) * T * S + F * stress_increment
    jacobian = ufl.inner(increment, ufl.grad(v) * T) * dx
    return MembraneForms(residual, jacobian)


def pressure_residual(u, pressure, frame: SurfaceFrame, dx: ufl.Measure) -> ufl.Form:
    """The follower pressure's virtual work int p (g1 x g2) . v dA (N; subtract it from R).

    `pressure` (N/mm^2, a Constant scaled by the load factor) pushes towards the reference
    normal's side, on the deformed surface.
    """
    v = ufl.TestFunction(u.function_space)
    F = surface_deformation_gradient(u, frame)
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


def contact_pressure(u, indenter: Indenter, origin, frame: SurfaceFrame):
    """(contact pressure k <-gap> N/mm^2, its unit direction on the fabric) at u, for the
    indenter whose origin is at `origin` (a Constant (3,), mm)."""
    gap, direction = indenter.gap(frame.position + u, origin)
    return penalty_pressure(gap, indenter.penalty), direction


def contact_residual(u, indenter: Indenter, origin, frame: SurfaceFrame, dx: ufl.Measure):
    """The contact force's virtual work int k <-gap> n . v dA (N; subtract it from R)."""
    v = ufl.TestFunction(u.function_space)
    pressure, direction = contact_pressure(u, indenter, origin, frame)
    return pressure * ufl.dot(direction, v) * dx
