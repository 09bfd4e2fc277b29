"""The relaxed cell: the bending energy of known curves, the relaxed ratios are constants of
the pattern where the template scales with w, the relaxed cell is the scan's least energy,
the rules that settle a fabric's w and c, and the cache."""

import dataclasses
import math

import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.geometry.bspline import interpolate
from rve_rod.geometry.relaxed import (
    bending_energy,
    cached_relaxed_knit,
    relaxed_knit,
    settled_fabric,
)
from rve_rod.presets import load_preset, make_fabric


def test_bending_energy_of_a_circle_and_of_a_line():
    radius = 0.7
    t = np.linspace(0.0, 2 * math.pi, 121)
    circle = interpolate(np.column_stack([radius * np.cos(t), radius * np.sin(t), 0 * t]), 4)
    assert bending_energy([circle]) == pytest.approx(math.pi / radius, rel=1e-4)
    line = interpolate(np.column_stack([t, 2 * t, -t]), 4)
    assert bending_energy([line]) == pytest.approx(0.0, abs=1e-10)


@pytest.fixture(scope="module")
def tight():
    """Jersey of cotton 20s/2 at two loop lengths where the relaxed w is below 8 r0 (r =
    w/8: the template scales with w)."""
    return [relaxed_knit("jersey", length, 0.19) for length in (4.5, 4.95)]


def test_where_the_template_scales_the_relaxed_ratios_are_constants(tight):
    first, second = tight
    assert first.wale_width < 8 * 0.19 and second.wale_width < 8 * 0.19
    np.testing.assert_allclose(first.ratios, second.ratios, rtol=1e-6)
    assert first.yarn_radius == pytest.approx(first.wale_width / 8, rel=1e-12)
    assert first.energy * first.loop_length == pytest.approx(
        second.energy * second.loop_length, rel=1e-6
    )


def test_the_relaxed_cell_has_the_least_energy_of_the_scan(tight):
    knit = tight[0]
    ratios = np.array([q for q, _ in knit.scan])
    energies = np.array([e for _, e in knit.scan])
    best = ratios[np.argmin(energies)]
    relaxed_ratio = knit.course_height / knit.wale_width
    assert abs(relaxed_ratio - best) <= 0.1 + 1e-9
    assert knit.energy * knit.loop_length <= energies.min() * (1 + 1e-3)
    assert knit.loop_length == 4.5


def test_a_presets_jersey_keeps_its_measured_w_and_c_and_another_pattern_is_relaxed(
    tmp_path, monkeypatch
):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    jersey = load_preset("cotton-20s2", 4.5)
    assert settled_fabric(jersey) == jersey
    rib = make_fabric("cotton-20s2", 4.5, pattern="rib1x1")
    assert rib.knit.wale_width == jersey.knit.wale_width  # a preset's jersey values ...
    relaxed = settled_fabric(rib)  # ... replaced by the relaxed cell's
    expected = relaxed_knit("rib1x1", 4.5, 0.19)
    assert (relaxed.knit.wale_width, relaxed.knit.course_height) == (
        expected.wale_width,
        expected.course_height,
    )
    assert relaxed.knit.pattern == ("KP",)
    given = make_fabric("cotton-20s2", 4.5, pattern="rib1x1", wale_width=1.1, course_height=0.9)
    assert settled_fabric(given, measured=True) == given
    relaxed_jersey = settled_fabric(jersey, relaxed=True)
    assert relaxed_jersey.knit.wale_width == pytest.approx(tight_ratio_width(4.5), rel=1e-9)


def tight_ratio_width(length):
    return relaxed_knit("jersey", length, 0.19).wale_width


def test_relaxing_needs_a_loop_length_and_no_measured_w_and_c():
    rib = make_fabric(
        None,
        wale_width=1.3,
        course_height=1.2,
        yarn_radius=0.19,
        youngs_modulus=80.0,
        pattern="rib1x1",
    )
    with pytest.raises(InputError, match="needs wale_width and course_height, or a preset"):
        settled_fabric(rib)
    with pytest.raises(InputError, match="not both"):
        settled_fabric(rib, relaxed=True, measured=True)
    with pytest.raises(InputError, match="loop_length=-1"):
        relaxed_knit("jersey", -1.0, 0.19)
    with pytest.raises(InputError, match="tuck"):
        relaxed_knit(["KT", "KK"], 4.5, 0.19)


def test_relaxed_cells_are_remembered_on_disk(tmp_path):
    first = cached_relaxed_knit("jersey", 4.5, 0.19, tmp_path)
    assert len(list(tmp_path.rglob("*.npz"))) == 1
    again = cached_relaxed_knit("jersey", 4.5, 0.19, tmp_path)
    assert dataclasses.asdict(again) == dataclasses.asdict(first)
