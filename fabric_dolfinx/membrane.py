"""Large-strain plane-stress membrane in total Lagrangian form: kinematics, stresses, forms.

Unknown: the in-plane displacement u (mm) on the undeformed configuration. F = I + grad u,
E = (F^T F - I) / 2, S from a material law (N/mm, force per unit undeformed width: the law
already is a plane-stress membrane law), P = F S, residual R(u; v) = int P : grad v dX.
The consistent tangent is the Gateaux derivative of R, assembled by UFL (see
`membrane_forms` for how it is split to keep the generated kernels small).
"""

from typing import NamedTuple

import ufl

from fabric_dolfinx.material import StressLaw, rotation

__all__ = [
    "MembraneForms",
    "MembraneStress",
    "cauchy_stress",
    "cell_measure",
    "deformation_gradient",
    "green_lagrange_strain",
    "membrane_forms",
    "membrane_stress",
]


def deformation_gradient(u: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
    """F = I + grad u, shape (2, 2), dimensionless."""
    return ufl.Identity(2) + ufl.grad(u)


def green_lagrange_strain(F: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
    """E = (F^T F - I) / 2, shape (2, 2), dimensionless (tensor shear E12)."""
    return 0.5 * (F.T * F - ufl.Identity(2))


def cauchy_stress(F: ufl.core.expr.Expr, S: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
    """sigma = F S F^T / J with J = det F (membrane area ratio): N/mm per deformed width."""
    return F * S * F.T / ufl.det(F)


class MembraneStress(NamedTuple):
    """UFL expressions of the membrane state at the displacement u (all shape (2, 2)).

    Attributes:
        deformation_gradient: F.
        strain: Green-Lagrange strain E in the global frame.
        material_strain: E in the material frame, R^T E R (axis 1 course-wise).
        second_piola_kirchhoff: S in the global frame, N/mm.
        first_piola_kirchhoff: P = F S, N/mm (force per undeformed width).
        cauchy: sigma = F S F^T / det F, N/mm (force per deformed width).
    """

    deformation_gradient: ufl.core.expr.Expr
    strain: ufl.core.expr.Expr
    material_strain: ufl.core.expr.Expr
    second_piola_kirchhoff: ufl.core.expr.Expr
    first_piola_kirchhoff: ufl.core.expr.Expr
    cauchy: ufl.core.expr.Expr


class MembraneForms(NamedTuple):
    """The nonlinear system of the membrane: residual R(u; v) and its Jacobian dR/du."""

    residual: ufl.Form
    jacobian: ufl.Form


def membrane_stress(u: ufl.Coefficient, law: StressLaw, angle=0.0) -> MembraneStress:
    """The membrane state for the displacement `u` and the material `law` rotated by `angle`.

    `angle` (radians, x axis to course direction) is a number, a `fem.Constant` or a scalar
    field; the law sees the material-frame strain R^T E R and its stress is rotated back.
    """
    F = deformation_gradient(u)
    E = green_lagrange_strain(F)
    R = rotation(angle)
    material_strain = R.T * E * R
    S = R * law(material_strain) * R.T
    P = F * S
    return MembraneStress(F, E, material_strain, S, P, cauchy_stress(F, S))


def cell_measure(space, quadrature_degree: int | None = None, measure=None):
    """The cell measure of the membrane forms: `measure` (e.g. `dx(region)` of a cell-tagged
    mesh; default the whole mesh of `space`) with a Gauss rule exact to `quadrature_degree`
    (default twice the element degree: 2 x 2 points for Q1, 3 x 3 for Q2)."""
    if quadrature_degree is None:
        quadrature_degree = 2 * space.ufl_element().degree()
    metadata = {"quadrature_degree": quadrature_degree}
    if measure is None:
        return ufl.dx(domain=space.mesh, metadata=metadata)
    return measure.reconstruct(metadata=metadata)


def membrane_forms(
    u: ufl.Coefficient,
    law: StressLaw,
    angle=0.0,
    quadrature_degree: int | None = None,
    measure: ufl.Measure | None = None,
) -> MembraneForms:
    """Residual int P : grad v dX and its consistent Jacobian for the displacement `u`.

    The Jacobian equals `ufl.derivative(residual, u)` (a test checks it to round-off) but is
    assembled by the chain rule dP = grad(du) S + F R (dS_m/dE_m : dE_m) R^T, with the material
    tangent dS_m/dE_m from `ufl.diff`. Differentiating the whole residual with
    `ufl.derivative` pushes the argument into every polynomial piece of the response-surface
    splines, and FFCx then factorizes each piece against each argument component: for a
    16 x 16 cubic surface that kernel holds 9600 intermediate values per quadrature point and
    takes 30 s to compile, against 3700 and 10 s here (docs/benchmarks.md).

    Args:
        quadrature_degree: Gauss rule per direction exact to this degree; default twice the
            element degree (2 x 2 points for Q1, 3 x 3 for Q2).
        measure: the cell measure to integrate over, e.g. `dx(region)` of a cell-tagged
            mesh (several regions, one law each: sum their forms); default the whole mesh.
            Its metadata is replaced by the quadrature degree.
    """
    space = u.function_space
    dx = cell_measure(space, quadrature_degree, measure)
    v = ufl.TestFunction(space)
    du = ufl.TrialFunction(space)
    F = deformation_gradient(u)
    R = rotation(angle)
    material_strain_value = R.T * green_lagrange_strain(F) * R
    material_strain = ufl.variable(material_strain_value)
    material_stress = law(material_strain)
    S = R * material_stress * R.T
    residual = ufl.inner(F * S, ufl.grad(v)) * dx
    tangent = ufl.diff(material_stress, material_strain)
    strain_increment = ufl.derivative(material_strain_value, u, du)
    i, j, k, m = ufl.indices(4)
    stress_increment = ufl.as_tensor(tangent[i, j, k, m] * strain_increment[k, m], (i, j))
    increment = ufl.grad(du) * S + F * (R * stress_increment * R.T)
    jacobian = ufl.inner(increment, ufl.grad(v)) * dx
    return MembraneForms(residual=residual, jacobian=jacobian)
