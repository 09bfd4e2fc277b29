"""Graded knits: a material whose stitch value varies over the fabric, from a family of laws.

A family holds the laws of one knit at a few stitch values s_0 < s_1 < ... < s_n (response
surfaces computed at those values). At a stitch value s the graded law is the piecewise-linear
interpolation in s of the members' stresses,

    S(E; s) = sum_k N_k(s) S_k(E),

with N_k the hat functions on the members' stitch values (N_k(s_k) = 1, linear between
neighbours, so exactly two members act between s_k and s_(k+1) and one at a member value;
constant beyond the ends). The weights depend on s only, which is a cell value (DG0), so the
tangent is the interpolated tangent dS/dE = sum_k N_k(s) dS_k/dE. A constant stitch at a
member value gives that member's law exactly (the other weights are 0). Evaluated with NumPy
at the quadrature points (`fabric_dolfinx.membrane.quadrature`) and by the design's cheap
models (`knitmech.design.family`), one formula for both.
"""

from collections.abc import Callable, Sequence

import numpy as np

from fabric_dolfinx.material import Material
from rve_rod.errors import InputError
from rve_rod.surface import StressResult

__all__ = [
    "graded_material",
    "graded_stress",
    "stitch_weights",
]


def stitch_weights(stitch_values: Sequence[float], stitch) -> np.ndarray:
    """Weights N_k(stitch) of the piecewise-linear interpolation on `stitch_values`
    (increasing, mm): N_k(s_k) = 1, linear between neighbours, constant beyond the ends.
    `stitch` a number (weights (n,)) or an array (m,) (weights (n, m))."""
    values = np.asarray(stitch_values, dtype=float)
    if values.size < 1 or np.any(np.diff(values) <= 0.0):
        raise InputError(f"stitch values {values.tolist()} must be increasing")
    stitch = np.asarray(stitch, dtype=float)
    if values.size == 1:
        return np.ones((1, *stitch.shape))
    return np.stack([np.interp(stitch, values, row) for row in np.eye(values.size)])


def graded_stress(
    laws: Sequence[Callable[[np.ndarray], StressResult]], weights: np.ndarray, E: np.ndarray
) -> StressResult:
    """sum_k weights[k] law_k(E) at strains E (m, 3): S (m, 3), dS/dE (m, 3, 3), and
    `outside` (m,) where a member that acts there (weight not 0) is outside its domain.
    `weights` (n,) (one stitch value) or (n, m) (one per point); members whose weights are
    all 0 are not evaluated."""
    E = np.asarray(E, dtype=float).reshape(-1, 3)
    weights = np.broadcast_to(np.asarray(weights, dtype=float).T, (E.shape[0], len(laws))).T
    S, tangent = np.zeros((E.shape[0], 3)), np.zeros((E.shape[0], 3, 3))
    outside = np.zeros(E.shape[0], dtype=bool)
    for law, weight in zip(laws, weights, strict=True):
        if not np.any(weight):
            continue
        result = law(E)
        S += weight[:, None] * result.S
        tangent += weight[:, None, None] * result.tangent
        outside |= result.outside & (weight != 0.0)
    return StressResult(S=S, tangent=tangent, outside=outside)


def graded_material(members: Sequence[tuple[float, Material]]) -> Material:
    """The law interpolated in the stitch value between `members` ((stitch value, Material),
    increasing stitch): its law reads the stitch value of every point.

    Its domain is where every member's law rests on data (the intersection of the domains;
    None if no member has one)."""
    members = sorted(members, key=lambda member: member[0])
    stitch_values = [value for value, _ in members]
    stitch_weights(stitch_values, 0.0)  # checks that they increase

    def law(E: np.ndarray, stitch: np.ndarray) -> StressResult:
        laws = [lambda E, m=material: m.law(E, stitch) for _, material in members]
        return graded_stress(laws, stitch_weights(stitch_values, stitch), E)

    domains = [material.domain for _, material in members if material.domain is not None]
    domain = None
    if domains:
        stacked = np.stack(domains)
        domain = np.column_stack([stacked[:, :, 0].max(axis=0), stacked[:, :, 1].min(axis=0)])
    names = ", ".join(f"{value:g}" for value in stitch_values)
    return Material(law, domain, f"graded over stitch values {names}")
