"""The synthetic surface: an interpolant of the analytic law
(tests/test_rve_rod/unit/test_analytic_rve.py), stress-free at E = 0."""

import numpy as np
import pytest
from support.surface_cases import COTTON_LIKE_LAW, synthetic_surface

from rve_rod.errors import InputError
from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.units import n_per_mm_to_gf_per_cm

LAW = COTTON_LIKE_LAW
RNG = np.random.default_rng(2)


def test_cotton_like_law_has_the_documented_stresses():
    # S11 = (k1 / b1) (exp(b1 E11) - 1) at E11 = 0.22: 0.01 (exp(2.64) - 1) = 0.1301 N/mm.
    S = LAW.stress(np.array([[0.22, 0.0, 0.0], [0.0, 0.22, 0.0]]))
    assert n_per_mm_to_gf_per_cm(S[0, 0]) == pytest.approx(132.7, rel=1e-3)
    assert n_per_mm_to_gf_per_cm(S[1, 1]) == pytest.approx(163.7, rel=1e-3)


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
        (
            lambda: synthetic_surface(AnalyticRve(coupling_22_11=0.0), kind="energy"),
            "kind='energy' needs a hyperelastic law: coupling_11_22=0.05 N/mm must equal",
        ),
        (lambda: synthetic_surface(kind="spline"), "kind='spline' must be"),
        (lambda: synthetic_surface(normal_domain=(0.0, 0.3)), "must contain E = 0"),
    ],
)
def test_bad_synthetic_input_is_rejected(make, message):
    with pytest.raises(InputError) as error:
        make()
    assert message in str(error.value)
