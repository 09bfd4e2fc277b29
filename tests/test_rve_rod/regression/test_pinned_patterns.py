"""Regression pins of the stitch patterns (tests/pins.py, PATTERNS): the templates' depths and
yarn per loop at cotton 20s/2 stitch 5.5's w and c, the relaxed jersey cell of stitch 4.5's loop
length, the rib's course-wise and the garter's wale-wise RVE at the balanced resolution
(36 control points, 0-20 % in 5 states, friction; `fabric_settings`), and the jersey's bending
moments per width along its uniaxial runs at the same settings (PATTERN_MOMENTS)."""

import dataclasses

from pins import assert_pinned

from rve_rod.geometry.pattern_cell import pattern_geometry
from rve_rod.geometry.relaxed import cached_relaxed_knit
from rve_rod.presets import load_preset
from rve_rod.rve.engine import fabric_settings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import simulate

COTTON = load_preset("cotton-20s2", 5.5)


def test_pattern_templates_and_the_relaxed_jersey_are_pinned(tmp_path):
    knit, r0 = COTTON.knit, COTTON.yarn.minimal_radius
    measured = {}
    for pattern in ("rib1x1", "garter", "seed"):
        cell = pattern_geometry(pattern, knit.wale_width, knit.course_height, r0)
        measured[f"{pattern} depth / r"] = cell.depth / cell.yarn_radius
        measured[f"{pattern} yarn per loop"] = cell.loop_length
    relaxed = cached_relaxed_knit("jersey", 4.5, r0, tmp_path)
    measured["relaxed jersey 4.5 w"] = relaxed.wale_width
    measured["relaxed jersey 4.5 c"] = relaxed.course_height
    assert_pinned("PATTERNS", measured)


def test_rib_and_garter_runs_are_pinned():
    measured = {}
    for pattern, name, label in (
        ("rib1x1", "uniaxial-course", "rib1x1 course"),
        ("garter", "uniaxial-wale", "garter wale"),
    ):
        fabric = dataclasses.replace(COTTON, knit=dataclasses.replace(COTTON.knit, pattern=pattern))
        result = simulate(fabric, load_case(name, 0.2, 5), fabric_settings(fabric, 36))
        assert result.complete
        force = result.series("force_gf_per_cm")
        measured[f"{label} force 10 %"] = force[2]
        measured[f"{label} force 20 %"] = force[4]
        measured[f"{label} Poisson ratio 20 %"] = result.poisson_ratio
    assert_pinned("PATTERN_RUNS", measured)


def test_jersey_bending_moments_are_pinned():
    measured = {}
    for name, label in (("uniaxial-course", "course"), ("uniaxial-wale", "wale")):
        settings = fabric_settings(COTTON, 36)
        result = simulate(COTTON, load_case(name, 0.2, 5), settings, moments=True)
        assert result.complete
        moments = result.series("bending_moment_gf_cm_per_cm")
        for step, percent in ((2, 10), (4, 20)):
            measured[f"jersey {label} M11 {percent} %"] = moments[step][0]
            measured[f"jersey {label} M22 {percent} %"] = moments[step][1]
    assert_pinned("PATTERN_MOMENTS", measured)


def test_jerseys_curl_at_rest_is_pinned():
    """The moment at rest of the jersey cell whose yarn keeps half its bending set (36 control
    points; docs/patterns.md, "Curl at rest")."""
    settings = fabric_settings(COTTON, 36)
    yarn = dataclasses.replace(settings.yarn, natural_curvature=0.5)
    result = simulate(
        COTTON,
        load_case("uniaxial-course", 0.05, 2),
        dataclasses.replace(settings, yarn=yarn),
        moments=True,
    )
    m11, m22 = result.steps[0].bending_moment_gf_cm_per_cm
    assert_pinned("PATTERN_MOMENTS", {"jersey rest M11 s 0.5": m11, "jersey rest M22 s 0.5": m22})
