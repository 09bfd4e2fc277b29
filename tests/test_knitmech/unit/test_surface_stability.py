"""The softest normal stiffness of a surface over its domain, and the warning when it is < 0."""

import logging

import numpy as np
import pytest

from knitmech.stages import surface_summary
from rve_rod.surface import ResponseSurface, Spline1D, Spline2D, softest_normal_tangents

DOMAIN = (-0.1, 0.3)


def quadratic_in(axis, value, slope, curvature):
    """Spline2D of f = value + slope t + curvature t^2 / 2 in input `axis` (t = E11 or E22),
    constant in the other: one Bezier span of degree 2 times degree 1."""
    low, high = DOMAIN
    f = lambda t: value + slope * t + curvature * t**2 / 2  # noqa: E731
    df = slope + curvature * low
    bezier = np.array([f(low), f(low) + df * (high - low) / 2, f(high)])
    coefficients = np.repeat(bezier[:, None], 2, axis=1)
    if axis == 1:
        coefficients = coefficients.T
    knots = {2: np.array([low] * 3 + [high] * 3), 1: np.array([low] * 2 + [high] * 2)}
    degrees = (2, 1) if axis == 0 else (1, 2)
    return Spline2D(degrees, tuple(knots[p] for p in degrees), coefficients, (1, 1))


def surface(curvature_22):
    shear = Spline1D(1, np.array([-0.2, -0.2, 0.2, 0.2]), np.array([-0.02, 0.02]), 1)
    return ResponseSurface(
        kind="stress",
        s11=quadratic_in(0, 0.0, 0.5, 4.0),  # dS11/dE11 = 0.5 + 4 E11: softest at E11 = -0.1
        s22=quadratic_in(1, 0.0, 0.2, curvature_22),  # dS22/dE22 = 0.2 + k E22
        s12=shear,
    )


def test_softest_stiffness_and_where(caplog):
    softest = softest_normal_tangents(surface(curvature_22=1.0))
    assert softest["dS11/dE11"]["value"] == pytest.approx(0.5 - 0.4, abs=1e-12)
    assert softest["dS11/dE11"]["strain"][0] == pytest.approx(-0.1)
    assert softest["dS22/dE22"]["value"] == pytest.approx(0.2 - 0.1, abs=1e-12)
    assert softest["dS22/dE22"]["strain"][1] == pytest.approx(-0.1)
    with caplog.at_level(logging.WARNING):
        surface_summary(surface(curvature_22=1.0))
    assert not caplog.records


def test_softening_surface_is_reported_and_warned(caplog):
    with caplog.at_level(logging.WARNING):
        summary = surface_summary(surface(curvature_22=-4.0))
    entry = summary.softest_tangents["dS22/dE22"]
    assert entry["value"] == pytest.approx(0.2 - 4.0 * 0.3, abs=1e-12)  # at E22 = 0.3
    assert entry["strain"][1] == pytest.approx(0.3)
    assert len(caplog.records) == 1 and "dS22/dE22 = -1 N/mm" in caplog.records[0].message


def test_round_off_below_zero_is_not_warned(caplog):
    # dS22/dE22 = 0.2 + k E22 with k = 2 + 1e-12: -1e-13 N/mm at E22 = -0.1, 0.8 at 0.3
    with caplog.at_level(logging.WARNING):
        summary = surface_summary(surface(curvature_22=2.0 + 1e-12))
    entry = summary.softest_tangents["dS22/dE22"]
    assert entry["value"] == pytest.approx(-1e-13, abs=1e-15)
    assert entry["largest"] == pytest.approx(0.8, abs=1e-12)
    assert not caplog.records
