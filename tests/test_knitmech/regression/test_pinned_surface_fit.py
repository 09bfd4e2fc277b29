"""Regression pins of the response-surface fit (tests/pins.py, SHIPPED_SURFACE_FIT): the
shipped surface (knitmech/data/cotton-20s2_stitch-5.5.h5) re-fitted from the samples and with
the fit options stored in it (0.4 s, no RVE run). The re-fit must also reproduce the residuals
stored in the file: the file is what the current fit makes of its samples (docs/pipeline.md
says how to remake it)."""

import numpy as np
from pins import assert_pinned

from knitmech.scene import default_surface_path
from rve_rod.homogenize.fit import FitOptions, fit_stress_surface
from rve_rod.homogenize.samples import stored_samples
from rve_rod.surface import read_surface


def test_refit_of_the_shipped_surface_reproduces_its_pinned_residuals():
    shipped = read_surface(default_surface_path())
    options = {key: value for key, value in shipped.parameters["fit"].items() if key != "kind"}
    assert shipped.kind == shipped.parameters["fit"]["kind"] == "stress"
    refit = fit_stress_surface(stored_samples(shipped), FitOptions(**options))
    for group in ("S11", "S22", "S12"):
        scale = np.abs(shipped.samples[group].values).max()
        np.testing.assert_allclose(
            refit.samples[group].residuals, shipped.samples[group].residuals, atol=1e-9 * scale
        )
    stats = refit.residual_stats()
    measured = {}
    for group in ("S11", "S22", "S12"):
        measured[f"{group} max abs"] = stats[group].max_abs
        measured[f"{group} rms abs"] = stats[group].rms_abs
    assert_pinned("SHIPPED_SURFACE_FIT", measured)
