"""Small contact scenes for verification and benchmarks: crossed rods and the knit's loop cell."""

from typing import NamedTuple

import numpy as np

from rve_rod.contact.layout import Patch, PeriodicLattice, YarnChain
from rve_rod.errors import check_integer, check_positive
from rve_rod.geometry.bspline import greville_abscissae, open_knot_vector
from rve_rod.geometry.loop import LoopGeometry


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


def knit_loop(geometry: LoopGeometry, n_control_points: int | None = None) -> Scene:
    """One loop of the knit (`rve_rod.geometry.loop`) as its 4 patches, periodic along a1.

    Args:
        geometry: the loop (e.g. `loop_geometry(knit, minimal_radius)`).
        n_control_points: control points per patch (each patch is a quarter loop): 12, 20,
            36, 68, 132, ... (`LoopGeometry.refined`, the same shape for all); None keeps
            the loop's own curves.

    The yarn runs through the patches 0, 1, 2, 3 and continues into the loop of the next wale,
    image (1, 0); the lattice is the loop's, a1 = (w, 0, 0), a2 = (0, c, 0). The loop clears
    its neighbours by exactly 2r where the yarns touch, so at F = I the contacts just touch.
    """
    curves = geometry.curves if n_control_points is None else geometry.refined(n_control_points)
    patches = [Patch(curve.degree, curve.knots) for curve in curves]
    positions = np.vstack([curve.control_points for curve in curves])
    lattice = PeriodicLattice(geometry.lattice)
    return Scene(patches, positions, [YarnChain((0, 1, 2, 3), (1, 0))], lattice)
