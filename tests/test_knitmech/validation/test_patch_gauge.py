"""The centre gauge of the patch tension test (`knitmech.jobs.patch.PatchProbe`), a tensile test's
extensometer: without lateral coupling the patch deforms homogeneously and the gauge reads the
nominal strain and no contraction; with coupling the clamps hold the fabric's width at its
ends, and the force where the gauge reads a strain lies between the material's with its width
free and held."""

import dataclasses

import numpy as np
import pytest
from support.surface_cases import COTTON_LIKE_LAW, synthetic_surface

from fabric_dolfinx.spec.tension import TensionTest
from knitmech.jobs.patch import run_patch
from knitmech.report import value_at
from knitmech.stages.records import PatchJob
from rve_rod.surface import homogeneous_response, write_surface
from rve_rod.units import n_per_mm_to_gf_per_cm

STEPS = 8
CONTRACTING = dataclasses.replace(COTTON_LIKE_LAW, coupling_11_22=0.04, coupling_22_11=0.04)
"""A fabric that narrows like a knit (Poisson ratios about 0.5-0.8 at small strains)."""
SURFACE = synthetic_surface(CONTRACTING, normal_domain=(-0.3, 0.3))


def patch(tmp_path, law, direction):
    path = tmp_path / "surface.h5"
    write_surface(path, synthetic_surface(law, normal_domain=(-0.3, 0.3)))
    test = TensionTest(direction=direction, elements=8, max_strain=0.2)
    return run_patch(PatchJob(test=test, steps=STEPS, field_step=2), path, tmp_path)


@pytest.mark.parametrize("direction", ["course", "wale"])
def test_without_coupling_the_gauge_reads_the_nominal_strain_and_no_contraction(
    tmp_path, direction
):
    law = dataclasses.replace(COTTON_LIKE_LAW, coupling_11_22=0.0, coupling_22_11=0.0)
    summary = patch(tmp_path, law, direction)
    assert summary.complete
    assert np.asarray(summary.gauge_strain) == pytest.approx(summary.strain, abs=1e-9)
    assert np.asarray(summary.gauge_lateral_strain) == pytest.approx(0.0, abs=1e-9)
    assert np.asarray(summary.lateral_strain) == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("direction", ["course", "wale"])
def test_with_coupling_the_centre_force_lies_between_free_and_held_contraction(tmp_path, direction):
    """Where the centre gauge reads the strain, the patch carries at least the material's
    uniaxial force (width free) and at most its strip-biaxial one (width held)."""
    summary = patch(tmp_path, CONTRACTING, direction)
    strain = summary.strain[-2]
    assert summary.gauge_lateral_strain[-1] < 0.0 and summary.lateral_strain[-1] < 0.0
    free, held = (
        n_per_mm_to_gf_per_cm(homogeneous_response(SURFACE, [strain], direction, lateral)[0])
        for lateral in ("free", "fixed")
    )
    centre = value_at(summary.gauge_strain, summary.force_gf_per_cm, strain)
    assert free < centre < held
    assert held - free > 0.02 * free  # the bounds are apart: the test can tell
