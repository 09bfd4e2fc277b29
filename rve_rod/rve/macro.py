"""Macro deformation and macro stress of the periodic loop cell.

The cell is one period of the yarn: its end sits at its start plus F a1 (a1 = (w, 0, 0)), and
its lattice images (i, j) at x + F L with L = i a1 + j a2 (a2 = (0, c, 0)). A pattern's cell
has one such period per course, all along a1 = (p w, 0, 0), on a lattice a2 = (q w, s c, 0);
its n_cut is the sum of the forces at the cuts, and A0 = |a1 x a2|. The in-plane
components of F are prescribed by the load case or are macro unknowns (`MacroDeformation`).

The macro stress P (first Piola-Kirchhoff, force per undeformed width, N/mm) is the derivative
of the cell's energy with respect to F per reference area A0 = w c. F enters in two places:
the end position (x_end = x_start + F a1), where the yarn transmits its internal force n, and
the image positions, where the contacts with the images act. Hence (virtual work)

    P = ( n_cut (x) a1  +  1/2 sum_k w_k f_k (x) L_k ) / A0,    A0 = w c for one loop

with f_k the line load of contact k on its slave collocation point (force on the cell from
image L_k), w_k that point's collocation weight (the integral of the line load's spline
interpolant, exact for constants) and n_cut the force at the periodic cut. Every contact
between the cell and an image appears twice in the collocation scheme (each yarn is slave
once: the cell against image L, and the image's points, i.e. the cell's, against image -L),
hence the 1/2; the wale-wise load runs only through these image contacts. Contacts at the two
end collocation points are left out because the rod does not apply them there (those rows hold
the periodicity conditions); the cell is cut where there is no contact (docs/rve.md).
"""

import functools
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from rve_rod.rod import Block, Condition, ConditionContext, RodEnd
from rve_rod.rve.load_cases import COMPONENTS, LoadCase

if TYPE_CHECKING:
    from rve_rod.rve.coupling import ContactCoupling

__all__ = [
    "MacroBalance",
    "MacroDeformation",
    "StressParts",
    "macro_stress",
]


@dataclass(frozen=True, eq=False)
class MacroDeformation:
    """The in-plane macro F of a load case: prescribed components and unknown ones.

    The unknowns are the displacement gradients H_ab = F_ab - delta_ab of the free
    components, stored at state indices `columns`.

    Attributes:
        case: the load case.
        columns: (n_free,) state indices of the free components, in the order of case.free.
    """

    case: LoadCase
    columns: np.ndarray

    def matrix(self, state: np.ndarray, load_factor: float) -> np.ndarray:
        """F (3, 3) with F33 = 1 and no out-of-plane coupling."""
        F = np.eye(3)
        F[:2, :2] = self.case.prescribed(load_factor)
        for (a, b), column in zip(self.case.free, self.columns, strict=True):
            F[a, b] = float(a == b) + state[column]
        return F

    def derivative(self) -> np.ndarray:
        """d F / d unknowns, shape (3, 3, n_free) (constant)."""
        d = np.zeros((3, 3, len(self.case.free)))
        for k, (a, b) in enumerate(self.case.free):
            d[a, b, k] = 1.0
        return d

    def contact_components(self) -> np.ndarray:
        """Index of each free component among (F11, F12, F21, F22), shape (n_free,)."""
        return np.array([COMPONENTS.index(ab) for ab in self.case.free], dtype=np.int64)


class StressParts(NamedTuple):
    """The macro stress of a state and where it comes from.

    Attributes:
        first_piola: (2, 2) P = cut + images (N/mm).
        cut: (2, 2) n_cut (x) a1 / A0, the yarn force through the periodic cut (N/mm).
        images: (2, 2) the contacts with the lattice images (N/mm).
        contacts_at_cut: contacts at the two end collocation points (not applied, left out).
        friction: (2, 2) the part of `images` carried by the friction loads (N/mm); the rest,
            images - friction, is the normal loads'.
    """

    first_piola: np.ndarray
    cut: np.ndarray
    images: np.ndarray
    contacts_at_cut: int
    friction: np.ndarray


def image_weights(
    coupling: "ContactCoupling", result, column: int
) -> tuple[np.ndarray, np.ndarray]:
    """Weights c_k = w_k L_k,b / (2 A0) (1/mm) of the contacts of `result` for P_ab, b =
    `column`, and a mask of the contacts at the cut (excluded, weight 0)."""
    contacts = result.contacts
    at_cut = coupling.at_end[contacts.slave]
    shifts = contacts.image @ coupling.lattice[:, :2]  # (k, 2) reference L
    weights = 0.5 * coupling.weights[contacts.slave] * shifts[:, column] / coupling.area
    return np.where(at_cut, 0.0, weights), at_cut


def macro_stress(
    coupling: "ContactCoupling", cut_force: np.ndarray, state: np.ndarray, load_factor: float
) -> StressParts:
    """P of a state (module docstring); `cut_force` is n(END) (3,) (N)."""
    result = coupling.result(state, load_factor, tangent=False)
    cut = np.zeros((2, 2))
    cut[:, 0] = cut_force[:2] * coupling.lattice[0, 0] / coupling.area
    images = np.zeros((2, 2))
    friction = np.zeros((2, 2))
    at_cut = np.zeros(0, dtype=bool)
    for b in range(2):
        weights, at_cut = image_weights(coupling, result, b)
        images[:, b] = result.contacts.load[:2] @ weights
        friction[:, b] = result.contacts.friction_load[:2] @ weights
    return StressParts(cut + images, cut, images, int(np.count_nonzero(at_cut)), friction)


@dataclass(frozen=True, eq=False)
class MacroBalance(Condition):
    """The equations of the free macro components: P_ab - (F P0)_ab + kappa H_ab = 0 for
    each, P0 the stress of the cell's rest state (zero unless it is pre-loaded at rest:
    `rve_rod.rve.cell.LoopCell.rest_state`), so that a free direction carries no load beyond
    the rest state's second Piola stress S0 = P0 (turned and stretched with the cell, which
    keeps the balance objective: a rigid turn R of the cell holds R P0).

    kappa is a tiny regularizing stiffness (N/mm per unit strain): without any contact with
    the images P_22 does not depend on F22 at all (the courses slide apart or together
    freely), so the system would be singular exactly at the unloaded start of a uniaxial
    course-wise test; kappa makes the course height stay put until the contacts take over,
    and its force kappa H_ab is reported so that it can be checked to be negligible.

    Attributes:
        macro: the macro deformation (free components and their state indices).
        coupling: the contact coupling (its cached evaluation, weights and lattice).
        cuts: the rod ends at the cuts (one per patch) whose internal forces sum to n_cut.
        position_columns: (3n,) state indices of all control-point positions.
        regularization: kappa (N/mm).
        rest_stress: (2, 2) P0 (N/mm), filled in place by the cell once its rest state is
            known (zeros until then).
    """

    macro: MacroDeformation
    coupling: "ContactCoupling"
    cuts: tuple[RodEnd, ...]
    position_columns: np.ndarray
    regularization: float
    rest_stress: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))

    @property
    def extra_equations(self) -> int:  # type: ignore[override]
        return len(self.macro.case.free)

    @property
    def ends(self) -> tuple[RodEnd, ...]:
        return ()

    def row_scales(self, length: float, force: float) -> np.ndarray:
        return np.full(self.extra_equations, force / length)

    @functools.cached_property
    def _indices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(n, 3) the column 3i + c of position c of control point i in the positions' part
        of a row, (n_free,) `MacroDeformation.contact_components`, and the columns of a row:
        all positions, then the free components."""
        return (
            np.arange(self.position_columns.size).reshape(-1, 3),
            self.macro.contact_components(),
            np.concatenate([self.position_columns, self.macro.columns]),
        )

    def evaluate(self, context: ConditionContext, load_factor: float) -> list[Block]:
        state = context.state
        ends = [context.model.end_values(state, cut) for cut in self.cuts]
        coupling = self.coupling
        result = coupling.result(state, load_factor)
        contacts, derivatives = result.contacts, result.derivatives
        k = contacts.slave.size
        n_positions = self.position_columns.size
        position_index, components, columns = self._indices
        period = coupling.lattice[0, 0]
        F = self.macro.matrix(state, load_factor)[:2, :2]
        blocks = []
        for row, ((a, b), unknown) in enumerate(
            zip(self.macro.case.free, self.macro.columns, strict=True)
        ):
            rows = context.rows[row : row + 1]
            # the yarn force through the cuts enters P_a1 only
            scale = period / coupling.area if b == 0 else 0.0
            blocks += [
                Block(
                    rows,
                    np.array([scale * end.force[a]]),
                    end.columns,
                    scale * end.d_force[a : a + 1],
                )
                for end in ends
            ]
            jacobian = np.zeros(columns.size)
            value = self.regularization * state[unknown] - (F @ self.rest_stress)[a, b]
            jacobian[n_positions + row] = self.regularization
            # d (F P0)_ab / d F_ac = P0_cb for each free component (a, c)
            for column, (a_free, c) in enumerate(self.macro.case.free):
                if a_free == a:
                    jacobian[n_positions + column] -= self.rest_stress[c, b]
            if k:
                weights, _ = image_weights(coupling, result, b)
                value += weights @ contacts.load[a]
                # d load_a / d positions of contact i, entries in row i
                load_rows = np.full((3, k), -1)
                load_rows[a] = np.arange(k)
                entries = derivatives.entries(load_rows, position_index)
                jacobian[:n_positions] += np.bincount(
                    entries.columns,
                    weights=entries.values * weights[entries.rows],
                    minlength=n_positions,
                )
                by_macro = weights @ derivatives.deformation[a * k : (a + 1) * k]
                jacobian[n_positions:] += by_macro[components]
            blocks.append(Block(rows, np.array([value]), columns, jacobian[None, :]))
        return blocks
