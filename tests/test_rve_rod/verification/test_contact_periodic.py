"""Periodic images: the lattice images equal explicit copies of the loop under a sheared F, the
broad phase loses nothing against a brute-force search, and its box size changes no result.

The scene is the loop of cotton 20s/2 at stitch 5.5 (`cotton_loop`), mapped affinely by a
compressive F together with its images, so that it presses into its four neighbours (as built,
at F = I, the yarns only touch).
"""

import numpy as np
import pytest
from support.contact_scenes import knit_loop

from rve_rod.contact import (
    CompressibleYarnLaw,
    ContactModel,
    ContactOptions,
    CoulombFriction,
    YarnChain,
)
from rve_rod.contact.closest_point import project

COMPRESSION = np.diag([0.95, 0.95, 1.0])
SHEAR = np.array([[0.97, 0.1, 0.0], [0.08, 0.96, 0.0], [0.0, 0.0, 1.0]])
CONTROL_POINTS = 36


@pytest.fixture(scope="module")
def scene(cotton_loop):
    return knit_loop(cotton_loop, CONTROL_POINTS)


@pytest.fixture(scope="module")
def law(cotton_loop):
    return CompressibleYarnLaw(stiffness=3.0, exponent=1.4, yarn_radius=cotton_loop.yarn_radius)


def explicit_neighbourhood(scene, deformation, wales=(-1, 0, 1), courses=(-2, -1, 0, 1, 2)):
    """The loop and its images, mapped by F, as explicit open yarns: one yarn of len(wales)
    loops per course.

    Returns (patches, positions, yarns, first point of the central loop's collocation points).
    """
    n_loop = scene.positions.shape[0]
    patches, blocks, yarns = [], [], []
    central = None
    for j in courses:
        chain = []
        for i in wales:
            shift = deformation @ (i * scene.lattice.vectors[0] + j * scene.lattice.vectors[1])
            if (i, j) == (0, 0):
                central = len(patches) * CONTROL_POINTS
            chain.extend(range(len(patches), len(patches) + 4))
            patches.extend(scene.patches)
            blocks.append(scene.positions @ deformation.T + shift)
        yarns.append(YarnChain(tuple(chain)))
    assert n_loop == 4 * CONTROL_POINTS
    return patches, np.vstack(blocks), yarns, central


@pytest.mark.parametrize("deformation", [COMPRESSION, SHEAR], ids=["compression", "shear"])
def test_images_equal_explicit_copies(scene, law, deformation):
    periodic = ContactModel(scene.patches, scene.positions, law, lattice=scene.lattice)
    result = periodic.evaluate(scene.positions @ deformation.T, deformation)
    images = {tuple(image) for image in result.contacts.image}
    assert len(images - {(0, 0)}) >= 4
    assert all(abs(i) <= 1 and abs(j) <= 2 for i, j in images)  # inside the explicit copies

    # the explicit copies' reference is the undeformed neighbourhood, as the periodic model's
    # (reference arc coordinates decide which minima share a contact)
    patches, reference, yarns, central = explicit_neighbourhood(scene, np.eye(3))
    positions = explicit_neighbourhood(scene, deformation)[1]
    explicit = ContactModel(patches, reference, law, yarns=yarns)
    loads = explicit.evaluate(positions).line_load[:, central : central + 4 * CONTROL_POINTS]
    scale = np.abs(result.line_load).max()
    assert scale > 0
    np.testing.assert_allclose(result.line_load, loads, rtol=0, atol=1e-12 * scale)


def brute_force_contacts(model, positions, deformation, max_shift=2):
    """Active contacts from projecting every point on every span of every image |i|,|j| <= 2.

    No boxes, no image selection, no group prefilter: the narrow phase on all pairs, then the
    model's definitions (penetration > 0, own-yarn minima closer than the exclusion dropped).
    Returns a sorted list of (point, i, j, span, penetration).
    """
    layout = model.layout
    shifts = np.arange(-max_shift, max_shift + 1)
    images = np.stack(np.meshgrid(shifts, shifts, indexing="ij"), -1).reshape(-1, 2)
    translations = model.lattice.shifts(images) @ deformation.T
    points = layout.collocation_positions(positions)
    point, image, span = (
        a.ravel()
        for a in np.meshgrid(
            np.arange(layout.n_points),
            np.arange(images.shape[0]),
            np.arange(layout.n_spans),
            indexing="ij",
        )
    )
    found = project(
        layout.coefficients(positions),
        np.stack([np.arange(layout.n_spans), np.ones(layout.n_spans, dtype=np.int64)]),
        layout.span_next,
        layout.span_closed_end,
        groups=span,
        targets=points[:, point] - translations[image].T,
    )
    point, image = point[found.candidate], image[found.candidate]
    gap = 2 * model.law.yarn_radius - np.linalg.norm(
        points[:, point] - found.point - translations[image].T, axis=0
    )
    key, shift = layout.strands(layout.span_yarn[found.span], images[image])
    own, _ = layout.strands(layout.span_yarn[layout.point_span[point]], 0 * images[image])
    arc = layout.span_arc_start[found.span] + found.tau * layout.span_arc_length[found.span]
    adjacent = (key == own) & (
        np.abs(arc + shift - layout.point_arc[point]) < model.exclusion_arc_length
    )
    keep = (gap > 0) & ~adjacent
    return sorted(
        zip(point[keep], *images[image[keep]].T, found.span[keep], gap[keep], strict=True)
    )


@pytest.mark.parametrize("deformation", [COMPRESSION, SHEAR], ids=["compression", "shear"])
def test_broad_phase_finds_every_contact_of_the_brute_force_search(scene, law, deformation):
    rng = np.random.default_rng(2)
    positions = scene.positions @ deformation.T + 0.01 * rng.normal(size=scene.positions.shape)
    model = ContactModel(scene.patches, positions, law, lattice=scene.lattice)
    result = model.evaluate(positions, deformation)
    contacts = result.contacts
    layout = model.layout
    spans = np.array(
        [
            np.flatnonzero(
                (layout.span_patch == patch)
                & (layout.span_start <= u)
                & (u <= layout.span_start + layout.span_length)
            )[0]
            for patch, u in zip(contacts.patch, contacts.parameter, strict=True)
        ]
    )
    mine = sorted(zip(contacts.slave, *contacts.image.T, spans, contacts.penetration, strict=True))
    brute = brute_force_contacts(model, positions, deformation)
    assert len(mine) == len(brute) > 30
    for a, b in zip(mine, brute, strict=True):
        assert a[:3] == b[:3]
        assert a[4] == pytest.approx(b[4], rel=1e-9, abs=1e-14)
    stats = result.statistics
    assert stats.span_tests < 0.1 * stats.all_pairs  # the broad phase pays off


def test_box_size_changes_cost_not_result(scene, law):
    friction = CoulombFriction(coefficient=0.15, tangential_stiffness=3.0)
    results = []
    for spans_per_box in (1, 3, 8, 64):
        options = ContactOptions(spans_per_box=spans_per_box)
        model = ContactModel(
            scene.patches,
            scene.positions,
            law,
            friction=friction,
            lattice=scene.lattice,
            options=options,
        )
        results.append(model.evaluate(scene.positions @ SHEAR.T + 0.003, SHEAR))
    for other in results[1:]:
        np.testing.assert_array_equal(other.line_load, results[0].line_load)
        np.testing.assert_array_equal(other.jacobian.toarray(), results[0].jacobian.toarray())
    pairs = [r.statistics.box_pairs for r in results]
    assert pairs == sorted(pairs, reverse=True)


@pytest.mark.parametrize("deformation", [COMPRESSION, SHEAR], ids=["compression", "shear"])
def test_in_plane_contact_forces_on_the_cell_cancel_by_symmetry(scene, law, deformation):
    # The loop maps onto itself under the half turn (x, y) -> (w/2 - x, -y), which commutes
    # with any in-plane F: contact forces come in pairs with opposite x and y components and
    # equal z. The z resultant is the two-pass imbalance of curved yarn pairs
    # (test_contact_crossed_rods; benchmarks/bench_contact.py measures it).
    model = ContactModel(scene.patches, scene.positions, law, lattice=scene.lattice)
    result = model.evaluate(scene.positions @ deformation.T, deformation)
    loads = result.line_load * model.collocation_weights
    gross = np.linalg.norm(loads, axis=0).sum()
    assert result.statistics.active_contacts > 30
    np.testing.assert_allclose(loads[:2].sum(axis=1), 0.0, atol=1e-12 * gross)
