"""Figures of membrane results: force-strain curves and cell fields on the deformed mesh (PNG).

`plot_cell_field` is collective under MPI (cell data are gathered to rank 0, which draws and
writes the file); `plot_force_strain` draws what it is given (call it on one rank).
"""

import textwrap
from collections.abc import Mapping
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import PolyCollection

from fabric_dolfinx.io.rve_curve import RVECurve
from fabric_dolfinx.part.fields import PartFields

__all__ = [
    "plot_cell_field",
    "plot_force_strain",
]


def plot_force_strain(
    curves: Mapping[str, tuple[np.ndarray, np.ndarray]],
    path: Path | str,
    rve: RVECurve | None = None,
    references: Mapping[str, tuple[np.ndarray, np.ndarray]] | None = None,
    *,
    title: str = "",
    xlabel: str = "nominal strain (%)",
) -> None:
    """Force per width (gf/cm) against strain (%) for each labelled curve.

    Args:
        curves: label -> (strain (k,), force_gf_per_cm (k,)), drawn with markers.
        rve: the RVE's uniaxial curve, drawn beside the membrane curves when given.
        references: further curves drawn as thin dashed lines (e.g. the material alone).
        title: the figure's title (e.g. the fabric and the test), none if empty.
        xlabel: the strain axis' label.
    """
    figure, axes = plt.subplots(figsize=(5.0, 3.6), dpi=110)
    for label, (strain, force) in curves.items():
        axes.plot(100 * np.asarray(strain), force, marker="o", markersize=3, label=label)
    for label, (strain, force) in (references or {}).items():
        axes.plot(100 * np.asarray(strain), force, "--", linewidth=1.0, label=label)
    if rve is not None:
        axes.plot(100 * rve.strain, rve.force_gf_per_cm, "k--", label="RVE (uniaxial)")
    axes.set_xlabel(xlabel)
    axes.set_ylabel("force per width (gf/cm)")
    axes.grid(alpha=0.3)
    axes.legend(frameon=False)
    if title:
        axes.set_title(textwrap.fill(title, 60), fontsize=9)  # a long title is wrapped, not cut
    figure.tight_layout()
    figure.savefig(path)
    plt.close(figure)


def _deformed_cells(fields: PartFields) -> np.ndarray:
    """Corners (owned cells, 4, 2) of the local cells in the deformed configuration (mm)."""
    displacement = fields.displacement
    space = displacement.function_space
    owned = space.mesh.topology.index_map(2).size_local
    dofs = space.dofmap.list.array.reshape(-1, 4)[:owned]
    points = space.tabulate_dof_coordinates()[:, :2] + displacement.x.array.reshape(-1, 2)
    # DOLFINx numbers quadrilateral vertices in tensor-product order; polygons go around.
    return points[dofs][:, [0, 1, 3, 2], :]


def plot_cell_field(
    fields: PartFields,
    path: Path | str,
    field: str = "cauchy",
    component: tuple[int, int] = (0, 0),
    title: str = "",
) -> None:
    """One component of a cell field (DG0) on the deformed mesh, like the paper's Figure 8.

    Args:
        fields: up-to-date PartFields of a plane part (call `update()` first).
        field: "cauchy" (N/mm), "strain" (-), or "principal": the largest principal Cauchy
            stress sigma_1 (N/mm).
        component: tensor indices, e.g. (0, 0) for sigma_xx (not for "principal").
    """
    comm = fields.strain.function_space.mesh.comm
    corners = comm.gather(_deformed_cells(fields), root=0)
    if field == "principal":  # sigma_1 of the 2 x 2 Cauchy stress
        a, b, d = (fields.component("cauchy", *ij) for ij in ((0, 0), (0, 1), (1, 1)))
        local = 0.5 * (a + d) + np.sqrt(0.25 * (a - d) ** 2 + b**2)
    else:
        local = fields.component(field, *component)
    values = comm.gather(local, root=0)
    if comm.rank != 0:
        return
    corners, values = np.concatenate(corners), np.concatenate(values)
    figure, axes = plt.subplots(figsize=(5.0, 4.2), dpi=110)
    cells = PolyCollection(corners, array=values, cmap="viridis", edgecolors="face")
    axes.add_collection(cells)
    axes.autoscale_view()
    axes.set_aspect("equal")
    axes.set_xlabel("x (mm)")
    axes.set_ylabel("y (mm)")
    if field == "principal":
        label = "largest principal stress sigma_1 (N/mm)"
    else:
        unit = "N/mm" if field == "cauchy" else "-"
        symbol = "sigma" if field == "cauchy" else "E"
        label = f"{symbol}_{'xy'[component[0]]}{'xy'[component[1]]} ({unit})"
    figure.colorbar(cells, ax=axes, label=label)
    if title:
        axes.set_title(textwrap.fill(title, 50), fontsize=9)
    figure.tight_layout()
    figure.savefig(path)
    plt.close(figure)
