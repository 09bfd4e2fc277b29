"""Regression pins of the response-surface fit (tests/pins.py, SHIPPED_SURFACE_FIT): the
shipped surface (knitmech/data/cotton-20s2_stitch-5.5.h5) re-fitted from the samples and with
the fit options stored in it (0.4 s, no RVE run). The re-fit must also reproduce the residuals
stored in the file: the file is what the current fit makes of its samples (docs/pipeline.md
says how to remake it)."""

import numpy as np
from pins import assert_pinned

from knitmech.scene import default_surface_path
from rve_rod.homogenize.fit import FitOptions, fit_stress_surface
from rve_rod.homogenize.samples import SurfaceSamples
from rve_rod.surface import read_surface


def stored_samples(surface):
    """The file's samples as the fit takes them: S11 and S22 share the (E11, E22) inputs, S12
    has E12 only (the fit reads no other component, so the others are left 0)."""
    groups = surface.samples
    np.testing.assert_array_equal(groups["S11"].inputs, groups["S22"].inputs)
    biaxial_strain = np.zeros((groups["S11"].values.size, 3))
    biaxial_strain[:, :2] = groups["S11"].inputs
    biaxial_stress = np.zeros_like(biaxial_strain)
    biaxial_stress[:, 0], biaxial_stress[:, 1] = groups["S11"].values, groups["S22"].values
    shear_strain = np.zeros((groups["S12"].values.size, 3))
    shear_strain[:, 2] = groups["S12"].inputs[:, 0]
    shear_stress = np.zeros_like(shear_strain)
    shear_stress[:, 2] = groups["S12"].values
    return SurfaceSamples(
        biaxial_strain, biaxial_stress, shear_strain, shear_stress, np.ones(1, bool), 0.0
    )


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
