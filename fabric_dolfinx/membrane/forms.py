"""The large-strain membrane in total Lagrangian form, in the plane and in space: frames,
kinematics, stresses, forms.

One formulation for every part (lengths mm). The unknown is the displacement u of every
point X of the reference surface, with 2 components (a plane part: plane stress) or 3 (a
part that moves in space); the reference surface is flat (a mesh of gdim 2) or curved (a
gmsh surface in space, gdim 3). At each point the fabric's material axes a1 (course) and a2
(wale) are orthonormal tangents of the reference surface, the columns of the frame T
(gdim x 2; on a flat reference the rotation by the course angle). The surface deformation
gradient in the course/wale frame is

    F = (I + grad u) T                    (components x 2; I the embedding of the reference)

whose columns g_a = F e_a are the deformed material lines. E = (F^T F - I) / 2 (2 x 2,
material frame, tensor shear E12), S = law(E) (N/mm, force per undeformed width: the law
already is a membrane law, `fabric_dolfinx.material`; the forms see S and its tangent at the
quadrature points, `fabric_dolfinx.membrane.quadrature`), P = F S and the weak form

    R(u; v) = int P : (grad v T) dA = 0.

On a flat frame with 2 components this is the plane membrane (F T = (I + grad u) R, so the
law sees R^T E R); with 3 components in-plane states equal it to round-off. The consistent
tangent is the Gateaux derivative of R, assembled by the chain rule (`membrane_forms`).
Loads in space (pressure, indenters) are in `fabric_dolfinx.membrane.loads`.
"""

from collections.abc import Callable
from typing import NamedTuple

import ufl

from fabric_dolfinx.membrane.quadrature import QuadratureMaterial
from rve_rod.errors import InputError, check_integer

__all__ = [
    "MaterialFrame",
    "MembraneForms",
    "MembraneState",
    "curved_frame",
    "deformation_gradient",
    "flat_frame",
    "green_lagrange",
    "material_frame",
    "membrane_forms",
    "membrane_state",
    "rotation",
]

VectorField = Callable[[ufl.core.expr.Expr], ufl.core.expr.Expr]
"""A vector field of the reference position: X (3,) -> UFL vector (3,)."""


class MaterialFrame(NamedTuple):
    """The material frame of the reference surface at every point.

    Attributes:
        tangents: T (gdim x 2), columns a1 (course) and a2 (wale), orthonormal.
        embedding: I (components x gdim), the reference position among the displacement's
            components (the identity unless a flat reference moves in space).
        position: X (components,), the reference position (mm).
        normal: N = a1 x a2 (3,), the side a positive pressure pushes towards; None for 2
            components.
    """

    tangents: ufl.core.expr.Expr
    embedding: ufl.core.expr.Expr
    position: ufl.core.expr.Expr
    normal: ufl.core.expr.Expr | None

    @property
    def components(self) -> int:
        """The displacement's components: 2 (plane) or 3 (in space)."""
        return self.embedding.ufl_shape[0]


def rotation(angle) -> ufl.core.expr.Expr:
    """R (2, 2) whose columns are the material axes a1 = (cos phi, sin phi), a2 = (-sin, cos).

    `angle` phi (radians, from the x axis to the course direction) is a number, a
    `fem.Constant` or a scalar field (DG0 or CG `fem.Function`).
    """
    c, s = ufl.cos(angle), ufl.sin(angle)
    return ufl.as_matrix([[c, -s], [s, c]])


def flat_frame(mesh, angle=0.0, components: int = 2) -> MaterialFrame:
    """The frame of a flat mesh (gdim 2) with the course at `angle` radians from the x axis
    (a number, a Constant or a DG0 field), for a displacement with `components` 2 (plane) or
    3 (in space; normal +z)."""
    check_integer("components", components, 2, 3)
    x = ufl.SpatialCoordinate(mesh)
    if components == 2:
        return MaterialFrame(rotation(angle), ufl.Identity(2), ufl.as_vector([x[0], x[1]]), None)
    return MaterialFrame(
        tangents=rotation(angle),
        embedding=ufl.as_matrix([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]),
        position=ufl.as_vector([x[0], x[1], 0.0]),
        normal=ufl.as_vector([0.0, 0.0, 1.0]),
    )


def curved_frame(mesh, course: VectorField, side: VectorField) -> MaterialFrame:
    """The frame of a curved surface mesh (gdim 3; 3 components).

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
    return MaterialFrame(tangents, ufl.Identity(3), ufl.as_vector([x[i] for i in range(3)]), normal)


def material_frame(mesh, components: int = 2, angle=0.0, course=None, side=None) -> MaterialFrame:
    """`flat_frame(mesh, angle, components)` for gdim 2, `curved_frame(mesh, course, side)`
    for gdim 3 (InputError naming the missing field when a curved mesh has no course or
    side field)."""
    gdim = mesh.geometry.dim
    if gdim == 2:
        return flat_frame(mesh, angle, components)
    missing = [name for name, value in (("course", course), ("side", side)) if value is None]
    if missing:
        raise InputError(
            f"a curved surface mesh (gdim {gdim}) needs the {' and '.join(missing)} direction "
            "field: the course direction is a tangent field the scene must give"
        )
    return curved_frame(mesh, course, side)


def deformation_gradient(u, frame: MaterialFrame) -> ufl.core.expr.Expr:
    """F = (I + grad u) T, shape (components, 2): the deformed course and wale line elements."""
    return (frame.embedding + ufl.grad(u)) * frame.tangents


def _area_ratio(F: ufl.core.expr.Expr) -> tuple[ufl.core.expr.Expr, ufl.core.expr.Expr | None]:
    """(J, deformed unit normal or None): J = det F for 2 components, |g1 x g2| for 3."""
    if F.ufl_shape[0] == 2:
        return ufl.det(F), None
    area = ufl.cross(F[:, 0], F[:, 1])
    J = ufl.sqrt(ufl.dot(area, area))
    return J, area / J


def green_lagrange(u, frame: MaterialFrame) -> ufl.core.expr.Expr:
    """E = (F^T F - I) / 2 (2, 2), the Green-Lagrange strain in the material frame (tensor
    shear E12): what the material law sees (`fabric_dolfinx.membrane.quadrature`)."""
    F = deformation_gradient(u, frame)
    return 0.5 * (F.T * F - ufl.Identity(2))


class MembraneState(NamedTuple):
    """UFL expressions of the membrane state at the displacement u.

    Attributes:
        deformation_gradient: F = (I + grad u) T (components, 2).
        strain: Green-Lagrange strain E (2, 2), material frame (course, wale).
        reference_strain: T E T^T (gdim, gdim), E in the axes of the mesh (for a plane part
            the global-frame strain).
        second_piola_kirchhoff: S (2, 2), material frame, N/mm.
        area_ratio: J, deformed over reference area (det F, or |g1 x g2| in space).
        cauchy: sigma = F S F^T / J (components, components), N/mm per deformed width.
        normal: the deformed unit normal (3,), None for 2 components.
    """

    deformation_gradient: ufl.core.expr.Expr
    strain: ufl.core.expr.Expr
    reference_strain: ufl.core.expr.Expr
    second_piola_kirchhoff: ufl.core.expr.Expr
    area_ratio: ufl.core.expr.Expr
    cauchy: ufl.core.expr.Expr
    normal: ufl.core.expr.Expr | None


def membrane_state(u, stress: ufl.core.expr.Expr, frame: MaterialFrame) -> MembraneState:
    """The membrane state for the displacement `u`, the stress S (2, 2) in the material frame
    (`QuadratureMaterial.stress`: valid at its quadrature points) and the `frame`."""
    F = deformation_gradient(u, frame)
    E = green_lagrange(u, frame)
    J, normal = _area_ratio(F)
    T = frame.tangents
    return MembraneState(F, E, T * E * T.T, stress, J, F * stress * F.T / J, normal)


class MembraneForms(NamedTuple):
    """The nonlinear system of the membrane: residual R(u; v) and its Jacobian dR/du."""

    residual: ufl.Form
    jacobian: ufl.Form


def membrane_forms(u, material: QuadratureMaterial, frame: MaterialFrame) -> MembraneForms:
    """Internal-force residual int P : (grad v T) dA over the whole mesh (each cell's law is
    in `material`) and its consistent Jacobian.

    S and the material tangent dS/dE are the quadrature Functions of `material` (call its
    `update` at the current u before assembling either form). The Jacobian is the chain rule
    dP = (grad du T) S + F (dS/dE : dE) with dE = ((grad du T)^T F + F^T (grad du T)) / 2:
    the Gateaux derivative of the residual, as `ufl.derivative` would give it with the law
    inside the form (a test checks it against finite differences and quadratic Newton
    convergence).

    Args:
        material: S and dS/dE at the quadrature points (`QuadratureMaterial` of the strain
            `green_lagrange(u, frame)`); its Gauss rule is the forms'.
        frame: the material frame (`flat_frame`, `curved_frame`), with as many components
            as `u`.
    """
    space = u.function_space
    dx = material.measure()
    v, du = ufl.TestFunction(space), ufl.TrialFunction(space)
    T = frame.tangents
    F = deformation_gradient(u, frame)
    S = material.stress
    residual = ufl.inner(F * S, ufl.grad(v) * T) * dx
    strain_increment = ufl.derivative(green_lagrange(u, frame), u, du)
    increment = ufl.grad(du) * T * S + F * material.stress_increment(strain_increment)
    jacobian = ufl.inner(increment, ufl.grad(v) * T) * dx
    return MembraneForms(residual, jacobian)
