"""Periodic images: the lattice images equal explicit copies of the loop under a sheared F, the
broad phase loses nothing against a brute-force search, and its box size changes no result."""

import numpy as np
import pytest

from rve_rod.contact import (
    CompressibleYarnLaw,
    ContactModel,
    ContactOptions,
    CoulombFriction,
    YarnChain,
)
from rve_rod.contact.closest_point import project
from rve_rod.contact.scenes import knit_like_loop

LAW = CompressibleYarnLaw(stiffness=3.0, exponent=1.4, yarn_radius=0.17)
SHEAR = np.array([[1.04, 0.12, 0.0], [0.09, 0.97, 0.0], [0.0, 0.0, 1.0]])
CONTROL_POINTS = 16


def explicit_neighbourhood(scene, deformation, wales=(-1, 0, 1), courses=(-2, -1, 0, 1, 2)):
    """The loop and its images as explicit open yarns: one yarn of len(wales) loops per course.

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
            blocks.append(scene.positions + shift)
        yarns.append(YarnChain(tuple(chain)))
    assert n_loop == 4 * CONTROL_POINTS
    return patches, np.vstack(blocks), yarns, central


@pytest.mark.parametrize("deformation", [np.eye(3), SHEAR], ids=["identity", "shear"])
def test_images_equal_explicit_copies(deformation):
    scene = knit_like_loop(n_control_points=CONTROL_POINTS)
    periodic = ContactModel(scene.patches, scene.positions, LAW, lattice=scene.lattice)
    result = periodic.evaluate(scene.positions, deformation)
    images = {tuple(image) for image in result.contacts.image}
    assert len(images - {(0, 0)}) >= 4
    assert all(abs(i) <= 1 and abs(j) <= 2 for i, j in images)  # inside the explicit copies

    patches, positions, yarns, central = explicit_neighbourhood(scene, deformation)
    explicit = ContactModel(patches, positions, LAW, yarns=yarns)
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
    gap = 2 * LAW.yarn_radius - np.linalg.norm(
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


@pytest.mark.parametrize("deformation", [np.eye(3), SHEAR], ids=["identity", "shear"])
def test_broad_phase_finds_every_contact_of_the_brute_force_search(deformation):
    scene = knit_like_loop(n_control_points=CONTROL_POINTS)
    rng = np.random.default_rng(2)
    positions = scene.positions + 0.01 * rng.normal(size=scene.positions.shape)
    model = ContactModel(scene.patches, positions, LAW, lattice=scene.lattice)
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


def test_box_size_changes_cost_not_result():
    scene = knit_like_loop(n_control_points=CONTROL_POINTS)
    friction = CoulombFriction(coefficient=0.15, tangential_stiffness=3.0)
    results = []
    for spans_per_box in (1, 3, 8, 64):
        options = ContactOptions(spans_per_box=spans_per_box)
        model = ContactModel(
            scene.patches,
            scene.positions,
            LAW,
            friction=friction,
            lattice=scene.lattice,
            options=options,
        )
        results.append(model.evaluate(scene.positions + 0.003, SHEAR))
    for other in results[1:]:
        np.testing.assert_array_equal(other.line_load, results[0].line_load)
        np.testing.assert_array_equal(other.jacobian.toarray(), results[0].jacobian.toarray())
    pairs = [r.statistics.box_pairs for r in results]
    assert pairs == sorted(pairs, reverse=True)


def test_net_contact_force_on_the_periodic_cell():
    # Translation invariance: the cell's contacts with image (i, j) mirror those of image
    # (-i, -j) with the cell, so exact action-reaction would give a zero resultant. Two-pass
    # line loads leave the imbalance of curved yarn pairs (test_contact_crossed_rods).
    scene = knit_like_loop(n_control_points=68)
    model = ContactModel(scene.patches, scene.positions, LAW, lattice=scene.lattice)
    loads = model.evaluate(scene.positions).line_load * model.collocation_weights
    net = np.linalg.norm(loads.sum(axis=1))
    gross = np.linalg.norm(loads, axis=0).sum()
    assert net < 0.05 * gross
