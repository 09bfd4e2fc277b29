"""Where the loop finds its yarn (docs/validation.md, "Where the loop finds its yarn";
`benchmarks/paper_rve_bulge.py --budget`): along the paper group's two rays nearest the axes, at
their last converged state, the default cell meets the yarn demand of the affine stretch (8 %
of the loop) with its in-plane shape (82-88 %), hardly with the yarn's stretch (2-3 %), and the
stress across the stretch is the contacts' normal loads, friction opposing it; their normals
already point about 0.4 along the wale. Stitch 5.5, 28 control points."""

import numpy as np
import pytest

from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.paper.comparison import (
    axis_rays,
    contact_directions,
    length_budget,
    run_case,
    run_or_history,
)
from rve_rod.rve.simulation import RveSettings


@pytest.fixture(scope="module")
def last_states():
    """(budget, stress parts across the stretch (3,), contact directions (3,)) at the last
    converged state of each of their two axis rays (course-wise first)."""
    fabric = load_preset("cotton-20s2", 5.5)
    settings = RveSettings(cell=CellSettings(control_points=28))
    found = []
    for ray, across in zip(axis_rays(5.5), (1, 0), strict=True):
        result = run_or_history(fabric, run_case(ray, ray.converged), settings)
        last = len(result.steps) - 1
        assert last == ray.converged
        step = result.steps[last]
        budget = length_budget(result.centreline(0), result.centreline(last), step.deformation)
        f = np.eye(3)
        f[:2, :2] = step.deformation
        directions = contact_directions(
            result.centreline(last), result.cell_lattice @ f.T, result.yarn.radius, result.yarn.law
        )
        found.append((budget, np.asarray(step.stress_parts)[:, across, across], directions))
    return found


def test_the_stretch_demands_eight_percent_of_the_loop_and_its_shape_gives_most(last_states):
    # course-wise 7.9 %: 2.0 / 9.8 / 88.2 %; wale-wise 8.0 %: 3.2 / 15.3 / 81.5 %
    for budget, _, _ in last_states:
        assert budget.demand == pytest.approx(0.08, abs=0.003)
        assert 0.0 < budget.stretch < 0.05
        assert 0.75 < budget.shape < 0.95
        assert budget.depth > 0.05


def test_the_stress_across_the_stretch_is_the_contacts_friction_opposing_it(last_states):
    (_, course, _), (_, wale, _) = last_states
    assert course[0] == pytest.approx(0.0, abs=1e-12 * np.abs(course).max())  # the cut: P11, P21
    for parts in (course, wale):  # yarn / contact / friction: 0 / 112 / -12 and -34 / 139 / -4 %
        assert parts.sum() > 0
        assert parts[1] > parts.sum()
        assert parts[2] < 0
    assert wale[0] < 0  # the yarn through the cut pushes where the cell is held from narrowing


def test_the_contacts_already_push_partly_along_the_wale(last_states):
    """Force-weighted |n| of the contacts at the last state: 0.62 / 0.42 / 0.56 (course-wise
    ray) and 0.53 / 0.47 / 0.57 (wale-wise): turning every normal along the wale could raise
    the pull across a course-wise stretch 2.4-fold at most."""
    for _, _, directions in last_states:
        assert np.all((directions > 0.3) & (directions < 0.7))
    (_, _, course), _ = last_states
    assert course[1] > 0.35  # 0.42 along the wale at the last state, 0.20 at the first
