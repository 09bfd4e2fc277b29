"""Synthetic photos of single jersey: a top view of the yarns of the loop model, for testing.

The renderer draws the yarn tubes (radius r) of the loop of `rve_rod.geometry.loop`, tiled
over the periodic cell [0, w) x [0, c), into a height map (a z-buffer: the top surface of the
highest yarn over each point), shades it by height and by the slope of the surface (light from
the upper left), blurs it with the optics' point-spread function, tiles it over the image at
the fabric's rotation angle, and adds the defects of a real photo: uneven lighting and sensor
noise. Because the blur is an isotropic Gaussian it commutes with the rotation and the tiling,
so it is applied once on the cell.

Frames: fabric x = course-wise (period w), y = wale-wise (period c). Image coordinates are
in mm from the image centre with Y pointing up (rows run downwards); the fabric appears
rotated counter-clockwise by `angle_deg`.
"""

import math
from dataclasses import dataclass

import numpy as np
import scipy.ndimage

from rve_rod.errors import InputError, check_integer, check_positive, check_range
from rve_rod.geometry.loop import LoopGeometry, loop_geometry, loop_polylines
from rve_rod.presets import Knit

__all__ = [
    "SyntheticPhoto",
    "cell_height_map",
    "image_coordinates",
    "render_photo",
]

BACKGROUND_INTENSITY = 0.05
"""Intensity of the gaps between the yarns (the dark backing of the photo)."""

LIGHT_DIRECTION = np.array([-1.0, 1.0, 2.0]) / math.sqrt(6.0)
"""Unit vector towards the light (x, y, z): from the upper left, 35 degrees above the plane."""

PIXEL_FILTER_WIDTH = 0.4
"""Standard deviation (pixels) of the Gaussian standing in for the pixel's area integration."""


@dataclass(frozen=True)
class SyntheticPhoto:
    """What the synthetic photo shows and how it is spoilt.

    Attributes:
        wale_width: w, loop period along the fabric x axis (mm).
        course_height: c, loop period along the fabric y axis (mm).
        minimal_radius: r0, the yarn's minimal radius (mm); the loop model draws the yarn with
            its adjusted radius r = min(r0, w/8).
        angle_deg: in-plane rotation of the fabric, counter-clockwise (degrees), |.| <= 45.
        pixels_per_mm: resolution (pixels per mm).
        width_px, height_px: image size (pixels), each >= 8.
        blur_mm: standard deviation of the Gaussian optical blur (mm), >= 0.
        noise: standard deviation of additive Gaussian noise (fraction of full scale), >= 0.
        lighting: relative amplitude of the uneven lighting, in [0, 0.9]: a linear gradient
            and a vignette, each of that amplitude across the image.
        seed: seed of the noise generator.
        side: "face" (the technical face, legs on top, seen from +z) or "back" (heads and
            sinker loops on top, seen from -z).
    """

    wale_width: float
    course_height: float
    minimal_radius: float
    angle_deg: float = 0.0
    pixels_per_mm: float = 25.0
    width_px: int = 512
    height_px: int = 512
    blur_mm: float = 0.0
    noise: float = 0.0
    lighting: float = 0.0
    seed: int = 0
    side: str = "face"

    def __post_init__(self):
        check_positive("wale_width", self.wale_width, "mm")
        check_positive("course_height", self.course_height, "mm")
        check_positive("minimal_radius", self.minimal_radius, "mm")
        check_range("angle_deg", self.angle_deg, -45.0, 45.0, "deg")
        check_positive("pixels_per_mm", self.pixels_per_mm)
        check_integer("width_px", self.width_px, 8)
        check_integer("height_px", self.height_px, 8)
        check_range("blur_mm", self.blur_mm, 0.0, math.inf, "mm")
        check_range("noise", self.noise, 0.0, math.inf)
        check_range("lighting", self.lighting, 0.0, 0.9)
        if self.side not in ("face", "back"):
            raise InputError(f"side={self.side!r} must be 'face' or 'back'")

    def loop(self) -> LoopGeometry:
        """The loop drawn (built about a second, once per process for each w, c, r0).

        Raises InputError when no loop of the model fits w, c and r0.
        """
        return loop_geometry(Knit(self.wale_width, self.course_height), self.minimal_radius)


def cell_height_map(
    centreline: np.ndarray,
    wale_width: float,
    course_height: float,
    yarn_radius: float,
    shape: tuple[int, int],
) -> np.ndarray:
    """Top surface height z (mm) of the yarn tubes over the periodic cell, shape (ny, nx).

    Grid point (j, i) sits at (x, y) = (i w / nx, j c / ny). The tube is the union of balls of
    radius r centred on the centreline, which is resampled (periodically, with the images of
    the cell) at a spacing of a quarter grid step; -inf where no yarn covers the point.
    """
    ny, nx = shape
    step_x, step_y = wale_width / nx, course_height / ny
    points = _resample(centreline, 0.25 * min(step_x, step_y))
    margin_x = math.ceil(yarn_radius / step_x) + 1
    margin_y = math.ceil(yarn_radius / step_y) + 1
    buffer = np.full((ny + 2 * margin_y, nx + 2 * margin_x), -np.inf)
    offsets_x = np.arange(-margin_x, margin_x + 1)
    offsets_y = np.arange(-margin_y, margin_y + 1)
    grid_x = np.mod(points[:, 0], wale_width) / step_x
    grid_y = np.mod(points[:, 1], course_height) / step_y
    for gx, gy, z in zip(grid_x, grid_y, points[:, 2], strict=True):
        ix, iy = min(int(gx), nx - 1), min(int(gy), ny - 1)  # mod may round up to w
        dx = (ix + offsets_x - gx) * step_x
        dy = (iy + offsets_y - gy) * step_y
        squared = yarn_radius**2 - dy[:, None] ** 2 - dx[None, :] ** 2
        cap = np.where(squared >= 0.0, np.sqrt(np.maximum(squared, 0.0)), -np.inf)
        window = buffer[iy : iy + 2 * margin_y + 1, ix : ix + 2 * margin_x + 1]
        np.maximum(window, z + cap, out=window)
    return _fold_margins(buffer, margin_y, margin_x)


def shade(height: np.ndarray, wale_width: float, course_height: float) -> np.ndarray:
    """Intensity in [0, 1] of the periodic height map (ny, nx): yarn by height and slope.

    Yarn: 0.15 + 0.55 * (relative height) + 0.3 * Lambert(normal, light), the normal from the
    periodic central-difference slope of the height map; gaps: BACKGROUND_INTENSITY.
    """
    ny, nx = height.shape
    yarn = np.isfinite(height)
    if not np.any(yarn):
        return np.full(height.shape, BACKGROUND_INTENSITY)
    low, high = height[yarn].min(), height[yarn].max()
    filled = np.where(yarn, height, low)
    slope_x = (np.roll(filled, -1, axis=1) - np.roll(filled, 1, axis=1)) * nx / (2 * wale_width)
    slope_y = (np.roll(filled, -1, axis=0) - np.roll(filled, 1, axis=0)) * ny / (2 * course_height)
    normal_z = 1.0 / np.sqrt(1.0 + slope_x**2 + slope_y**2)
    lambert = normal_z * (
        -slope_x * LIGHT_DIRECTION[0] - slope_y * LIGHT_DIRECTION[1] + LIGHT_DIRECTION[2]
    )
    relative = (filled - low) / max(high - low, 1e-300)
    intensity = 0.15 + 0.55 * relative + 0.3 * np.clip(lambert, 0.0, 1.0)
    return np.where(yarn, intensity, BACKGROUND_INTENSITY)


def render_photo(photo: SyntheticPhoto) -> np.ndarray:
    """The grayscale photo of `photo`, intensities in [0, 1], shape (height_px, width_px)."""
    loop = photo.loop()
    w, c, r = photo.wale_width, photo.course_height, loop.yarn_radius
    pixel = 1.0 / photo.pixels_per_mm
    step = min(r / 6.0, 0.5 * pixel)
    shape = (max(8, math.ceil(c / step)), max(8, math.ceil(w / step)))
    ((_, centreline),) = loop_polylines(loop, neighbours=0)  # one yarn period, along x
    if photo.side == "back":
        # Seen from -z: mirror z, and y too so that the view stays right-handed.
        centreline = centreline * np.array([1.0, -1.0, -1.0])
    height = cell_height_map(centreline, w, c, r, shape)
    cell = shade(height, w, c)
    sigma = math.hypot(photo.blur_mm, PIXEL_FILTER_WIDTH * pixel)
    cell = scipy.ndimage.gaussian_filter(
        cell, sigma=(sigma * shape[0] / c, sigma * shape[1] / w), mode="wrap"
    )
    X, Y = image_coordinates(photo.height_px, photo.width_px, photo.pixels_per_mm)
    angle = math.radians(photo.angle_deg)
    x = math.cos(angle) * X + math.sin(angle) * Y
    y = -math.sin(angle) * X + math.cos(angle) * Y
    # grid-wrap: the cell map is periodic, so the lookup tiles the fabric.
    image = scipy.ndimage.map_coordinates(
        cell, [y * shape[0] / c, x * shape[1] / w], order=1, mode="grid-wrap"
    )
    image *= _illumination(photo.height_px, photo.width_px, photo.lighting)
    if photo.noise > 0.0:
        image += np.random.default_rng(photo.seed).normal(0.0, photo.noise, image.shape)
    return np.clip(image, 0.0, 1.0)


def image_coordinates(
    height_px: int, width_px: int, pixels_per_mm: float
) -> tuple[np.ndarray, np.ndarray]:
    """Pixel-centre coordinates (X, Y) in mm from the image centre, Y up; each (H, W)."""
    columns = (np.arange(width_px) - 0.5 * (width_px - 1)) / pixels_per_mm
    rows = (0.5 * (height_px - 1) - np.arange(height_px)) / pixels_per_mm
    return np.meshgrid(columns, rows)


def _illumination(height_px: int, width_px: int, amplitude: float) -> np.ndarray:
    """1 + a (gradient along the diagonal) - a (vignette), normalized coordinates in [-1, 1]."""
    u, v = np.meshgrid(np.linspace(-1.0, 1.0, width_px), np.linspace(-1.0, 1.0, height_px))
    return 1.0 + 0.5 * amplitude * (u + v) / 2.0 - 0.5 * amplitude * (u**2 + v**2) / 2.0


def _resample(polyline: np.ndarray, spacing: float) -> np.ndarray:
    """The polyline (n, 3) resampled linearly at arc-length `spacing` or finer."""
    segments = np.linalg.norm(np.diff(polyline, axis=0), axis=1)
    per_segment = np.maximum(1, np.ceil(segments / spacing).astype(int))
    fractions = np.concatenate([np.arange(k) / k for k in per_segment])
    starts = np.repeat(np.arange(segments.size), per_segment)
    points = polyline[starts] + fractions[:, None] * (polyline[starts + 1] - polyline[starts])
    return np.vstack([points, polyline[-1:]])


def _fold_margins(buffer: np.ndarray, margin_y: int, margin_x: int) -> np.ndarray:
    """Fold the margins of a padded periodic buffer back onto the cell (maximum)."""
    ny, nx = buffer.shape[0] - 2 * margin_y, buffer.shape[1] - 2 * margin_x
    if margin_x > nx or margin_y > ny:
        raise InputError("yarn radius exceeds the cell size")
    columns = buffer[:, margin_x : margin_x + nx].copy()
    np.maximum(columns[:, nx - margin_x :], buffer[:, :margin_x], out=columns[:, nx - margin_x :])
    np.maximum(columns[:, :margin_x], buffer[:, margin_x + nx :], out=columns[:, :margin_x])
    cell = columns[margin_y : margin_y + ny].copy()
    np.maximum(cell[ny - margin_y :], columns[:margin_y], out=cell[ny - margin_y :])
    np.maximum(cell[:margin_y], columns[margin_y + ny :], out=cell[:margin_y])
    return cell
