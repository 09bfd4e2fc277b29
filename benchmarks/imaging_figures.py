"""Figures of docs/imaging.md: a measured photo with its lattice, and its power spectrum.

Run: .venv/bin/python benchmarks/imaging_figures.py  (writes docs/figures/imaging_*.png)
"""

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from rve_rod.imaging.measure import measure_photo
from rve_rod.imaging.overlay import plot_overlay
from rve_rod.imaging.spectrum import flatten_illumination, power_spectrum
from rve_rod.imaging.synthetic import SyntheticPhoto, render_photo

FIGURES = Path(__file__).parents[1] / "docs" / "figures"


def main() -> None:
    FIGURES.mkdir(parents=True, exist_ok=True)
    photo = SyntheticPhoto(
        1.33,
        1.26,
        0.19,
        angle_deg=10.0,
        width_px=250,
        height_px=250,
        blur_mm=0.04,
        noise=0.02,
        lighting=0.4,
    )
    image = render_photo(photo)
    estimate = measure_photo(image, photo.pixels_per_mm)
    plot_overlay(image, estimate, FIGURES / "imaging_overlay.png", dpi=60)

    # The spectrum with the fitted lattice points (n1, n2) of the wale and course vectors.
    spectrum = power_spectrum(flatten_illumination(image))
    scale = photo.pixels_per_mm
    cell = np.column_stack([estimate.wale_vector, estimate.course_vector]) * scale
    reciprocal = np.linalg.inv(cell).T  # cycles per pixel
    height, width = spectrum.power.shape
    reach = 0.075
    figure = Figure(figsize=(4.6, 4.2))
    axes = figure.subplots()
    extent = (-0.5, 0.5 - 1 / width, -(0.5 - 1 / height), 0.5)
    axes.imshow(np.log10(spectrum.power + 1e-12), cmap="magma", extent=extent, vmin=0)
    for n1 in range(-4, 5):
        for n2 in range(-3, 4):
            point = reciprocal @ [n1, n2]
            if np.abs(point).max() < reach * 0.95 and (n1, n2) != (0, 0):
                axes.plot(*point, "o", mfc="none", mec="cyan", ms=9, mew=0.7)
                axes.annotate(
                    f"{n1},{n2}",
                    point,
                    xytext=(4, 4),
                    textcoords="offset points",
                    color="cyan",
                    fontsize=6,
                )
    axes.set_xlim(-reach, reach)
    axes.set_ylim(-reach, reach)
    axes.set_xlabel("f_X (cycles per pixel)")
    axes.set_ylabel("f_Y (cycles per pixel)")
    axes.set_title("log10 power; circles: fitted lattice (n1, n2)", fontsize=9)
    figure.tight_layout()
    figure.savefig(FIGURES / "imaging_spectrum.png", dpi=80)
    for name in ("imaging_overlay.png", "imaging_spectrum.png"):
        print(f"wrote {FIGURES / name} ({(FIGURES / name).stat().st_size / 1024:.0f} kB)")


if __name__ == "__main__":
    main()
