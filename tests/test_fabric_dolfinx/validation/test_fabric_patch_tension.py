"""The paper's patch tension test against what the material alone predicts: the clamped
patch's force lies between the uniaxial-stress response (lateral contraction free) and the
strip-biaxial one (lateral contraction prevented), both from the numpy surface evaluation;
strains beyond the surface domain give one warning and the run goes on."""

import logging

import numpy as np
import pytest
import scipy.optimize
from support.surface_cases import synthetic_surface

from fabric_dolfinx.material import surface_material
from fabric_dolfinx.part.tension import TensionSetup
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.tension import TensionTest

SURFACE = synthetic_surface()
MATERIAL = surface_material(SURFACE)


def homogeneous_bounds(strain: float, axis: int) -> tuple[float, float]:
    """First Piola-Kirchhoff P (N/mm) along `axis` at F = 1 + strain along it, with the other
    stretch free (S = 0 across: uniaxial) or held at 1 (strip-biaxial)."""
    other = 1 - axis
    E_load = ((1.0 + strain) ** 2 - 1.0) / 2.0

    def stress(E_lateral):
        E = np.zeros(3)
        E[axis], E[other] = E_load, E_lateral
        return SURFACE.stress(E).S[0]

    lateral = scipy.optimize.brentq(lambda e: stress(e)[other], -0.4, 0.4, xtol=1e-14)
    return (1.0 + strain) * stress(lateral)[axis], (1.0 + strain) * stress(0.0)[axis]


@pytest.mark.parametrize(("direction", "axis"), [("course", 0), ("wale", 1)])
def test_clamped_patch_force_lies_between_uniaxial_and_strip_biaxial(direction, axis):
    result = TensionSetup(MATERIAL, TensionTest(direction=direction), SolverOptions(steps=10)).run()
    assert not result.outside_domain
    assert np.all(np.diff(result.force_n_per_mm) > 0.0)
    for strain, force in zip(result.strain[1:], result.force_n_per_mm[1:], strict=True):
        uniaxial, strip = homogeneous_bounds(strain, axis)
        assert uniaxial < force < strip


def test_strains_beyond_the_surface_domain_warn_once_and_continue(caplog):
    """E11 = 0.3 (the domain's end) is reached at 26.5 % strain; the path goes to 35 %."""
    setup = TensionSetup(MATERIAL, TensionTest(max_strain=0.35), SolverOptions(steps=7))
    with caplog.at_level(logging.WARNING, logger="fabric_dolfinx.part.range_check"):
        result = setup.run()
    warnings = [r for r in caplog.records if r.name == "fabric_dolfinx.part.range_check"]
    assert len(warnings) == 1
    assert "left the response-surface domain at load 0.3" in warnings[0].getMessage()
    assert result.outside_domain and result.strain[-1] == pytest.approx(0.35)
    assert np.all(np.diff(result.force_n_per_mm) > 0.0)
