"""Test fixture: a synthetic family of response surfaces over the stitch value.

Each member is the B-spline interpolant of the analytic law (`surface_cases.synthetic_surface`)
with stiffnesses that fall with the stitch value as a knit's do (looser loops: softer), and
the cotton 20s/2 preset's wale widths and course heights. Cheap (no RVE run) and independent
of the yarn model: the design's tests recover members of it.
"""

from dataclasses import replace

import numpy as np

from knitmech.design.family import FamilyMember, SurfaceFamily
from rve_rod.presets import load_preset
from rve_rod.surface import write_surface
from support.surface_cases import COTTON_LIKE_LAW, synthetic_surface

STITCHES = (4.5, 5.0, 5.5, 6.0, 6.5, 7.0)
"""The cotton 20s/2 preset's stitch values (mm)."""


def member_law(stitch: float, wale_factor: float = 1.0):
    """The analytic law of the member at `stitch` (mm): course stiffness ~ s^-3, wale ~ s^-2,
    the wale stiffness times `wale_factor`."""
    ratio = 5.5 / stitch
    return replace(
        COTTON_LIKE_LAW,
        course_stiffness=COTTON_LIKE_LAW.course_stiffness * ratio**3,
        wale_stiffness=COTTON_LIKE_LAW.wale_stiffness * ratio**2 * wale_factor,
        coupling_11_22=COTTON_LIKE_LAW.coupling_11_22 * ratio**2,
        coupling_22_11=COTTON_LIKE_LAW.coupling_22_11 * ratio**2,
    )


def synthetic_family(stitches=STITCHES, folder=None, wale_factor: float = 1.0) -> SurfaceFamily:
    """The family at `stitches` (mm), wale stiffness times `wale_factor`; with `folder`, each
    member's surface is written there (`<stitch>.h5`) and named by its path."""
    members, surfaces = [], []
    for stitch in stitches:
        law = member_law(stitch, wale_factor)
        surface = synthetic_surface(law, spans=8, normal_domain=(-0.15, 0.4))
        knit = load_preset("cotton-20s2", stitch).knit
        path = ""
        if folder is not None:
            path = str(write_surface(folder / f"{stitch:g}.h5", surface))
        members.append(FamilyMember(stitch, path, knit.wale_width, knit.course_height))
        surfaces.append(surface)
    return SurfaceFamily(tuple(members), tuple(surfaces))


def curve_at(family: SurfaceFamily, stitch: float, direction: str, strains=(0.05, 0.1, 0.2)):
    """(strain, force N/mm) of the family's uniaxial curve at `stitch`."""
    strain = np.asarray(strains, dtype=float)
    return strain, family.uniaxial(stitch, strain, direction)
