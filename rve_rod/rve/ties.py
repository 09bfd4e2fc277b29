"""Soft ties between the yarns of a cell with several courses (garter, moss, supercells), and
the diagnostic spring that holds a cell's depth.

One yarn of a cell is held against its rigid motion by the point support of the cell
(`rve_rod.rve.cell`); every other yarn is held only by its contacts with the first and with
the images. In the template those contacts just touch (the penalty law has no stiffness at
zero penetration), so the other yarns' rigid motions relative to the first (three translations
and the rotation about the course direction) have no stiffness until the load presses the
yarns together, and Newton's matrix is singular. A `YarnTie` is a spring of stiffness kappa
(the cell's regularizing stiffness, `CellSettings.lateral_stiffness` times EA / c) between a
point of yarn k and the same point of yarn 0, at rest where the affine map carries them:

    f_k = -kappa (x_k - x_0 - F (X_k - X_0)),    f_0 = -f_k,

each lumped onto the collocation points as a point load. Two ties per yarn, at points apart
along y, hold the rotation about the course direction too. The ties are internal (no net
force); their contribution to the macro stress, f_k (x) (X_k - X_0) / A0, is reported with the
cell's other regularization (`rve_rod.rve.cell.CellState.regularization`), to be checked
negligible, as kappa H of the free macro components is.

A `DepthHold` is a diagnostic, not a model: springs f_z = -kappa (z - z_rest) that pull points
of the centrelines (one per control point of each patch, its ends excluded) towards the z they
had at rest, lumped like the ties. It holds a cell's depth (its extent through the thickness)
so that an experiment can tell what the loop's thinning does (docs/validation.md, "The squeezed
rest, balanced"; `rve_rod.rve.paper.comparison.depth_held_runner`).
"""

from dataclasses import dataclass

import numpy as np

from rve_rod.rod import Block, Condition, ConditionContext, RodEnd
from rve_rod.rod.layout import DOFS_PER_POINT
from rve_rod.rve.macro import MacroDeformation

__all__ = [
    "DepthHold",
    "YarnTie",
]


@dataclass(frozen=True, eq=False)
class YarnTie(Condition):
    """A soft spring between the point at `parameter` of patch `patch` and of patch 0
    (module docstring).

    Attributes:
        patch: the tied patch (>= 1).
        parameter: the patch parameter of both points.
        stiffness: kappa (N/mm).
        macro: the macro deformation (F and its free components).
    """

    patch: int
    parameter: float
    stiffness: float
    macro: MacroDeformation

    @property
    def ends(self) -> tuple[RodEnd, ...]:
        return ()

    def _points(self, model, state):
        """Per tied patch (k, then 0): control-point columns (p+1, 3), basis values (p+1,),
        reference and current point (3,) (mm)."""
        layout = model.layout
        for patch in (self.patch, 0):
            local, values = model.point_basis(patch, self.parameter)
            columns = layout.position_dofs(patch)[local]
            reference = values @ model.patches[patch].centreline.control_points[local]
            yield columns, values, reference, values @ state[columns]

    def gap(self, model, state: np.ndarray, load_factor: float) -> tuple[np.ndarray, np.ndarray]:
        """x_k - x_0 - F (X_k - X_0) (3,) and X_k - X_0 (3,) (mm)."""
        (_, _, tied, current), (_, _, anchor, anchored) = self._points(model, state)
        offset = tied - anchor
        F = self.macro.matrix(state, load_factor)
        return current - anchored - F @ offset, offset

    def evaluate(self, context: ConditionContext, load_factor: float) -> list[Block]:
        model, state = context.model, context.state
        (tied_columns, tied_values, _, _), (anchor_columns, anchor_values, _, _) = self._points(
            model, state
        )
        gap, offset = self.gap(model, state, load_factor)
        kappa = self.stiffness
        by_macro = -np.array(
            [[offset[b] if a == c else 0.0 for a, b in self.macro.case.free] for c in range(3)]
        ).reshape(3, -1)
        blocks = []
        for patch, sign in ((self.patch, -1.0), (0, 1.0)):
            lumped = model.point_load_weights(patch, self.parameter)
            for c in range(3):
                columns = np.concatenate(
                    [tied_columns[:, c], anchor_columns[:, c], self.macro.columns]
                )
                derivative = (
                    sign * kappa * np.concatenate([tied_values, -anchor_values, by_macro[c]])
                )
                blocks.append(
                    Block(
                        DOFS_PER_POINT * lumped.points + c,
                        lumped.weights * sign * kappa * gap[c],
                        columns,
                        lumped.weights[:, None] * derivative[None, :],
                    )
                )
        return blocks

    def stress(self, model, state: np.ndarray, load_factor: float, area: float) -> np.ndarray:
        """The tie's share of the macro stress, f_k (x) (X_k - X_0) / A0, (2, 2) (N/mm)."""
        gap, offset = self.gap(model, state, load_factor)
        return np.outer(-self.stiffness * gap[:2], offset[:2]) / area


class DepthHold(Condition):
    """Springs f_z = -kappa (z - z_rest) at one point per control point of every patch, its
    ends excluded (module docstring); off (kappa = 0) until `hold` gives the rest state."""

    def __init__(self):
        self.stiffness = 0.0
        self.rest_z: np.ndarray | None = None
        self._samples: list | None = None

    @property
    def ends(self) -> tuple[RodEnd, ...]:
        return ()

    def samples(self, model) -> list:
        """Per held point: patch, parameter, z columns (p+1,) and basis values (p+1,)."""
        if self._samples is None:
            self._samples = []
            for patch, rod in enumerate(model.patches):
                low, high = rod.centreline.domain
                for u in np.linspace(low, high, rod.centreline.n_control_points)[1:-1]:
                    local, values = model.point_basis(patch, float(u))
                    columns = model.layout.position_dofs(patch)[local][:, 2]
                    self._samples.append((patch, float(u), columns, values))
        return self._samples

    def z_values(self, model, state: np.ndarray) -> np.ndarray:
        """(k,) z of the held points at `state` (mm)."""
        return np.array([values @ state[columns] for *_, columns, values in self.samples(model)])

    def hold(self, model, rest: np.ndarray, stiffness: float) -> None:
        """Hold the points at their z in `rest` with springs of `stiffness` kappa (N/mm)."""
        self.rest_z = self.z_values(model, rest)
        self.stiffness = stiffness

    def evaluate(self, context: ConditionContext, load_factor: float) -> list[Block]:
        model, state = context.model, context.state
        current = self.z_values(model, state)
        rest = current if self.rest_z is None else self.rest_z
        blocks = []
        for (patch, parameter, columns, values), z, z_rest in zip(
            self.samples(model), current, rest, strict=True
        ):
            lumped = model.point_load_weights(patch, parameter)
            blocks.append(
                Block(
                    DOFS_PER_POINT * lumped.points + 2,
                    -self.stiffness * (z - z_rest) * lumped.weights,
                    columns,
                    -self.stiffness * lumped.weights[:, None] * values[None, :],
                )
            )
        return blocks
