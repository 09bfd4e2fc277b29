"""Scenes with a fabric part: reading, every problem at once naming its key, the TOML round
trip, which surfaces a part needs, and the command line's exit status 2 for bad input."""

import tomllib

import pytest

from knitmech.cli import main
from knitmech.fidelity import fidelity_level
from knitmech.scene import SceneError, scene_from_dict
from knitmech.stages import plan_run
from knitmech.stages.fabric import knit_surfaces

BASE = {
    "name": "part",
    "fidelity": "fast",
    "fabric": {
        "preset": "cotton-20s2",
        "stitch": 5.5,
        "shape": {"kind": "rectangle", "width": 50.0, "height": 200.0},
    },
    "meso": {"cases": []},
    "boundary": [
        {"name": "bottom", "kind": "clamp"},
        {"name": "top", "kind": "displacement", "displacement": [0.0, 20.0]},
    ],
}


def scene_with(**changes):
    data = {**BASE, **changes}
    return scene_from_dict(data)


def problems_of(data) -> list[str]:
    with pytest.raises(SceneError) as caught:
        scene_from_dict(data)
    return caught.value.problems


def test_a_part_scene_fills_the_element_size_from_the_fidelity_level_and_round_trips():
    scene = scene_with(
        region=[
            {"name": "fabric", "angle": "90 + 10 * sin(pi * y / 200)"},
            {"name": "band", "where": "abs(y - 100) < 20", "stitch": 7.0, "angle": 30.0},
            {"name": "svk", "where": "y > 190", "svk": {"course_stiffness": 2.0}},
        ],
        probe=[{"name": "centre", "x": 25.0, "y": 100.0}],
    )
    assert scene.part.mesh.element_size is None
    resolved = scene.resolved(fidelity_level("fast"))
    assert resolved.part.mesh.element_size == pytest.approx(50.0 / 6)
    assert scene_from_dict(tomllib.loads(resolved.to_toml())) == resolved
    assert resolved.part.probes == {"centre": (25.0, 100.0)}


def test_a_scene_without_a_part_is_unchanged():
    data = {key: value for key, value in BASE.items() if key != "boundary"}
    data["fabric"] = {"preset": "cotton-20s2", "stitch": 5.5}
    assert scene_from_dict(data).part is None
    problems = problems_of({**data, "boundary": BASE["boundary"]})
    assert problems == ["boundary: needs [fabric.shape] or [fabric.mesh]"]


def test_every_problem_is_reported_at_once_naming_its_key():
    data = {
        **BASE,
        "fabric": {
            "preset": "cotton-20s2",
            "stitch": 5.5,
            "shape": {"kind": "rectangle", "width": -50.0, "heigth": 200.0},
        },
        "region": [
            {"name": "core", "angle": "z + 1"},
            {"name": "fine", "where": "y > 100", "stitch": 9.0},
        ],
        "boundary": [
            {"name": "top", "kind": "pull"},
            {"name": "side", "kind": "traction", "traction": [1.0]},
            {"name": "left", "kind": "free"},
            {"name": "left", "kind": "clamp"},
        ],
    }
    problems = problems_of(data)
    keys = [problem.split(":")[0] for problem in problems]
    assert keys == [
        "fabric.shape.heigth",
        "fabric.shape.width",
        "region[0].angle",
        "region[1]",
        "boundary[0].kind",
        "boundary[1].traction",
        "boundary",
        "region[0].name",
    ]
    assert "stitch=9.0 mm is not measured; valid stitch values: 4.5" in problems[3]
    assert "conditions overlap, 'left' is given twice" in problems[6]
    assert "its regions: fabric" in problems[7]


def test_a_part_held_by_nothing_and_an_unknown_boundary_are_refused():
    loose = [{"name": "top", "kind": "traction", "traction": [0.0, 1.0]}]
    assert problems_of({**BASE, "boundary": loose}) == [
        "boundary: no clamp, displacement or roller: nothing holds the part in place"
    ]
    side = [{"name": "side", "kind": "clamp"}]
    (problem,) = problems_of({**BASE, "boundary": side})
    assert problem.startswith("boundary[0].name: rectangle has no boundary 'side'; its ")
    assert problem.endswith("boundaries: left, right, bottom, top")


def test_a_gmsh_file_names_are_checked_before_anything_runs(tmp_path):
    geometry = (
        "Point(1) = {0, 0, 0}; Point(2) = {10, 0, 0}; Point(3) = {10, 10, 0};\n"
        "Point(4) = {0, 10, 0}; Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4};\n"
        "Line(4) = {4, 1}; Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
        'Physical Curve("grip") = {4}; Physical Curve("pull") = {2};\n'
        'Physical Surface("panel") = {1};\n'
    )
    (tmp_path / "part.geo").write_text(geometry)  # gmsh meshes it with triangles
    data = {**BASE, "fabric": {"preset": "cotton-20s2", "stitch": 5.5}}
    data["fabric"]["mesh"] = {"file": "part.geo"}
    data["boundary"] = [{"name": "grip", "kind": "clamp"}, {"name": "top", "kind": "free"}]
    (problem,) = problems_of_with_base(data, tmp_path)
    assert problem.startswith("fabric.mesh.file: part.geo: the mesh has Triangle 3 elements")
    (tmp_path / "part.geo").write_text(geometry + "Recombine Surface{1};\n")
    with pytest.raises(SceneError) as caught:
        scene_from_dict(data, base=tmp_path)
    assert caught.value.problems == [
        "boundary[1].name: part.geo has no boundary 'top'; its boundaries: grip, pull"
    ]
    data["boundary"][1]["name"] = "pull"
    scene = scene_from_dict(data, base=tmp_path)
    assert [region.name for region in scene.part.regions] == ["panel"]
    data["fabric"]["mesh"] = {"file": "missing.msh"}
    (problem,) = problems_of_with_base(data, tmp_path)
    assert problem.startswith("fabric.mesh.file: no such file")


def problems_of_with_base(data, base):
    with pytest.raises(SceneError) as caught:
        scene_from_dict(data, base=base)
    return caught.value.problems


def test_only_the_surfaces_of_the_knits_that_occur_are_planned():
    scene = scene_with(
        region=[
            {"name": "fabric"},
            {"name": "loose", "where": "y > 150", "stitch": 7.0},
            {"name": "loose-again", "where": "y < 20", "stitch": 7.0},
            {"name": "svk", "where": "y > 190", "svk": {"course_stiffness": 2.0}},
        ]
    )
    knits = knit_surfaces(plan_run(scene, fidelity_level("fast")))
    assert knits.scene_knit
    assert list(knits.others) == ["cotton-20s2_stitch-7"]
    assert knits.region_knits == ("", "cotton-20s2_stitch-7", "cotton-20s2_stitch-7", None)
    svk_only = scene_with(region=[{"name": "fabric", "svk": {"course_stiffness": 2.0}}])
    knits = knit_surfaces(plan_run(svk_only, fidelity_level("fast")))
    assert not knits.scene_knit and not knits.others


def test_the_command_line_exits_2_on_a_bad_part_and_writes_nothing(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text(
        '[fabric]\npreset = "cotton-20s2"\nstitch = 5.5\n[fabric.shape]\nkind = "disc"\n'
        '[[boundary]]\nname = "left"\nkind = "clamp"\n'
    )
    output = tmp_path / "out"
    assert main(["run", str(scene), "-o", str(output)]) == 2
    error = capsys.readouterr().err
    assert "boundary[0].name: disc has no boundary 'left'; its boundaries: rim" in error
    assert not output.exists()


def test_a_graded_stitch_plans_only_the_members_its_range_needs():
    region = {"name": "fabric", "stitch": "5.2 + 0.5 * y / 200"}
    scene = scene_with(region=[region])
    (graded,) = scene.part.regions
    assert graded.graded_stitch == region["stitch"] and graded.members == (5.0, 5.5, 6.0)
    knits = knit_surfaces(plan_run(scene, fidelity_level("fast")))
    assert knits.scene_knit and list(knits.others) == [
        "cotton-20s2_stitch-5",
        "cotton-20s2_stitch-6",
    ]
    assert knits.region_families == (
        ((5.0, "cotton-20s2_stitch-5"), (5.5, ""), (6.0, "cotton-20s2_stitch-6")),
    )
    assert knits.region_knits == (None,)
    resolved = scene.resolved(fidelity_level("fast"))
    assert scene_from_dict(tomllib.loads(resolved.to_toml())) == resolved


def test_a_graded_stitch_outside_the_family_or_with_svk_is_refused():
    wide = [{"name": "fabric", "stitch": "4.0 + 3.5 * y / 200"}]
    assert problems_of({**BASE, "region": wide}) == [
        "region[0].stitch: 4 ... 7.5 mm over the region leaves the family's range [4.5, 7] mm "
        "of cotton-20s2"
    ]
    mixed = [{"name": "fabric", "stitch": "5.5 + 0 * x", "svk": {"course_stiffness": 1.0}}]
    assert problems_of({**BASE, "region": mixed}) == [
        "region[0]: give one of svk, knit values, not several"
    ]


def test_a_graded_stitch_on_a_gmsh_file_is_planned_from_its_element_centres(tmp_path):
    (tmp_path / "strip.geo").write_text(
        "Point(1) = {0, 0, 0}; Point(2) = {100, 0, 0}; Point(3) = {100, 20, 0};\n"
        "Point(4) = {0, 20, 0}; Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4};\n"
        "Line(4) = {4, 1}; Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
        "Transfinite Curve{1, 3} = 11; Transfinite Curve{2, 4} = 3; Transfinite Surface{1};\n"
        'Recombine Surface{1}; Physical Curve("grip") = {4}; Physical Surface("panel") = {1};\n'
    )
    data = {**BASE, "fabric": {"preset": "cotton-20s2", "stitch": 5.5}}
    data["fabric"]["mesh"] = {"file": "strip.geo"}
    data["boundary"] = [{"name": "grip", "kind": "clamp"}]
    # 10 mm quads: centres at x = 5 ... 95 mm, so the stitch spans 5.2 + 0.005 x = 5.225 ... 5.675
    data["region"] = [{"name": "panel", "stitch": "5.2 + 0.005 * x"}]
    (panel,) = scene_from_dict(data, base=tmp_path).part.regions
    assert panel.members == (5.0, 5.5, 6.0)
    data["region"] = [{"name": "panel", "stitch": "4.5 + 0.01 * (x - 5)"}]  # 4.5 ... 5.4
    (panel,) = scene_from_dict(data, base=tmp_path).part.regions
    assert panel.members == (4.5, 5.0, 5.5)
    data["fabric"]["mesh"]["refinements"] = 1  # 5 mm quads: centres at 2.5 ... 97.5 mm
    assert problems_of_with_base(data, tmp_path) == [
        "region[0].stitch: 4.475 ... 5.425 mm over the region leaves the family's range "
        "[4.5, 7] mm of cotton-20s2"
    ]


def test_a_part_without_a_knit_is_one_problem_naming_the_regions_that_need_one():
    shape = {"kind": "rectangle"}
    held = [{"name": "bottom", "kind": "clamp"}]
    svk = {"course_stiffness": 1.0}
    band = {"name": "band", "where": "y > 10", "svk": svk}
    bare = {"fabric": {"shape": shape}, "region": [{"name": "fabric"}, band], "boundary": held}
    assert problems_of(bare) == [
        "fabric: no knit for region[0] 'fabric': give [fabric] preset and stitch, or "
        "wale_width, course_height, yarn_radius and youngs_modulus, or the region a preset, "
        "surface or svk"
    ]
    own = {"fabric": {"shape": shape}, "region": [{"name": "fabric", "svk": svk}], "boundary": held}
    assert problems_of(own) == [
        "fabric: no knit (the scene's own, for its geometry and meso stages): give [fabric] "
        "preset and stitch, or wale_width, course_height, yarn_radius and youngs_modulus"
    ]
