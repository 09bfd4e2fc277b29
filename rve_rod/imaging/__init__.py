"""Knit geometry from photos: wale width, course height and angle of single jersey measured
on a photo (`measure`), and synthetic photos of the loop model (`synthetic`) to test the
measurement against a known truth."""

from rve_rod.imaging.measure import MeasureOptions, PhotoEstimate, knit_from_photo, measure_photo
from rve_rod.imaging.synthetic import SyntheticPhoto, render_photo

__all__ = [
    "MeasureOptions",
    "PhotoEstimate",
    "SyntheticPhoto",
    "knit_from_photo",
    "measure_photo",
    "render_photo",
]
