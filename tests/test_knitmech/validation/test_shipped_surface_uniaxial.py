"""The shipped surface, as a material alone in uniaxial tension (free lateral contraction),
reproduces the RVE it was sampled from: its uniaxial runs at the same settings, course- and
wale-wise at 5, 10 and 20 % (issue 14: patch vs RVE within 5 %).

The uniaxial states lie between the surface's rays, where only the fit speaks for the RVE; at
5 % course-wise the knit's lateral stress changes from slack to taut within about 0.02 of E22
(shipped surface at E11 = 0.051: dS22/dE22 0.003 N/mm at E22 = -0.02, 0.076 at the RVE's
-0.011, 0.32 at +0.05), which a fit on too coarse knots smooths over (12 knot spans: the
material alone 15 % softer; docs/benchmarks.md, "Knot spans").
"""

import numpy as np
import pytest

from knitmech.fidelity import DEFAULT, fidelity_level
from knitmech.scene import default_surface_path, load_scene
from knitmech.stages import plan_run
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import simulate
from rve_rod.surface import homogeneous_response, read_surface
from rve_rod.units import n_per_mm_to_gf_per_cm

pytestmark = pytest.mark.slow

STRAINS = (0.05, 0.10, 0.20)


@pytest.mark.parametrize("direction", ["course", "wale"])
def test_shipped_surface_reproduces_the_uniaxial_rve(direction):
    plan = plan_run(load_scene(), fidelity_level(DEFAULT))
    run = simulate(plan.fabric, load_case(f"uniaxial-{direction}", 0.2, 21), plan.rve)
    assert run.complete
    strain = run.series("strain")
    indices = [int(np.argmin(np.abs(strain - value))) for value in STRAINS]
    np.testing.assert_allclose(strain[indices], STRAINS, atol=1e-12)
    rve = np.array([run.steps[i].force_gf_per_cm for i in indices])
    surface = read_surface(default_surface_path())
    material = n_per_mm_to_gf_per_cm(homogeneous_response(surface, list(STRAINS), direction))
    np.testing.assert_allclose(material, rve, rtol=0.05)
