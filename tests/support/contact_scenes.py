"""Small contact scenes for the tests and benchmarks: crossed rods, wrapped rods, the loop cell.

Benchmarks import it with tests/ on sys.path (as pytest does for the tests).
"""

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


def wrapped_rods(
    tilt: float = 0.0,
    lean: float = 0.02,
    n_control_points: int = 17,
    degree: int = 4,
    *,
    periodic: bool = False,
) -> Scene:
    """A straight rod along x and a rod that wraps around it: two close distance minima.

    Rod 0 runs along x from -1 to 1 (mm). Rod 1 lies near the y-z plane, at polar angle t
    in [-1.8, 1.8] about the x axis at the radius rho(t) = 0.36 + tilt t +
    0.02 ((t / 0.8)^2 - 1)^2 (mm), shifted by lean t along x: seen from the origin, for
    tilt = 0 it has two equal distance minima rho = 0.36 at t = +-0.8 and a maximum 0.38 at
    t = 0, i.e. two minima 0.58 mm apart along rod 1, both within 2r = 0.4 mm for r = 0.2;
    the tilt makes one deeper, and near tilt = 0.025 the shallower minimum and the maximum
    meet and vanish (a fold). The control points sample the formulas at the Greville
    abscissae.

    periodic: put rod 1 one course higher (y + 1.5) in a lattice a1 = (3, 0, 0),
    a2 = (0, 1.5, 0), so that rod 0 touches its image (0, -1) (and rod 1 rod 0's image (0, 1)).
    """
    check_integer("n_control_points", n_control_points, degree + 1)
    knots = open_knot_vector(degree, n_control_points)
    g = greville_abscissae(knots, degree)
    rod_0 = np.stack([-1.0 + 2.0 * g, 0.0 * g, 0.0 * g], axis=1)
    t = -1.8 + 3.6 * g
    rho = 0.36 + tilt * t + 0.02 * ((t / 0.8) ** 2 - 1.0) ** 2
    rod_1 = np.stack([lean * t, rho * np.sin(t), -rho * np.cos(t)], axis=1)
    lattice = None
    if periodic:
        rod_1[:, 1] += 1.5
        lattice = PeriodicLattice.rectangular(3.0, 1.5)
    patches = [Patch(degree, knots), Patch(degree, knots)]
    return Scene(patches, np.vstack([rod_0, rod_1]), [YarnChain((0,)), YarnChain((1,))], lattice)
