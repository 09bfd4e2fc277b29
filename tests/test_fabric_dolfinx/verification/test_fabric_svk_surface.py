"""A response surface that is exactly an orthotropic Saint Venant-Kirchhoff law (bilinear
splines) against the SVK law itself: in closed form for homogeneous tension, and through the
finite-element patch test the two UFL paths must give the same forces."""

import numpy as np
import pytest

from fabric_dolfinx.material import OrthotropicSVK, surface_material, svk_material
from fabric_dolfinx.part.tension import TensionSetup
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.tension import TensionTest
from rve_rod.surface import ResponseSurface, Spline1D, Spline2D, homogeneous_response

SVK = OrthotropicSVK(
    course_stiffness=1.0, wale_stiffness=0.5, poissons_ratio=0.3, shear_stiffness=0.2
)
C = SVK.plane_stress_matrix()
KNOTS = np.array([-0.5, -0.5, 0.5, 0.5])  # degree 1: linear functions are exact, also outside
ENDS = np.array([-0.5, 0.5])
EXACT = ResponseSurface(
    kind="stress",
    s11=Spline2D((1, 1), (KNOTS, KNOTS), C[0, 0] * ENDS[:, None] + C[0, 1] * ENDS[None, :]),
    s22=Spline2D((1, 1), (KNOTS, KNOTS), C[1, 0] * ENDS[:, None] + C[1, 1] * ENDS[None, :]),
    s12=Spline1D(1, KNOTS, C[2, 2] * ENDS),
)


@pytest.mark.parametrize(("direction", "modulus", "strip"), [("course", 1.0, 0), ("wale", 0.5, 1)])
def test_homogeneous_response_in_closed_form(direction, modulus, strip):
    """Uniaxial: S across = 0 leaves P = F E1 E11; strip-biaxial: P = F Q11 E11."""
    strain = np.array([0.01, 0.1, 0.3])
    E = ((1 + strain) ** 2 - 1) / 2
    uniaxial = homogeneous_response(EXACT, strain, direction, "free")
    fixed = homogeneous_response(EXACT, strain, direction, "fixed")
    np.testing.assert_allclose(uniaxial, (1 + strain) * modulus * E, rtol=1e-12)
    np.testing.assert_allclose(fixed, (1 + strain) * C[strip, strip] * E, rtol=1e-12)


@pytest.mark.parametrize("angle", [0.0, 35.0])
def test_exact_surface_and_svk_give_the_same_patch_forces(angle):
    test = TensionTest(max_strain=0.3, angle=angle, elements=6)
    options = SolverOptions(steps=3)
    surface = TensionSetup(surface_material(EXACT), test, options).run()
    svk = TensionSetup(svk_material(SVK), test, options).run()
    np.testing.assert_allclose(surface.force_n_per_mm, svk.force_n_per_mm, rtol=1e-10, atol=0)
    assert surface.outside_domain is False and svk.outside_domain is False
