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
  COVERAGE_FACTOR anywhere on the domain (it would be extrapolating a wiggle, not data),
  except beyond the end of a ray that stopped early (`beyond_stopped_rays`): there the cell
  has no state to sample (e.g. a knit jammed at the penetration limit in biaxial tension),
  more rays cannot help, and the surface's parameters name those runs (`incomplete_runs`).

`generate_surface` stores the problems in the surface's parameters (`checks`) and logs each
as a warning; `rve-rod surface` and `rve-rod surface-info` print them.
"""

import numpy as np

from rve_rod.surface import ResponseSurface, softest_normal_tangents

__all__ = [
    "COVERAGE_FACTOR",
    "SIGN_TOLERANCE",
    "SOFTENING_TOLERANCE",
    "beyond_stopped_rays",
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
        reached = ~beyond_stopped_rays(strain[:, :2], samples.inputs, domain[:2])
        at = int(np.flatnonzero(reached)[np.argmax(np.abs(stress[reached, axis]))])
        if abs(stress[at, axis]) > COVERAGE_FACTOR * sampled:
            problems.append(
                f"coverage: {name} = {stress[at, axis]:.3g} N/mm at E = ({strain[at, 0]:.3g}, "
                f"{strain[at, 1]:.3g}), {abs(stress[at, axis]) / sampled:.2g} x the largest "
                "sample: the fit has no data there (more rays)"
            )
    return problems


def beyond_stopped_rays(strain: np.ndarray, sampled: np.ndarray, box: np.ndarray) -> np.ndarray:
    """Which points `strain` (n, 2) of Green-Lagrange (E11, E22) lie beyond the end of a ray
    that stopped early: the ray nearest in direction (engineering strain about the origin) to
    the point ends inside the `box` ((2, 2) [min, max] of E11, E22) and the point is farther
    out. The rays are the directions of the `sampled` states (m, 2); shape (n,) of bool."""

    def polar(E):
        e = np.sqrt(1.0 + 2.0 * np.asarray(E, dtype=float)) - 1.0
        return np.arctan2(e[:, 1], e[:, 0]), np.hypot(e[:, 0], e[:, 1])

    angles, radii = polar(sampled)
    keep = radii > 1e-12
    rays, index = np.unique(np.round(angles[keep], 6), return_inverse=True)
    reach = np.zeros(rays.size)
    np.maximum.at(reach, index, radii[keep])
    limits = np.sqrt(1.0 + 2.0 * np.asarray(box, dtype=float)) - 1.0  # engineering box
    direction = np.stack([np.cos(rays), np.sin(rays)], axis=1)
    with np.errstate(divide="ignore"):
        ends = np.where(direction > 0, limits[:, 1] / direction, limits[:, 0] / direction)
    full = np.min(np.where(direction != 0, ends, np.inf), axis=1)
    stopped = reach < (1.0 - 1e-6) * full
    point_angles, point_radii = polar(strain)
    gap = np.abs((point_angles[:, None] - rays[None, :] + np.pi) % (2 * np.pi) - np.pi)
    nearest = np.argmin(gap, axis=1)
    return stopped[nearest] & (point_radii > reach[nearest] * (1.0 + 1e-9))
