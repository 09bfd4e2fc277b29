"""The deformed yarns of an RVE run as VTK files for ParaView (one .vtu per output state).

Each file holds the cell's yarn and its periodic neighbours (the images x + F L for
|i|, |j| <= `neighbours`) as polylines sampled along the centreline, with point data
`radius` (mm, the adjusted yarn radius: render with ParaView's Tube filter, "vary radius" by
scalar), `image_i`, `image_j` and `arc_parameter` (the patch parameter in quarter loops).
"""

from pathlib import Path

import numpy as np

from rve_rod.errors import InputError
from rve_rod.rve.simulation import RveResult
from rve_rod.vtk import write_polylines, write_pvd

SAMPLES_PER_QUARTER = 48
"""Polyline points per quarter loop."""


def write_vtk(result: RveResult, folder, neighbours: int = 1) -> list[Path]:
    """Write `state_000.vtu`, ... into `folder` (created if missing) and `states.pvd`, their
    collection with the strain of each state as its time (open it in ParaView); returns the
    paths, the .pvd last."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"--vtk {folder} exists and is not a folder")
    folder.mkdir(parents=True, exist_ok=True)
    low, high = result.curve.domain
    parameters = np.linspace(low, high, int(SAMPLES_PER_QUARTER * (high - low)) + 1)
    knit = result.fabric.knit
    lattice = np.array([[knit.wale_width, 0.0, 0.0], [0.0, knit.course_height, 0.0]])
    shifts = [
        (i, j)
        for i in range(-neighbours, neighbours + 1)
        for j in range(-neighbours, neighbours + 1)
    ]
    paths = []
    for index, step in enumerate(result.steps):
        F = np.eye(3)
        F[:2, :2] = step.deformation
        centreline = result.centreline(index)(parameters)
        offsets = [F @ (i * lattice[0] + j * lattice[1]) for i, j in shifts]
        data = {
            "image_i": [np.full(parameters.size, float(i)) for i, _ in shifts],
            "image_j": [np.full(parameters.size, float(j)) for _, j in shifts],
            "arc_parameter": [parameters] * len(shifts),
        }
        path = folder / f"state_{index:03d}.vtu"
        write_polylines(path, [centreline + offset for offset in offsets], result.yarn.radius, data)
        paths.append(path)
    strains = [step.strain for step in result.steps]
    return [*paths, write_pvd(folder / "states.pvd", paths, strains)]
