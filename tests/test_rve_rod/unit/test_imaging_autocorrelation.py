"""The all-shift autocorrelation against a plain per-shift correlation, and the best repeat
of patterns with a known period."""

import math

import numpy as np
import pytest

from rve_rod.imaging.autocorrelation import autocorrelation, shift_correlation, strongest_repeat


def textured(shape=(23, 31), seed=0):
    """A random image with correlated columns, offsets and a gradient (a non-trivial map)."""
    rng = np.random.default_rng(seed)
    rows = np.arange(shape[0])[:, None]
    return rng.normal(size=shape).cumsum(axis=1) + 0.05 * rows + 3.0


def plain_correlation(image, shift_x, shift_y):
    """np.corrcoef of the pixels f(X, Y) and f(X + shift_x, Y + shift_y) (Y up) that exist."""
    height, width = image.shape
    rows, cols = np.indices(image.shape)
    moved_rows, moved_cols = rows - shift_y, cols + shift_x
    inside = (moved_rows >= 0) & (moved_rows < height) & (moved_cols >= 0) & (moved_cols < width)
    first = image[inside]
    second = image[moved_rows[inside], moved_cols[inside]]
    return np.corrcoef(first, second)[0, 1], inside.mean()


@pytest.mark.parametrize(
    ("shift_x", "shift_y"),
    [(3, 2), (-5, 7), (10, -4), (0, 5), (7, 0), (-29, 21), (28, -20)],
)
def test_map_matches_the_correlation_of_each_shift(shift_x, shift_y):
    image = textured()
    result = autocorrelation(image)
    height, width = image.shape
    row, col = (height - 1) - shift_y, shift_x + (width - 1)
    expected, overlap = plain_correlation(image, shift_x, shift_y)
    assert result.correlation[row, col] == pytest.approx(expected, abs=1e-9)
    assert result.overlap[row, col] == pytest.approx(overlap, rel=1e-12)
    assert result.shift_of(row, col) == pytest.approx([shift_x, shift_y])
    if overlap >= 0.05:  # shift_correlation's smallest overlap
        assert shift_correlation(image, np.array([shift_x, shift_y], float)) == pytest.approx(
            expected, abs=1e-9
        )


def test_map_is_symmetric_and_one_at_zero_shift():
    result = autocorrelation(textured())
    assert result.correlation[22, 30] == pytest.approx(1.0, abs=1e-12)
    assert result.overlap[22, 30] == 1.0
    assert np.allclose(result.correlation, result.correlation[::-1, ::-1], equal_nan=True)


@pytest.mark.parametrize(("max_side", "tolerance_px"), [(192, 0.1), (40, 0.3)], ids=["full", "1:3"])
@pytest.mark.parametrize("angle_deg", [0.0, 12.0, -25.0])
def test_best_repeat_is_a_period(angle_deg, max_side, tolerance_px):
    # Plane waves of the lattice (18, 0), (0, 11) rotated: its lattice vectors repeat it,
    # shifts between the lattice points do not.
    angle = math.radians(angle_deg)
    rotation = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    real = rotation @ np.diag([18.0, 11.0])
    reciprocal = np.linalg.inv(real).T
    rows, cols = np.indices((90, 110))
    phase = np.stack([cols, -rows], axis=-1) @ reciprocal
    image = (
        np.cos(2 * np.pi * phase[..., 0])
        + 0.6 * np.cos(2 * np.pi * (phase[..., 0] + phase[..., 1]))
        + 0.4 * np.cos(2 * np.pi * phase[..., 1])
    )
    repeat = strongest_repeat(image, min_overlap=0.3, max_side=max_side)
    # A lattice vector, refined to a fraction of a pixel (of a block of 3 x 3 pixels).
    lattice_point = real @ np.rint(np.linalg.solve(real, repeat.shift))
    assert np.any(lattice_point != 0)
    assert np.abs(repeat.shift - lattice_point).max() <= tolerance_px
    assert repeat.correlation > 0.98


def test_noise_has_no_strong_repeat():
    noise = np.random.default_rng(3).normal(size=(120, 140))
    assert strongest_repeat(noise, min_overlap=0.3).correlation < 0.1


def test_no_repeat_when_no_shift_overlaps_enough():
    assert strongest_repeat(textured(), min_overlap=0.99) is None
