"""Scene files: the default scene reads, and bad scenes are refused with one line per problem."""

import pytest

from knitmech.scene import SceneError, load_scene, scene_from_dict


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
