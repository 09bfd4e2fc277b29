"""Checks of a response surface as a material: symmetry and sign of its tangent, and its
homogeneous tension response.

Plain NumPy/SciPy on `ResponseSurface.stress` (no finite elements, no dolfinx), so the surface
stage of the pipeline, the fit and the macro scale use the same checks.
"""

import numpy as np

from rve_rod.errors import InputError, check_integer
from rve_rod.surface.response import ResponseSurface

__all__ = [
    "homogeneous_response",
    "softest_normal_tangents",
    "tangent_asymmetry",
]

LOAD_AXES = {"course": 0, "wale": 1}
"""Load direction -> the strain component (E11 or E22) it stretches."""


def normal_grid(surface: ResponseSurface, points_per_axis: int = 41) -> np.ndarray:
    """Strains (m, 3) on a points_per_axis^2 grid over the (E11, E22) domain, E12 = 0."""
    check_integer("points_per_axis", points_per_axis, 2)
    (x_low, x_high), (y_low, y_high) = surface.domain[:2]
    x, y = np.meshgrid(
        np.linspace(x_low, x_high, points_per_axis), np.linspace(y_low, y_high, points_per_axis)
    )
    return np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)


def tangent_asymmetry(surface: ResponseSurface, points_per_axis: int = 41) -> float:
    """max |dS11/dE22 - dS22/dE11| / max ||dS/dE (normal block)||_F on a grid over the domain.

    Zero (to round-off) for energy surfaces; for stress fits it measures how far the
    material is from hyperelastic.
    """
    tangent = surface.stress(normal_grid(surface, points_per_axis)).tangent[:, :2, :2]
    norm = float(np.sqrt((tangent**2).sum(axis=(1, 2))).max())
    if norm == 0.0:
        return 0.0
    return float(np.abs(tangent[:, 0, 1] - tangent[:, 1, 0]).max()) / norm


def softest_normal_tangents(surface: ResponseSurface, points_per_axis: int = 41) -> dict:
    """The smallest dS11/dE11 and dS22/dE22 (N/mm) on a grid over the (E11, E22) domain,
    the strain (E11, E22) where each occurs and the largest of each (`largest`): a negative
    value means the fitted material softens there, where a membrane has no unique
    equilibrium."""
    strain = normal_grid(surface, points_per_axis)
    tangent = surface.stress(strain).tangent
    softest = {}
    for index, name in enumerate(("dS11/dE11", "dS22/dE22")):
        values = tangent[:, index, index]
        at = int(np.argmin(values))
        softest[name] = {
            "value": values[at],
            "strain": strain[at, :2],
            "largest": float(values.max()),
        }
    return softest


def homogeneous_response(
    surface: ResponseSurface, strain: np.ndarray, direction: str, lateral: str = "free"
) -> np.ndarray:
    """Force per width (N/mm) of the material alone under homogeneous tension.

    F = 1 + strain along the load; across it the stretch is free with zero stress
    ("free": uniaxial tension, as the RVE's uniaxial load case) or held at 1 ("fixed":
    strip-biaxial). The clamped patch lies between the two. Returns P = F S along the load
    for each strain (numpy evaluation of the surface, every strain at once; no finite
    elements). `surface` is anything with `stress(E)` returning S and the tangent.
    """
    if direction not in LOAD_AXES:
        raise InputError(f"direction={direction!r} is not one of {', '.join(LOAD_AXES)}")
    if lateral not in ("free", "fixed"):
        raise InputError(f"lateral={lateral!r} must be 'free' or 'fixed'")
    axis = LOAD_AXES[direction]
    other = 1 - axis
    strain = np.atleast_1d(np.asarray(strain, dtype=float))
    E_load = ((1.0 + strain) ** 2 - 1.0) / 2.0

    def stress(E_lateral: np.ndarray):
        E = np.zeros((E_lateral.size, 3))
        E[:, axis] = np.resize(E_load, E_lateral.size)
        E[:, other] = E_lateral
        return surface.stress(E)

    def lateral_stress(E_lateral: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        evaluated = stress(E_lateral)
        return evaluated.S[:, other], evaluated.tangent[:, other, other]

    lateral_strain = np.zeros_like(strain)
    if lateral == "free":
        lateral_strain = _free_lateral_strains(lateral_stress, strain)
    return (1.0 + strain) * stress(lateral_strain).S[:, axis]


_LATERAL_LIMIT = 0.5
"""Largest |E| searched for the free lateral strain."""
_LATERAL_SCAN = 0.01
"""Step of the scan outward from E = 0 for a sign change of the lateral stress."""


def _free_lateral_strains(lateral_stress, strain: np.ndarray) -> np.ndarray:
    """(m,) for each strain the lateral Green-Lagrange strain nearest to 0 at which the
    lateral stress vanishes.

    `lateral_stress(E (k,))` returns the lateral stress and its derivative (k,) at the
    lateral strains E, the k = j m points being j rounds of the m strains. Scans outward from
    0 on both sides (the negative side first at each step) for the first sign change, then
    solves in that bracket by Newton's method, bisecting where a Newton step would leave it:
    a fitted surface may turn over far outside its data (its linear extension), so a root
    there must not be taken for the physical one nearer to the reference state.
    """
    m = strain.size
    steps = round(_LATERAL_LIMIT / _LATERAL_SCAN)
    offsets = _LATERAL_SCAN * np.arange(-steps, steps + 1)
    values = lateral_stress(np.repeat(offsets, m))[0].reshape(offsets.size, m)
    signs = np.sign(values)
    low, high = np.zeros(m), np.zeros(m)
    found = signs[steps] == 0.0  # the lateral stress vanishes at E = 0
    for step in range(1, steps + 1):
        for end, start in ((steps - step, steps - step + 1), (steps + step, steps + step - 1)):
            change = ~found & (signs[end] != signs[start])
            low[change] = np.minimum(offsets[end], offsets[start])
            high[change] = np.maximum(offsets[end], offsets[start])
            on_grid = change & (signs[end] == 0.0)  # the root itself: no bracket to search
            low[on_grid] = high[on_grid] = offsets[end]
            found |= change
    if not found.all():
        missing = float(strain[np.flatnonzero(~found)[0]])
        raise InputError(
            f"at strain {missing:.4g} no lateral strain in [-{_LATERAL_LIMIT}, "
            f"{_LATERAL_LIMIT}] makes the lateral stress vanish"
        )
    f_low = lateral_stress(low)[0]
    root = 0.5 * (low + high)
    done = low == high
    for _ in range(200):
        value, slope = lateral_stress(root)
        left = np.sign(value) == np.sign(f_low)
        low, f_low = np.where(left, root, low), np.where(left, value, f_low)
        high = np.where(left, high, root)
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = root - value / slope
        tolerance = 1e-15 + 4e-16 * np.abs(root)
        # converged when Newton's own step is below round-off, wherever it points: a root at
        # an end of the bracket is not then approached by bisection from the other end
        done |= (value == 0.0) | (np.abs(newton - root) <= tolerance)
        inside = np.isfinite(newton) & (newton >= low) & (newton <= high)
        step = np.where(inside, newton, 0.5 * (low + high)) - root
        done |= np.abs(step) <= tolerance
        if done.all():
            return root
        root = np.where(done, root, root + step)
    return root
