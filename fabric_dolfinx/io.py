"""Output of membrane solutions: cell fields, XDMF files for ParaView, the RVE curve input.

`CellFields` holds the Green-Lagrange strain and the Cauchy stress per cell (DG0: the value
at the cell centre, interpolated, not projected) and the displacement in the mesh's
coordinate degree (XDMF in DOLFINx 0.5 writes only functions of the mesh degree; a Q2
displacement is interpolated to Q1 for output). `XDMFOutput` writes them once per converged
step; as a context manager it closes (and so flushes) the file also when a solve fails.
"""

import json
from pathlib import Path
from typing import NamedTuple

import numpy as np
from dolfinx import fem
from dolfinx.io import XDMFFile

from fabric_dolfinx.membrane import MembraneState
from rve_rod.errors import InputError

__all__ = [
    "CellFields",
    "RVECurve",
    "XDMFOutput",
    "read_rve_curve",
]


class CellFields:
    """DG0 strain and Cauchy stress and the output displacement of a membrane state.

    Attributes:
        strain: Green-Lagrange strain E per cell (2 x 2 tensor, dimensionless).
        cauchy: Cauchy stress sigma = F S F^T / det F per cell (2 x 2, N/mm).
        displacement: u in the coordinate degree of the mesh (mm).
    """

    def __init__(self, u: fem.Function, stress: MembraneState):
        mesh = u.function_space.mesh
        cells = fem.TensorFunctionSpace(mesh, ("DG", 0))
        points = cells.element.interpolation_points()
        self.strain = fem.Function(cells, name="green_lagrange_strain")
        self.cauchy = fem.Function(cells, name="cauchy_stress")
        self._expressions = [
            (fem.Expression(stress.reference_strain, points), self.strain),
            (fem.Expression(stress.cauchy, points), self.cauchy),
        ]
        self._u = u
        if u.function_space.ufl_element().degree() == mesh.geometry.cmap.degree:
            self.displacement = u
        else:
            space = fem.VectorFunctionSpace(mesh, ("Lagrange", mesh.geometry.cmap.degree))
            self.displacement = fem.Function(space, name="displacement")
        u.name = "displacement"

    def update(self) -> None:
        """Evaluate the fields at the current displacement."""
        for expression, function in self._expressions:
            function.interpolate(expression)
        if self.displacement is not self._u:
            self.displacement.interpolate(self._u)

    def component(self, field: str, i: int, j: int) -> np.ndarray:
        """Local cell values (num_owned_cells,) of component (i, j) of "strain" or "cauchy"."""
        function = getattr(self, field)
        size = function.function_space.dofmap.index_map.size_local
        return function.x.array.reshape(-1, 2, 2)[:size, i, j].copy()


class XDMFOutput:
    """An XDMF file receiving the CellFields of every converged step (time = step label)."""

    def __init__(self, path: Path | str, fields: CellFields):
        self.path = Path(path)
        self.fields = fields
        mesh = fields.strain.function_space.mesh
        self._file = XDMFFile(mesh.comm, str(self.path), "w")
        self._file.write_mesh(mesh)

    def write(self, time: float) -> None:
        """Update the fields and append them at `time` (e.g. the nominal strain)."""
        self.fields.update()
        for function in (self.fields.displacement, self.fields.strain, self.fields.cauchy):
            self._file.write_function(function, time)

    def close(self) -> None:
        self._file.close()

    def __enter__(self) -> "XDMFOutput":
        return self

    def __exit__(self, *exception) -> None:
        self.close()


class RVECurve(NamedTuple):
    """A uniaxial force-strain curve of the RVE (as `rve-rod simulate --json` prints it).

    Attributes:
        strain: (k,) nominal strain (-).
        force_gf_per_cm: (k,) force per width (gf/cm).
    """

    strain: np.ndarray
    force_gf_per_cm: np.ndarray


def read_rve_curve(path: Path | str) -> RVECurve:
    """Read a JSON object with equal-length lists `strain` and `force_gf_per_cm`."""
    path = Path(path)
    try:
        data = json.loads(path.read_text())
        strain = np.asarray(data["strain"], dtype=float)
        force = np.asarray(data["force_gf_per_cm"], dtype=float)
    except FileNotFoundError:
        raise InputError(f"RVE curve file {path} does not exist") from None
    except (OSError, ValueError, TypeError, KeyError) as error:
        raise InputError(
            f"RVE curve file {path} is not a JSON object with lists 'strain' and "
            f"'force_gf_per_cm' ({type(error).__name__}: {error})"
        ) from None
    if strain.ndim != 1 or strain.shape != force.shape or strain.size < 2:
        raise InputError(
            f"RVE curve file {path}: 'strain' and 'force_gf_per_cm' must be lists of equal "
            f"length >= 2, got {strain.shape} and {force.shape}"
        )
    if not (np.all(np.isfinite(strain)) and np.all(np.isfinite(force))):
        raise InputError(f"RVE curve file {path}: values must be finite numbers")
    return RVECurve(strain=strain, force_gf_per_cm=force)
