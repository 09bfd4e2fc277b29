"""Probes at points of a part: which rank's cell holds a point, the displacement there, and
the state of that cell (all collective: every rank gets the owner's values)."""

import numpy as np
from dolfinx import fem, geometry

from rve_rod.errors import InputError

__all__ = [
    "CellProbe",
    "PointProbe",
    "locate_points",
    "shear_angle",
]


def locate_points(mesh, points: np.ndarray, what: str = "probe point") -> np.ndarray:
    """(n,) the owned local cell holding each point (n, 2 or 3) mm on the lowest rank that
    holds it, -1 on the other ranks; InputError naming the first point no rank holds."""
    points = np.asarray(points, dtype=float)
    padded = np.zeros((points.shape[0], 3))
    padded[:, : points.shape[1]] = points
    tree = geometry.BoundingBoxTree(mesh, mesh.topology.dim)
    candidates = geometry.compute_collisions(tree, padded)
    colliding = geometry.compute_colliding_cells(mesh, candidates, padded)
    owned = mesh.topology.index_map(mesh.topology.dim).size_local
    cells = np.full(points.shape[0], -1, dtype=np.int32)
    for i in range(points.shape[0]):
        local = [int(c) for c in colliding.links(i) if c < owned]
        cells[i] = local[0] if local else -1
    found = np.array(mesh.comm.allgather(cells >= 0))  # (ranks, n)
    for i in np.flatnonzero(~found.any(axis=0)):
        coordinates = ", ".join(f"{c:.6g}" for c in points[i])
        raise InputError(f"{what} ({coordinates}) mm is not in the part")
    first = np.argmax(found, axis=0)  # one owner: the lowest rank that holds it
    return np.where(first == mesh.comm.rank, cells, -1)


def _gathered(comm, local: list) -> list:
    """Entry i from the rank whose `local[i]` is not None."""
    ranks = comm.allgather(local)
    return [next(rank[i] for rank in ranks if rank[i] is not None) for i in range(len(local))]


class PointProbe:
    """The displacement at fixed points (n, 2) of a plane part (collective)."""

    def __init__(self, u: fem.Function, points: np.ndarray):
        self.u = u
        self.points = np.column_stack([points, np.zeros(len(points))])
        self.cells = locate_points(u.function_space.mesh, points)

    def __call__(self) -> np.ndarray:
        """The displacement (mm) at the points, shape (points, components)."""
        local = [
            self.u.eval(point, [cell]).tolist() if cell >= 0 else None
            for point, cell in zip(self.points, self.cells, strict=True)
        ]
        return np.array(_gathered(self.u.function_space.mesh.comm, local))


def shear_angle(strain: np.ndarray, angle: float) -> float:
    """Change of the angle between the material axes (degrees; positive when it closes)
    under the Green-Lagrange strain `strain` (2, 2), axes at `angle` radians:
    asin(a1.C a2 / sqrt(a1.C a1 a2.C a2)), C = I + 2E."""
    C = np.eye(2) + 2.0 * strain
    a1 = np.array([np.cos(angle), np.sin(angle)])
    a2 = np.array([-np.sin(angle), np.cos(angle)])
    cosine = a1 @ C @ a2 / np.sqrt((a1 @ C @ a1) * (a2 @ C @ a2))
    return float(np.degrees(np.arcsin(np.clip(cosine, -1.0, 1.0))))


class CellProbe:
    """The state of the cells holding named points of a plane part, from its `PartFields`.

    Attributes:
        points: name -> (x, y) mm; cells: name -> owned local cell or -1.
    """

    def __init__(self, problem, points: dict[str, tuple[float, float]]):
        self.points = {name: tuple(point) for name, point in points.items()}
        located = locate_points(problem.tagged.mesh, np.array(list(self.points.values())))
        self.cells = dict(zip(self.points, located, strict=True))
        self._problem = problem

    def __call__(self, fields) -> dict[str, tuple]:
        """Name -> (cell centre (2,), strain (2, 2), Cauchy stress (2, 2), shear angle) from
        up-to-date `fields` (collective)."""
        local = []
        for cell in self.cells.values():
            if cell < 0:
                local.append(None)
                continue
            strain = fields.cell_values("strain", cell).reshape(2, 2)
            local.append(
                (
                    self._problem.cells.centres[cell].copy(),
                    strain,
                    fields.cell_values("cauchy", cell).reshape(2, 2),
                    shear_angle(strain, self._problem.angle.x.array[fields.cell_dofs[cell]]),
                )
            )
        return dict(zip(self.cells, _gathered(self._problem.tagged.mesh.comm, local), strict=True))
