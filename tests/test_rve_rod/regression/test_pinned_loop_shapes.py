"""Regression pins of the issue-14 loop-shape experiment (tests/pins.py, LOOP_SHAPE_EXPERIMENT):
the loop lengths of cotton 20s/2 stitch 5.5 with the literature out-of-plane profiles, and the
RVE on the "parabolic" loop at the coarse settings of benchmarks/poisson_loop_shapes.py (20
control points, 0-20 % in 11 states; about 1 s a run). Not the model: the experiment of
docs/validation.md, "Literature loop shapes"."""

from pins import assert_pinned, uniaxial_numbers

from rve_rod.geometry.loop import single_jersey_loop
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings, LoopCell
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import RveSettings, run_cell
from rve_rod.rve.yarn import YarnSettings, yarn_model

COARSE = RveSettings(cell=CellSettings(control_points=20), yarn=YarnSettings(bending="section"))
STATES = 11  # 0-20 % in 2 % steps: 10 % is state 5, 20 % state 10
FABRIC = load_preset("cotton-20s2", 5.5)


def loop(profile):
    knit = FABRIC.knit
    return single_jersey_loop(
        knit.wale_width, knit.course_height, FABRIC.yarn.minimal_radius, profile=profile
    )


def test_loop_lengths_of_the_literature_profiles_are_pinned():
    measured = {f"{name} loop length": loop(name).loop_length for name in ("parabolic", "helical")}
    assert_pinned("LOOP_SHAPE_EXPERIMENT", measured)


def test_rve_on_the_parabolic_loop_is_pinned():
    measured = {}
    curves = list(loop("parabolic").curves)
    yarn = yarn_model(FABRIC, COARSE.yarn)
    for direction in ("course", "wale"):
        case = load_case(f"uniaxial-{direction}", 0.2, STATES)
        result = run_cell(LoopCell(curves, FABRIC.knit, yarn, case, COARSE.cell), FABRIC, COARSE)
        measured |= uniaxial_numbers(result, "parabolic ", direction, STATES)
    assert_pinned("LOOP_SHAPE_EXPERIMENT", measured)
