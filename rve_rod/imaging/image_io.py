"""Reading and writing photos: any format Pillow reads, converted to a grayscale float array."""

import os

import numpy as np
from PIL import Image, UnidentifiedImageError

from rve_rod.errors import InputError

__all__ = [
    "block_mean",
    "read_image",
    "to_grayscale",
    "write_image",
]

LUMA_WEIGHTS = np.array([0.2126, 0.7152, 0.0722])
"""Rec. 709 luma weights of the red, green and blue channels (sum 1)."""


def to_grayscale(image: np.ndarray) -> np.ndarray:
    """A float64 grayscale image (H, W) from a grayscale (H, W) or colour (H, W, 3|4) array.

    Colour is converted by the Rec. 709 luma weights; an alpha channel (4th or 2nd channel)
    is dropped. Integer arrays are scaled by their type's maximum (uint8 -> [0, 1]).
    """
    array = np.asarray(image)
    if np.issubdtype(array.dtype, np.integer):
        array = array.astype(np.float64) / np.iinfo(array.dtype).max
    elif array.dtype == np.bool_:
        array = array.astype(np.float64)
    else:
        array = array.astype(np.float64)
    if array.ndim == 3 and array.shape[2] in (1, 2):
        array = array[:, :, 0]
    elif array.ndim == 3 and array.shape[2] in (3, 4):
        array = array[:, :, :3] @ LUMA_WEIGHTS
    if array.ndim != 2:
        raise InputError(
            f"image of shape {image.shape} is neither grayscale (H, W) nor colour (H, W, 3|4)"
        )
    if not np.all(np.isfinite(array)):
        raise InputError("image contains values that are not finite numbers")
    return array


def block_mean(image: np.ndarray, factor: int) -> np.ndarray:
    """The image (H, W) averaged over factor x factor blocks, shape (H // factor, W // factor)
    (a remainder of rows and columns is dropped)."""
    height, width = (image.shape[0] // factor) * factor, (image.shape[1] // factor) * factor
    blocks = image[:height, :width].reshape(height // factor, factor, width // factor, factor)
    return blocks.mean(axis=(1, 3))


def read_image(path: str | os.PathLike) -> np.ndarray:
    """The photo at `path` as a float64 grayscale array (H, W); InputError if unreadable."""
    try:
        with Image.open(path) as opened:
            opened.load()
            native = opened.mode in ("L", "LA", "I", "I;16", "F", "RGB", "RGBA")
            array = np.asarray(opened if native else opened.convert("RGB"))
    except FileNotFoundError:
        raise InputError(f"photo={os.fspath(path)!r} does not exist") from None
    except (UnidentifiedImageError, OSError, ValueError) as error:
        raise InputError(f"photo={os.fspath(path)!r} cannot be read as an image: {error}") from None
    return to_grayscale(array)


def write_image(path: str | os.PathLike, image: np.ndarray) -> None:
    """Save an image with intensities in [0, 1] (H, W) or (H, W, 3) as 8-bit (PNG, JPEG...)."""
    array = np.clip(np.asarray(image, dtype=np.float64), 0.0, 1.0)
    Image.fromarray(np.round(255.0 * array).astype(np.uint8)).save(path)
