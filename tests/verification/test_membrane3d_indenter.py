"""A rigid sphere pushed into a clamped disc (the ball-burst geometry, SVK stand-in): the
reported force converges as the penalty grows (error ~ 1/k) and is independent of it within
0.1 % from k = 100 N/mm^3 on; the force on the sphere balances the clamp's reaction (to the
Newton tolerance)."""

import numpy as np
import pytest

from fabric_dolfinx.material import OrthotropicSVK, svk_material
from fabric_dolfinx.membrane3d import SphereIndenter
from fabric_dolfinx.membrane3d_solve import Membrane3DProblem, Support
from fabric_dolfinx.part_spec import MeshSpec
from fabric_dolfinx.shapes import make_mesh
from fabric_dolfinx.solve import SolverOptions
from rve_rod.errors import InputError

CLAMP, BALL, DEPTH = 22.225, 12.7, 3.0  # mm: ASTM D3787 ring radius, ball radius, travel
SVK = svk_material(OrthotropicSVK(10.0, 10.0, 0.3, 10.0 / 2.6))


@pytest.fixture(scope="module")
def tagged():
    return make_mesh(MeshSpec("disc", {"radius": CLAMP}, element_size=4.0))


def indent(tagged, penalty):
    sphere = SphereIndenter(BALL, (0.0, 0.0, -BALL), (0.0, 0.0, DEPTH), penalty)
    problem = Membrane3DProblem(
        tagged, SVK, [Support("rim")], indenter=sphere, options=SolverOptions(steps=3)
    )
    return problem.run()


def test_force_converges_with_the_penalty(tagged):
    penalties = (10.0, 100.0, 1000.0, 10000.0)
    results = [indent(tagged, k) for k in penalties]
    # the fabric pushes the sphere back (-z)
    forces = -np.array([r.indenter_force[-1, 2] for r in results])
    assert np.all(forces > 0.0)
    changes = np.abs(np.diff(forces)) / forces[-1]
    # error ~ 1/k: each tenfold penalty cuts the change about tenfold
    assert np.all(changes[1:] < 0.2 * changes[:-1]), changes
    # from k = 100 N/mm^3 on, the force is independent of k within 0.1 %
    assert np.all(changes[1:] < 1e-3), changes
    for result in results:
        np.testing.assert_allclose(
            result.indenter_force, result.reactions["rim"], rtol=0, atol=1e-5 * forces[-1]
        )
        assert np.all(np.diff(result.indenter_force[:, 2]) < 0.0)
        assert result.dome_amplitude > 0.0


def test_an_indenter_starting_inside_the_fabric_is_refused(tagged):
    sphere = SphereIndenter(BALL, (0.0, 0.0, -BALL + 0.5), (0.0, 0.0, DEPTH), 100.0)
    with pytest.raises(InputError, match="starts inside the fabric"):
        Membrane3DProblem(tagged, SVK, [Support("rim")], indenter=sphere)
