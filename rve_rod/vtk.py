"""Yarn centrelines as VTK files for ParaView: polylines with point data, via meshio.

`write_polylines` writes any set of centrelines (the loop geometry of `rve-rod geometry`);
`write_vtk` the deformed yarns of an RVE run, one .vtu per output state: the cell's yarns and
their periodic neighbours (the images x + F L for |i|, |j| <= `neighbours`) as polylines sampled
along the centreline, with point data `radius` (mm, the adjusted yarn radius), `image_i`,
`image_j` and `arc_parameter` (the patch parameter in quarter loops).

Render the yarns with ParaView's Tube filter, radius from the `radius` point array
("Vary Radius: By Absolute Scalar").
"""

from pathlib import Path
from typing import TYPE_CHECKING

import meshio
import numpy as np

from rve_rod.errors import InputError

if TYPE_CHECKING:
    from rve_rod.rve.simulation import RveResult

__all__ = [
    "write_polylines",
    "write_pvd",
    "write_vtk",
]

SAMPLES_PER_QUARTER = 48
"""Polyline points per quarter loop of an RVE run."""


def write_polylines(
    path: str | Path,
    polylines: list[np.ndarray],
    radius: float,
    point_data: dict[str, list[np.ndarray]] | None = None,
) -> Path:
    """Write polylines to an unstructured-grid file (.vtu).

    Args:
        path: output file; its folder is created if missing.
        polylines: one (m_k, 3) array of points per yarn piece (mm).
        radius: yarn radius (mm), stored as the point array `radius`.
        point_data: optional named arrays, one (m_k,) array per polyline each.

    Returns the path written. Besides `radius`, the point array `polyline` numbers the pieces.
    """
    path = Path(path)
    if path.suffix != ".vtu":
        raise InputError(f"VTK output {path}: the file name must end in .vtu")
    if not polylines:
        raise InputError(f"VTK output {path}: nothing to write")
    path.parent.mkdir(parents=True, exist_ok=True)
    points, lines, offset = [], [], 0
    for line in polylines:
        count = line.shape[0]
        points.append(line)
        lines.append(offset + np.stack([np.arange(count - 1), np.arange(1, count)], axis=1))
        offset += count
    data = {
        name: np.concatenate(values).astype(float) for name, values in (point_data or {}).items()
    }
    data["radius"] = np.full(offset, float(radius))
    data["polyline"] = np.concatenate(
        [np.full(line.shape[0], k, dtype=float) for k, line in enumerate(polylines)]
    )
    meshio.Mesh(np.vstack(points), [("line", np.vstack(lines))], point_data=data).write(path)
    return path


def write_pvd(path: str | Path, files: list[Path], times: list[float]) -> Path:
    """Write a ParaView collection (.pvd) of a series of files, one time value each (e.g. the
    strain of each state): open it instead of the files to step through the series.

    Args:
        path: the .pvd file; the series' files are referenced relative to its folder.
        files: the files of the series, in order.
        times: one value per file (ParaView's time).
    """
    path = Path(path)
    if len(files) != len(times):
        raise InputError(f"write_pvd: {len(files)} files but {len(times)} times")
    datasets = "\n".join(
        f'    <DataSet timestep="{time:.9g}" part="0" file="{name}"/>'
        for name, time in zip(
            (Path(file).relative_to(path.parent) for file in files), times, strict=True
        )
    )
    path.write_text(
        '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
        f"{datasets}\n  </Collection>\n</VTKFile>\n"
    )
    return path


def write_vtk(result: "RveResult", folder, neighbours: int = 1) -> list[Path]:
    """Write `state_000.vtu`, ... into `folder` (created if missing) and `states.pvd`, their
    collection with the strain of each state as its time (open it in ParaView); returns the
    paths, the .pvd last."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"--vtk {folder} exists and is not a folder")
    folder.mkdir(parents=True, exist_ok=True)
    low, high = result.curve.domain
    parameters = np.linspace(low, high, int(SAMPLES_PER_QUARTER * (high - low)) + 1)
    lattice = result.cell_lattice
    shifts = [
        (i, j)
        for i in range(-neighbours, neighbours + 1)
        for j in range(-neighbours, neighbours + 1)
    ]
    paths = []
    for index, step in enumerate(result.steps):
        F = np.eye(3)
        F[:2, :2] = step.deformation
        centrelines = [
            result.centreline(index, patch)(parameters) for patch in range(len(result.curves))
        ]
        offsets = [F @ (i * lattice[0] + j * lattice[1]) for i, j in shifts]
        data = {
            "image_i": [np.full(parameters.size, float(i)) for i, _ in shifts for _ in centrelines],
            "image_j": [np.full(parameters.size, float(j)) for _, j in shifts for _ in centrelines],
            "arc_parameter": [parameters] * (len(shifts) * len(centrelines)),
        }
        path = folder / f"state_{index:03d}.vtu"
        lines = [line + offset for offset in offsets for line in centrelines]
        write_polylines(path, lines, result.yarn.radius, data)
        paths.append(path)
    strains = [step.strain for step in result.steps]
    return [*paths, write_pvd(folder / "states.pvd", paths, strains)]
