"""Model loop length against the reference data (Vassiliadis sample 2, the six cotton fabrics).

Target (issue 2): within 4 % of the measured loop length, with the yarns 2r apart.
"""

import pytest

from rve_rod.geometry.loop import loop_geometry
from rve_rod.presets import load_preset, stitch_values

FABRICS = [("vassiliadis-sample2", None)] + [
    ("cotton-20s2", stitch) for stitch in stitch_values("cotton-20s2")
]


@pytest.mark.parametrize(("preset", "stitch"), FABRICS)
def test_loop_length_within_four_percent(preset, stitch):
    fabric = load_preset(preset, stitch)
    loop = loop_geometry(fabric.knit, fabric.yarn.minimal_radius)
    assert loop.min_clearance >= 2 * loop.yarn_radius * (1 - 1e-3)
    assert abs(loop.loop_length / fabric.knit.measured_loop_length - 1) <= 0.04
