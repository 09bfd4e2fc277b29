"""Graded knits: a material whose stitch value varies over the fabric, from a family of laws.

A family holds the laws of one knit at a few stitch values s_0 < s_1 < ... < s_n (response
surfaces computed at those values). At a stitch value s the graded law is the piecewise-linear
interpolation in s of the members' stresses,

    S(E; s) = sum_k N_k(s) S_k(E),

with N_k the hat functions on the members' stitch values (N_k(s_k) = 1, linear between
neighbours, so exactly two members act between s_k and s_(k+1) and one at a member value;
constant beyond the ends). The weights depend on s only, which is a cell value (DG0), so the
tangent dS/dE = sum_k N_k(s) dS_k/dE is the interpolated tangent and `ufl.diff` in
`membrane.forms.membrane_forms` derives it consistently. A constant stitch at a member value gives
that member's law exactly (the other weights are 0).
"""

from collections.abc import Sequence

import numpy as np
import ufl

from fabric_dolfinx.material import Material
from rve_rod.errors import InputError

__all__ = [
    "graded_material",
    "hat_weights",
]


def hat_weights(stitch_values: Sequence[float], stitch) -> list:
    """UFL weights N_k(stitch) of the piecewise-linear interpolation on `stitch_values`
    (increasing); `stitch` is a UFL expression (a DG0 function) or a number."""
    values = [float(s) for s in stitch_values]
    if len(values) < 1 or np.any(np.diff(values) <= 0.0):
        raise InputError(f"stitch values {values} must be increasing")
    weights = []
    for k, value in enumerate(values):
        if len(values) == 1:
            weights.append(ufl.as_ufl(1.0))
            continue
        rising = (
            ufl.as_ufl(1.0)
            if k == 0
            else ufl.max_value((stitch - values[k - 1]) / (value - values[k - 1]), 0.0)
        )
        falling = (
            ufl.as_ufl(1.0)
            if k == len(values) - 1
            else ufl.max_value((values[k + 1] - stitch) / (values[k + 1] - value), 0.0)
        )
        weights.append(ufl.conditional(ufl.lt(stitch, value), rising, falling))
    return weights


def graded_material(members: Sequence[tuple[float, Material]], stitch) -> Material:
    """The law interpolated in the stitch value between `members` ((stitch value, Material),
    increasing stitch); `stitch` a UFL scalar (e.g. the DG0 stitch field of the region).

    Its domain is where every member's law rests on data (the intersection of the domains;
    None if no member has one)."""
    members = sorted(members, key=lambda member: member[0])
    stitch_values = [value for value, _ in members]
    weights = hat_weights(stitch_values, stitch)
    laws = [material.law for _, material in members]

    def law(E):
        terms = [w * member(E) for w, member in zip(weights, laws, strict=True)]
        return sum(terms[1:], terms[0])

    domains = [material.domain for _, material in members if material.domain is not None]
    domain = None
    if domains:
        stacked = np.stack(domains)
        domain = np.column_stack([stacked[:, :, 0].max(axis=0), stacked[:, :, 1].min(axis=0)])
    names = ", ".join(f"{value:g}" for value in stitch_values)
    return Material(law, domain, f"graded over stitch values {names}")
