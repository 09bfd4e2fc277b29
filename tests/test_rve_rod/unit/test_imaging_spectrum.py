"""Power spectrum peaks: sub-bin positions of plane waves, illumination removal, background."""

import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.imaging.spectrum import (
    annulus_medians,
    find_peaks,
    flatten_illumination,
    power_spectrum,
    ring_index,
)


def plane_wave(shape, frequency, amplitude=0.3):
    """1 + a cos(2 pi f . (X, Y)) with X = column, Y = -row (pixels, Y up)."""
    rows, cols = np.indices(shape)
    return 1.0 + amplitude * np.cos(2 * np.pi * (frequency[0] * cols - frequency[1] * rows))


@pytest.mark.parametrize(
    "frequency", [(0.0731, 0.0412), (-0.1013, 0.0577), (0.2117, 0.0), (0.0, 0.1533)]
)
def test_plane_wave_peak_is_found_to_a_small_fraction_of_a_bin(frequency):
    shape = (128, 160)  # non-square: different bin widths along X and Y
    contrast = flatten_illumination(plane_wave(shape, frequency))
    peaks = find_peaks(power_spectrum(contrast), 20.0, 1.5, 0.35, 5)
    assert peaks.frequencies.shape == (1, 2)
    error_in_bins = (peaks.frequencies[0] - frequency) * [shape[1], shape[0]]
    assert np.abs(error_in_bins).max() < 0.05


def test_flattening_divides_out_a_quadratic_illumination():
    shape = (120, 150)
    v, u = np.meshgrid(np.linspace(-1, 1, shape[0]), np.linspace(-1, 1, shape[1]), indexing="ij")
    lighting = 1.0 + 0.3 * u - 0.2 * v + 0.1 * u**2
    texture = plane_wave(shape, (0.081, 0.063), amplitude=0.2) - 1.0
    contrast = flatten_illumination(lighting * (1.0 + texture))
    # The quadratic fit absorbs a little of the texture: a few per cent at most.
    assert np.abs(contrast - texture).max() < 0.02


@pytest.mark.parametrize(
    "image", [np.full((64, 64), 0.4), np.add.outer(np.arange(64), np.arange(64))]
)
def test_flat_and_ramp_images_have_no_structure(image):
    with pytest.raises(InputError, match="flat"):
        flatten_illumination(image.astype(float))


def test_background_of_white_noise_is_the_exponential_median():
    # The power of white noise is exponentially distributed: median = ln 2 x mean.
    noise = np.random.default_rng(1).normal(size=(256, 256))
    spectrum = power_spectrum(noise - noise.mean(), pad_factor=1)
    fx, fy = spectrum.frequency_axes()
    rings = ring_index(spectrum, np.hypot(fx[None, :], fy[:, None]))
    medians = annulus_medians(spectrum)
    band = np.arange(13, 102)  # |f| from 0.05 to 0.4 cycles per pixel
    means = np.array([spectrum.power[rings == ring].mean() for ring in band])
    assert np.median(medians[band] / means) == pytest.approx(np.log(2.0), rel=0.05)


def test_pure_noise_has_no_significant_peak():
    for seed in range(5):
        noise = np.random.default_rng(seed).normal(size=(200, 300))
        peaks = find_peaks(power_spectrum(noise - noise.mean()), 20.0, 1.5, 0.35, 40)
        assert peaks.power.size <= 1
