"""The bulge (docs/validation.md, "The bulge"): along their ray nearest the course axis at
stitch 4.5, the parabolic loop of free-fibre yarn with the shifted contact exponent bulges out of
the plane at the first state (its in-plane length falls although the cell is stretched), and the
rest of the ray pulls it back; the default model's loop and the loop of the section's rigidity
keep their depth. At the fast level's 28 control points (68 in benchmarks/paper_rve_bulge.py:
depth x1.65 at the first state, x1.33 at the last). What pushes the legs is the two-pass
contact's out-of-plane imbalance, which the support at the head carries (test_contact_imbalance.py):
a balanced contact would change these runs."""

import pytest

from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.paper.comparison import axis_rays, loop_extents, loop_profile_runner, run_case
from rve_rod.rve.simulation import RveSettings
from rve_rod.rve.yarn import YarnSettings

STITCH = 4.5


def _extents(profile, yarn):
    ray = axis_rays(STITCH)[0]
    settings = RveSettings(cell=CellSettings(control_points=28), yarn=yarn)
    result = loop_profile_runner(profile)(
        load_preset("cotton-20s2", STITCH), run_case(ray, ray.converged), settings
    )
    assert result.complete, result.message
    return loop_extents(result)


def test_the_soft_parabolic_loop_bulges_at_the_first_state_and_is_pulled_flat():
    extent = _extents("parabolic", YarnSettings(contact_exponent_shift=-0.25))
    depth = extent.depth / extent.depth[0]
    assert depth[1] > 1.3
    assert extent.in_plane_length[1] < extent.in_plane_length[0]
    assert depth[-1] < depth[1] - 0.15
    assert extent.in_plane_length[-1] > extent.in_plane_length[1]


@pytest.mark.parametrize(
    "profile, yarn",
    [
        ("band", YarnSettings()),
        ("parabolic", YarnSettings(bending="section", contact_exponent_shift=-0.25)),
    ],
    ids=["default", "section-parabolic"],
)
def test_the_default_loop_and_the_stiff_loop_keep_their_depth(profile, yarn):
    extent = _extents(profile, yarn)
    depth = extent.depth / extent.depth[0]
    assert abs(depth[1] - 1) < 0.1  # the bulging loop: 1.66
    assert extent.in_plane_length[1] >= extent.in_plane_length[0] * (1 - 1e-3)
