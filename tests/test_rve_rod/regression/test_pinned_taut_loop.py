"""Regression pin of how much of the stiffness at rest runs through the loop's length
(tests/pins.py, TAUT_LOOP_FAST; docs/validation.md, point 6 of "What the shape of their
response says"): theirs at 4.5, 5.5 and 6.5 (their first states, split with our loop's
length gradient) and ours, the default model at the fast level's 28 control points."""

import numpy as np
from pins import assert_pinned

from rve_rod.geometry.loop import loop_length_gradient, single_jersey_loop
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.paper_comparison import AXIS_RAYS, compare_run, secant_at_rest, taut_loop_split
from rve_rod.rve.paper_data import biaxial_rays
from rve_rod.rve.simulation import RveSettings
from rve_rod.rve.yarn import yarn_model


def test_the_stiffness_of_the_loops_length_at_rest_is_pinned():
    settings = RveSettings(cell=CellSettings(control_points=28))
    measured = {}
    for stitch in (4.5, 5.5, 6.5):
        fabric = load_preset("cotton-20s2", stitch)
        w, c = fabric.knit.wale_width, fabric.knit.course_height
        loop = single_jersey_loop(w, c, fabric.yarn.minimal_radius)
        gradient = loop_length_gradient(w, c, loop.yarn_radius)
        affine = yarn_model(fabric).section.axial / (loop.loop_length * w * c)
        rays = biaxial_rays(stitch)
        axes = [min(rays, key=lambda ray, a=a: abs(ray.angle_deg - a)) for a in AXIS_RAYS]
        theirs = secant_at_rest(axes, [np.diagonal(ray.second_piola[0]) for ray in axes])
        split = taut_loop_split(theirs, gradient)
        measured[f"{stitch} theirs k / affine"] = split.stiffness / affine
        measured[f"{stitch} theirs coupling"] = split.coupling
        if stitch == 6.5:
            continue  # ours has no coupling there (k 0.2 gf/cm/mm^2): nothing to pin but 0
        first = [compare_run(fabric, ray, settings, states=1).second_piola[0] for ray in axes]
        ours = taut_loop_split(secant_at_rest(axes, [np.diagonal(s) for s in first]), gradient)
        measured[f"{stitch} ours k / affine"] = ours.stiffness / affine
        measured[f"{stitch} ours coupling"] = ours.coupling
    assert_pinned("TAUT_LOOP_FAST", measured)
