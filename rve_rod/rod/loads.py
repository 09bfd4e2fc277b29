"""External loads on rods: distributed line loads at collocation points and point loads.

The collocated balance equations read dn/ds + f = 0 and dm/ds + r' x n + l = 0, so external
loads enter as line loads f (N/mm) and l (N mm/mm = N) at the collocation points. Values at a
patch's first and last collocation point are not used there: those rows hold the end
conditions (a load exactly at an end belongs in the end condition, e.g. EndLoad or Joint).

Point loads inside a patch have no strong-form counterpart on a smooth spline (n would jump),
so a point force P at parameter u* is lumped onto the collocation points with the basis
functions: f_i = P N_i(u*) / l_i, where l_i = integral of N_i ds over the reference arc length
is the tributary length of collocation point i. This conserves the resultant (sum_i f_i l_i = P)
and converges as the mesh is refined; the shares of the two end points go to their interior
neighbours so no force is lost. Contact forces arrive already as line loads at collocation
points and are added unchanged.
"""

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, NamedTuple, Protocol

import numpy as np
import scipy.sparse

from rve_rod.rod.conditions import as_vector

if TYPE_CHECKING:
    from rve_rod.rod.model import RodModel

__all__ = [
    "DistributedLoad",
    "LineLoads",
    "PointLoad",
    "StateDependentLoad",
]


class LineLoads(NamedTuple):
    """Line loads at all collocation points (global collocation order, M points).

    Attributes:
        force: (3, M) distributed force f (N/mm).
        moment: (3, M) distributed moment l (N), or None.
        force_jacobian: sparse (3M, n_dofs) d force.ravel() / d state (C order of (3, M):
            row c*M + j; any format, repeated COO entries are summed), or None if the force
            does not depend on the state.
        moment_jacobian: the same for the moment, or None.
    """

    force: np.ndarray
    moment: np.ndarray | None = None
    force_jacobian: scipy.sparse.spmatrix | None = None
    moment_jacobian: scipy.sparse.spmatrix | None = None


class StateDependentLoad(Protocol):
    """A configuration-dependent load, e.g. contact: called at every residual evaluation."""

    def __call__(self, model: "RodModel", state: np.ndarray, load_factor: float) -> LineLoads:
        """Line loads (and their state derivatives) at `state` and `load_factor`."""


@dataclass(frozen=True, eq=False)
class DistributedLoad:
    """A uniform dead line load, scaled by the load factor.

    Attributes:
        force: (3,) force per reference length at t = 1 (N/mm).
        moment: (3,) moment per reference length at t = 1 (N).
        patches: the loaded patches, or None for all.
    """

    force: np.ndarray = field(default_factory=lambda: np.zeros(3))
    moment: np.ndarray = field(default_factory=lambda: np.zeros(3))
    patches: tuple[int, ...] | None = None

    def __post_init__(self):
        object.__setattr__(self, "force", as_vector("force", self.force))
        object.__setattr__(self, "moment", as_vector("moment", self.moment))

    def line_loads(self, model: "RodModel") -> np.ndarray:
        """(6, M) force and moment at the collocation points at t = 1."""
        out = np.zeros((6, model.n_collocation))
        patches = range(model.layout.n_patches) if self.patches is None else self.patches
        for patch in patches:
            points = model.layout.points(patch)
            out[:3, points] += self.force[:, None]
            out[3:, points] += self.moment[:, None]
        return out


@dataclass(frozen=True, eq=False)
class PointLoad:
    """A dead point force and moment at parameter `parameter` of `patch`, lumped onto the
    collocation points (module docstring).

    Attributes:
        patch: patch index.
        parameter: u* inside the patch's parameter domain.
        force: (3,) force at t = 1 (N).
        moment: (3,) moment at t = 1 (N mm).
    """

    patch: int
    parameter: float
    force: np.ndarray = field(default_factory=lambda: np.zeros(3))
    moment: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        object.__setattr__(self, "force", as_vector("force", self.force))
        object.__setattr__(self, "moment", as_vector("moment", self.moment))

    def line_loads(self, model: "RodModel") -> np.ndarray:
        """(6, M) force and moment at the collocation points at t = 1."""
        out = np.zeros((6, model.n_collocation))
        points, weights = model.point_load_weights(self.patch, self.parameter)
        np.add.at(out, (slice(0, 3), points), self.force[:, None] * weights[None, :])
        np.add.at(out, (slice(3, 6), points), self.moment[:, None] * weights[None, :])
        return out
