"""The analytic stand-in law: stress is the gradient of its energy; bad parameters are refused."""

import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.homogenize.analytic import AnalyticRve


@pytest.mark.parametrize(
    "law",
    [
        AnalyticRve(),
        AnalyticRve(
            course_stiffness=0.12,
            course_stiffening=12.0,
            coupling_11_22=-0.02,
            coupling_22_11=-0.02,
            shear_stiffening_strain=0.3,
        ),
    ],
    ids=["default", "other"],
)
def test_stress_is_the_gradient_of_the_energy(law):
    # W(E11, E22, E12) with tensor shear: dW/dE12 = 2 S12.
    E = np.random.default_rng(2).uniform(-0.1, 0.3, size=(50, 3))
    h = 1e-6
    gradient = np.stack(
        [(law.energy(E + h * e) - law.energy(E - h * e)) / (2 * h) for e in np.eye(3)], axis=1
    )
    np.testing.assert_allclose(gradient, law.stress(E) * [1, 1, 2], rtol=1e-8, atol=1e-10)


@pytest.mark.parametrize(
    ("parameters", "message"),
    [
        ({"course_stiffening": -1.0}, "course_stiffening=-1 must be > 0"),
        ({"coupling_22_11": np.inf}, "coupling_22_11=inf"),
        ({"coupling_11_22": 0.3, "coupling_22_11": 0.4}, "coupling (c12 + c21)/2=0.35 N/mm"),
        ({"compression_limit": 0.0}, "compression_limit=0 must be > 0"),
    ],
)
def test_bad_parameters_are_refused(parameters, message):
    with pytest.raises(InputError) as error:
        AnalyticRve(**parameters)
    assert message in str(error.value)
