"""The compiled kernels of the clearance search against their plain NumPy references."""

import numpy as np
import pytest
from support.proximity_reference import nearest_reference, refine_reference

from rve_rod.geometry import _kernels, pattern_cell, proximity
from rve_rod.geometry._kernels import Images, Samples
from rve_rod.geometry.bspline import basis_functions, open_knot_vector
from rve_rod.geometry.loop import single_jersey_loop


@pytest.mark.parametrize("degree", [1, 2, 3, 4, 5])
def test_kernel_basis_functions_are_bspline_basis_functions_bit_for_bit(degree):
    rng = np.random.default_rng(degree)
    knots = open_knot_vector(degree, 11)
    knots[degree + 1 : 11] = np.sort(rng.uniform(0.0, 1.0, 10 - degree))
    knots[degree + 2] = knots[degree + 1]  # a double knot
    params = np.concatenate([rng.uniform(0.0, 1.0, 100), knots, [0.0, 1.0]])
    p = degree
    for derivatives in range(3):  # the refinement's: up to the second
        expected = basis_functions(knots, p, params, derivatives)
        work = _kernels._Work(
            np.empty((p + 1, p + 1)),
            np.empty((2, p + 1)),
            np.empty(p + 1),
            np.empty(p + 1),
            np.zeros((3, p + 1)),
            np.empty((3, 3)),
            np.empty((3, 3)),
        )
        for i, u in enumerate(params):
            assert _kernels._basis(knots, p, u, derivatives, work) == expected.spans[i]
            np.testing.assert_array_equal(work.basis[: derivatives + 1], expected.values[:, i])


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


def cell_samples(pattern, w, c):
    """The samples of each yarn of a pattern's template cell (as `cell_clearance` takes them),
    their arc coordinates and period lengths, and the lattice."""
    cell = pattern_cell.pattern_geometry(pattern, w, c, 0.19).periodic_yarns()
    found = []
    for yarn in cell.yarns:
        chain = proximity._Chain(yarn, cell.lattice[0])
        s = (np.arange(len(yarn) * proximity._SAMPLES_PER_CURVE) + 0.5) / (
            proximity._SAMPLES_PER_CURVE
        )
        points = chain.evaluate(s, basis_functions(chain.knots, chain.degree, s - np.floor(s)))[0]
        steps = np.linalg.norm(np.diff(points, axis=0, append=points[:1] + cell.lattice[0]), axis=1)
        found.append((points, np.concatenate([[0.0], np.cumsum(steps)[:-1]]), steps.sum()))
    return found, cell.lattice


@pytest.mark.parametrize(("pattern", "w", "c"), [("garter", 1.12, 1.46), ("seed", 0.83, 1.08)])
def test_nearest_samples_are_the_full_distance_matrix_minima_bit_for_bit(pattern, w, c):
    yarns, lattice = cell_samples(pattern, w, c)
    for m, (points, arcs, period) in enumerate(yarns):
        for n, (other, other_arcs, _) in enumerate(yarns):
            samples = Samples(points, other, arcs, other_arcs)
            shifts = [(i, j) for j in (-1, 0, 1) for i in (-1, 0, 1)]
            images = Images(
                np.array([i * lattice[0] + j * lattice[1] for i, j in shifts]),
                np.array([i * period for i, _ in shifts]),
                np.array([np.pi * w / 8 if m == n and j == 0 else 0.0 for _, j in shifts]),
            )
            found = proximity._nearest_samples(samples, images)
            for k in range(len(shifts)):
                image = (images.offsets[k], images.shifts[k], images.adjacent_arcs[k])
                distances, partners = nearest_reference(samples, *image)
                np.testing.assert_array_equal(found.distances[k], distances)
                np.testing.assert_array_equal(found.partners[k], partners)


def test_nearest_samples_take_the_first_of_equal_distances_and_skip_adjacent_pairs():
    # a grid of integer points: many exactly equal distances, in several chunks of samples
    rng = np.random.default_rng(3)
    points = rng.integers(-3, 4, size=(300, 3)).astype(float)
    other = rng.integers(-3, 4, size=(250, 3)).astype(float)
    samples = Samples(points, other, np.arange(300.0), np.arange(250.0))
    adjacent = np.array([0.0, 40.0, 1e9])  # none, some, every pair adjacent
    offset = np.array([0.5, 0.0, 1.0])
    found = proximity._nearest_samples(
        samples, Images(np.tile(offset, (3, 1)), np.full(3, 7.0), adjacent)
    )
    for k in range(3):
        distances, partners = nearest_reference(samples, offset, 7.0, adjacent[k])
        np.testing.assert_array_equal(found.distances[k], distances)
        np.testing.assert_array_equal(found.partners[k], partners)
