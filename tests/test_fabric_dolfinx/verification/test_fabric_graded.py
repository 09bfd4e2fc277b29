"""Graded knits: a law interpolated in the stitch value between members of a family.

- A constant stitch at a member's value reproduces that member's solution to round-off, and
  between two SVK members (linear in their constants) the interpolated law is the SVK law with
  interpolated constants: the same solution to round-off.
- A strip whose stitch varies along it (one value per cell) under an edge traction: each
  column of cells is in uniaxial stress with its own modulus, so the elongation is the sum of
  the columns' exact SVK elongations.
- The tangent the solver assembles is consistent: Newton converges quadratically.
"""

import numpy as np
import pytest
import scipy.optimize

from fabric_dolfinx.graded import stitch_weights
from fabric_dolfinx.material import OrthotropicSVK, svk_material
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.part.problem import PartProblem
from fabric_dolfinx.part.regions import Region
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.expression import FieldExpression
from fabric_dolfinx.spec.part import BoundaryCondition, MeshSpec
from rve_rod.errors import InputError

LOOSE = OrthotropicSVK(course_stiffness=1.0, wale_stiffness=0.5, poissons_ratio=0.0)
TIGHT = OrthotropicSVK(course_stiffness=3.0, wale_stiffness=1.5, poissons_ratio=0.0)
FAMILY = ((4.5, svk_material(LOOSE)), (7.0, svk_material(TIGHT)))
STRIP = MeshSpec("rectangle", {"width": 100.0, "height": 20.0}, element_size=10.0)
TRACTION = 0.05


def run_strip(region, traction=(TRACTION, 0.0), shear=0.0):
    conditions = [
        BoundaryCondition("left", "roller", component="x"),
        BoundaryCondition("bottom", "roller", component="y"),
        BoundaryCondition("right", "traction", vector=(traction[0], shear)),
    ]
    problem = PartProblem(make_mesh(STRIP), [region], conditions, options=SolverOptions(steps=2))
    return problem.run()


def blend(weight):
    """The SVK material with constants (1 - weight) LOOSE + weight TIGHT."""
    return OrthotropicSVK(
        course_stiffness=(1 - weight) * 1.0 + weight * 3.0,
        wale_stiffness=(1 - weight) * 0.5 + weight * 1.5,
        poissons_ratio=0.0,
        shear_stiffness=0.2,
    )


@pytest.mark.parametrize(("stitch", "weight"), [(4.5, 0.0), (7.0, 1.0), (5.25, 0.3)])
def test_constant_stitch_reproduces_the_uniform_material(stitch, weight):
    graded = run_strip(Region("fabric", None, stitch=stitch, family=FAMILY), shear=0.01)
    uniform = run_strip(Region("fabric", svk_material(blend(weight))), shear=0.01)
    for name in ("right", "left", "bottom"):
        np.testing.assert_allclose(
            graded.boundaries[name].displacement,
            uniform.boundaries[name].displacement,
            rtol=1e-12,
            atol=1e-13,
        )


def test_a_stitch_graded_along_the_strip_elongates_like_its_columns_in_series():
    stitch = FieldExpression("4.5 + 2.5 * x / 100")
    result = run_strip(Region("fabric", None, stitch=stitch, family=FAMILY))
    centres = np.arange(5.0, 100.0, 10.0)  # 10 columns of 10 mm
    weights = (stitch(centres, 0 * centres) - 4.5) / 2.5
    stiffness = 1.0 + 2.0 * weights

    def strain(E):
        return scipy.optimize.brentq(
            lambda e: (1 + e) * E * ((1 + e) ** 2 - 1) / 2 - TRACTION, 0.0, 1.0, xtol=1e-15
        )

    exact = sum(10.0 * strain(E) for E in stiffness)
    elongation = result.boundaries["right"].displacement[-1, 0]
    assert elongation == pytest.approx(exact, rel=1e-9)
    # the consistent tangent: the last Newton steps of each load step converge quadratically
    for step in result.path.steps:
        norms = np.array(step.residual_norms)
        assert norms[-1] < 1e-10 * norms[0]
        assert step.iterations <= 5


def test_stitch_weights_are_hats_exact_at_the_members():
    """Hand values: a quarter of the way from 4.5 to 5 half each, 5.6 (0.6 of the way from 5
    to 6) 0.4 and 0.6; members exact; every point of an array at once."""
    values = [4.5, 5.0, 6.0, 7.0]
    stitch = np.array([4.5, 4.75, 5.0, 5.6, 6.0, 7.0])
    expected = [
        [1.0, 0.0, 0.0, 0.0],
        [0.5, 0.5, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.4, 0.6, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
    np.testing.assert_allclose(stitch_weights(values, stitch).T, expected, rtol=0, atol=1e-15)


def test_stitch_values_outside_the_family_are_refused():
    stitch = FieldExpression("4.0 + 3.5 * x / 100")
    with pytest.raises(InputError, match=r"stitch values 4\.175 \.\.\. 7\.325 mm leave"):
        run_strip(Region("fabric", None, stitch=stitch, family=FAMILY))
    with pytest.raises(InputError, match="a graded region needs its stitch value"):
        Region("fabric", None, family=FAMILY)
