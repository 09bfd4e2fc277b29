"""The reaction force of a non-homogeneous problem converges under mesh refinement: a plate
with a hole on rollers, stretched by 10 %, on uniformly refined unstructured quad meshes."""

import numpy as np
import pytest
from support.plate_cases import stretched_plate

ELEMENT_SIZE = 5.0  # mm, halved by every refinement


def stretched_plate_reaction(refinements: int) -> float:
    """Reaction (N) on the right edge of the plate (`support.plate_cases`); its y component
    is the pinned corner's, zero."""
    reaction = stretched_plate(refinements, element_size=ELEMENT_SIZE).reaction
    assert abs(reaction[1]) < 1e-12 * abs(reaction[0])
    return float(reaction[0])


@pytest.mark.slow
def test_reaction_converges_at_second_order_under_refinement():
    levels = np.arange(4)
    reactions = np.array([stretched_plate_reaction(int(level)) for level in levels])
    sizes = ELEMENT_SIZE / 2.0**levels
    changes = np.abs(np.diff(reactions))
    slope = np.polyfit(np.log(sizes[1:]), np.log(changes), 1)[0]
    # Q1 reactions (a functional) and the polygonal hole both converge as h^2; the fit over
    # these levels sees 1.7 (pre-asymptotic on the coarsest mesh).
    assert 1.5 < slope < 2.5
    finest_error = changes[-1] / (2.0**slope - 1.0)  # Richardson estimate of |R_3 - R|
    assert finest_error < 1.5e-3 * reactions[-1]
    assert np.all(np.diff(reactions) < 0.0)  # monotone: coarse meshes are too stiff
