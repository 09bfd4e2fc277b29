"""A stand-in loop for the RVE tests: Crane's parametric plain-knit yarn as 4 exact C2 quarters.

K. Crane, "A simple parametric model of plain-knit yarns" (2023): one loop of a course row is
gamma(t) = (t + a sin 2t, h cos t, d cos 2t), t in [0, 2 pi], scaled so that its period along x
is the wale width. The loop is interpolated by a uniform periodic B-spline (control points
P_(i+N) = P_i + a1), so it is exactly periodic and C3, and cut into 4 clamped quarter curves
(t in [0, pi/2], ... from the head of the loop) as the project's loop geometry delivers them.
It is not the project's loop model, only a loop of the right size, shape and interlocking.
"""

import numpy as np

from rve_rod.geometry.bspline import BSplineCurve, basis_functions

DEGREE = 4


def crane_point(t, wale_width, course_height, *, roundness=1.5, height=0.84, depth=2.0):
    """gamma(t) (m, 3) in mm: x period w; y amplitude height * c; z amplitude depth w / 2 pi."""
    scale = wale_width / (2.0 * np.pi)
    return np.stack(
        [
            scale * (t + roundness * np.sin(2 * t)),
            height * course_height * np.cos(t),
            scale * depth * np.cos(2 * t),
        ],
        axis=-1,
    )


def crane_quarters(wale_width, course_height, spans_per_quarter=8, **shape):
    """The 4 quarter curves (degree 4, spans_per_quarter + 4 control points each, domain
    [0, 1]) of Crane's loop, exactly C3 at the joins and across the period."""
    p, s = DEGREE, spans_per_quarter
    n = 4 * s  # periodic control points per loop
    h = 1.0 / s
    period = np.array([wale_width, 0.0, 0.0])
    count = 6 * s + p  # control points of the uniform spline on [-1, 5]
    knots = -1.0 + h * (np.arange(count + p + 1) - p)
    samples = (np.arange(n) + 0.5) * h  # span midpoints in [0, 4): a regular system (p even)
    basis = basis_functions(knots, p, samples)
    matrix = np.zeros((n, n))
    rhs = crane_point(samples * 0.5 * np.pi, wale_width, course_height, **shape)
    for j in range(n):
        for a in range(p + 1):
            index = basis.spans[j] - p + a - s  # periodic index relative to u = 0
            matrix[j, index % n] += basis.values[0, j, a]
            rhs[j] -= basis.values[0, j, a] * (index // n) * period
    periodic = np.linalg.solve(matrix, rhs)
    index = np.arange(count) - s
    points = periodic[index % n] + (index // n)[:, None] * period
    curve = BSplineCurve(p, knots, points)
    quarters = []
    rest = curve.split(0.0).right
    for start in range(4):
        pieces = rest.split(start + 1.0)
        quarters.append(pieces.left.reparametrized(0.0))
        rest = pieces.right
    return quarters
