"""Regression pins of the loop geometry (tests/pins.py, LOOP_LENGTHS): the model loop length of
the seven reference fabrics (Vassiliadis sample 2, cotton 20s/2 at stitch 4.5-7.0). The loops
are memoized in memory: tests/test_rve_rod/validation/test_loop_length.py builds the same ones."""

from pins import assert_pinned

from rve_rod.geometry.loop import loop_geometry
from rve_rod.presets import load_preset, stitch_values


def test_loop_lengths_of_the_reference_fabrics_are_pinned():
    fabrics = {"vassiliadis-sample2": load_preset("vassiliadis-sample2")}
    for stitch in stitch_values("cotton-20s2"):
        fabrics[f"cotton-20s2 {stitch:.1f}"] = load_preset("cotton-20s2", stitch)
    measured = {
        name: loop_geometry(fabric.knit, fabric.yarn.minimal_radius).loop_length
        for name, fabric in fabrics.items()
    }
    assert len(measured) == 7
    assert_pinned("LOOP_LENGTHS", measured)
