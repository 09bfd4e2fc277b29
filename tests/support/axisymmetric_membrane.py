"""An independent reference for a rigid sphere pushed into a clamped circular membrane.

The axisymmetric problem in one dimension, with the same continuum model as the membrane in
space but none of its code: a disc of radius a (mm), clamped at r = a, isotropic Saint
Venant-Kirchhoff (membrane stiffness E h N/mm, Poisson's ratio nu), exact kinematics. A
material point at radius r moves to (r + u(r), w(r)) (radial, axial); the Green-Lagrange
strains and the plane-stress SVK energy per reference area are

    E_r = u' + (u'^2 + w'^2) / 2,   E_t = u / r + (u / r)^2 / 2,
    W = E h / (2 (1 - nu^2)) (E_r^2 + 2 nu E_r E_t + E_t^2).

A sphere of radius R centred on the axis at height z_c pushes it up through frictionless
penalty contact, the law of `membrane.loads`: energy k/2 <-g>^2 per reference area, g = |x - c|
- R. The total energy 2 pi int (W + k/2 <-g>^2) r dr is discretized with linear elements
(two-point Gauss) on a radial grid and minimized by Newton's method (the banded Hessian from
central differences of the exact gradient, backtracking on the energy). The force on the
sphere is 2 pi int k <-g> n_z r dr (N), n the unit vector from its centre.
"""

from typing import NamedTuple

import numpy as np
import scipy.linalg

GAUSS = np.array([0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0)])


class AxisymmetricIndentation(NamedTuple):
    """A solved indentation: travel (mm), force on the sphere (N, along +z the fabric resists),
    contact radius (mm, reference radius of the outermost quadrature point in contact), the
    grid radii (mm) and u, w there (mm)."""

    travel: float
    force: float
    contact_radius: float
    radii: np.ndarray
    radial: np.ndarray
    axial: np.ndarray


class _Disc:
    def __init__(self, radius, stiffness, poisson, *, sphere, penalty, elements):
        # grid graded towards the centre, where contact and the curvature sit
        s = np.linspace(0.0, 1.0, elements + 1)
        self.r = radius * (0.5 * s + 0.5 * s**2)
        self.h = np.diff(self.r)
        self.rq = self.r[:-1, None] + GAUSS[None, :] * self.h[:, None]  # (elements, 2)
        self.wq = 0.5 * self.h[:, None] * np.ones((1, 2))
        self.scale = stiffness / (1.0 - poisson**2)
        self.nu, self.sphere, self.k = poisson, sphere, penalty
        self.centre = 0.0
        count = 2 * (elements + 1)
        self.free = np.setdiff1d(np.arange(count), [0, count - 2, count - 1])

    def _fields(self, x):
        u, w = x[0::2], x[1::2]
        ua, ub, wa, wb = u[:-1, None], u[1:, None], w[:-1, None], w[1:, None]
        uq = ua + GAUSS * (ub - ua)
        wq = wa + GAUSS * (wb - wa)
        du = ((ub - ua) / self.h[:, None]) * np.ones((1, 2))
        dw = ((wb - wa) / self.h[:, None]) * np.ones((1, 2))
        return uq, wq, du, dw

    def _state(self, x):
        uq, wq, du, dw = self._fields(x)
        strain_r = du + 0.5 * (du**2 + dw**2)
        hoop = uq / self.rq
        strain_t = hoop + 0.5 * hoop**2
        stress_r = self.scale * (strain_r + self.nu * strain_t)
        stress_t = self.scale * (strain_t + self.nu * strain_r)
        offset_r, offset_z = self.rq + uq, wq - self.centre
        distance = np.hypot(offset_r, offset_z)
        overlap = np.minimum(distance - self.sphere, 0.0)  # <g>_- (mm, <= 0)
        return (
            uq,
            du,
            dw,
            strain_r,
            strain_t,
            stress_r,
            stress_t,
            offset_r,
            offset_z,
            distance,
            overlap,
        )

    def energy(self, x):
        _, _, _, er, et, sr, st, _, _, _, overlap = self._state(x)
        density = 0.5 * (sr * er + st * et) + 0.5 * self.k * overlap**2
        return 2.0 * np.pi * np.sum(self.wq * self.rq * density)

    def gradient(self, x):
        uq, du, dw, _, _, sr, st, orr, oz, d, overlap = self._state(x)
        weight = 2.0 * np.pi * self.wq * self.rq
        pressure = self.k * overlap
        # d(density)/d(u, u', w, w') at the quadrature points
        by_u = st * (1.0 + uq / self.rq) / self.rq + pressure * orr / d
        by_du = sr * (1.0 + du)
        by_w = pressure * oz / d
        by_dw = sr * dw
        grad = np.zeros_like(x)
        for values, slope, offset in ((by_u, by_du, 0), (by_w, by_dw, 1)):
            left = np.sum(weight * (values * (1.0 - GAUSS) - slope / self.h[:, None]), axis=1)
            right = np.sum(weight * (values * GAUSS + slope / self.h[:, None]), axis=1)
            grad[offset : -2 + offset or None : 2] += left
            grad[2 + offset :: 2] += right
        return grad

    def banded_hessian(self, x, step=1e-7):
        """The Hessian of the free dofs in scipy's (7, n) banded storage (bandwidth 3)."""
        n = self.free.size
        bands = np.zeros((7, n))
        for color in range(7):
            columns = np.arange(color, n, 7)
            probe = np.zeros_like(x)
            probe[self.free[columns]] = step
            diff = (self.gradient(x + probe) - self.gradient(x - probe))[self.free] / (2 * step)
            for column in columns:
                rows = np.arange(max(0, column - 3), min(n, column + 4))
                bands[3 + rows - column, column] = diff[rows]
        return bands

    def force(self, x):
        _, _, _, _, _, _, _, _, oz, d, overlap = self._state(x)
        return -2.0 * np.pi * np.sum(self.wq * self.rq * self.k * overlap * oz / d)

    def solve(self, x, tolerance, iterations=60):
        """Newton until |dPi/dx| <= tolerance (N)."""
        for _ in range(iterations):
            grad = self.gradient(x)[self.free]
            norm = np.linalg.norm(grad)
            if norm <= tolerance:
                return x
            step = np.zeros_like(x)
            step[self.free] = scipy.linalg.solve_banded((3, 3), self.banded_hessian(x), -grad)
            energy, factor = self.energy(x), 1.0
            while self.energy(x + factor * step) > energy + 1e-4 * factor * grad @ step[self.free]:
                factor *= 0.5
                if factor < 1e-8:
                    break
            x = x + factor * step
        raise RuntimeError(f"the axisymmetric reference did not converge (|grad| {norm:.3g})")


def indent_clamped_disc(
    travel: float,
    *,
    radius: float,
    stiffness: float,
    poisson: float,
    sphere: float,
    penalty: float,
    elements: int = 1600,
    steps: int = 12,
) -> AxisymmetricIndentation:
    """Push a sphere (radius `sphere` mm, touching the flat disc from below at t = 0) up by
    `travel` mm into a clamped SVK disc (`radius` mm, E h = `stiffness` N/mm, `poisson`),
    penalty `penalty` N/mm^3, in `steps` equal steps on a grid of `elements` elements."""
    disc = _Disc(radius, stiffness, poisson, sphere=sphere, penalty=penalty, elements=elements)
    x = np.zeros(2 * (elements + 1))
    # the flat, unstressed disc has no stiffness out of its plane: start from a dome
    x[1::2] = 0.1 * travel / steps * (1.0 - (disc.r / radius) ** 2)
    previous = 0.0
    for depth in np.linspace(0.0, travel, steps + 1)[1:]:
        disc.centre = depth - sphere
        if previous > 0.0:
            x = x * (depth / previous)  # the membrane scales about linearly with the depth
        x = disc.solve(x, 1e-10 * stiffness * radius)
        previous = depth
    *_, overlap = disc._state(x)
    touching = disc.rq[overlap < 0.0]
    return AxisymmetricIndentation(
        travel=travel,
        force=disc.force(x),
        contact_radius=float(touching.max()) if touching.size else 0.0,
        radii=disc.r,
        radial=x[0::2],
        axial=x[1::2],
    )
