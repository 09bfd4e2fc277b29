"""The contact of the loop cell with itself and its images as a state-dependent load on the rod.

`ContactCoupling` is the rod's `StateDependentLoad`: it evaluates `rve_rod.contact` at the
control-point positions of a state and the macro F of that state, and returns the line loads
with their derivatives with respect to the state (positions and the free macro components).
It keeps the last evaluation, so the macro stress, which needs the same contacts one by one,
and the friction commit after a converged step reuse it instead of searching again.
"""

import logging
from typing import NamedTuple

import numpy as np
import scipy.sparse

from rve_rod.contact import ContactModel, ContactResult
from rve_rod.rod import LineLoads
from rve_rod.rod.layout import DOFS_PER_POINT
from rve_rod.rve.macro import MacroDeformation

__all__ = [
    "ContactCoupling",
]

logger = logging.getLogger(__name__)


class _Cached(NamedTuple):
    state: np.ndarray
    load_factor: float
    tangent: bool
    result: ContactResult


class ContactCoupling:
    """Contact line loads on the rod patches of a cell whose images sit at x + F L.

    Args:
        contact: the contact model of the cell's yarns (one patch each, periodic lattice).
        macro: the macro deformation (prescribed and unknown components of F).
        n_control_points: control points of the rod (= collocation points).

    Attributes:
        contact, macro: as given.
        weights: (n,) collocation weights (mm) of the contact layout.
        lattice: (2, 3) reference lattice vectors a1, a2 (mm).
        area: reference cell area |a1 x a2| (mm^2).
        end_points: (2 k,) the collocation points at the cuts of the k patches (where the rod
            ignores line loads).
        at_end: (n,) bool, True at the `end_points`.
    """

    def __init__(self, contact: ContactModel, macro: MacroDeformation, n_control_points: int):
        self.contact = contact
        self.macro = macro
        self.weights = contact.collocation_weights
        self.lattice = contact.lattice.vectors
        self.area = float(abs(np.linalg.det(self.lattice[:, :2])))
        layout = contact.layout
        patch_of_point = layout.span_patch[layout.point_span]
        self.end_points = np.array(
            [
                index
                for patch in range(int(patch_of_point.max()) + 1)
                for index in np.flatnonzero(patch_of_point == patch)[[0, -1]]
            ]
        )
        self.at_end = np.zeros(patch_of_point.size, dtype=bool)
        self.at_end[self.end_points] = True
        self._n = int(n_control_points)
        self._position_columns = (
            DOFS_PER_POINT * np.arange(self._n)[:, None] + np.arange(3)[None, :]
        )  # (n, 3) state index of position c of control point i
        self._cached: _Cached | None = None

    def positions(self, state: np.ndarray) -> np.ndarray:
        """Control-point positions (n, 3) of a state (mm)."""
        return state[: DOFS_PER_POINT * self._n].reshape(self._n, DOFS_PER_POINT)[:, :3]

    def result(self, state: np.ndarray, load_factor: float, tangent: bool = True) -> ContactResult:
        """The contact evaluation at `state` and t (cached: one search per state)."""
        cached = self._cached
        if (
            cached is not None
            and cached.load_factor == load_factor
            and (cached.tangent or not tangent)
            and np.array_equal(cached.state, state)
        ):
            return cached.result
        F = self.macro.matrix(state, load_factor)
        result = self.contact.evaluate(self.positions(state), F, tangent=tangent)
        self._cached = _Cached(np.array(state, copy=True), load_factor, tangent, result)
        return result

    def use_law(self, law) -> None:
        """Evaluate the contacts with `law` (a `CompressibleYarnLaw`) from now on."""
        self.contact.use_law(law)
        self._cached = None

    def anchor_at(self, state: np.ndarray, load_factor: float) -> None:
        """Make the contacts of `state` the friction anchors (`ContactModel.anchor_at`)."""
        self.contact.anchor_at(self.positions(state), self.macro.matrix(state, load_factor))
        self._cached = None

    def commit(self, state: np.ndarray, load_factor: float) -> None:
        """Adopt the friction anchors of a converged state (after each converged step).

        The cached evaluation is dropped: it was made with the previous anchors.
        """
        self.contact.commit(self.result(state, load_factor, tangent=False))
        self._cached = None

    def __call__(self, model, state: np.ndarray, load_factor: float) -> LineLoads:
        result = self.result(state, load_factor)
        derivatives = result.line_derivatives
        m, k = result.line_load.shape[1], derivatives.slave.size
        # component c of contact i loads line-load row c m + slave_i (as LineLoads counts)
        load_rows = m * np.arange(3)[:, None] + derivatives.slave[None, :]
        rows, columns, values = derivatives.entries(load_rows, self._position_columns)
        free = self.macro.columns
        if free.size:
            by_macro = derivatives.deformation.reshape(3, k, 4)[
                :, :, self.macro.contact_components()
            ]  # (3, k, f)
            rows = np.concatenate([rows, np.repeat(load_rows.ravel(), free.size)], dtype=np.int32)
            columns = np.concatenate([columns, np.tile(free, 3 * k)], dtype=np.int32)
            values = np.concatenate([values, by_macro.ravel()])
        force_jacobian = scipy.sparse.coo_matrix(
            (values, (rows, columns)), shape=(3 * m, model.n_dofs)
        )
        return LineLoads(result.line_load, None, force_jacobian, None)
