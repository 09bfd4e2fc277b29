"""Where the periodic cell's yarn is cut (`CellSettings.cut`) must not change its answer.

Two cuts that the jersey loop's mirror symmetry about its wale axis maps onto each other (1 -
0.25 and 1 + 0.25 quarter curves) give the same cell: the same force, lateral strain and
bending moments, the support's moment about the period axis opposite. Cuts that no symmetry
relates differ by the two-pass contact's imbalance (docs/patterns.md, "The periodic cut"): by
1-4 % for jersey, seed and garter, by about 20 % for 1x1 rib wale-wise, whose forces at three
cuts are pinned (PATTERN_CUT) so that a balanced contact is noticed."""

import dataclasses

import numpy as np
import pytest
from pins import assert_pinned

from rve_rod.presets import load_preset
from rve_rod.rve.engine import fabric_settings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import simulate

COTTON = load_preset("cotton-20s2", 5.5)


def _at_cut(fabric, name, cut):
    settings = fabric_settings(fabric, 36)
    settings = dataclasses.replace(settings, cell=dataclasses.replace(settings.cell, cut=cut))
    result = simulate(fabric, load_case(name, 0.1, 2), settings, moments=True)
    assert result.complete
    step = result.steps[-1]
    assert step.contacts_at_cut == 0
    return step


@pytest.mark.parametrize("name", ["uniaxial-course", "uniaxial-wale"])
def test_jersey_cuts_mirrored_about_the_wale_axis_give_the_same_cell(name):
    before, after = (_at_cut(COTTON, name, cut) for cut in (0.75, 1.25))
    assert after.force_gf_per_cm == pytest.approx(before.force_gf_per_cm, rel=1e-8)
    assert after.lateral_strain == pytest.approx(before.lateral_strain, rel=1e-8)
    np.testing.assert_allclose(
        after.bending_moment_gf_cm_per_cm, before.bending_moment_gf_cm_per_cm, rtol=1e-7
    )
    assert after.support_reaction[3] == pytest.approx(-before.support_reaction[3], rel=1e-6)
    assert abs(before.support_reaction[3]) > 1e-4  # N mm: a moment to mirror, not a zero


def test_the_rib_cells_wale_wise_force_at_three_cuts_is_pinned():
    rib = dataclasses.replace(COTTON, knit=dataclasses.replace(COTTON.knit, pattern="rib1x1"))
    measured = {
        f"rib1x1 wale force 10 % cut {cut}": _at_cut(rib, "uniaxial-wale", cut).force_gf_per_cm
        for cut in (0.75, 1.0, 1.25)
    }
    assert_pinned("PATTERN_CUT", measured)
