"""Scene files: the default scene reads, and bad scenes are refused with one line per problem."""

from pathlib import Path

import pytest

from knitmech.fidelity import LEVELS
from knitmech.scene import SceneError, default_scene_path, load_scene, scene_from_dict
from knitmech.stages import plan_run
from rve_rod.errors import InputError
from rve_rod.presets import load_preset
from rve_rod.rve.engine import SEVERAL_COURSES_CONTROL_POINTS

COTTON = {"fabric": {"preset": "cotton-20s2", "stitch": 5.5}}


def test_default_scene_is_the_cotton_patch():
    scene = load_scene()
    assert scene.fabric.preset == "cotton-20s2"
    assert scene.fabric.stitch == 5.5
    assert scene.macro.size == 50.0
    assert scene.macro.directions == ("course", "wale")
    assert scene.fidelity == "balanced"


def test_round_trip_through_plain_data():
    scene = load_scene()
    assert scene_from_dict(scene.to_dict()) == scene


def test_every_problem_is_reported_once_naming_its_key(tmp_path):
    bad = {
        "colour": "red",
        "fidelity": "ultra",
        "fabric": {"preset": "cotton-20s2", "stitch": 5.25, "friction": "high"},
        "meso": {"cases": ["uniaxial-course", "twist"], "steps": 1},
        "surface": {"kind": "magic", "path": "missing.h5"},
        "macro": {"size": -5, "elements": 2.5, "directions": ["diagonal"], "speed": 3},
    }
    with pytest.raises(SceneError) as caught:
        scene_from_dict(bad, base=tmp_path)
    problems = caught.value.problems
    expected_keys = [
        "colour",
        "fidelity",
        "fabric.friction",
        "fabric.stitch",
        "meso.cases",
        "meso.steps",
        "surface.kind",
        "surface.path",
        "macro.speed",
        "macro.elements",
        "macro.directions",
        "macro.size",
    ]
    assert len(problems) == len(expected_keys)
    for key in expected_keys:
        assert sum(problem.startswith(f"{key}:") for problem in problems) == 1, key


def test_explicit_fabric_needs_its_four_values():
    with pytest.raises(SceneError) as caught:
        scene_from_dict({"fabric": {"wale_width": 1.3}})
    keys = sorted(p.split(":")[0] for p in caught.value.problems)
    assert keys == ["fabric.course_height", "fabric.yarn_radius", "fabric.youngs_modulus"]


def test_unreadable_and_invalid_toml_files(tmp_path):
    with pytest.raises(Exception, match="cannot be read"):
        load_scene(tmp_path / "absent.toml")
    broken = tmp_path / "broken.toml"
    broken.write_text("name = \n")
    with pytest.raises(Exception, match="not valid TOML"):
        load_scene(broken)


def test_toml_text_reads_back_to_the_same_scene(tmp_path):
    scene = load_scene().resolved(LEVELS["fast"])
    path = tmp_path / "scene.toml"
    path.write_text(scene.to_toml())
    assert load_scene(path) == scene


def test_fidelity_fills_only_what_the_scene_leaves_out():
    scene = scene_from_dict(
        {"fabric": {"preset": "cotton-20s2", "stitch": 5.5}, "meso": {"steps": 7}}
    )
    level = LEVELS["accurate"]
    resolved = scene.resolved(level)
    assert resolved.meso.steps == 7
    assert resolved.meso.control_points == level.control_points
    assert resolved.surface.rays == level.rays
    assert (resolved.macro.elements, resolved.macro.steps) == (level.elements, level.macro_steps)
    assert resolved.fidelity == "accurate"


def test_explicit_fabric_values_override_the_preset():
    scene = scene_from_dict(
        {"fabric": {"preset": "cotton-20s2", "stitch": 5.5, "yarn_radius": 0.15, "friction": 0.0}}
    )
    fabric = scene.fabric_model()
    preset = load_preset("cotton-20s2", 5.5)
    assert fabric.yarn.minimal_radius == 0.15
    assert fabric.yarn.friction_coefficient == 0.0
    assert fabric.knit == preset.knit
    assert fabric.yarn.youngs_modulus == preset.yarn.youngs_modulus


def test_compression_limit_may_be_zero_but_not_negative():
    assert (
        scene_from_dict({"surface": {"max_compression": 0}, **COTTON}).surface.max_compression == 0
    )
    with pytest.raises(SceneError, match=r"surface.max_compression: -0.1 is outside"):
        scene_from_dict({"surface": {"max_compression": -0.1}, **COTTON})


def test_a_preset_of_the_wrong_type_is_one_problem():
    with pytest.raises(SceneError) as caught:
        scene_from_dict({"fabric": {"preset": 5, "stitch": 5.5}})
    assert caught.value.problems == ["fabric.preset: expected str, got int 5"]


def test_the_default_bends_with_the_fibres_where_known_and_the_example_with_the_section():
    path = Path(__file__).resolve().parents[3] / "examples" / "models" / "section_bending.toml"
    scene = load_scene(path)
    assert plan_run(scene, LEVELS[scene.fidelity]).rve.yarn.bending == "section"
    plan = plan_run(load_scene(), LEVELS["balanced"])
    assert plan.rve.yarn.bending == "free-fibres"
    # the fibre data come with the preset; a yarn given by values has none: "auto" falls back
    # to the section, "free-fibres" is refused
    assert plan.fabric.yarn.fibres.name == "cotton"
    explicit = {
        "fabric": {
            "wale_width": 1.33,
            "course_height": 1.26,
            "yarn_radius": 0.19,
            "youngs_modulus": 80.0,
        }
    }
    assert plan_run(scene_from_dict(explicit), LEVELS["fast"]).rve.yarn.bending == "section"
    explicit["fabric"]["bending"] = "free-fibres"
    with pytest.raises(InputError, match="needs the yarn's fibres"):
        plan_run(scene_from_dict(explicit), LEVELS["fast"])


@pytest.mark.parametrize("encoding", ["utf-8-sig", "utf-16"])
def test_a_scene_saved_with_a_byte_order_mark_reads_as_plain_utf8(tmp_path, encoding):
    """Editors put a byte-order mark before UTF-8 (and Windows' "Unicode" is UTF-16): such a
    scene gave "Invalid statement (at line 1, column 1)" or a UnicodeDecodeError traceback."""
    text = default_scene_path().read_text(encoding="utf-8") + '# "ü" in a comment\n'
    path = tmp_path / "scene.toml"
    path.write_bytes(text.encode(encoding))
    assert load_scene(path) == load_scene(default_scene_path())


def test_a_cell_of_several_courses_runs_finer_than_the_fast_level_and_the_run_says_so(caplog):
    """Garter at the fast level: its RVE runs at SEVERAL_COURSES_CONTROL_POINTS, not 28, and
    the plan logs it where knitmech's progress goes."""
    scene = scene_from_dict(
        {"fabric": {"preset": "cotton-20s2", "stitch": 5.5, "pattern": "garter"}}
    )
    with caplog.at_level("INFO", logger="knitmech.stages"):
        plan = plan_run(scene, LEVELS["fast"])
    assert LEVELS["fast"].control_points == 28
    assert plan.rve.cell.control_points == SEVERAL_COURSES_CONTROL_POINTS
    assert "runs at 36 control points per quarter, not the 28 of the scene (fidelity fast)" in (
        caplog.text
    )
    jersey = scene_from_dict({"fabric": {"preset": "cotton-20s2", "stitch": 5.5}})
    assert plan_run(jersey, LEVELS["fast"]).rve.cell.control_points == 28
