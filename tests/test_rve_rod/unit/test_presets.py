"""`make_fabric`: the one rule for a fabric from a preset and explicit values (the rve-rod
options and the scene's [fabric] table both use it)."""

from pathlib import Path

import pytest

from rve_rod.cache import default_cache_root, default_runs_dir
from rve_rod.errors import InputError
from rve_rod.presets import load_preset, make_fabric


def test_a_preset_alone_is_the_preset():
    assert make_fabric("cotton-20s2", 5.5) == load_preset("cotton-20s2", 5.5)


def test_explicit_values_override_only_themselves():
    preset = load_preset("cotton-20s2", 5.5)
    fabric = make_fabric("cotton-20s2", 5.5, wale_width=1.4, youngs_modulus=90.0, friction=0.2)
    assert (fabric.knit.wale_width, fabric.knit.course_height) == (1.4, preset.knit.course_height)
    assert fabric.yarn.youngs_modulus == 90.0 and fabric.yarn.friction_coefficient == 0.2
    assert fabric.yarn.minimal_radius == preset.yarn.minimal_radius
    assert fabric.knit.measured_loop_length == preset.knit.measured_loop_length
    assert fabric.name == "cotton-20s2"


def test_without_a_preset_every_value_is_given():
    fabric = make_fabric(
        None, wale_width=1.33, course_height=1.26, yarn_radius=0.19, youngs_modulus=80.0
    )
    assert (fabric.knit.wale_width, fabric.yarn.youngs_modulus, fabric.name) == (1.33, 80.0, "")
    assert fabric.yarn.poissons_ratio == 0.3  # the Yarn default
    geometry_only = make_fabric(
        None, wale_width=1.33, course_height=1.26, yarn_radius=0.19, need_material=False
    )
    assert geometry_only.yarn.minimal_radius == 0.19


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ({"wale_width": 1.3}, "give a preset, or all of course_height, yarn_radius, youngs"),
        ({"stitch": 5.5}, "stitch=5.5 needs a preset"),
        ({"preset": "wool"}, "preset='wool' is unknown"),
        ({"preset": "cotton-20s2", "stitch": 5.5, "yarn_radius": -0.1}, "yarn_radius=-0.1 mm"),
    ],
)
def test_bad_values_are_named(arguments, message):
    with pytest.raises(InputError, match=message):
        make_fabric(**{"preset": None, **arguments})


def test_cache_root_follows_xdg_cache_home(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert default_cache_root() == tmp_path / "knitmech"
    assert default_runs_dir() == tmp_path / "knitmech" / "rve-runs"
    monkeypatch.setenv("XDG_CACHE_HOME", "")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert default_cache_root() == Path(tmp_path / "home" / ".cache" / "knitmech")
