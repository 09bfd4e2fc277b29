"""The windowed 2D power spectrum of a photo and its sharp peaks, the fabric's lattice.

A periodic texture has a power spectrum made of sharp peaks at the points of its reciprocal
lattice. The photo is flattened (divided by its least-squares quadratic illumination
surface), multiplied by a 2D Hann window (no leakage from the image edges), zero-padded and
transformed. A peak is a local maximum whose power stands `threshold` times above the median
power of its annulus |f| = const (the broadband background of noise and texture); its
position is refined to a fraction of a frequency bin by Gaussian (log-parabolic) interpolation
along each axis.

Frequencies are in cycles per pixel in the image frame with X to the right and Y up (rows run
downwards), so a peak at f corresponds to the plane wave cos(2 pi f . (X, Y)).
"""

from typing import NamedTuple

import numpy as np
import scipy.fft
import scipy.ndimage

from rve_rod.errors import InputError

__all__ = [
    "PowerSpectrum",
    "SpectralPeaks",
    "annulus_medians",
    "find_peaks",
    "flatten_illumination",
    "parabola_vertex",
    "power_spectrum",
    "ring_index",
    "strongest_near",
]

FLATNESS = 1e-6
"""Relative standard deviation below which an image counts as flat (no structure at all)."""

DYNAMIC_RANGE = 1e-5
"""Peaks weaker than this fraction of the strongest are ignored: in a noise-free image the
far side lobes of the Hann window stand far above the (vanishing) background."""


class PowerSpectrum(NamedTuple):
    """Centred power spectrum of a windowed, zero-padded image.

    Attributes:
        power: (P_h, P_w) |FFT|^2, zero frequency at (P_h // 2, P_w // 2).
        image_shape: (H, W) of the image before padding (pixels).
    """

    power: np.ndarray
    image_shape: tuple[int, int]

    def frequency(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """(fx, fy) in cycles per pixel of (fractional) bins, shape (..., 2), Y up."""
        height, width = self.power.shape
        fx = (np.asarray(cols, dtype=float) - width // 2) / width
        fy = -(np.asarray(rows, dtype=float) - height // 2) / height
        return np.stack([fx, fy], axis=-1)

    def frequency_axes(self) -> tuple[np.ndarray, np.ndarray]:
        """fx of the columns (P_w,) and fy of the rows (P_h,), cycles per pixel, Y up."""
        height, width = self.power.shape
        return (np.arange(width) - width // 2) / width, -(np.arange(height) - height // 2) / height

    def bin_of(self, frequency: np.ndarray) -> np.ndarray:
        """Fractional (row, col) of frequencies (..., 2); the inverse of `frequency`."""
        height, width = self.power.shape
        frequency = np.asarray(frequency, dtype=float)
        return np.stack(
            [height // 2 - frequency[..., 1] * height, width // 2 + frequency[..., 0] * width],
            axis=-1,
        )


class SpectralPeaks(NamedTuple):
    """Peaks of a power spectrum, one of each +-f pair, strongest first.

    Attributes:
        frequencies: (K, 2) refined peak positions (cycles per pixel), fy > 0 or fy = 0 < fx.
        power: (K,) power at the peak bin.
        significance: (K,) power over the median power of its annulus (-).
    """

    frequencies: np.ndarray
    power: np.ndarray
    significance: np.ndarray


def flatten_illumination(image: np.ndarray) -> np.ndarray:
    """The image divided by its least-squares quadratic surface, minus 1: zero-mean contrast.

    Removes uneven lighting (gradients, vignetting) that would otherwise leak into the low
    frequencies. Raises InputError for a flat image (no structure to measure).
    """
    height, width = image.shape
    # A smooth surface of 6 coefficients: fitted to the means of stride x stride blocks
    # (a low-pass, so the texture does not alias into it), then evaluated everywhere.
    stride = max(1, min(height, width) // 128)
    rows, cols = (height // stride) * stride, (width // stride) * stride
    blocks = image[:rows, :cols].reshape(rows // stride, stride, cols // stride, stride)
    coordinate_v = np.linspace(-1, 1, height)[:rows].reshape(-1, stride).mean(axis=1)
    coordinate_u = np.linspace(-1, 1, width)[:cols].reshape(-1, stride).mean(axis=1)
    v, u = np.meshgrid(coordinate_v, coordinate_u, indexing="ij")
    coefficients, *_ = np.linalg.lstsq(
        _quadratic_terms(u, v).reshape(-1, 6), blocks.mean(axis=(1, 3)).ravel(), rcond=None
    )
    v, u = np.meshgrid(np.linspace(-1, 1, height), np.linspace(-1, 1, width), indexing="ij")
    surface = _quadratic_terms(u, v) @ coefficients
    scale = np.abs(surface).max()
    residual = image - surface
    if not scale > 0.0 or residual.std() <= FLATNESS * scale:
        raise InputError("the photo is flat (uniform intensity): no periodic structure to measure")
    # Divide where the illumination is positive; a dark corner would blow up the contrast.
    return residual / np.maximum(surface, 0.05 * scale)


def power_spectrum(contrast: np.ndarray, pad_factor: int = 2) -> PowerSpectrum:
    """The centred power spectrum of a zero-mean image (H, W), Hann-windowed and zero-padded."""
    height, width = contrast.shape
    window = np.outer(np.hanning(height), np.hanning(width))
    padded = (
        scipy.fft.next_fast_len(pad_factor * height, real=True),
        scipy.fft.next_fast_len(pad_factor * width, real=True),
    )
    transform = scipy.fft.fft2(contrast * window, s=padded, workers=-1)
    power = scipy.fft.fftshift(np.abs(transform) ** 2)
    return PowerSpectrum(power=power, image_shape=(height, width))


def annulus_medians(spectrum: PowerSpectrum) -> np.ndarray:
    """Median power of each annulus k <= |f| min(H, W) < k + 1 (one image bin wide), (K,).

    The medians are taken over the bins of the unpadded transform (every pad-th bin; the
    ones between are interpolated from them and add no information).
    """
    step_rows = max(1, spectrum.power.shape[0] // spectrum.image_shape[0])
    step_cols = max(1, spectrum.power.shape[1] // spectrum.image_shape[1])
    fx, fy = spectrum.frequency_axes()
    rings = ring_index(spectrum, np.hypot(fx[None, ::step_cols], fy[::step_rows, None])).ravel()
    sample = spectrum.power[::step_rows, ::step_cols].ravel()
    # One sort orders by ring, then by power within the ring (power scaled into [0, 0.5]).
    order = np.argsort(rings + 0.5 * sample / max(sample.max(), np.finfo(float).tiny))
    starts = np.searchsorted(rings[order], np.arange(rings.max() + 2))
    middle = starts[:-1] + np.maximum(np.diff(starts) - 1, 0) // 2
    return sample[order][np.minimum(middle, sample.size - 1)]


def ring_index(spectrum: PowerSpectrum, radius: np.ndarray) -> np.ndarray:
    """The annulus of `annulus_medians` holding frequencies of magnitude `radius` (cycles/px)."""
    return np.floor(np.asarray(radius) * min(spectrum.image_shape)).astype(np.int64)


def find_peaks(
    spectrum: PowerSpectrum,
    threshold: float,
    min_cycles: float,
    max_frequency: float,
    max_peaks: int,
) -> SpectralPeaks:
    """The strongest `max_peaks` local maxima with significance >= `threshold`.

    Args:
        threshold: minimum power over the annulus median (-).
        min_cycles: ignore frequencies below this many cycles across the image (the
            illumination residue); measured in the image's own (anisotropic) bins.
        max_frequency: ignore |f| above this (cycles per pixel), below Nyquist 0.5.
    """
    power = spectrum.power
    height, width = power.shape
    pad = max(1, round(min(height / spectrum.image_shape[0], width / spectrum.image_shape[1])))
    # Two image bins each side: wider than the Hann main lobe, so side lobes are no peaks.
    footprint = 4 * pad + 1
    fx, fy = spectrum.frequency_axes()
    radius = np.hypot(fx[None, :], fy[:, None])
    cycles = np.hypot(fx[None, :] * spectrum.image_shape[1], fy[:, None] * spectrum.image_shape[0])
    half_plane = (fy[:, None] > 0) | ((fy[:, None] == 0) & (fx[None, :] > 0))
    band = half_plane & (cycles >= min_cycles) & (radius <= max_frequency) & (power > 0)
    is_peak = power == scipy.ndimage.maximum_filter(power, size=footprint, mode="wrap")
    rows, cols = np.nonzero(is_peak & band)
    medians = annulus_medians(spectrum)
    background = medians[ring_index(spectrum, radius[rows, cols])]
    with np.errstate(divide="ignore"):
        significance = np.where(background > 0, power[rows, cols] / background, np.inf)
    keep = significance >= threshold
    keep &= power[rows, cols] >= DYNAMIC_RANGE * power[rows, cols][keep].max(initial=0.0)
    rows, cols, significance = rows[keep], cols[keep], significance[keep]
    order = np.argsort(-power[rows, cols])[:max_peaks]
    rows, cols, significance = rows[order], cols[order], significance[order]
    refined = np.array([refine_bin(power, r, c) for r, c in zip(rows, cols, strict=True)])
    refined = refined.reshape(-1, 2)
    return SpectralPeaks(
        frequencies=spectrum.frequency(refined[:, 0], refined[:, 1]),
        power=power[rows, cols],
        significance=significance,
    )


def refine_bin(power: np.ndarray, row: int, col: int) -> tuple[float, float]:
    """Sub-bin (row, col) of the peak at bin (row, col): Gaussian interpolation on each axis.

    The log-power parabola through the bin and its two neighbours has its vertex at
    delta = (ln P[-1] - ln P[+1]) / (2 (ln P[-1] - 2 ln P[0] + ln P[+1])), clipped to +-0.5.
    """
    height, width = power.shape
    tiny = np.finfo(float).tiny
    along_rows = np.log(np.maximum(power[[(row - 1) % height, row, (row + 1) % height], col], tiny))
    along_cols = np.log(np.maximum(power[row, [(col - 1) % width, col, (col + 1) % width]], tiny))
    return row + parabola_vertex(along_rows), col + parabola_vertex(along_cols)


def strongest_near(
    spectrum: PowerSpectrum, frequency: np.ndarray, radius_bins: float
) -> tuple[np.ndarray, float]:
    """The refined frequency (2,) and power of the strongest bin within `radius_bins` image bins
    of `frequency` (cycles per pixel)."""
    power = spectrum.power
    row, col = spectrum.bin_of(frequency)
    pad_rows = power.shape[0] / spectrum.image_shape[0]
    pad_cols = power.shape[1] / spectrum.image_shape[1]
    reach_rows = max(1, int(radius_bins * pad_rows))
    reach_cols = max(1, int(radius_bins * pad_cols))
    rows = np.arange(round(row) - reach_rows, round(row) + reach_rows + 1) % power.shape[0]
    cols = np.arange(round(col) - reach_cols, round(col) + reach_cols + 1) % power.shape[1]
    window = power[np.ix_(rows, cols)]
    best_row, best_col = np.unravel_index(np.argmax(window), window.shape)
    refined = refine_bin(power, rows[best_row], cols[best_col])
    return spectrum.frequency(*refined), float(window[best_row, best_col])


def _quadratic_terms(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The monomials 1, u, v, u^2, u v, v^2 stacked on a last axis, shape (..., 6)."""
    return np.stack([np.ones_like(u), u, v, u * u, u * v, v * v], axis=-1)


def parabola_vertex(values: np.ndarray) -> float:
    """Offset in [-0.5, 0.5] of the vertex of the parabola through three equally spaced values
    (at -1, 0, +1) from the middle one; 0 if it does not open downwards."""
    left, centre, right = values
    curvature = left - 2.0 * centre + right
    if curvature >= 0.0:
        return 0.0
    return float(np.clip(0.5 * (left - right) / curvature, -0.5, 0.5))
