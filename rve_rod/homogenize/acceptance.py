"""Checks of a newly fitted response surface before it is written: sign, monotonicity and data
coverage.

A fit to too few rays can exit cleanly with a surface that is wrong where it has no data
(issue 19: 3 rays gave S11 = -0.043 N/mm at equibiaxial E = 0.2, tension giving compression;
8 rays put a spike of S22 = 0.2 N/mm in an empty corner). `surface_problems` lists what a
knit in tension cannot do:

- sign: in the tension quadrant (E11 >= 0, E22 >= 0) neither S11 nor S22 is compressive (a
  knit stretched both ways pulls both ways), beyond SIGN_TOLERANCE of the largest stress;
- monotonicity: dS11/dE11 and dS22/dE22 are not negative on the domain beyond
  SOFTENING_TOLERANCE of their largest (`rve_rod.surface.softest_normal_tangents`);
- coverage: the fit does not exceed the largest sample of its group by more than
  COVERAGE_FACTOR anywhere on the domain (it would be extrapolating a wiggle, not data).

`generate_surface` stores the problems in the surface's parameters (`checks`) and logs each
as a warning; `rve-rod surface` and `rve-rod surface-info` print them.
"""

import numpy as np

from rve_rod.surface import ResponseSurface, softest_normal_tangents

__all__ = [
    "COVERAGE_FACTOR",
    "SIGN_TOLERANCE",
    "SOFTENING_TOLERANCE",
    "surface_problems",
]

SIGN_TOLERANCE = 0.01
"""A compressive S11 or S22 in the tension quadrant is a problem beyond this fraction of the
largest |S| there (fit noise near E = 0 stays below)."""
SOFTENING_TOLERANCE = 1e-9
"""A normal stiffness below -SOFTENING_TOLERANCE times its largest value is a problem; above,
it is round-off of a fit held at zero slope (the monotone stress fit)."""
COVERAGE_FACTOR = 1.25
"""A fitted |S| above this times the largest |sample| of its group is a problem."""

_POINTS_PER_AXIS = 41


def _grid(low: np.ndarray, high: np.ndarray) -> np.ndarray:
    x, y = np.meshgrid(
        np.linspace(low[0], high[0], _POINTS_PER_AXIS),
        np.linspace(low[1], high[1], _POINTS_PER_AXIS),
    )
    return np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)


def surface_problems(surface: ResponseSurface) -> list[str]:
    """What is wrong with `surface` as a knit's response (see the module); [] when nothing.

    Each problem is one line naming the quantity, its value (N/mm), the strain (E11, E22)
    where it occurs and the check it fails.
    """
    problems = []
    domain = np.asarray(surface.domain, dtype=float)
    low, high = domain[:2, 0], domain[:2, 1]
    if np.all(high > 0.0):
        strain = _grid(np.maximum(low, 0.0), high)
        stress = surface.stress(strain).S[:, :2]
        largest = float(np.abs(stress).max())
        for axis, name in enumerate(("S11", "S22")):
            at = int(np.argmin(stress[:, axis]))
            if stress[at, axis] < -SIGN_TOLERANCE * largest:
                problems.append(
                    f"sign: {name} = {stress[at, axis]:.3g} N/mm at E = "
                    f"({strain[at, 0]:.3g}, {strain[at, 1]:.3g}): compression in biaxial tension"
                )
    for name, entry in softest_normal_tangents(surface).items():
        if entry["value"] < -SOFTENING_TOLERANCE * entry["largest"]:
            problems.append(
                f"monotonicity: {name} = {entry['value']:.3g} N/mm at E = "
                f"({entry['strain'][0]:.3g}, {entry['strain'][1]:.3g}): the material softens"
            )
    strain = _grid(low, high)
    stress = surface.stress(strain).S
    for axis, name in enumerate(("S11", "S22")):
        samples = surface.samples.get(name)
        if samples is None or samples.values.size == 0:
            continue
        sampled = float(np.abs(samples.values).max())
        at = int(np.argmax(np.abs(stress[:, axis])))
        if abs(stress[at, axis]) > COVERAGE_FACTOR * sampled:
            problems.append(
                f"coverage: {name} = {stress[at, axis]:.3g} N/mm at E = ({strain[at, 0]:.3g}, "
                f"{strain[at, 1]:.3g}), {abs(stress[at, axis]) / sampled:.2g} x the largest "
                "sample: the fit has no data there (more rays)"
            )
    return problems
