"""Friction history: the stick anchors that carry Coulomb friction from one load step to the next.

Every slave point that was within the detection radius of a master at the last converged
(committed) state keeps an anchor: the master material point (span, tau, lattice image) it was
closest to and the offset o from that point at which it sticks, o = v - g_e (v = x_s - x_m,
g_e the elastic slip left by the return mapping). During the next step the slip of the slave
point is the tangential part of w = x_s - x_a - o, where x_a is the anchor's current position:
the motion of the slave point relative to the master's material point since the last commit.
The offset turns with the cell as a whole: it is kept in the frame of the macro F's rotation
(`MacroTurn`, the polar rotation R of the in-plane F) and used as R o, so that a rigid turn of
the cell and its images registers no slip (docs/contact.md, "The cell's turn").
A current contact finds its anchor by slave point, strand (the endless yarn through the
lattice images) and nearest unwrapped arc coordinate along it.
"""

from typing import NamedTuple

import numpy as np

__all__ = [
    "FrictionHistory",
    "MacroTurn",
    "SortedAnchors",
    "match_anchors",
    "sort_anchors",
]

_STRAND_BITS = 31  # strand keys stay below 2^31 (yarn << 20 | image offsets)


class FrictionHistory(NamedTuple):
    """Stick anchors of the committed state (arrays over h anchors).

    Attributes:
        slave: (h,) collocation point that owns the anchor.
        strand: (h,) strand key of the master yarn piece (ContactLayout.strands).
        arc: (h,) unwrapped reference arc coordinate of the anchor along its strand (mm).
        span: (h,) master span of the anchor; tau: (h,) its local parameter.
        image: (h, 2) lattice image of the anchor's master.
        offset: (3, h) stick offset o (mm), in the frame of the macro turn (`MacroTurn`):
            R^T o of the committed state's R.
    """

    slave: np.ndarray
    strand: np.ndarray
    arc: np.ndarray
    span: np.ndarray
    tau: np.ndarray
    image: np.ndarray
    offset: np.ndarray

    @classmethod
    def empty(cls) -> "FrictionHistory":
        """No anchors: every contact starts without friction until the next commit."""
        none = np.zeros(0, dtype=np.int64)
        return cls(
            none, none, np.zeros(0), none, np.zeros(0), np.zeros((0, 2), np.int64), np.zeros((3, 0))
        )

    def __len__(self) -> int:
        return self.slave.size


class MacroTurn(NamedTuple):
    """The rotation of the in-plane macro F, F = R U (polar), about the fabric's normal z.

    For a 2 x 2 F its angle is theta = atan2(F21 - F12, F11 + F22).

    Attributes:
        rotation: (3, 3) R.
        rate: (3, 3) dR / dtheta.
        gradient: (4,) dtheta / d(F11, F12, F21, F22).
    """

    rotation: np.ndarray
    rate: np.ndarray
    gradient: np.ndarray

    @classmethod
    def of(cls, deformation: np.ndarray) -> "MacroTurn":
        """The turn of F (3, 3) (its in-plane block)."""
        trace = deformation[0, 0] + deformation[1, 1]
        skew = deformation[1, 0] - deformation[0, 1]
        theta = np.arctan2(skew, trace)
        c, s = np.cos(theta), np.sin(theta)
        rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        rate = np.array([[-s, -c, 0.0], [c, -s, 0.0], [0.0, 0.0, 0.0]])
        size = trace * trace + skew * skew
        gradient = np.array([-skew, -trace, trace, -skew]) / size
        return cls(rotation, rate, gradient)


class SortedAnchors(NamedTuple):
    """The anchors of a `FrictionHistory` as `match_anchors` searches them (`sort_anchors`).

    Attributes:
        order: (h,) the anchors by slave point and strand, then arc coordinate.
        key: (h,) the slave-and-strand key of each, in that order.
        arc: (h,) the arc coordinate of each, in that order (mm).
    """

    order: np.ndarray
    key: np.ndarray
    arc: np.ndarray


def sort_anchors(history: FrictionHistory) -> SortedAnchors:
    """The anchors of `history` sorted for `match_anchors` (made once per committed history,
    searched at every evaluation)."""
    history_key = (history.slave.astype(np.int64) << _STRAND_BITS) + history.strand
    order = np.lexsort((history.arc, history_key))
    return SortedAnchors(order, history_key[order], history.arc[order])


def match_anchors(
    anchors: SortedAnchors,
    slave: np.ndarray,
    strand: np.ndarray,
    arc: np.ndarray,
    window: float,
) -> np.ndarray:
    """Anchor of each current contact: index into the history of `anchors`, or -1 if it has
    none.

    A contact (slave point, strand, arc coordinate) takes the anchor of the same slave point
    on the same strand whose arc coordinate is nearest, if it lies within `window` (mm).
    """
    result = np.full(slave.size, -1, dtype=np.int64)
    order, sorted_key, sorted_arc = anchors
    if order.size == 0 or slave.size == 0:
        return result
    key = (slave.astype(np.int64) << _STRAND_BITS) + strand
    low = np.searchsorted(sorted_key, key, side="left")
    high = np.searchsorted(sorted_key, key, side="right")
    best = np.full(slave.size, np.inf)
    widest = int((high - low).max())
    for offset in range(widest):
        index = low + offset
        valid = index < high
        distance = np.where(
            valid, np.abs(sorted_arc[np.minimum(index, order.size - 1)] - arc), np.inf
        )
        better = valid & (distance < best) & (distance <= window)
        best = np.where(better, distance, best)
        result = np.where(better, order[np.minimum(index, order.size - 1)], result)
    return result
