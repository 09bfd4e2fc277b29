"""Small contact scenes for verification and benchmarks: crossed rods and a knit-like loop cell.

The knit-like loop is Crane's parametric plain-knit yarn (K. Crane, "A simple parametric model
of plain-knit yarns", 2023): one loop of a course row is gamma(t) = (t + a sin 2t, h cos t,
d cos 2t), t in [0, 2 pi], scaled so that its period along x is the wale width; courses repeat
along y. It is not the project's loop geometry (rve_rod.geometry), only an interlocking,
periodic yarn of the right size and shape to exercise the contact search on.
"""

from typing import NamedTuple

import numpy as np

from rve_rod.contact.layout import Patch, PeriodicLattice, YarnChain
from rve_rod.errors import check_integer, check_positive
from rve_rod.geometry.bspline import greville_abscissae, interpolate, open_knot_vector


class Scene(NamedTuple):
    """Yarn centrelines as B-spline patches.

    Attributes:
        patches: the patches (Greville collocation).
        positions: (n_total, 3) control points (mm).
        yarns: how the patches chain into yarns.
        lattice: the periodic cell, or None.
    """

    patches: list[Patch]
    positions: np.ndarray
    yarns: list[YarnChain]
    lattice: PeriodicLattice | None


def crossed_rods(
    separation: float,
    angle: float = 0.5 * np.pi,
    length: float = 2.0,
    n_control_points: int = 24,
    degree: int = 4,
) -> Scene:
    """Two straight rods crossing at the origin, centrelines `separation` apart along z.

    Rod 0 runs along x at z = +separation/2, rod 1 along (cos angle, sin angle, 0) at
    z = -separation/2; both have the given length (mm) and are centred at the crossing.
    """
    check_positive("separation", separation, "mm")
    check_positive("length", length, "mm")
    check_integer("n_control_points", n_control_points, degree + 1)
    knots = open_knot_vector(degree, n_control_points)
    s = length * (greville_abscissae(knots, degree) - 0.5)
    zeros = np.zeros_like(s)
    rod_0 = np.stack([s, zeros, zeros + 0.5 * separation], axis=1)
    rod_1 = np.stack([s * np.cos(angle), s * np.sin(angle), zeros - 0.5 * separation], axis=1)
    patches = [Patch(degree, knots), Patch(degree, knots)]
    return Scene(patches, np.vstack([rod_0, rod_1]), [YarnChain((0,)), YarnChain((1,))], None)


def knit_like_loop(
    wale_width: float = 1.33,
    course_height: float = 0.95,
    n_control_points: int = 68,
    degree: int = 4,
    *,
    roundness: float = 1.5,
    height: float = 4.0,
    depth: float = 1.0,
) -> Scene:
    """One loop of Crane's plain-knit yarn as 4 patches, periodic along a1 = (w, 0, 0).

    Args:
        wale_width: w, the loop period along x (mm).
        course_height: c, the course spacing along y (mm).
        n_control_points: control points per patch (each patch is a quarter loop).
        degree: B-spline degree.
        roundness, height, depth: Crane's a, h, d in units where the period is 2 pi.
    """
    check_positive("wale_width", wale_width, "mm")
    check_positive("course_height", course_height, "mm")
    check_integer("n_control_points", n_control_points, degree + 1)
    scale = wale_width / (2.0 * np.pi)
    knots = open_knot_vector(degree, n_control_points)
    params = greville_abscissae(knots, degree)
    patches, positions = [], []
    for quarter in range(4):
        t = 0.5 * np.pi * (quarter + params)
        points = scale * np.stack(
            [t + roundness * np.sin(2 * t), height * np.cos(t), depth * np.cos(2 * t)], axis=1
        )
        curve = interpolate(points, degree, params=params, knots=knots)
        patches.append(Patch(degree, knots))
        positions.append(curve.control_points)
    lattice = PeriodicLattice.rectangular(wale_width, course_height)
    return Scene(patches, np.vstack(positions), [YarnChain((0, 1, 2, 3), (1, 0))], lattice)
