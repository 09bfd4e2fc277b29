"""The figure of a response surface, as the paper's Figure 7: S11 and S22 over (E11, E22) with the
samples they were fitted to, and the S12 curve with its samples."""

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from rve_rod.surface import ResponseSurface

__all__ = [
    "plot_surface",
]


def plot_surface(surface: ResponseSurface, path: str | Path, points_per_axis: int = 41) -> Path:
    """Write a PNG of S11(E11, E22), S22(E11, E22) (surfaces and samples) and S12(E12) (N/mm)."""
    path = Path(path)
    (x0, x1), (y0, y1), (g0, g1) = surface.domain
    x, y = np.meshgrid(np.linspace(x0, x1, points_per_axis), np.linspace(y0, y1, points_per_axis))
    grid = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    stress = surface.stress(grid).S
    figure = Figure(figsize=(15.0, 5.4))
    for column, name in enumerate(("S11", "S22")):
        axes = figure.add_subplot(1, 3, column + 1, projection="3d")
        drawn = axes.plot_surface(
            x, y, stress[:, column].reshape(x.shape), cmap="viridis", alpha=0.75, linewidth=0
        )
        samples = surface.samples.get(name)
        if samples is not None:
            axes.scatter(samples.inputs[:, 0], samples.inputs[:, 1], samples.values, color="k", s=6)
        axes.set_xlabel("E11")
        axes.set_ylabel("E22")
        axes.set_zlabel(f"{name} (N/mm)", labelpad=12)
        axes.tick_params(axis="z", pad=6)
        axes.set_title(f"{name}(E11, E22), samples in black")
        figure.colorbar(
            drawn, ax=axes, orientation="horizontal", shrink=0.6, pad=0.08, label=f"{name} (N/mm)"
        )
    axes = figure.add_subplot(1, 3, 3)
    shear = np.linspace(g0, g1, 201)
    strains = np.stack([np.zeros_like(shear), np.zeros_like(shear), shear], axis=1)
    axes.plot(shear, surface.stress(strains).S[:, 2], label="fit")
    samples = surface.samples.get("S12")
    if samples is not None:
        axes.plot(samples.inputs[:, 0], samples.values, "k.", label="samples")
    axes.set_xlabel("E12")
    axes.set_ylabel("S12 (N/mm)")
    axes.set_title(f"S12 ({surface.kind} fit)")
    axes.grid(alpha=0.3)
    axes.legend()
    figure.subplots_adjust(left=0.01, right=0.97, bottom=0.1, top=0.92, wspace=0.35)
    figure.savefig(path, dpi=90)
    return path
