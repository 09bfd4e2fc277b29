"""Wale width, course height and angle of single jersey from a photo, averaged over the image.

Method (docs/imaging.md): the photo's illumination is flattened, its Hann-windowed power
spectrum computed, the sharp peaks found and refined to a fraction of a frequency bin
(`rve_rod.imaging.spectrum`), the fundamental reciprocal lattice identified among them and
fitted by least squares over all indexed peaks (`rve_rod.imaging.lattice`). Its real-space
cell gives w (the lattice vector across the wales), c (along the wales) and the angle of the
courses against the image's X axis. The uncertainty is the standard error of the mean of the
same measurement on k x k tiles of the photo (each indexed with the whole-image lattice).
"""

import logging
import math
import os
from dataclasses import asdict, dataclass

import numpy as np

from rve_rod.errors import InputError, check_integer, check_positive, check_range
from rve_rod.imaging.autocorrelation import shift_correlation
from rve_rod.imaging.image_io import block_mean, read_image, to_grayscale
from rve_rod.imaging.lattice import (
    MIN_INDEXED,
    LatticeFit,
    confirm_periods,
    fabric_cell,
    fit_basis,
    index_peaks,
    refit_on,
    spans_plane,
)
from rve_rod.imaging.spectrum import (
    annulus_medians,
    find_peaks,
    flatten_illumination,
    power_spectrum,
    ring_index,
    strongest_near,
)
from rve_rod.presets import Knit

__all__ = [
    "MeasureOptions",
    "PhotoEstimate",
    "knit_from_photo",
    "measure_photo",
]

logger = logging.getLogger(__name__)

MIN_SIDE_PX = 32
"""Smallest photo side (pixels) worth a spectrum."""


PLAUSIBLE_LOOP_MM = (0.2, 20.0)
"""Range of wale widths and course heights of real knits (mm): fine-gauge hosiery to coarse
hand knits. A measurement outside it comes from a wrong `pixels_per_mm`."""

HALF_CELL_ALTERNATION = -0.95
"""A photo that alternates like a checkerboard is refused: its contrast correlates with itself
shifted by half a wale, and by half a course, at below this times its correlation at a whole
wale and a whole course (-1 for a checkerboard, -0.997 blurred by 2 px with noise 0.2: all
its even harmonics vanish). In single jersey the two legs of a loop give the half-wale shift
-0.11 to +0.36 and the half course -0.03 to -0.48 (synthetic face and back photos, c/w
0.58-1.3, turned by 0-12 degrees, noise up to 0.2); a centred pattern of the (1, +-1)
harmonics with 5 % of its power in (2, 0) gives -0.89 (tests/test_rve_rod/verification)."""


@dataclass(frozen=True)
class MeasureOptions:
    """Settings of the photo measurement; the defaults suit photos of 200-2000 pixels.

    Attributes:
        threshold: minimum peak power over its annulus' median power (-). In pure noise
            the strongest local maximum of a 512 x 512 photo's spectrum reaches about 20
            (24 at most over 20 photos), so 30 leaves false peaks out.
        max_peaks: number of strongest peaks indexed and fitted.
        max_frequency: highest frequency searched (cycles per pixel), below Nyquist 0.5 so
            that aliased harmonics stay out.
        min_cycles: lowest frequency searched (cycles across the image): below lies the
            residue of the illumination.
        pad_factor: zero-padding of the FFT (finer bins for the sub-bin interpolation).
        power_fraction: share of the peak power the fundamental lattice must index (-).
        min_loops: fewest wales and courses across the photo (along its lattice vectors).
        min_correlation: lowest correlation of the (smoothed) photo with itself shifted by
            a lattice vector (-): below it the photo is not taken as periodic.
        tiles: the photo is cut into tiles x tiles pieces for the uncertainty (fewer if a
            tile would hold fewer than min_loops wales or courses).
        max_side: photos with a longer side (pixels) are block-averaged down to it first,
            which bounds time and memory; a loop should keep 5 pixels or more after it.
    """

    threshold: float = 30.0
    max_peaks: int = 40
    max_frequency: float = 0.35
    min_cycles: float = 1.5
    pad_factor: int = 2
    power_fraction: float = 0.98
    min_loops: float = 3.0
    min_correlation: float = 0.2
    tiles: int = 3
    max_side: int = 1024

    def __post_init__(self):
        check_range("threshold", self.threshold, 2.0, math.inf)
        check_integer("max_peaks", self.max_peaks, 2)
        check_range("max_frequency", self.max_frequency, 0.01, 0.5)
        check_range("min_cycles", self.min_cycles, 0.5, math.inf)
        check_integer("pad_factor", self.pad_factor, 1, 8)
        check_range("power_fraction", self.power_fraction, 0.5, 1.0)
        check_range("min_loops", self.min_loops, 1.0, math.inf)
        check_range("min_correlation", self.min_correlation, -1.0, 1.0)
        check_integer("tiles", self.tiles, 1, 8)
        check_integer("max_side", self.max_side, MIN_SIDE_PX)


@dataclass(frozen=True)
class PhotoEstimate:
    """Knit geometry measured on a photo (image frame: X right, Y up).

    Attributes:
        wale_width: w, mean loop period across the wales (mm).
        course_height: c, mean loop period along the wales (mm).
        angle_deg: counter-clockwise angle of the courses against the image's X axis (deg).
        wale_width_uncertainty, course_height_uncertainty: standard uncertainty (mm).
        angle_uncertainty_deg: standard uncertainty of the angle (deg).
        skew_deg: angle between wales and courses minus 90 degrees (0 for a square knit).
        wales_in_image, courses_in_image: loops across the photo along each lattice vector.
        wale_vector, course_vector: the lattice vectors (mm), image frame.
        centred: the spectrum showed a centred lattice; its rectangular cell is reported.
        pixels_per_mm: the scale the lengths were converted with.
        peaks_indexed: number of spectral peaks the fitted lattice explains.
        tiles_used: number of tiles behind the uncertainty (1: from the fit residuals).
    """

    wale_width: float
    course_height: float
    angle_deg: float
    wale_width_uncertainty: float
    course_height_uncertainty: float
    angle_uncertainty_deg: float
    skew_deg: float
    wales_in_image: float
    courses_in_image: float
    wale_vector: tuple[float, float]
    course_vector: tuple[float, float]
    centred: bool
    pixels_per_mm: float
    peaks_indexed: int
    tiles_used: int

    def to_dict(self) -> dict:
        """The estimate as a JSON-ready dict (lengths mm, angles degrees)."""
        return asdict(self)


def measure_photo(
    photo: str | os.PathLike | np.ndarray,
    pixels_per_mm: float,
    options: MeasureOptions | None = None,
) -> PhotoEstimate:
    """Measure w, c and the angle on a photo of single jersey (a file or an image array).

    Args:
        photo: path of an image file (any format Pillow reads), or an array (H, W) or
            (H, W, 3|4); colour is converted to luma.
        pixels_per_mm: the photo's scale (pixels per mm), from a ruler in the photo.
        options: measurement settings (defaults: MeasureOptions()).

    Raises InputError for an unreadable file, a photo smaller than 32 pixels or spanning
    fewer than `min_loops` wales or courses, a photo without periodic structure, a photo that
    alternates like a checkerboard (HALF_CELL_ALTERNATION), and a
    wale width or course height outside PLAUSIBLE_LOOP_MM (a wrong scale).
    """
    options = options or MeasureOptions()
    pixels_per_mm = check_positive("pixels_per_mm", pixels_per_mm)
    if isinstance(photo, np.ndarray):
        image = to_grayscale(photo)
    else:
        image = read_image(photo)
    if min(image.shape) < MIN_SIDE_PX:
        raise InputError(
            f"photo of {image.shape[1]} x {image.shape[0]} pixels is too small: "
            f"both sides must be >= {MIN_SIDE_PX} pixels"
        )
    factor = math.ceil(max(image.shape) / options.max_side)
    if factor > 1:
        logger.info("block-averaging the %s-pixel photo by %d", image.shape, factor)
        image = block_mean(image, factor)
    scale = pixels_per_mm / factor
    contrast = flatten_illumination(image)
    try:
        fit = _lattice_of(contrast, options)
    except InputError as error:
        raise InputError(
            f"{error} (is the photo sharp, and does it span at least "
            f"{options.min_loops:g} wales and courses?)"
        ) from None
    real = np.linalg.inv(fit.basis).T
    cell = fabric_cell(real)
    # Integer coordinates of the wale and course vectors in the fitted real-space basis.
    coefficients = np.rint(np.linalg.solve(real, np.column_stack(cell[:2]))).astype(int)
    wales = _loops_across(image.shape, cell.wale_vector)
    courses = _loops_across(image.shape, cell.course_vector)
    if min(wales, courses) < options.min_loops:
        raise InputError(
            f"the photo spans only {wales:.1f} wales and {courses:.1f} courses; "
            f"at least {options.min_loops:g} of each are needed"
        )
    _refuse_alternation(contrast, cell, photo)
    values = _cell_values(fit.basis, coefficients, scale)
    tiles = _tile_count(image.shape, cell, options)
    samples = np.empty((0, 3))
    if tiles > 1:
        samples = _tile_values(
            contrast, tiles=tiles, fit=fit, coefficients=coefficients, scale=scale, options=options
        )
    if samples.shape[0] >= 2:
        uncertainty = samples.std(axis=0, ddof=1) / math.sqrt(samples.shape[0])
        tiles_used = samples.shape[0]
    else:
        logger.info("uncertainty from the fit residuals: no 2 tiles hold and show 3 loops")
        uncertainty = _fit_uncertainty(fit, coefficients, scale)
        tiles_used = 1
    wale_vector = cell.wale_vector / scale
    course_vector = cell.course_vector / scale
    low, high = PLAUSIBLE_LOOP_MM
    for name, value in (("wale_width", values[0]), ("course_height", values[1])):
        if not low <= value <= high:
            raise InputError(
                f"pixels_per_mm={pixels_per_mm:g} gives {name} = {value:.4g} mm, outside the "
                f"plausible range [{low:g}, {high:g}] mm of a knit's loop: check the scale"
            )
    return PhotoEstimate(
        wale_width=float(values[0]),
        course_height=float(values[1]),
        angle_deg=float(values[2]),
        wale_width_uncertainty=float(uncertainty[0]),
        course_height_uncertainty=float(uncertainty[1]),
        angle_uncertainty_deg=float(uncertainty[2]),
        skew_deg=float(values[3]),
        wales_in_image=float(wales),
        courses_in_image=float(courses),
        wale_vector=(float(wale_vector[0]), float(wale_vector[1])),
        course_vector=(float(course_vector[0]), float(course_vector[1])),
        centred=cell.centred,
        pixels_per_mm=float(pixels_per_mm),
        peaks_indexed=int(fit.indexed.sum()),
        tiles_used=tiles_used,
    )


def knit_from_photo(photo: str | os.PathLike, pixels_per_mm: float) -> Knit:
    """The knit geometry (w, c) measured on a photo, as the geometric model's input."""
    estimate = measure_photo(photo, pixels_per_mm)
    return Knit(wale_width=estimate.wale_width, course_height=estimate.course_height)


def _refuse_alternation(contrast: np.ndarray, cell, photo) -> None:
    """InputError if the photo alternates by half a cell along both lattice vectors (a
    checkerboard: a periodic pattern, not the loops of a knit; see HALF_CELL_ALTERNATION)."""
    ratios = [
        shift_correlation(contrast, vector / 2.0) / shift_correlation(contrast, vector)
        for vector in cell[:2]
    ]
    if all(ratio < HALF_CELL_ALTERNATION for ratio in ratios):
        name = "the photo" if isinstance(photo, np.ndarray) else f"photo={os.fspath(photo)!r}"
        raise InputError(
            f"{name}: half a wale and half a course shift its contrast into its negative "
            f"(correlation {ratios[0]:.2f} and {ratios[1]:.2f} of a whole cell's; a knit's is "
            f"above {HALF_CELL_ALTERNATION:g} for at least one): a checkerboard-like "
            "alternation, not the loops of a knit"
        )


def _lattice_of(contrast: np.ndarray, options: MeasureOptions) -> LatticeFit:
    spectrum = power_spectrum(contrast, options.pad_factor)
    peaks = find_peaks(
        spectrum, options.threshold, options.min_cycles, options.max_frequency, options.max_peaks
    )
    if peaks.power.size < MIN_INDEXED:
        raise InputError(
            f"no periodic structure: {peaks.power.size} spectral peak(s) stand "
            f"{options.threshold:g} times above the background, {MIN_INDEXED} or more "
            "are needed"
        )
    tolerance = 0.5 / min(contrast.shape)
    fit = index_peaks(
        peaks.frequencies,
        peaks.power,
        tolerance=tolerance,
        min_length=1.0 / max(contrast.shape),
        power_fraction=options.power_fraction,
    )
    periods = confirm_periods(contrast, np.linalg.inv(fit.basis).T, options.min_correlation)
    return refit_on(peaks.frequencies, fit, periods.basis)


def _cell_values(basis: np.ndarray, coefficients: np.ndarray, scale: float) -> np.ndarray:
    """(w, c, angle_deg, skew_deg) of the reciprocal basis (2, 2) and cell coefficients."""
    wale, course = (np.linalg.inv(basis).T @ coefficients).T
    angle = math.atan2(wale[1], wale[0])
    between = math.atan2(wale[0] * course[1] - wale[1] * course[0], wale @ course)
    return np.array(
        [
            np.linalg.norm(wale) / scale,
            np.linalg.norm(course) / scale,
            math.degrees(angle),
            math.degrees(between) - 90.0,
        ]
    )


def _fit_uncertainty(fit: LatticeFit, coefficients: np.ndarray, scale: float) -> np.ndarray:
    """Standard uncertainty of (w, c, angle) from the fit covariance (central differences)."""
    if not np.all(np.isfinite(fit.covariance)):
        return np.full(3, np.inf)
    parameters = fit.basis.ravel()
    step = 1e-6 * np.abs(parameters).max()
    jacobian = np.empty((3, 4))
    for k in range(4):
        delta = np.zeros(4)
        delta[k] = step
        plus = _cell_values((parameters + delta).reshape(2, 2), coefficients, scale)[:3]
        minus = _cell_values((parameters - delta).reshape(2, 2), coefficients, scale)[:3]
        jacobian[:, k] = (plus - minus) / (2.0 * step)
    return np.sqrt(np.diag(jacobian @ fit.covariance @ jacobian.T))


def _tile_count(shape: tuple[int, int], cell, options: MeasureOptions) -> int:
    """Largest k <= options.tiles whose k x k tiles each span min_loops wales and courses."""
    for tiles in range(options.tiles, 1, -1):
        tile_shape = (shape[0] // tiles, shape[1] // tiles)
        if (
            min(tile_shape) >= MIN_SIDE_PX
            and min(
                _loops_across(tile_shape, cell.wale_vector),
                _loops_across(tile_shape, cell.course_vector),
            )
            >= options.min_loops
        ):
            return tiles
    return 1


def _tile_values(
    contrast: np.ndarray,
    *,
    tiles: int,
    fit: LatticeFit,
    coefficients: np.ndarray,
    scale: float,
    options: MeasureOptions,
) -> np.ndarray:
    """(w, c, angle) measured on each of the tiles x tiles tiles, shape (n, 3).

    Each tile's peaks are searched near the whole-image lattice points of the indexed peaks
    and fitted with the same indices, so a small tile cannot be mis-indexed; tiles where too
    few of them stand out are left out.
    """
    height, width = contrast.shape[0] // tiles, contrast.shape[1] // tiles
    indices = fit.indices[fit.indexed]
    predicted = indices @ fit.basis.T
    samples = []
    for row in range(tiles):
        for col in range(tiles):
            tile = contrast[row * height : (row + 1) * height, col * width : (col + 1) * width]
            spectrum = power_spectrum(tile - tile.mean(), options.pad_factor)
            medians = annulus_medians(spectrum)
            found, keep = [], []
            for frequency in predicted:
                refined, power = strongest_near(spectrum, frequency, radius_bins=1.0)
                ring = min(ring_index(spectrum, np.linalg.norm(refined)), medians.size - 1)
                found.append(refined)
                keep.append(power >= options.threshold * medians[ring])
            keep = np.array(keep)
            if not spans_plane(indices[keep]):
                continue
            basis, _, _ = fit_basis(np.array(found)[keep], indices[keep])
            samples.append(_cell_values(basis, coefficients, scale)[:3])
    return np.array(samples).reshape(-1, 3)


def _loops_across(shape: tuple[int, int], vector: np.ndarray) -> float:
    """Number of periods of `vector` (pixels) on the line through the image centre along it."""
    height, width = shape
    direction = np.abs(vector) / np.linalg.norm(vector)
    with np.errstate(divide="ignore"):
        extent = min(width / direction[0], height / direction[1])
    return float(extent / np.linalg.norm(vector))
