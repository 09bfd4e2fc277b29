"""Photo reading: grayscale conversion by the Rec. 709 luma weights, integer scaling, errors."""

import numpy as np
import pytest
from PIL import Image

from rve_rod.errors import InputError
from rve_rod.imaging.image_io import read_image, to_grayscale, write_image


def test_colour_is_converted_by_rec709_luma():
    rgb = np.zeros((2, 3, 3))
    rgb[0, 0] = [1.0, 0.0, 0.0]
    rgb[0, 1] = [0.0, 1.0, 0.0]
    rgb[0, 2] = [0.0, 0.0, 1.0]
    rgb[1, :] = [0.5, 0.5, 0.5]
    gray = to_grayscale(rgb)
    np.testing.assert_allclose(gray[0], [0.2126, 0.7152, 0.0722], atol=1e-15)
    np.testing.assert_allclose(gray[1], 0.5, atol=1e-15)


def test_alpha_is_dropped_and_integers_are_scaled_by_their_maximum():
    rgba = np.zeros((1, 2, 4), dtype=np.uint8)
    rgba[0, 0] = [255, 255, 255, 0]
    rgba[0, 1] = [0, 0, 0, 255]
    np.testing.assert_allclose(to_grayscale(rgba), [[1.0, 0.0]], atol=1e-12)
    sixteen = np.array([[0, 65535, 32768]], dtype=np.uint16)
    np.testing.assert_allclose(to_grayscale(sixteen), [[0.0, 1.0, 32768 / 65535]])


@pytest.mark.parametrize("shape", [(4,), (2, 3, 5), (2, 2, 2, 2)])
def test_other_shapes_are_refused(shape):
    with pytest.raises(InputError, match="neither grayscale"):
        to_grayscale(np.zeros(shape))


def test_non_finite_values_are_refused():
    with pytest.raises(InputError, match="not finite"):
        to_grayscale(np.array([[0.0, np.nan]]))


def test_png_round_trip_quantizes_to_eight_bits(tmp_path):
    image = np.random.default_rng(0).random((20, 30))
    path = tmp_path / "photo.png"
    write_image(path, image)
    back = read_image(path)
    assert back.shape == image.shape
    assert np.abs(back - image).max() <= 0.5 / 255 + 1e-12


def test_colour_file_reads_as_luma(tmp_path):
    rgb = np.zeros((8, 8, 3), dtype=np.uint8)
    rgb[..., 0] = 200
    rgb[..., 2] = 100
    path = tmp_path / "colour.png"
    Image.fromarray(rgb).save(path)
    expected = (0.2126 * 200 + 0.0722 * 100) / 255
    np.testing.assert_allclose(read_image(path), expected, atol=1e-12)


def test_palette_file_is_converted(tmp_path):
    path = tmp_path / "palette.gif"
    Image.fromarray(np.full((8, 8, 3), 255, dtype=np.uint8)).convert("P").save(path)
    np.testing.assert_allclose(read_image(path), 1.0)


def test_unreadable_and_missing_files_name_the_path(tmp_path):
    text = tmp_path / "notes.png"
    text.write_text("not an image")
    with pytest.raises(InputError, match=r"photo='.*notes.png' cannot be read as an image"):
        read_image(text)
    with pytest.raises(InputError, match=r"photo='.*absent.png' does not exist"):
        read_image(tmp_path / "absent.png")
