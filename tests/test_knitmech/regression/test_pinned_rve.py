"""Regression pins of the RVE (tests/pins.py, RVE_FAST and RVE_SECTION_FAST): uniaxial forces at
10 and 20 % and the effective Poisson ratios at 20 %, course- and wale-wise, for cotton 20s/2 at
stitch 5.5 at the fast level's settings (2.5 % steps; about 1 s a run), with the default bending
rigidity (the cotton fibres'; the fast level's 28 control points per quarter loop) and the
paper's (the section's; 20 control points, the fast level's when it was the default).

`simulate` keeps no cache on disk (only the loop geometry is memoized, in memory), so these
runs are computed afresh in every session.
"""

import pytest
from pins import assert_pinned, uniaxial_numbers

from knitmech.fidelity import LEVELS
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import RveSettings, simulate
from rve_rod.rve.yarn import YarnSettings

STATES = 9  # 0-20 % in 2.5 % steps: 10 % is state 4, 20 % state 8


@pytest.mark.parametrize(
    ("bending", "control_points", "table"),
    [("auto", LEVELS["fast"].control_points, "RVE_FAST"), ("section", 20, "RVE_SECTION_FAST")],
)
def test_rve_forces_and_poisson_ratios_of_cotton_5_5_are_pinned(bending, control_points, table):
    fast = RveSettings(
        cell=CellSettings(control_points=control_points), yarn=YarnSettings(bending=bending)
    )
    fabric = load_preset("cotton-20s2", 5.5)
    measured = {}
    for direction in ("course", "wale"):
        result = simulate(fabric, load_case(f"uniaxial-{direction}", 0.2, STATES), fast)
        measured |= uniaxial_numbers(result, "", direction, STATES)
    assert_pinned(table, measured)
