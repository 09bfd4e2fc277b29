"""Narrow phase: closest points of collocation points on candidate groups of knot spans.

Each (point, span group) candidate is searched span by span by
`_kernels.project_on_groups`: a span reports every local minimum of the distance that it owns.
The slope of the squared distance is a polynomial on the span; where its Bernstein
coefficients change sign more than once, the span is split into pieces with at most one
root each, and a piece owns a minimum when the slope changes sign from <= 0 at its start to
> 0 at its end. Each is found by Newton's method safeguarded by bisection, so the projection
stays in its piece and cannot fail to converge. A minimum on a knot is owned by exactly one
of the two spans, so no contact is counted twice.
"""

from typing import NamedTuple

import numpy as np

from rve_rod.contact import _kernels

__all__ = [
    "Projections",
    "project",
]

TOLERANCE = 1e-14
"""Convergence tolerance on the local span parameter tau."""


class Projections(NamedTuple):
    """Local distance minima found for the candidates (arrays over k minima).

    Attributes:
        candidate: (k,) index of the candidate (target) the minimum belongs to.
        span: (k,) span holding the minimum.
        tau: (k,) its local span parameter.
        point: (3, k) closest point C(tau) in the cell (mm; add the image translation).
        tangent: (3, k) dC/dtau (mm).
        curvature: (3, k) d2C/dtau2 (mm).
    """

    candidate: np.ndarray
    span: np.ndarray
    tau: np.ndarray
    point: np.ndarray
    tangent: np.ndarray
    curvature: np.ndarray


def project(
    coefficients: np.ndarray,
    group_spans: np.ndarray,
    span_next: np.ndarray,
    closed_end: np.ndarray,
    *,
    groups: np.ndarray,
    targets: np.ndarray,
    reach: float = np.inf,
) -> Projections:
    """All local distance minima of targets (3, k) on their span groups (k,).

    Args:
        coefficients: (3, p+1, S) power-basis coefficients of the spans.
        group_spans: (2, B) first span and number of spans of each group.
        span_next: (S,) next span in the same patch, -1 at a patch end.
        closed_end: (S,) spans that own their end parameter (last span of an open yarn).
        groups: (k,) group of each target.
        targets: (3, k) points to project (slave points minus the image translation).
        reach: minima farther than this from their target (mm) may be left out (spans whose
            bounding box lies beyond it are skipped); default: every minimum.
    """
    capacity = max(16, groups.size // 4)
    coefficients = np.ascontiguousarray(coefficients)
    targets = np.ascontiguousarray(targets)
    groups = groups.astype(np.int64)
    spans = _kernels.SpanGroups(coefficients, group_spans, span_next, closed_end)
    while True:
        out = _kernels.Minima(np.empty((2, capacity), dtype=np.int64), np.empty((10, capacity)))
        count = _kernels.project_on_groups(spans, groups, targets, TOLERANCE, float(reach), out)
        if count <= capacity:
            break
        capacity = count
    out_index, out = out
    return Projections(
        candidate=out_index[0, :count],
        span=out_index[1, :count],
        tau=out[0, :count],
        point=out[1:4, :count],
        tangent=out[4:7, :count],
        curvature=out[7:10, :count],
    )
