"""Broad phase of the contact search: which collocation points may touch which yarn pieces.

A degree-p B-spline span lies in the convex hull of its p+1 control points, so the
axis-aligned box of the control points of a group of consecutive spans bounds the group. A
collocation point can come within the detection radius (2r + margin) of a group only if it
lies in the group's box inflated by that radius. The sweep along x
(`_kernels.box_overlaps`) finds those (point, group) pairs over the groups of the cell and of
its periodic images (translated by F (i a1 + j a2)); groups of a point's own yarn that lie
entirely within the exclusion arc length of it are dropped (the model drops the remaining
minima closer than that along the yarn after the narrow phase). Groups of one span are the
classic per-span boxes; larger groups trade a few more span tests in the narrow phase for
fewer, larger boxes.
"""

import functools
from typing import NamedTuple

import numpy as np

from rve_rod.contact import _kernels
from rve_rod.contact.layout import ContactLayout, PeriodicLattice

__all__ = [
    "Boxes",
    "Candidates",
    "SpanGroups",
    "find_candidates",
    "group_boxes",
    "group_spans",
    "overlapping_boxes",
    "select_images",
]


class SpanGroups(NamedTuple):
    """Consecutive spans of one patch that share a box (arrays over B groups).

    Attributes:
        spans: (2, B) first span and number of spans of each group.
        yarn: (B,) yarn of each group.
        arc_start, arc_end: (B,) reference arc interval of each group along its yarn (mm).
    """

    spans: np.ndarray
    yarn: np.ndarray
    arc_start: np.ndarray
    arc_end: np.ndarray


class Boxes(NamedTuple):
    """Axis-aligned boxes: low, high (k, 3) corners (mm)."""

    low: np.ndarray
    high: np.ndarray


class Candidates(NamedTuple):
    """(collocation point, span group, image) triples for the narrow phase.

    Attributes:
        slave: (k,) collocation point.
        group: (k,) span group.
        image: (k,) index into the list of images.
        box_pairs: (point, group box) pairs found by the sweep (before the arc exclusion).
        all_pairs: every (point, span, image) combination: what a search without a broad
            phase would project.
    """

    slave: np.ndarray
    group: np.ndarray
    image: np.ndarray
    box_pairs: int
    all_pairs: int


def group_spans(layout: ContactLayout, spans_per_box: int) -> SpanGroups:
    """Split every patch's spans into consecutive groups of at most `spans_per_box`."""
    firsts, counts = [], []
    for patch in np.unique(layout.span_patch):
        spans = np.flatnonzero(layout.span_patch == patch)
        starts = spans[::spans_per_box]
        firsts.append(starts)
        counts.append(np.minimum(spans_per_box, spans[-1] + 1 - starts))
    first = np.concatenate(firsts)
    count = np.concatenate(counts)
    last = first + count - 1
    return SpanGroups(
        spans=np.stack([first, count]).astype(np.int64),
        yarn=layout.span_yarn[first],
        arc_start=layout.span_arc_start[first],
        arc_end=layout.span_arc_start[last] + layout.span_arc_length[last],
    )


def group_boxes(layout: ContactLayout, groups: SpanGroups, positions: np.ndarray) -> Boxes:
    """Boxes of the span groups from their control points, positions (n, 3) (mm)."""
    out = np.empty((2, groups.spans.shape[1], 3))
    _kernels.control_point_boxes(positions, layout.span_first, groups.spans, layout.degree + 1, out)
    return Boxes(low=out[0], high=out[1])


def select_images(
    boxes: Boxes,
    lattice: PeriodicLattice | None,
    deformation_gradient: np.ndarray,
    reach: float,
    max_shift: int,
) -> np.ndarray:
    """Lattice images (k, 2) whose yarns can come within `reach` of the cell's yarns.

    An image (i, j) is kept when the box of all yarns, translated by F (i a1 + j a2), overlaps
    the same box inflated by `reach`. Image (0, 0) (contact within the cell) comes first.
    """
    if lattice is None:
        return np.zeros((1, 2), dtype=np.int64)
    grid = _image_grid(max_shift)
    translations = lattice.shifts(grid) @ deformation_gradient.T
    size = boxes.high.max(axis=0) - boxes.low.min(axis=0) + reach
    return grid[np.all(np.abs(translations) <= size, axis=1)]


@functools.cache
def _image_grid(max_shift: int) -> np.ndarray:
    """The images (i, j), |i|, |j| <= max_shift, shape ((2 max_shift + 1)^2, 2) int64, in the
    order `select_images` returns them: by |i| + |j|, then i, then j (read-only)."""
    shifts = np.arange(-max_shift, max_shift + 1)
    grid = np.stack(np.meshgrid(shifts, shifts, indexing="ij"), axis=-1).reshape(-1, 2)
    order = np.lexsort((grid[:, 1], grid[:, 0], np.abs(grid).sum(axis=1)))
    grid = grid[order].astype(np.int64)
    grid.flags.writeable = False
    return grid


def find_candidates(
    layout: ContactLayout,
    groups: SpanGroups,
    boxes: Boxes,
    *,
    slave_points: np.ndarray,
    slave_strands: np.ndarray,
    images: np.ndarray,
    translations: np.ndarray,
    reach: float,
    exclusion_arc_length: float,
) -> Candidates:
    """(point, group, image) triples closer than `reach` by the boxes, minus own-yarn neighbours.

    Args:
        layout: the contact layout; groups, boxes: the span groups and their current boxes.
        slave_points: (3, m) collocation point positions (mm).
        slave_strands: (m,) strand key of each collocation point (image (0, 0)).
        images: (nI, 2) lattice images; translations: (nI, 3) their current translations.
        reach: detection radius 2r + margin (mm).
        exclusion_arc_length: groups of the point's own strand whose arc interval lies within
            this arc length of the point are dropped (mm).
    """
    n_groups = groups.yarn.size
    master_low = (boxes.low[None] + translations[:, None]).reshape(-1, 3) - reach
    master_high = (boxes.high[None] + translations[:, None]).reshape(-1, 3) + reach
    master_boxes = np.ascontiguousarray(np.concatenate([master_low, master_high], axis=1).T)
    slave_boxes = np.ascontiguousarray(np.concatenate([slave_points, slave_points]))
    order = np.argsort(master_boxes[0], kind="stable")
    slave, master = overlapping_boxes(slave_boxes, master_boxes, order)

    # Strand and arc shift of every master box (group in image), then the exclusion.
    box_image = np.repeat(np.arange(images.shape[0]), n_groups)
    box_group = np.tile(np.arange(n_groups), images.shape[0])
    box_strand, box_shift = layout.strands(groups.yarn[box_group], images[box_image])
    kept = np.empty((3, slave.size), dtype=np.int64)
    count = _kernels.apart_pairs(
        slave,
        master,
        _kernels.MasterStrands(
            box_strand, np.asarray(box_shift, dtype=float), groups.arc_start, groups.arc_end
        ),
        _kernels.PointStrands(layout.point_arc, np.asarray(slave_strands, dtype=np.int64)),
        float(exclusion_arc_length),
        kept,
    )
    return Candidates(
        slave=kept[0, :count],
        group=kept[1, :count],
        image=kept[2, :count],
        box_pairs=int(slave.size),
        all_pairs=int(slave_points.shape[1] * layout.n_spans * images.shape[0]),
    )


def overlapping_boxes(
    slave_boxes: np.ndarray, master_boxes: np.ndarray, order: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Index pairs (slave, master) of overlapping boxes (6, a) and (6, b) by the sweep kernel.

    order: master indices sorted by their lower x bound.
    """
    pairs = slave_boxes.shape[1] * master_boxes.shape[1]
    capacity = min(pairs, 64 * (slave_boxes.shape[1] + master_boxes.shape[1]))
    while True:
        out_slave = np.empty(capacity, dtype=np.int64)
        out_master = np.empty(capacity, dtype=np.int64)
        count = _kernels.box_overlaps(slave_boxes, master_boxes, order, out_slave, out_master)
        if count <= capacity:
            return out_slave[:count], out_master[:count]
        capacity = count
