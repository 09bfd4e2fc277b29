"""Checks of a response surface as a material: symmetry and sign of its tangent, and its
homogeneous tension response.

Plain NumPy/SciPy on `ResponseSurface.stress` (no finite elements, no dolfinx), so the surface
stage of the pipeline, the fit and the macro scale use the same checks.
"""

import numpy as np
import scipy.optimize

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
    for each strain (numpy evaluation of the surface, no finite elements).
    """
    if direction not in LOAD_AXES:
        raise InputError(f"direction={direction!r} is not one of {', '.join(LOAD_AXES)}")
    if lateral not in ("free", "fixed"):
        raise InputError(f"lateral={lateral!r} must be 'free' or 'fixed'")
    axis = LOAD_AXES[direction]
    other = 1 - axis
    forces = []
    for value in np.atleast_1d(np.asarray(strain, dtype=float)):
        E_load = ((1.0 + value) ** 2 - 1.0) / 2.0

        def stress(E_lateral, E_load=E_load):
            E = np.zeros(3)
            E[axis], E[other] = E_load, E_lateral
            return surface.stress(E).S[0]

        lateral_strain = 0.0
        if lateral == "free":
            lateral_strain = _free_lateral_strain(lambda e, stress=stress: stress(e)[other], value)
        forces.append((1.0 + value) * stress(lateral_strain)[axis])
    return np.array(forces)


_LATERAL_LIMIT = 0.5
"""Largest |E| searched for the free lateral strain."""
_LATERAL_SCAN = 0.01
"""Step of the scan outward from E = 0 for a sign change of the lateral stress."""


def _free_lateral_strain(lateral_stress, strain: float) -> float:
    """The lateral Green-Lagrange strain nearest to 0 at which `lateral_stress` vanishes.

    Scans outward from 0 on both sides for the first sign change, then solves with Brent's
    method: a fitted surface may turn over far outside its data (its linear extension), so
    a root there must not be taken for the physical one nearer to the reference state.
    """
    at_zero = lateral_stress(0.0)
    if at_zero == 0.0:
        return 0.0
    for step in range(1, round(_LATERAL_LIMIT / _LATERAL_SCAN) + 1):
        for sign in (-1.0, 1.0):
            end = sign * step * _LATERAL_SCAN
            start = end - sign * _LATERAL_SCAN
            if np.sign(lateral_stress(end)) != np.sign(lateral_stress(start)):
                return scipy.optimize.brentq(lateral_stress, *sorted((start, end)), xtol=1e-15)
    raise InputError(
        f"at strain {strain:.4g} no lateral strain in [-{_LATERAL_LIMIT}, {_LATERAL_LIMIT}] "
        "makes the lateral stress vanish"
    )
