"""Where the periodic cell's yarn is cut (`CellSettings.cut`) must not change its answer.

Two cuts that the jersey loop's mirror symmetry about its wale axis maps onto each other (1 -
0.25 and 1 + 0.25 quarter curves) give the same cell: the same force, lateral strain and
bending moments, the support's moment about the period axis opposite. Cuts that no symmetry
relates differ (docs/patterns.md, "The periodic cut"): by 1-4 % for jersey, seed and garter,
by about 20 % for 1x1 rib wale-wise, whose forces at three cuts are pinned (PATTERN_CUT). The
cause is the point support, which sits in the middle of the first patch and so moves along
the yarn with the cut, and holds a moment about the course axis: with its rotation
regularized (`CellSettings.support_rotation = "regularized"`) the spreads fall to 0.01-1 %
and the moment to zero."""

import dataclasses

import numpy as np
import pytest
from pins import assert_pinned

from rve_rod.errors import InputError
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.engine import fabric_settings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import simulate

COTTON = load_preset("cotton-20s2", 5.5)


def _at_cut(fabric, name, cut, support_rotation="held"):
    settings = fabric_settings(fabric, 36)
    cell = dataclasses.replace(settings.cell, cut=cut, support_rotation=support_rotation)
    settings = dataclasses.replace(settings, cell=cell)
    result = simulate(fabric, load_case(name, 0.1, 2), settings, moments=True)
    assert result.complete
    step = result.steps[-1]
    assert step.contacts_at_cut == 0
    return step


def _pattern(name):
    return dataclasses.replace(COTTON, knit=dataclasses.replace(COTTON.knit, pattern=name))


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
    rib = _pattern("rib1x1")
    measured = {
        f"rib1x1 wale force 10 % cut {cut}": _at_cut(rib, "uniaxial-wale", cut).force_gf_per_cm
        for cut in (0.75, 1.0, 1.25)
    }
    assert_pinned("PATTERN_CUT", measured)


@pytest.mark.parametrize(
    ("pattern", "name", "held_spread", "spread"),
    [("rib1x1", "uniaxial-wale", 0.15, 0.02), ("garter", "uniaxial-wale", 0.03, 0.001)],
)
def test_with_the_support_rotation_regularized_the_cut_leaves_the_answer(
    pattern, name, held_spread, spread
):
    """Measured (36 control points, 10 % in 2 steps): rib wale-wise 2.23 / 2.37 / 2.72 gf/cm
    held, 2.26 / 2.26 / 2.24 regularized (19.7 % -> 1.0 %); garter wale-wise 16.72 / 17.43 /
    16.75 held, 16.64 at every cut regularized (4.2 % -> 0.01 %); the support's moment from up
    to 3.7 mN mm to below 2e-3 mN mm."""
    fabric = _pattern(pattern)
    spreads = {}
    for support in ("held", "regularized"):
        steps = [_at_cut(fabric, name, cut, support) for cut in (0.75, 1.0, 1.25)]
        forces = np.array([step.force_gf_per_cm for step in steps])
        spreads[support] = np.ptp(forces) / forces.mean()
        if support == "regularized":
            assert max(abs(step.support_reaction[3]) for step in steps) < 1e-5  # N mm
    assert spreads["held"] > held_spread
    assert spreads["regularized"] < spread


def test_the_regularized_support_is_the_held_one_where_the_cell_holds_no_moment():
    """At jersey's default cut the support sits on the loop's mirror axis, where the held
    rotation carries no moment: the spring does nothing there."""
    held = _at_cut(COTTON, "uniaxial-wale", 1.0)
    regularized = _at_cut(COTTON, "uniaxial-wale", 1.0, "regularized")
    assert abs(held.support_reaction[3]) < 1e-9
    assert regularized.force_gf_per_cm == pytest.approx(held.force_gf_per_cm, rel=1e-8)


def test_an_unknown_support_rotation_is_refused():
    with pytest.raises(InputError, match="support_rotation='loose' is unknown; valid: held"):
        CellSettings(support_rotation="loose")
    with pytest.raises(InputError, match="needs lateral_stiffness > 0"):
        CellSettings(support_rotation="regularized", lateral_stiffness=0.0)
