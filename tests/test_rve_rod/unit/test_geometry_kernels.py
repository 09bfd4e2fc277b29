"""The compiled refinement of the clearance search against its plain NumPy reference."""

import numpy as np
import pytest
from support.proximity_reference import refine_reference

from rve_rod.geometry import pattern_cell, proximity
from rve_rod.geometry.loop import single_jersey_loop


def recorded_refinements(monkeypatch, build):
    """The arguments of every refinement while `build()` runs its clearance searches."""
    calls = []
    refine = proximity._refine

    def recording(first, second, s, t, offsets):
        calls.append((first, second, s.copy(), t.copy(), offsets.copy()))
        return refine(first, second, s, t, offsets)

    monkeypatch.setattr(proximity, "_refine", recording)
    build()
    return calls


@pytest.mark.parametrize(
    "build",
    [
        # the jersey loop's shape search (chain_clearance) at sizes no other test caches
        lambda: single_jersey_loop.__wrapped__(1.37, 1.11, 0.19),
        # mixed charts' depth searches (cell_clearance across yarns; seed's lattice oblique)
        lambda: pattern_cell._pattern_geometry.__wrapped__(("KP", "PK"), 0.91, 1.07, 0.19),
        lambda: pattern_cell._pattern_geometry.__wrapped__(("K", "P"), 1.13, 1.41, 0.19),
    ],
    ids=["jersey-loop", "seed-cell", "garter-cell"],
)
def test_compiled_refinement_is_the_numpy_reference_bit_for_bit(build, monkeypatch):
    calls = recorded_refinements(monkeypatch, build)
    assert calls
    rng = np.random.default_rng(7)
    for first, second, s, t, offsets in calls[:: max(1, len(calls) // 40)]:
        # the sampled pairs, and pairs moved off them by up to 3 sample spacings: steps that
        # are cut by the trust region, halved, or follow negative curvature
        jitter = 3.0 / proximity._SAMPLES_PER_CURVE
        for start_s, start_t in (
            (s, t),
            (s + rng.uniform(-jitter, jitter, s.size), t + rng.uniform(-jitter, jitter, t.size)),
        ):
            compiled = proximity._refine(first, second, start_s, start_t, offsets)
            reference = refine_reference(first, second, start_s, start_t, offsets)
            for found, expected in zip(compiled, reference, strict=True):
                np.testing.assert_array_equal(found, expected)
