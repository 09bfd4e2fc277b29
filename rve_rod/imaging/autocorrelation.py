"""How well a photo repeats with each shift: its normalized autocorrelation over all shifts.

The correlation coefficient of an image with itself shifted by s, taken over the pixels the
two overlap, is 1 for a period of a perfectly periodic image and well below 1 for any shift
that is not a period. Computed for every integer shift at once (one FFT for the products,
summed-area tables for the overlap's means and variances), it shows the photo's strongest
repeat without knowing its lattice: the check that a lattice found in the spectrum is the
photo's own and not a harmonic of it (`rve_rod.imaging.lattice.confirm_periods`).
"""

import math
from typing import NamedTuple

import numpy as np
import scipy.fft
import scipy.ndimage

from rve_rod.imaging.image_io import block_mean
from rve_rod.imaging.spectrum import parabola_vertex

__all__ = [
    "Autocorrelation",
    "Repeat",
    "autocorrelation",
    "shift_correlation",
    "strongest_repeat",
]

MIN_OVERLAP = 0.05
"""Smallest overlap (fraction of the image) of a shifted image worth a correlation."""

REPEAT_SIDE = 192
"""Longest side (pixels) of the block-averaged image whose autocorrelation map is searched
for the best repeat: the map of an (H, W) image costs FFTs and tables of (2H, 2W)."""


class Autocorrelation(NamedTuple):
    """Correlation coefficient and overlap of an image (H, W) with itself for every shift.

    Attributes:
        correlation: (2H - 1, 2W - 1) correlation coefficient of the overlapping pixels of
            the image and the image shifted by (X, Y) = (col - (W - 1), (H - 1) - row)
            pixels (Y up); NaN where the overlap holds fewer than 2 pixels or is flat.
        overlap: (2H - 1, 2W - 1) overlap of the shifted image, fraction of its area.
    """

    correlation: np.ndarray
    overlap: np.ndarray

    @property
    def zero(self) -> tuple[int, int]:
        """(row, col) of the zero shift in the maps."""
        return (self.correlation.shape[0] // 2, self.correlation.shape[1] // 2)

    def shift_of(self, row: np.ndarray, col: np.ndarray) -> np.ndarray:
        """(X, Y) shifts (pixels, Y up) of (fractional) map positions, shape (..., 2)."""
        zero_row, zero_col = self.zero
        return np.stack([np.asarray(col) - zero_col, zero_row - np.asarray(row)], axis=-1)


class Repeat(NamedTuple):
    """A shift with which the image repeats (a local maximum of its autocorrelation).

    Attributes:
        shift: (2,) (X, Y) shift (pixels, Y up), Y > 0 or Y = 0 < X (one of each +-s pair).
        correlation: correlation coefficient at the shift (-).
    """

    shift: np.ndarray
    correlation: float


def autocorrelation(image: np.ndarray) -> Autocorrelation:
    """The correlation coefficient of an image (H, W) with itself shifted, for all shifts.

    For a shift of (dr, dc) rows and columns the pairs are (f[i, j], f[i + dr, j + dc])
    over the overlap of n = (H - |dr|)(W - |dc|) pixels; the coefficient is
    (sum f g - sum f sum g / n) / sqrt((sum f^2 - (sum f)^2 / n)(sum g^2 - (sum g)^2 / n)),
    the sums of products from the zero-padded FFT, those of f and f^2 over each of the two
    rectangles from summed-area tables. Symmetric: the map at s equals that at -s.
    """
    image = np.asarray(image, dtype=float)
    image = image - image.mean()  # conditioning only: the coefficient ignores offsets
    height, width = image.shape
    padded = (
        scipy.fft.next_fast_len(2 * height - 1, real=True),
        scipy.fft.next_fast_len(2 * width - 1, real=True),
    )
    transform = scipy.fft.rfft2(image, s=padded, workers=-1)
    products = scipy.fft.irfft2(np.abs(transform) ** 2, s=padded, workers=-1)
    # products[dr, dc] = sum f[i, j] f[i + dr, j + dc] (indices mod the padded size).
    rows = np.arange(-(height - 1), height)
    cols = np.arange(-(width - 1), width)
    products = products[np.ix_(rows % padded[0], cols % padded[1])]
    # The first rectangle of the overlap holds rows max(0, -dr) .. H - max(0, dr) - 1, the
    # second the same rows moved by dr; likewise the columns.
    first_rows = (np.maximum(0, -rows), height - np.maximum(0, rows))
    first_cols = (np.maximum(0, -cols), width - np.maximum(0, cols))
    second_rows = (first_rows[0] + rows, first_rows[1] + rows)
    second_cols = (first_cols[0] + cols, first_cols[1] + cols)
    count = np.outer(height - np.abs(rows), width - np.abs(cols)).astype(float)
    sums, squares = _summed_area(image), _summed_area(image**2)
    sum_first = _rectangle_sums(sums, first_rows, first_cols)
    sum_second = _rectangle_sums(sums, second_rows, second_cols)
    variance_first = _rectangle_sums(squares, first_rows, first_cols) - sum_first**2 / count
    variance_second = _rectangle_sums(squares, second_rows, second_cols) - sum_second**2 / count
    covariance = products - sum_first * sum_second / count
    denominator = np.sqrt(np.maximum(variance_first, 0.0) * np.maximum(variance_second, 0.0))
    tiny = 1e-12 * float(np.sum(image**2))
    with np.errstate(invalid="ignore", divide="ignore"):
        correlation = np.where(
            (denominator > tiny) & (count >= 2), covariance / denominator, np.nan
        )
    # Row dr of the map pairs f(X, Y) with f(X + dc, Y - dr) (rows run downwards).
    return Autocorrelation(correlation=np.clip(correlation, -1.0, 1.0), overlap=count / image.size)


def shift_correlation(image: np.ndarray, shift: np.ndarray) -> float:
    """Correlation coefficient of the image (H, W) with itself shifted by (X, Y) pixels (Y up,
    fractional shifts by bilinear interpolation), over the pixels the two overlap.

    NaN if the overlap is under MIN_OVERLAP of the image (too few pixels to tell).
    """
    moved = scipy.ndimage.shift(image, (-shift[1], shift[0]), order=1, mode="constant", cval=np.nan)
    overlap = np.isfinite(moved)
    if overlap.sum() < max(16, MIN_OVERLAP * image.size):
        return np.nan
    first, second = image[overlap], moved[overlap]
    first, second = first - first.mean(), second - second.mean()
    norm = np.sqrt((first @ first) * (second @ second))
    return float(first @ second / norm) if norm > 0 else 0.0


def strongest_repeat(
    image: np.ndarray, min_overlap: float, max_side: int = REPEAT_SIDE, candidates: int = 3
) -> Repeat | None:
    """The image's best repeat: the highest local maximum of its autocorrelation away from
    the zero shift, among shifts whose overlap is at least `min_overlap` of the image
    (fewer pixels correlate by chance); None if there is no such maximum.

    A local maximum is a shift whose correlation is the largest of its 3 x 3 neighbours; the
    slope of the central peak (correlation near 1 for short shifts) has none, so it needs no
    cut-off length. The map is computed on the image block-averaged to at most `max_side`
    pixels (its cost grows as the square of the image's area); the `candidates` highest
    maxima are refined to a fraction of a block (parabola through each axis' neighbours)
    and their correlation taken on the full image by `shift_correlation`, like any other
    shift's. Of those within 0.01 of the highest, the shortest shift is returned.
    """
    factor = max(1, math.ceil(max(image.shape) / max_side))
    coarse = block_mean(image, factor) if factor > 1 else np.asarray(image, dtype=float)
    correlation = autocorrelation(coarse)
    values = np.where(correlation.overlap >= min_overlap, correlation.correlation, np.nan)
    filled = np.nan_to_num(values, nan=-np.inf)
    is_peak = np.isfinite(filled) & (
        filled == scipy.ndimage.maximum_filter(filled, size=3, mode="constant", cval=-np.inf)
    )
    rows, cols = np.nonzero(is_peak)
    half_plane = (rows < correlation.zero[0]) | (
        (rows == correlation.zero[0]) & (cols > correlation.zero[1])
    )
    rows, cols = rows[half_plane], cols[half_plane]
    if rows.size == 0:
        return None
    highest = np.argsort(-filled[rows, cols])[:candidates]
    shifts, repeats = [], []
    # A missing neighbour (edge of the overlap) gives no curvature: no refinement that way.
    bordered = np.pad(np.nan_to_num(values, nan=np.inf), 1, constant_values=np.inf)
    for row, col in zip(rows[highest], cols[highest], strict=True):
        along_rows = bordered[row : row + 3, col + 1]
        along_cols = bordered[row + 1, col : col + 3]
        refined = correlation.shift_of(
            row + parabola_vertex(along_rows), col + parabola_vertex(along_cols)
        )
        shifts.append(factor * refined)
        repeats.append(shift_correlation(image, factor * refined))
    shifts, repeats = np.array(shifts), np.nan_to_num(repeats, nan=-np.inf)
    # Of a lattice's equally good periods, the shortest (within 0.01 of the best).
    near_best = np.flatnonzero(repeats >= repeats.max() - 0.01)
    best = near_best[np.argmin(np.linalg.norm(shifts[near_best], axis=1))]
    if not np.isfinite(repeats[best]):
        return None
    return Repeat(shift=shifts[best], correlation=float(repeats[best]))


def _summed_area(image: np.ndarray) -> np.ndarray:
    """Summed-area table (H + 1, W + 1): entry [i, j] is the sum of image[:i, :j]."""
    table = np.zeros((image.shape[0] + 1, image.shape[1] + 1))
    table[1:, 1:] = image.cumsum(axis=0).cumsum(axis=1)
    return table


def _rectangle_sums(table: np.ndarray, rows: tuple, cols: tuple) -> np.ndarray:
    """Sums over the rectangles rows[0][a] <= i < rows[1][a], cols[0][b] <= j < cols[1][b],
    shape (len(rows[0]), len(cols[0]))."""
    start_r, stop_r = rows
    start_c, stop_c = cols
    return (
        table[np.ix_(stop_r, stop_c)]
        - table[np.ix_(start_r, stop_c)]
        - table[np.ix_(stop_r, start_c)]
        + table[np.ix_(start_r, start_c)]
    )
