"""Synthetic photos: tube heights, exact periodicity, rotation sense, blur, lighting, noise."""

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from rve_rod.errors import InputError
from rve_rod.imaging.synthetic import (
    SyntheticPhoto,
    cell_height_map,
    image_coordinates,
    render_photo,
)

LOOP = (1.0, 1.0, 0.12)
"""w, c, r0 (mm) of the photos: one loop for all tests (the loop takes about a second)."""


def pixel_of(photo, x, y):
    """(row, column) of the pixel at fabric point (x, y) mm of an unrotated photo."""
    column = round(x * photo.pixels_per_mm + 0.5 * (photo.width_px - 1))
    row = round(0.5 * (photo.height_px - 1) - y * photo.pixels_per_mm)
    return row, column


def test_photo_draws_the_tubes_of_the_model_loop():
    # Yarn where the pixel lies within r of the loop's centreline (its curves sampled densely,
    # with the 3 x 3 neighbouring cells, in projection), background beyond r; 2 pixels of
    # margin for the pixel filter.
    photo = SyntheticPhoto(*LOOP, pixels_per_mm=50.0, width_px=150, height_px=120)
    image = render_photo(photo)
    loop = photo.loop()
    u = np.linspace(0.0, 1.0, 2000)
    centreline = np.vstack([curve(u)[:, :2] for curve in loop.curves])
    shifts = [
        i * loop.lattice[0, :2] + j * loop.lattice[1, :2]
        for i in (-2, -1, 0, 1, 2)
        for j in (-2, -1, 0, 1, 2)
    ]
    tree = cKDTree(np.vstack([centreline + shift for shift in shifts]))
    X, Y = image_coordinates(photo.height_px, photo.width_px, photo.pixels_per_mm)
    distance, _ = tree.query(np.column_stack([X.ravel(), Y.ravel()]))
    distance = distance.reshape(image.shape)
    margin = 2.0 / photo.pixels_per_mm
    r = loop.yarn_radius
    assert r == pytest.approx(0.12)
    assert image[distance < r - margin].min() > 0.14
    assert image[distance > r + margin].max() < 0.06
    assert np.mean(distance < r - margin) > 0.3


def test_face_shows_the_legs_on_top_and_back_the_heads():
    # The loop's highest z (depth / 2) is at the leg point L = (w/4, 0), where the legs cross
    # over the heads of the neighbouring courses; its lowest (-depth / 2) at the head apex
    # (0, h). The face is seen from +z, the back from -z (and mirrored in y). The top of a
    # yarn, lit at 35 degrees, is 0.15 + 0.55 + 0.3 sin(35.26 deg) = 0.945.
    settings = {"pixels_per_mm": 50.0, "width_px": 100, "height_px": 100}
    face = SyntheticPhoto(*LOOP, **settings)
    back = SyntheticPhoto(*LOOP, side="back", **settings)
    head_height = face.loop().course_height / 2 + face.loop().shape_parameter
    leg, apex = pixel_of(face, 0.25, 0.0), pixel_of(back, 0.0, -head_height)
    face_image, back_image = render_photo(face), render_photo(back)
    top = 0.15 + 0.55 + 0.3 * math.sqrt(2.0 / 3.0)
    assert face_image[leg] == pytest.approx(top, abs=0.01)
    assert back_image[apex] == pytest.approx(top, abs=0.01)
    assert back_image[leg] < 0.6


def test_straight_yarn_has_the_height_profile_of_a_tube():
    width, height, radius, level = 1.0, 0.8, 0.1, 0.05
    line = np.array([[0.0, 0.4, level], [width, 0.4, level]])
    shape = (160, 200)
    tube = cell_height_map(line, width, height, radius, shape)
    y = np.arange(shape[0]) * height / shape[0]
    offset = y - 0.4
    inside = np.abs(offset) < 0.95 * radius
    expected = level + np.sqrt(radius**2 - offset[inside] ** 2)
    # Same profile in every column (the tube runs along x and wraps across the cell edge).
    np.testing.assert_allclose(tube[inside], np.tile(expected[:, None], (1, shape[1])), atol=1e-4)
    assert np.all(np.isneginf(tube[np.abs(offset) > radius * (1 + 1e-9)]))


def test_yarn_across_the_cell_edge_wraps_to_the_other_side():
    line = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    tube = cell_height_map(line, 1.0, 1.0, 0.1, (100, 100))
    # Rows within r of y = 0, on both sides of the periodic edge, are covered.
    assert np.all(np.isfinite(tube[:9])) and np.all(np.isfinite(tube[-9:]))
    assert np.all(np.isneginf(tube[12:-12]))


def test_photo_repeats_exactly_with_the_lattice_rotated_counter_clockwise():
    # w = c = 1 mm at 25 px/mm rotated by atan(7/24): the lattice vectors are the integer
    # pixel vectors (24, 7) and (-7, 24) (X right, Y up; rows run down).
    angle = math.degrees(math.atan2(7, 24))
    image = render_photo(SyntheticPhoto(*LOOP, angle_deg=angle, width_px=96, height_px=96))
    np.testing.assert_allclose(image[7:, :-24], image[:-7, 24:], atol=1e-9)
    np.testing.assert_allclose(image[24:, 7:], image[:-24, :-7], atol=1e-9)
    # The clockwise rotation would repeat with (24, -7) instead.
    assert np.abs(image[:-7, :-24] - image[7:, 24:]).max() > 0.1


def test_blur_attenuates_a_harmonic_by_the_gaussian_transfer_function():
    # 8 periods of 32 px each way: lattice peaks fall on exact FFT bins. Both photos are
    # blurred enough that no harmonic above the pixels' Nyquist frequency aliases back.
    settings = {"width_px": 256, "height_px": 256, "pixels_per_mm": 32.0}
    first, second = 0.06, 0.08
    less = render_photo(SyntheticPhoto(*LOOP, blur_mm=first, **settings))
    more = render_photo(SyntheticPhoto(*LOOP, blur_mm=second, **settings))
    for row, col in [(0, 16), (8, 8), (8, 0), (16, 8)]:
        frequency = math.hypot(row, col) / 8 / 1.0  # cycles per mm
        ratio = abs(np.fft.fft2(more)[row, col]) / abs(np.fft.fft2(less)[row, col])
        expected = math.exp(-2 * math.pi**2 * (second**2 - first**2) * frequency**2)
        assert ratio == pytest.approx(expected, rel=1e-3)


def test_lighting_and_noise_have_the_documented_amplitude():
    clean = render_photo(SyntheticPhoto(*LOOP, width_px=200, height_px=150))
    lit = render_photo(SyntheticPhoto(*LOOP, width_px=200, height_px=150, lighting=0.4))
    # Illumination 1 + a (u + v)/4 - a (u^2 + v^2)/4 over u, v in [-1, 1]: 1 - a at the
    # corner (-1, -1), 1 at (1, 1), 1 + a/8 at its maximum u = v = 1/2.
    ratio = lit / clean
    assert ratio.min() == pytest.approx(0.6, abs=1e-9)
    assert ratio.max() == pytest.approx(1.05, abs=2e-3)
    noisy = render_photo(SyntheticPhoto(*LOOP, width_px=200, height_px=150, noise=0.02, seed=4))
    assert np.std(noisy - clean) == pytest.approx(0.02, rel=0.05)


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("minimal_radius", 0.0, "minimal_radius=0 mm must be > 0"),
        ("angle_deg", 60.0, "angle_deg=60 deg is outside"),
        ("lighting", 1.5, "lighting=1.5 is outside"),
        ("width_px", 4, "width_px=4 is outside"),
        ("side", "top", "side='top' must be"),
    ],
)
def test_bad_settings_are_refused(field, value, message):
    settings = {"wale_width": 1.3, "course_height": 1.2, "minimal_radius": 0.15, field: value}
    with pytest.raises(InputError, match=message):
        SyntheticPhoto(**settings)


def test_tube_wider_than_the_cell_is_refused():
    line = np.array([[0.0, 0.5, 0.0], [1.0, 0.5, 0.0]])
    with pytest.raises(InputError, match="yarn radius exceeds the cell"):
        cell_height_map(line, 1.0, 1.0, 1.5, (8, 8))
