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
    figure = plt.figure(figsize=(15, 5.2))
    grid = figure.add_gridspec(1, 3, width_ratios=(1.3, 1.0, 1.0), wspace=0.35)
    view = figure.add_subplot(grid[0], projection="3d")
    face = figure.add_subplot(grid[1])
    side = figure.add_subplot(grid[2])
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
    # true scale: the box has the extents of what it shows (no exaggerated depth)
    heights = np.concatenate([points[:, 2] for _, points in pieces])
    low, high = float(heights.min()), float(heights.max())
    view.set(
        xlim=(-1.5 * w, 1.5 * w),
        ylim=(-1.5 * c, 1.5 * c),
        zlim=(low, high),
        xlabel="x (mm)",
        ylabel="y (mm)",
        title="3D, true scale",
    )
    view.set_zticks([round(low, 2), round(high, 2)])
    side.set(ylim=(low - r, high + r), yticks=[round(low, 2), round(high, 2)])
    view.set_zlabel("z (mm)", labelpad=6)
    view.view_init(elev=35, azim=-60)
    view.set_box_aspect((3 * w, 3 * c, high - low))
    figure.suptitle(
        f"single-jersey loop: w = {w:.3g} mm, c = {c:.3g} mm, r = {r:.3g} mm, "
        f"loop length {geometry.loop_length:.3f} mm"
    )
    figure.subplots_adjust(left=0.0, right=0.98)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=90)
    plt.close(figure)
    return path
