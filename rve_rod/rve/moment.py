"""The bending moment per width of the periodic cell: the moment a fabric's edge has to carry
to stay flat, whose sign says which way a free edge curls (docs/rve.md, "Bending moment").

Cut the fabric by the plane of reference coordinate xi_b = X0 (xi = F^-1 x in the plane: the
image under F of the reference plane normal to e_b; b = 1 normal to the courses, x = F11 X0 in
the uniaxial cases, b = 2 normal to the wales) and take the moment, about the line of that
plane at the mid-plane height z_m (the arc-length mean z of the yarn), of everything the side
xi_b > X0 exerts on the side xi_b < X0, per unit reference length of the cut:

    m_b = (1 / l_b) [ sum_crossings s_i ((r_i - p0) x n_i + m_i)
                      + 1/2 sum_contacts s_k int C_k(u) ((r(u) - p0) x f_k) ds ] . t_b

* the yarns crossing the plane at r_i, with the rod's internal force n_i and couple m_i there
  (what the part at larger arc length exerts on the part before it), s_i = +1 where the yarn
  crosses to the + side, -1 where it crosses back;
* the contacts between yarns on the two sides: contact k's line load f_k on its slave
  collocation point, spread along the slave yarn as the rod sees it (C_k the cardinal function
  of that point in the spline interpolant of the line loads, whose integral is the collocation
  weight w_k of the macro stress), counted where the slave yarn and the master point lie on
  opposite sides, s_k = +1 with the slave on the - side; 1/2 because the two-pass scheme
  evaluates every contact twice, as in the macro stress (`rve_rod.rve.macro`);
* t_b the unit vector of the line (F e_2 for b = 1, F e_1 for b = 2), p0 a point of it; only
  the height z - z_m and, for a contact, the distance from the plane give a moment about it;
* l_b = A0 / m_b the length of the cut per set of crossings: the yarns of the cell and their
  images cross the plane xi_b = X0 wherever xi_b(r) = X0 modulo m_b, the smallest positive
  b-component of the lattice vectors (c s for b = 2; w gcd(p, q) for b = 1).

The bending moments are reported in the layout of P (moment of the force component a on the
cut normal to b, as a plate's M_ab = int z N_ab dz): M_11 = m_1 . t_1 and M_22 = -m_2 . t_2,
positive when the yarn force on the cut acts above the mid-plane (N mm / mm). Held flat, a cell
with M_bb > 0 carries more tension on its +z side; a free edge normal to e_b relaxes it by
curling towards +z (the fabric's technical face, `rve_rod.geometry.pattern_cell`), M_bb < 0
towards -z (the back).

The moment on one cut moves with X0: the slab between two parallel cuts is in equilibrium,
so dM/dX0 = V, the transverse force across the cut, which would vanish if the out-of-plane
contact forces balanced; the two-pass contact's do not (the point support carries their sum,
docs/rve.md), and V is of the order of 5 % of the in-plane force. The cell's moment is
therefore the mean over the cut positions X0 in one period (`MomentCuts.mean`), in which each
point of the yarn is passed by the cut for |d xi_b / du| du of X0 and a contact pair lies
across it for |Delta| of X0 (Delta = xi_b(master) - xi_b(slave point)), its lever averaged:

    m_b . t_b = (1 / A0) [ int (d xi_b / du) ((z - z_m) e3 x n + m) . t_b du
        + 1/2 sum_k int C_k (Delta_k (z - z_m) e3 x f_k - Delta_k^2 / 2 F e_b x f_k) . t_b ds ]

and the same integral with n and Delta_k f_k is the force across the cut, whose in-plane part
is the macro stress P[:, b] again and whose transverse part averages to zero (tested). The
rod's collocation equations hold at the collocation points; between them n, m and the
interpolated loads balance to the discretization error.
"""

import fractions
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import scipy.optimize
import scipy.sparse

from rve_rod.errors import InputError
from rve_rod.geometry.bspline import BSplineCurve, basis_matrix
from rve_rod.rod.model import SectionPoints

if TYPE_CHECKING:
    from rve_rod.rve.cell import LoopCell

__all__ = [
    "BendingMoment",
    "MomentCuts",
]

GAUSS_POINTS = 4
"""Gauss points per knot span where the contact loads are integrated along the slave yarn."""

SAMPLES_PER_SPAN = 8
"""Samples per knot span where the crossings of a cut plane are bracketed."""


class BendingMoment(NamedTuple):
    """The bending moments per width of a state of the cell (module docstring).

    Attributes:
        moment: (2,) M_11 on the cut normal to the courses (x), M_22 on the cut normal to the
            wales (y) (N mm / mm).
        parts: (3, 2) where they come from: the yarn force at the crossings (lever z - z_m),
            the rod couple at the crossings, the contacts across the cut (N mm / mm).
        mid_plane: z_m, the arc-length mean z of the yarn (mm).
        force: (3, 2) the force per width across each cut (column b: what the + side exerts
            on the - side, N/mm): its in-plane part is the macro stress P[:, b] again, its z
            part the transverse force V_b, whose change along e_b moves the moment.
    """

    moment: np.ndarray
    parts: np.ndarray
    mid_plane: float
    force: np.ndarray


class _Quadrature(NamedTuple):
    """Gauss points along one patch and the cardinal functions of its collocation points."""

    parameters: np.ndarray  # (G,)
    weights: np.ndarray  # (G,) Gauss weight times the reference speed |r0'| (mm)
    speed: np.ndarray  # (G,) the reference speed |r0'| (mm per unit u)
    cardinal: np.ndarray  # (G, n) C_i(u_g): the interpolant of values 1 at point i, 0 elsewhere


def _quadrature(curve: BSplineCurve, inverse: np.ndarray, breaks=()) -> _Quadrature:
    """Gauss points on every knot span of the reference `curve`, its spans split at `breaks`
    (where the integrand jumps); `inverse`: B^-1, B the basis matrix at the collocation
    points."""
    edges = np.union1d(curve.breakpoints(), np.asarray(breaks, dtype=float))
    nodes, weights = np.polynomial.legendre.leggauss(GAUSS_POINTS)
    half = 0.5 * np.diff(edges)
    parameters = (edges[:-1, None] + half[:, None] * (nodes[None, :] + 1.0)).ravel()
    speed = np.linalg.norm(curve(parameters, 1), axis=1)
    cardinal = basis_matrix(curve.knots, curve.degree, parameters) @ inverse
    gauss = (half[:, None] * weights[None, :]).ravel()
    return _Quadrature(parameters, gauss * speed, speed, cardinal)


def _lattice_modulus(lattice: np.ndarray, b: int) -> float:
    """m_b, the smallest positive b-component of the lattice vectors i a1 + j a2 (mm)."""
    if b == 1:
        return abs(float(lattice[1, 1]))
    along, oblique = float(lattice[0, 0]), float(lattice[1, 0])
    ratio = fractions.Fraction(oblique / along).limit_denominator(64)
    if abs(ratio - oblique / along) > 1e-9:
        raise InputError(
            f"the lattice's a2_x / a1_x = {oblique / along:.12g} is no ratio of small integers: "
            "the cut normal to the courses meets no periodic set of crossings"
        )
    return abs(along) / ratio.denominator


class _Deformed(NamedTuple):
    """What the moments of one state need."""

    F: np.ndarray  # (3, 3) macro F (in-plane)
    inverse: np.ndarray  # (2, 2) in-plane F^-1: xi = inverse @ x
    curves: list  # the deformed centreline of every patch
    mid_plane: float  # z_m (mm)
    slave: list  # per patch: (c,) local collocation index of its contacts' slave points
    load: list  # per patch: (3, c) the contacts' line loads (N/mm)
    master: list  # per patch: (c, 3) the contacts' master points, images included (mm)


class _PatchPoints(NamedTuple):
    """The Gauss points of one patch and what does not change there with the state."""

    quadrature: _Quadrature  # with the cardinal functions (G, n)
    values: scipy.sparse.csr_matrix  # (G, n) basis functions at the Gauss points
    slopes: scipy.sparse.csr_matrix  # (G, n) their u-derivatives
    section: SectionPoints  # for the rod's n and m there


class MomentCuts:
    """The bending moments of the states of one cell (module docstring).

    Args:
        cell: the loop cell.

    The Gauss points of every patch, the basis and reference data there and the cardinal
    functions of its collocation points are made once; `mean` gives the moments of a state
    averaged over the cut positions (what a run reports), `at_cut` at one cut.
    """

    def __init__(self, cell: "LoopCell"):
        self.cell = cell
        self.lattice = cell.coupling.lattice
        self.area = cell.coupling.area
        self.moduli = np.array([_lattice_modulus(self.lattice, b) for b in range(2)])
        self._inverses = [
            np.linalg.inv(basis_matrix(curve.knots, curve.degree, curve.greville()).toarray())
            for curve in cell.curves
        ]
        self._patches = []
        for k, (curve, inverse) in enumerate(zip(cell.curves, self._inverses, strict=True)):
            q = _quadrature(curve, inverse)
            self._patches.append(
                _PatchPoints(
                    q,
                    basis_matrix(curve.knots, curve.degree, q.parameters),
                    basis_matrix(curve.knots, curve.degree, q.parameters, 1),
                    cell.model.section_points(k, q.parameters),
                )
            )
        self._first = np.cumsum([0] + [curve.n_control_points for curve in cell.curves])

    def check_weights(self) -> float:
        """The largest difference between the integral of each cardinal function and the
        collocation weight the macro stress uses (mm): zero up to round-off."""
        weights = self.cell.coupling.weights
        return max(
            float(
                np.abs(
                    patch.quadrature.weights @ patch.quadrature.cardinal
                    - weights[first : first + patch.quadrature.cardinal.shape[1]]
                ).max()
            )
            for patch, first in zip(self._patches, self._first, strict=False)
        )

    def _deformed(self, state, load_factor, mid_plane) -> _Deformed:
        cell = self.cell
        F = np.eye(3)
        F[:2, :2] = cell.macro.matrix(state, load_factor)[:2, :2]
        positions = [cell.model.control_points(state, k).positions for k in range(len(cell.curves))]
        curves = [
            BSplineCurve(curve.degree, curve.knots, points)
            for curve, points in zip(cell.curves, positions, strict=True)
        ]
        if mid_plane is None:
            heights, lengths = [], []
            for patch, points in zip(self._patches, positions, strict=True):
                q = patch.quadrature
                heights.append(patch.values @ points[:, 2])
                speed = np.linalg.norm(patch.slopes @ points, axis=1)
                lengths.append(speed * q.weights / q.speed)
            mid_plane = float(np.concatenate(heights) @ np.concatenate(lengths))
            mid_plane /= float(np.concatenate(lengths).sum())
        contacts = cell.coupling.result(state, load_factor, tangent=False).contacts
        kept = ~cell.coupling.at_end[contacts.slave]  # not applied by the rod (macro stress)
        slave = contacts.slave[kept]
        master = np.zeros((slave.size, 3))
        for k, curve in enumerate(curves):
            mine = contacts.patch[kept] == k
            master[mine] = curve(contacts.parameter[kept][mine])
        master += contacts.image[kept] @ self.lattice @ F.T
        patch_of = np.searchsorted(self._first, slave, side="right") - 1
        mine = [np.flatnonzero(patch_of == k) for k in range(len(curves))]
        return _Deformed(
            F,
            np.linalg.inv(F[:2, :2]),
            curves,
            mid_plane,
            [slave[m] - self._first[k] for k, m in enumerate(mine)],
            [contacts.load[:, kept][:, m] for m in mine],
            [master[m] for m in mine],
        )

    def mean(
        self, state: np.ndarray, load_factor: float, mid_plane: float | None = None
    ) -> BendingMoment:
        """The moments of a state averaged over the positions X0 of the cuts (the cell's
        bending moment, what a run reports; module docstring).

        Args:
            state: the cell's state; load_factor: its t.
            mid_plane: z_m (mm); None takes the arc-length mean z of the yarn.
        """
        deformed = self._deformed(state, load_factor, mid_plane)
        F, inverse = deformed.F, deformed.inverse
        lines = np.array([F[:, 1] / np.linalg.norm(F[:, 1]), F[:, 0] / np.linalg.norm(F[:, 0])])
        parts = np.zeros((3, 2))
        force = np.zeros((3, 2))
        for k, patch in enumerate(self._patches):
            q = patch.quadrature
            positions = deformed.curves[k].control_points
            points, tangents = patch.values @ positions, patch.slopes @ positions
            section = self.cell.model.section_forces(state, patch.section)
            height = points[:, 2] - deformed.mid_plane
            # the rod: every point is passed by the cut for |d xi_b / du| du of X0
            rate = (tangents[:, :2] @ inverse.T) * (q.weights / q.speed)[:, None]  # (G, 2)
            lever = np.cross([0.0, 0.0, 1.0], section.force.T)  # e3 x n, (G, 3)
            parts[0] += np.einsum("gb,g,gb->b", rate, height, lever @ lines.T)
            parts[1] += np.einsum("gb,gb->b", rate, section.moment.T @ lines.T)
            force += section.force @ rate
            # the contacts: across the cut for |Delta| of X0, their lever averaged over it;
            # Delta = xi_b(master) - xi_b(u) expanded, so that the integrals over u of the
            # cardinal functions are the sums S of C_i w_g times 1, xi, h, xi h, xi^2
            slave = deformed.slave[k]
            if not slave.size:
                continue
            xi = points[:, :2] @ inverse.T  # (G, 2)
            columns = np.column_stack(
                [np.ones_like(height), xi, height, xi * height[:, None], xi**2]
            )
            sums = (patch.quadrature.cardinal.T @ (q.weights[:, None] * columns))[slave]  # (c, 8)
            load = deformed.load[k]
            master = deformed.master[k][:, :2] @ inverse.T  # (c, 2)
            out_of_plane = np.cross([0.0, 0.0, 1.0], load.T) @ lines.T  # (c, 2)
            for b in range(2):
                total, along, high, both, square = sums[:, [0, 1 + b, 3, 4 + b, 6 + b]].T
                in_plane = np.cross(F[:, b], load.T) @ lines[b]
                at = master[:, b]
                torque = out_of_plane[:, b] * (at * high - both) - 0.5 * in_plane * (
                    at**2 * total - 2.0 * at * along + square
                )  # int C (Delta h o - Delta^2 / 2 a), Delta = at - xi
                parts[2, b] += 0.5 * torque.sum()
                force[:, b] += 0.5 * load @ (at * total - along)
        return self._moments(parts / self.area, force / self.area, deformed.mid_plane)

    def at_cut(
        self,
        state: np.ndarray,
        load_factor: float,
        at: tuple[float, float] = (0.0, 0.0),
        mid_plane: float | None = None,
    ) -> BendingMoment:
        """The moments of a state on one cut of each direction (module docstring).

        Args:
            state: the cell's state; load_factor: its t.
            at: (2,) the cuts' reference positions X0, as fractions of m_b (of the period of
                the crossings along e_b): the cut normal to the courses, then to the wales.
            mid_plane: z_m (mm); None takes the arc-length mean z of the yarn.
        """
        cell = self.cell
        deformed = self._deformed(state, load_factor, mid_plane)
        F, height0 = deformed.F, deformed.mid_plane
        parts = np.zeros((3, 2))
        force = np.zeros((3, 2))
        for b in range(2):
            line = F[:, 1 - b] / np.linalg.norm(F[:, 1 - b])
            modulus = self.moduli[b]
            level = at[b] * modulus

            def phase(points, b=b, level=level, modulus=modulus):
                return (points[:, :2] @ deformed.inverse[b] - level) / modulus

            for k, curve in enumerate(deformed.curves):
                crossings = _crossings(curve, phase)
                for u, sign in crossings:
                    point = cell.model.section_points(k, np.array([u]))
                    section = cell.model.section_forces(state, point)
                    lever = np.array([0.0, 0.0, curve(np.array([u]))[0, 2] - height0])
                    parts[0, b] += sign * np.cross(lever, section.force[:, 0]) @ line
                    parts[1, b] += sign * section.moment[:, 0] @ line
                    force[:, b] += sign * section.force[:, 0]
                load = deformed.load[k]
                if not load.shape[1]:
                    continue
                # the slave yarn's side flips at the crossings: split the quadrature there
                q = _quadrature(cell.curves[k], self._inverses[k], [u for u, _ in crossings])
                points = curve(q.parameters)
                along = phase(points)  # (G,)
                below = np.floor(along)[:, None]  # (G, 1) the plane below each Gauss point
                master_below = np.floor(phase(deformed.master[k]))[None, :]  # (1, c)
                sides = np.sign(master_below - below)  # +1: slave below a plane, master above
                plane = np.maximum(below, master_below)  # the plane between them (G, c)
                distance = (along[:, None] - plane) * modulus  # from the plane, reference mm
                # (d x f) . t with d = F e_b distance + (z - z_m) e3
                in_plane = np.cross(F[:, b], load.T) @ line  # (c,)
                out_of_plane = np.cross([0.0, 0.0, 1.0], load.T) @ line  # (c,)
                height = points[:, 2:] - height0
                torque = distance * in_plane[None, :] + height * out_of_plane[None, :]
                density = q.cardinal[:, deformed.slave[k]] * q.weights[:, None]
                parts[2, b] += 0.5 * np.sum(sides * density * torque)
                force[:, b] += 0.5 * load @ np.sum(sides * density, axis=0)
        scale = self.moduli / self.area
        return self._moments(parts * scale, force * scale, height0)

    @staticmethod
    def _moments(parts, force, mid_plane) -> BendingMoment:
        """M_11 = m_1 . t_1, M_22 = -m_2 . t_2 (module docstring) from m_b . t_b."""
        parts = parts * np.array([1.0, -1.0])
        return BendingMoment(parts.sum(axis=0), parts, mid_plane, force)


def _crossings(curve: BSplineCurve, phase) -> list[tuple[float, float]]:
    """Where `phase` (of points (m, 3)) along `curve` passes an integer, over the curve's
    domain: (parameter, +1 upwards / -1 downwards) each."""
    edges = curve.breakpoints()
    within = np.arange(SAMPLES_PER_SPAN) / SAMPLES_PER_SPAN
    samples = np.append((edges[:-1, None] + np.diff(edges)[:, None] * within).ravel(), edges[-1])
    values = phase(curve(samples))
    levels = np.floor(values)
    found = []
    for i in np.flatnonzero(levels[1:] != levels[:-1]):
        low, high = levels[i], levels[i + 1]
        sign = 1.0 if high > low else -1.0
        for integer in np.arange(min(low, high) + 1, max(low, high) + 1):

            def offset(u, integer=integer):
                return phase(curve(np.array([u])))[0] - integer

            u = scipy.optimize.brentq(offset, samples[i], samples[i + 1], xtol=1e-14)
            found.append((u, sign))
    return found
