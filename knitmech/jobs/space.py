"""The curves and figures of a part in space (`knitmech.jobs.fabric.run_fabric` solves it).

Boundary conditions of the plane part keep their meaning with z added: `clamp` holds x, y
and z; `displacement` moves the boundary by (dx, dy, 0); `roller` holds one in-plane
component; `traction` is the dead load (tx, ty, 0); `free` imposes nothing
(`fabric_dolfinx.part.boundary`). The fabric stage of a part in space writes

- `paraview/fabric.xdmf` (+ `.h5`): displacement (3D), strain and second Piola-Kirchhoff
  stress (course/wale frame), Cauchy stress in space, principal stresses and direction, the
  slack/wrinkle indicator;
- `fabric/curves.json`: per Dirichlet boundary the reaction (Fx, Fy, Fz) per step; the
  indenter's force against its travel; the pressure against the largest displacement (dome
  height); the fractions of the area that are wrinkled and slack per step;
- `figures/fabric_indenter.png` and/or `figures/fabric_pressure.png`.
"""

from pathlib import Path

import numpy as np

from fabric_dolfinx.part.problem import PartResult
from fabric_dolfinx.spec.space import SpaceSpec

__all__ = [
    "plot_space",
    "space_curves",
]


def space_curves(result: PartResult, space: SpaceSpec) -> dict:
    """The curves of `fabric/curves.json` (module docstring; numpy values)."""
    t = result.load_factor
    curves = {
        "load_factor": t,
        "reactions": {
            name: curve.force
            for name, curve in result.boundaries.items()
            if curve.kind in ("clamp", "displacement", "roller")
        },
        "peak_displacement": result.space.peak_displacement,
        "wrinkled_area": result.space.wrinkled_area,
        "slack_area": result.space.slack_area,
        "dome_amplitude": result.space.dome_amplitude,
        "stabilization_force": result.space.stabilization_force,
    }
    if space.pressure:
        curves["pressure"] = t * space.pressure
    if result.space.indenter_force is not None:
        curves["indenter_travel"] = result.space.indenter_travel
        curves["indenter_force"] = result.space.indenter_force
        if np.any(space.indenter.travel):  # an expanding body of revolution need not move
            direction = np.asarray(space.indenter.travel) / np.linalg.norm(space.indenter.travel)
            # the force that pushes the indenter along its travel (the fabric resists: > 0)
            curves["indenter_resistance"] = -result.space.indenter_force @ direction
    return curves


def plot_space(curves: dict, folder: Path) -> None:
    """`figures/fabric_indenter.png` and/or `figures/fabric_pressure.png` of `curves`."""
    import matplotlib.pyplot as plt  # noqa: PLC0415 (matplotlib on demand)

    plots = []
    if "indenter_resistance" in curves:
        plots.append(("indenter", curves["indenter_travel"], curves["indenter_resistance"]))
    if "pressure" in curves:
        plots.append(("pressure", curves["peak_displacement"], curves["pressure"]))
    labels = {
        "indenter": ("indenter travel (mm)", "force on the indenter (N)"),
        "pressure": ("largest displacement (mm)", "pressure (N/mm^2)"),
    }
    for name, x, y in plots:
        figure, axes = plt.subplots(figsize=(5, 3.5))
        axes.plot(x, y, "o-")
        axes.set_xlabel(labels[name][0])
        axes.set_ylabel(labels[name][1])
        axes.grid(alpha=0.3)
        figure.tight_layout()
        figure.savefig(folder / f"fabric_{name}.png", dpi=120)
        plt.close(figure)
