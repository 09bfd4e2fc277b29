"""The synthetic surface: an interpolant of the analytic law, stress-free at E = 0, and the
analytic law itself consistent with its potential."""

import numpy as np
import pytest

from fabric_dolfinx.synthetic import StiffeningLaw, synthetic_surface
from rve_rod.errors import InputError

LAW = StiffeningLaw()
RNG = np.random.default_rng(2)


def test_law_is_the_gradient_of_its_potentials():
    E = RNG.uniform(-0.1, 0.3, size=(50, 3))
    h = 1e-6
    S = LAW.stress(E)
    dpsi_11 = (LAW.potential(E[:, 0] + h, E[:, 1]) - LAW.potential(E[:, 0] - h, E[:, 1])) / (2 * h)
    dpsi_22 = (LAW.potential(E[:, 0], E[:, 1] + h) - LAW.potential(E[:, 0], E[:, 1] - h)) / (2 * h)
    dshear = (LAW.shear_potential(E[:, 2] + h) - LAW.shear_potential(E[:, 2] - h)) / (2 * h)
    np.testing.assert_allclose(np.stack([dpsi_11, dpsi_22, dshear], axis=1), S, atol=1e-9)


@pytest.mark.parametrize("kind", ["stress", "energy"])
def test_surface_approximates_the_law_and_is_stress_free_at_zero(kind):
    surface = synthetic_surface(LAW, kind)
    assert surface.kind == kind
    np.testing.assert_allclose(surface.domain, [[-0.1, 0.3], [-0.1, 0.3], [-0.2, 0.2]])
    E = np.column_stack(
        [RNG.uniform(-0.1, 0.3, 400), RNG.uniform(-0.1, 0.3, 400), RNG.uniform(-0.2, 0.2, 400)]
    )
    np.testing.assert_allclose(surface.stress(E).S, LAW.stress(E), atol=1e-3)
    np.testing.assert_allclose(surface.stress(np.zeros(3)).S, 0.0, atol=1e-15)
    shear = surface.stress(E * [0, 0, 1]).S[:, 2] + surface.stress(-E * [0, 0, 1]).S[:, 2]
    np.testing.assert_allclose(shear, 0.0, atol=1e-15)  # S12 odd


def test_stress_surface_interpolates_the_law_at_the_greville_points_up_to_the_shift():
    surface = synthetic_surface(LAW, degree=2, spans=4)
    knots = surface.s11.knots[0]
    greville = (knots[1:-2] + knots[2:-1]) / 2  # degree 2
    x, y = np.meshgrid(greville, greville)
    E = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    # Equal up to one constant per component: the shift that makes S(0) = 0.
    difference = surface.stress(E).S[:, :2] - LAW.stress(E)[:, :2]
    np.testing.assert_allclose(difference - difference[0], 0.0, rtol=0, atol=1e-15)
    assert np.abs(difference[0]).max() > 1e-6  # 0 is no Greville point: the shift is real


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: StiffeningLaw(course_rate=-1.0), "course_rate=-1 must be > 0"),
        (lambda: StiffeningLaw(coupling=1.0), "coupling=1 N/mm must satisfy |c| <"),
        (lambda: synthetic_surface(kind="spline"), "kind='spline' must be"),
        (lambda: synthetic_surface(normal_domain=(0.0, 0.3)), "must contain E = 0"),
    ],
)
def test_bad_synthetic_input_is_rejected(make, message):
    with pytest.raises(InputError) as error:
        make()
    assert message in str(error.value)
