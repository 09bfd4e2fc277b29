"""The softest normal stiffness of a surface over its domain, and the warning when it is < 0."""

import logging

import pytest
from support.surface_cases import two_quadratics_surface

from knitmech.stages import surface_summary
from rve_rod.surface import softest_normal_tangents


def test_softest_stiffness_and_where(caplog):
    softest = softest_normal_tangents(two_quadratics_surface(curvature_22=1.0))
    assert softest["dS11/dE11"]["value"] == pytest.approx(0.5 - 0.4, abs=1e-12)
    assert softest["dS11/dE11"]["strain"][0] == pytest.approx(-0.1)
    assert softest["dS22/dE22"]["value"] == pytest.approx(0.2 - 0.1, abs=1e-12)
    assert softest["dS22/dE22"]["strain"][1] == pytest.approx(-0.1)
    with caplog.at_level(logging.WARNING):
        surface_summary(two_quadratics_surface(curvature_22=1.0))
    assert not caplog.records


def test_softening_surface_is_reported_and_warned(caplog):
    with caplog.at_level(logging.WARNING):
        summary = surface_summary(two_quadratics_surface(curvature_22=-4.0))
    entry = summary.softest_tangents["dS22/dE22"]
    assert entry["value"] == pytest.approx(0.2 - 4.0 * 0.3, abs=1e-12)  # at E22 = 0.3
    assert entry["strain"][1] == pytest.approx(0.3)
    assert len(caplog.records) == 1 and "dS22/dE22 = -1 N/mm" in caplog.records[0].message


def test_round_off_below_zero_is_not_warned(caplog):
    # dS22/dE22 = 0.2 + k E22 with k = 2 + 1e-12: -1e-13 N/mm at E22 = -0.1, 0.8 at 0.3
    with caplog.at_level(logging.WARNING):
        summary = surface_summary(two_quadratics_surface(curvature_22=2.0 + 1e-12))
    entry = summary.softest_tangents["dS22/dE22"]
    assert entry["value"] == pytest.approx(-1e-13, abs=1e-15)
    assert entry["largest"] == pytest.approx(0.8, abs=1e-12)
    assert not caplog.records
