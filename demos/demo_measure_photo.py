# Course height and wale width from a photo of single jersey
# ==========================================================
#
# The geometric model of a knit needs the wale width w (loop period across the wales) and the
# course height c (loop period along them). Textile labs measure them on a photo of the
# fabric, averaged over dozens of loops. This demo makes such a photo from the loop model
# with a known w and c (so we can check the answer), spoils it the way a camera does, and
# measures it back with `rve_rod.imaging.measure_photo`.
#
# Run: `python demos/demo_measure_photo.py [output_dir]` (default: results/).

import sys
from pathlib import Path

from rve_rod.imaging import SyntheticPhoto, knit_from_photo, measure_photo, render_photo
from rve_rod.imaging.image_io import read_image, write_image
from rve_rod.imaging.overlay import plot_overlay
from rve_rod.presets import load_preset

output = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results")
output.mkdir(parents=True, exist_ok=True)

# The fabric: cotton 20s/2 knitted at stitch value 5.5 (w = 1.33 mm, c = 1.26 mm). The photo
# shows the model's loop (`rve_rod.geometry.loop`), its yarn drawn with the adjusted radius
# r = min(r0, w/8).
fabric = load_preset("cotton-20s2", stitch=5.5)
wale_width, course_height = fabric.knit.wale_width, fabric.knit.course_height

# The photo: 20 x 20 mm at 25 pixels per mm, the fabric turned by 8 degrees, slightly out of
# focus (blur 0.04 mm), lit from one side with some vignetting, and noisy. It is saved as
# an 8-bit PNG and read back, as a user's photo would be.
photo = SyntheticPhoto(
    wale_width,
    course_height,
    fabric.yarn.minimal_radius,
    angle_deg=8.0,
    pixels_per_mm=25.0,
    width_px=500,
    height_px=500,
    blur_mm=0.04,
    noise=0.1,
    lighting=0.4,
)
photo_path = output / "knit_photo.png"
write_image(photo_path, render_photo(photo))

# The measurement: the photo's power spectrum has sharp peaks on the fabric's reciprocal
# lattice; the fundamental lattice among them, refined over all peaks, gives w, c and the
# angle. The uncertainty is the standard error over 3 x 3 tiles of the photo.
estimate = measure_photo(photo_path, photo.pixels_per_mm)
wales, courses = estimate.wales_in_image, estimate.courses_in_image
print(f"photo {photo_path}: {wales:.1f} wales and {courses:.1f} courses across")
print(f"{'':14s}{'true':>8s}{'measured':>10s}{'+-':>8s}{'error':>9s}")
for name, truth, value, uncertainty in [
    ("w (mm)", wale_width, estimate.wale_width, estimate.wale_width_uncertainty),
    ("c (mm)", course_height, estimate.course_height, estimate.course_height_uncertainty),
    ("angle (deg)", photo.angle_deg, estimate.angle_deg, estimate.angle_uncertainty_deg),
]:
    print(f"{name:14s}{truth:8.4f}{value:10.4f}{uncertainty:8.4f}{value - truth:+9.4f}")

# The overlay draws the measured course lines (along the courses, spaced c) and wale lines
# (spaced w) through the gaps between the loops: a quick visual check of the lattice.
overlay_path = output / "knit_photo_lattice.png"
plot_overlay(read_image(photo_path), estimate, overlay_path)
print(f"wrote {overlay_path}")

# The measured knit is the input of the geometric model (`rve-rod geometry`), in one call.
knit = knit_from_photo(photo_path, photo.pixels_per_mm)
print(f"knit for the geometry: w = {knit.wale_width:.3f} mm, c = {knit.course_height:.3f} mm")
