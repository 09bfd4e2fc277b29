"""Where each unknown lives in the global state vector, and each equation in the residual.

Control points are numbered globally, patch after patch: control point i of patch k is global
point g = first_point[k] + i. Its seven unknowns sit at state[7 g : 7 g + 7] as
(x, y, z, q0, q1, q2, q3); user-defined extra unknowns (e.g. macro strains, multipliers) follow
all control points. Residual rows mirror the unknowns: collocation point i of patch k is the
Greville point of control point i, and rows 7 g + (0, 1, 2) hold its force balance, 7 g +
(3, 4, 5) its moment balance and 7 g + 6 its gauge |q|^2 = 1. At the first and last collocation
point of a patch rows 0..5 belong to that rod end instead; the condition that claims the end
fills them. Extra equations follow all collocation rows.
"""

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rve_rod.errors import InputError

__all__ = [
    "DOFS_PER_POINT",
    "END",
    "START",
    "DofLayout",
    "RodEnd",
]

START = "start"
"""The rod end at the first parameter of a patch (u = u_min)."""

END = "end"
"""The rod end at the last parameter of a patch (u = u_max)."""

DOFS_PER_POINT = 7
"""Unknowns per control point: position (3) and quaternion (4)."""


class RodEnd(NamedTuple):
    """One end of one patch: `patch` index and `side` (START or END)."""

    patch: int
    side: str


@dataclass(frozen=True)
class DofLayout:
    """Numbering of the unknowns and equations (see the module docstring).

    Attributes:
        points_per_patch: number of control points of each patch.
        n_extra: number of extra global unknowns (and of extra equations).
    """

    points_per_patch: tuple[int, ...]
    n_extra: int = 0

    @property
    def n_patches(self) -> int:
        return len(self.points_per_patch)

    @property
    def n_points(self) -> int:
        """Control points (= collocation points) of all patches."""
        return int(sum(self.points_per_patch))

    @property
    def n_dofs(self) -> int:
        """Length of the state vector and of the residual."""
        return DOFS_PER_POINT * self.n_points + self.n_extra

    @property
    def extra_offset(self) -> int:
        """Index of the first extra unknown (and the first extra equation)."""
        return DOFS_PER_POINT * self.n_points

    def first_point(self, patch: int) -> int:
        """Global index of control point 0 of `patch`."""
        self._check_patch(patch)
        return int(sum(self.points_per_patch[:patch]))

    def points(self, patch: int) -> np.ndarray:
        """Global control-point indices of `patch`, shape (n_k,)."""
        first = self.first_point(patch)
        return np.arange(first, first + self.points_per_patch[patch])

    def position_dofs(self, patch: int) -> np.ndarray:
        """State indices of the control-point positions of `patch`, shape (n_k, 3)."""
        return DOFS_PER_POINT * self.points(patch)[:, None] + np.arange(3)[None, :]

    def quaternion_dofs(self, patch: int) -> np.ndarray:
        """State indices of the control-point quaternions of `patch`, shape (n_k, 4)."""
        return DOFS_PER_POINT * self.points(patch)[:, None] + 3 + np.arange(4)[None, :]

    def extra_dofs(self) -> np.ndarray:
        """State indices of the extra unknowns, shape (n_extra,)."""
        return self.extra_offset + np.arange(self.n_extra)

    def end_point(self, end: RodEnd) -> int:
        """Global control (and collocation) point index of a rod end."""
        self._check_patch(end.patch)
        if end.side == START:
            return self.first_point(end.patch)
        if end.side == END:
            return self.first_point(end.patch) + self.points_per_patch[end.patch] - 1
        raise InputError(f"side={end.side!r} is not one of {START!r}, {END!r}")

    def end_rows(self, end: RodEnd) -> np.ndarray:
        """The six residual rows of a rod end, shape (6,)."""
        return DOFS_PER_POINT * self.end_point(end) + np.arange(6)

    def _check_patch(self, patch: int) -> None:
        if not 0 <= patch < self.n_patches:
            raise InputError(f"patch={patch} is outside the valid range [0, {self.n_patches - 1}]")
