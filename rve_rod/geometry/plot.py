"""Figures of the loop geometry: a 3D view of the loop among its neighbours and its projections."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rve_rod.geometry.loop import LoopGeometry, loop_polylines

__all__ = [
    "plot_loop",
]


def plot_loop(geometry: LoopGeometry, path: str | Path) -> Path:
    """Save a PNG: 3D view, x/y projection (the fabric face) and y/z side view of the loop
    (blue) among its neighbours (grey), with the periodic cell outlined."""
    w, c, r = geometry.wale_width, geometry.course_height, geometry.yarn_radius
    pieces = loop_polylines(geometry)
    figure = plt.figure(figsize=(14, 5.0))
    view = figure.add_subplot(1, 3, 1, projection="3d")
    face = figure.add_subplot(1, 3, 2)
    side = figure.add_subplot(1, 3, 3)
    # line width in points so that it shows the yarn diameter at the face view's scale
    width = 2 * r * 72 * 4.0 / (3 * w)
    for (i, j), points in pieces:
        colour = "tab:blue" if (i, j) == (0, 0) else ("0.55" if j % 2 else "0.75")
        order = 3 if (i, j) == (0, 0) else 1
        view.plot(*points.T, color=colour, lw=1.5, zorder=order)
        face.plot(
            points[:, 0], points[:, 1], color=colour, lw=width, solid_capstyle="round", zorder=order
        )
        if i == 0:
            side.plot(points[:, 1], points[:, 2], color=colour, lw=1.5, zorder=order)
    cell = np.array(
        [[-w / 2, -c / 2], [w / 2, -c / 2], [w / 2, c / 2], [-w / 2, c / 2], [-w / 2, -c / 2]]
    )
    face.plot(cell[:, 0], cell[:, 1], "k--", lw=1, zorder=4)
    face.set(
        xlim=(-1.5 * w, 1.5 * w),
        ylim=(-1.5 * c, 1.5 * c),
        aspect="equal",
        xlabel="x, course-wise (mm)",
        ylabel="y, wale-wise (mm)",
        title="face (x/y)",
    )
    side.set(
        xlim=(-1.5 * c, 1.5 * c),
        aspect="equal",
        xlabel="y (mm)",
        ylabel="z (mm)",
        title="side (y/z), one wale",
    )
    view.set(xlabel="x", ylabel="y", zlabel="z", title="3D")
    view.set_box_aspect((3 * w, 3 * c, max(4 * geometry.depth, w)))
    figure.suptitle(
        f"single-jersey loop: w = {w:.3g} mm, c = {c:.3g} mm, r = {r:.3g} mm, "
        f"loop length {geometry.loop_length:.3f} mm"
    )
    figure.subplots_adjust(left=0.02, right=0.98, wspace=0.3)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=90)
    plt.close(figure)
    return path
