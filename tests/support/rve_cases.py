"""The loop of the RVE tests: the cotton stitch-5.5 loop of `rve_rod.geometry.loop`, built for
the adjusted radius r = w/8 = 0.166 mm, carrying a yarn of radius 0.16 mm, so that the yarn
touches nothing at rest and the first contacts come from the load."""

from rve_rod.geometry.loop import loop_geometry
from rve_rod.presets import Fabric, Knit, Yarn

KNIT = Knit(1.33, 1.26)
CURVES = loop_geometry(KNIT, 0.19).curves
FABRIC = Fabric(Yarn(minimal_radius=0.16, youngs_modulus=80.0), KNIT)
