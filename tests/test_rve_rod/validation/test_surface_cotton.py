"""The cotton 20s/2, stitch 5.5 response surface from the rod RVE: fit residuals bounded.

The bounds are fit-quality targets for a usable surface, not values taken from a run.
"""

import pytest

from rve_rod.cache import ResultCache
from rve_rod.homogenize.generate import generate_surface
from rve_rod.homogenize.sampling import SamplingPlan
from rve_rod.presets import load_preset
from rve_rod.rve.engine import surface_engine


@pytest.mark.slow
def test_cotton_surface_residuals_are_bounded(tmp_path):
    plan = SamplingPlan(rays=8, steps_per_ray=5, shear_steps=5)
    generated = generate_surface(
        load_preset("cotton-20s2", 5.5), surface_engine(), plan, cache=ResultCache(tmp_path), jobs=2
    )
    for kind, report in generated.reports.items():
        for group, stats in report.residuals.items():
            assert stats.max_rel < 0.05, f"{kind} fit, {group}: {stats}"
    assert generated.reports["energy"].tangent_asymmetry < 1e-12
    # S = F^-1 P is symmetric for a cell in balance; the two-pass contact is not (docs/rve.md:
    # about 2 % error in the shear components). Measured: 0.4 % on the old loop, 1.2 % on the
    # flatter loop model M, whose head wraps more of the legs above; bound 1.5 %.
    assert generated.samples.max_asymmetry < 1.5e-2 * abs(generated.samples.biaxial_stress).max()
