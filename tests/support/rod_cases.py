"""Test geometries for the rod engine (straight rods, circular arcs, helices, twisted frames)
and a user-defined condition as the knit RVE will write them."""

from dataclasses import dataclass

import numpy as np

from rve_rod.geometry.bspline import BSplineCurve, basis_matrix, open_knot_vector
from rve_rod.rod import (
    Block,
    Condition,
    RodEnd,
    RodPatch,
    quaternions_from_frames,
    reference_quaternions,
)
from rve_rod.rod.quaternion import from_rotation_vector, rotation_matrix


def interpolated_curve(function, degree, n, domain=(0.0, 1.0)):
    """The degree-p B-spline with n control points on an open uniform knot vector that
    interpolates `function(u)` (u in [0, 1], returns (m, 3)) at its Greville points."""
    knots = open_knot_vector(degree, n, domain)
    greville = BSplineCurve(degree, knots, np.zeros((n, 3))).greville()
    matrix = basis_matrix(knots, degree, greville).toarray()
    fraction = (greville - domain[0]) / (domain[1] - domain[0])
    return BSplineCurve(degree, knots, np.linalg.solve(matrix, function(fraction)))


def straight(length, degree, n, *, start=0.0, stop=1.0):
    """Straight rod along x from x = start*length to x = stop*length (exactly linear in u)."""
    return interpolated_curve(
        lambda u: np.stack([length * (start + (stop - start) * u), 0 * u, 0 * u], axis=1),
        degree,
        n,
    )


def arc(radius, angle, degree, n, *, start=0.0, stop=1.0):
    """Circular arc in the xy-plane from the origin, initial tangent +x, centre (0, R, 0);
    the piece between fractions `start` and `stop` of the full `angle`."""

    def points(u):
        theta = angle * (start + (stop - start) * u)
        return np.stack([radius * np.sin(theta), radius * (1 - np.cos(theta)), 0 * theta], axis=1)

    return interpolated_curve(points, degree, n)


def helix(radius, pitch, turns, degree, n):
    """Helix about z: (R cos t, R sin t, pitch t / 2 pi), t in [0, 2 pi turns]."""

    def points(u):
        t = 2 * np.pi * turns * u
        return np.stack([radius * np.cos(t), radius * np.sin(t), pitch * t / (2 * np.pi)], 1)

    return interpolated_curve(points, degree, n)


def twisted_patches(curves, section, twist):
    """Patches with the rotation-minimizing frame turned about the tangent by twist * u
    (rad per unit parameter), so the reference carries twist as well as curvature."""
    patches = []
    previous = None
    for curve, controls in zip(curves, reference_quaternions(curves), strict=True):
        greville = curve.greville()
        frames = rotation_matrix(BSplineCurve(curve.degree, curve.knots, controls)(greville))
        d3 = frames[:, :, 2]
        turn = rotation_matrix(from_rotation_vector(twist * greville[:, None] * d3))
        twisted = quaternions_from_frames(curve, turn @ frames, previous)
        patches.append(RodPatch(curve, twisted, section))
        previous = twisted[-1]
    return patches


@dataclass(frozen=True, eq=False)
class ForceControl(Condition):
    """The equation of the stretch unknown: the force carried through the periodic joint,
    along `direction`, equals t * target (N)."""

    end: RodEnd
    direction: np.ndarray
    target: float
    extra_equations = 1

    @property
    def ends(self):
        return ()

    def row_scales(self, length, force):
        return np.array([force])

    def evaluate(self, context, load_factor):
        values = context.model.end_values(context.state, self.end)
        residual = np.array([self.direction @ values.force - load_factor * self.target])
        return [
            Block(context.rows, residual, values.columns, (self.direction @ values.d_force)[None])
        ]
