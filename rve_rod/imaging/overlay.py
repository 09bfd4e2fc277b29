"""The measured course and wale lattice drawn over the photo, and the photo's mean cell.

The lines run through the gaps between the loops: the photo is folded into one lattice cell
(the mean intensity at each position of the cell, averaged over all cells of the photo) and
the lattice origin put at the darkest point of that mean cell.
"""

import os
from typing import NamedTuple

import numpy as np
import scipy.ndimage
from matplotlib.figure import Figure

from rve_rod.imaging.measure import PhotoEstimate
from rve_rod.imaging.synthetic import image_coordinates

__all__ = [
    "plot_overlay",
]

CELL_BINS = 32
"""Bins per lattice vector of the folded mean cell."""


class MeanCell(NamedTuple):
    """The photo averaged over its lattice cells.

    Attributes:
        intensity: (CELL_BINS, CELL_BINS) mean intensity; [j, i] at the fractional cell
            coordinates (i / CELL_BINS along the wale vector, j / CELL_BINS along the course
            vector).
        origin: (2,) a lattice point (mm, image frame): the darkest point of the mean cell.
    """

    intensity: np.ndarray
    origin: np.ndarray


def mean_cell(image: np.ndarray, estimate: PhotoEstimate) -> MeanCell:
    """Fold the grayscale photo (H, W) into the lattice cell of `estimate`."""
    X, Y = image_coordinates(image.shape[0], image.shape[1], estimate.pixels_per_mm)
    cell = np.column_stack([estimate.wale_vector, estimate.course_vector])
    fractions = np.linalg.solve(cell, np.vstack([X.ravel(), Y.ravel()]))
    bins = np.floor(np.mod(fractions, 1.0) * CELL_BINS).astype(int) % CELL_BINS
    flat = bins[1] * CELL_BINS + bins[0]
    total = np.bincount(flat, weights=image.ravel(), minlength=CELL_BINS**2)
    count = np.bincount(flat, minlength=CELL_BINS**2)
    intensity = (total / np.maximum(count, 1)).reshape(CELL_BINS, CELL_BINS)
    smooth = scipy.ndimage.gaussian_filter(intensity, 1.0, mode="wrap")
    row, col = np.unravel_index(np.argmin(smooth), smooth.shape)
    origin = cell @ (np.array([col, row]) + 0.5) / CELL_BINS
    return MeanCell(intensity=intensity, origin=origin)


def plot_overlay(
    image: np.ndarray, estimate: PhotoEstimate, path: str | os.PathLike, dpi: int = 100
) -> None:
    """Save the photo (H, W) with the wale lines (along the course vector, spaced w) and the
    course lines (along the wale vector, spaced c) through the gaps between the loops."""
    height, width = image.shape
    scale = estimate.pixels_per_mm
    half_x, half_y = 0.5 * width / scale, 0.5 * height / scale
    origin = mean_cell(image, estimate).origin
    wale, course = np.asarray(estimate.wale_vector), np.asarray(estimate.course_vector)
    figure = Figure(figsize=(7.0, 7.0 * height / width + 0.6))
    axes = figure.subplots()
    axes.imshow(image, cmap="gray", extent=(-half_x, half_x, -half_y, half_y), vmin=0, vmax=1)
    reach = np.hypot(half_x, half_y)
    for step, direction, colour, label in (
        (course, wale, "tab:orange", "courses"),
        (wale, course, "tab:cyan", "wales"),
    ):
        unit = direction / np.linalg.norm(direction)
        normal = np.array([-unit[1], unit[0]])
        spacing = abs(step @ normal)
        first = int(np.floor((-reach - origin @ normal) / spacing))
        last = int(np.ceil((reach - origin @ normal) / spacing))
        for k in range(first, last + 1):
            centre = origin + k * step
            ends = np.array([centre - 2 * reach * unit, centre + 2 * reach * unit])
            axes.plot(
                ends[:, 0], ends[:, 1], color=colour, lw=0.8, label=label if k == first else None
            )
    axes.set_xlim(-half_x, half_x)
    axes.set_ylim(-half_y, half_y)
    axes.set_xlabel("X (mm)")
    axes.set_ylabel("Y (mm)")
    axes.legend(loc="upper right", framealpha=0.8)
    axes.set_title(
        f"w = {estimate.wale_width:.4f} ± {estimate.wale_width_uncertainty:.4f} mm, "
        f"c = {estimate.course_height:.4f} ± {estimate.course_height_uncertainty:.4f} mm, "
        f"angle {estimate.angle_deg:.2f}°",
        fontsize=10,
    )
    figure.tight_layout()
    figure.savefig(path, dpi=dpi)
