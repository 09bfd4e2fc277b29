"""Regression pin of the comparison with the paper group's RVE (tests/pins.py,
PAPER_COMPARISON_FAST): our S along three of their rays (equibiaxial tension, wale-wise
compression, near-uniaxial wale-wise tension) and their shear (S12 and the normal stresses it
causes), at the fast level's 28 control points (about 10 s)."""

from pins import assert_pinned

from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.paper.comparison import compare_run
from rve_rod.rve.paper.data import biaxial_rays, shear_run
from rve_rod.rve.simulation import RveSettings
from rve_rod.rve.yarn import YarnSettings
from rve_rod.units import n_per_mm_to_gf_per_cm


def test_our_stresses_along_their_runs_are_pinned():
    settings = RveSettings(cell=CellSettings(control_points=28))
    fabric = load_preset("cotton-20s2", 5.5)
    rays = {round(ray.angle_deg, 1): ray for ray in biaxial_rays(5.5)}
    runs = {
        "ray 45": (rays[45.0], None),
        "ray -83": (rays[-83.0], 8),
        "ray 128": (rays[128.3], None),
        "shear": (shear_run(5.5), 12),
    }
    ours = {
        name: n_per_mm_to_gf_per_cm(compare_run(fabric, run, settings, states=n).second_piola)
        for name, (run, n) in runs.items()
    }
    measured = {
        "ray 45 S11 state 6": ours["ray 45"][5, 0, 0],
        "ray 45 S22 state 6": ours["ray 45"][5, 1, 1],
        "ray -83 S22 state 8": ours["ray -83"][7, 1, 1],
        "ray 128 S11 state 9": ours["ray 128"][8, 0, 0],
        "ray 128 S22 state 9": ours["ray 128"][8, 1, 1],
        "shear S12 state 6": ours["shear"][5, 0, 1],
        "shear S12 state 12": ours["shear"][11, 0, 1],
        # the normal stresses of the shear (E11 = E22 = 0; theirs 0.9, -6.5, 1.9 gf/cm)
        "shear S22 state 6": ours["shear"][5, 1, 1],
        "shear S11 state 12": ours["shear"][11, 0, 0],
        "shear S22 state 12": ours["shear"][11, 1, 1],
    }
    assert_pinned("PAPER_COMPARISON_FAST", measured)


def test_the_squeezed_rests_shear_is_pinned():
    """Their picture-frame shear at 5.5 from the squeezed rest (the law at the yarn's own
    radius, `YarnSettings.contact_radius = "measured"`), with and without friction, at their
    6th state (19.8 degrees; docs/validation.md, "A pre-loaded rest, measured objectively"):
    the number the objective rest stress and the turning friction offsets moved most. With
    friction the run has 7 states: a run of 6 meets a fold of its frictional path
    (test_squeezed_fold.py); frictionless, 6."""
    fabric = load_preset("cotton-20s2", 5.5)
    measured = {}
    for label, friction, states in (("friction", True, 7), ("frictionless", False, 6)):
        settings = RveSettings(
            cell=CellSettings(control_points=28),
            yarn=YarnSettings(contact_radius="measured", friction=friction),
        )
        shear = compare_run(fabric, shear_run(5.5), settings, states=states).second_piola
        measured[f"squeezed, {label}: shear S12 state 6"] = n_per_mm_to_gf_per_cm(shear[5, 0, 1])
    assert_pinned("PAPER_PRELOADED_SHEAR_FAST", measured)
