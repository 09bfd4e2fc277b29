"""Scenes with the membrane in space: reading, the TOML round trip, and bad input with one
clear message each and exit status 2 (a pressure or indenter on a plane-stress scene, a tube
without [space], a gmsh surface without a course field, a sphere or a plane starting inside
the fabric, the keys of the other indenter shape)."""

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

from knitmech.cli import main
from knitmech.fidelity import fidelity_level
from knitmech.scene import SceneError, scene_from_dict
from knitmech.scene.fabric import part_problems

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"
BASE = {
    "name": "dome",
    "fidelity": "fast",
    "fabric": {
        "preset": "cotton-20s2",
        "stitch": 5.5,
        "shape": {"kind": "disc", "radius": 20.0},
    },
    "meso": {"cases": []},
    "boundary": [{"name": "rim", "kind": "clamp"}],
}
SPHERE = {"radius": 5.0, "centre": [0.0, 0.0, -5.0], "travel": [0.0, 0.0, 3.0], "penalty": 10.0}
PLANE = {"shape": "plane", "point": [0, 0, 2.0], "normal": [0, 0, -1], "travel": [0, 0, -2.0]}
SVK = {
    "course_stiffness": 0.2,
    "wale_stiffness": 0.4,
    "poissons_ratio": 0.2,
    "shear_stiffness": 0.05,
}
REVOLUTION = {"shape": "revolution", "profile": [[0, 5.0], [10, 6.0]], "start_scale": 0.5}


def problems_of(data) -> list[str]:
    with pytest.raises(SceneError) as caught:
        scene_from_dict(data)
    return caught.value.problems


def test_a_scene_in_space_reads_and_round_trips():
    scene = scene_from_dict({**BASE, "space": {}, "pressure": {"value": 0.01}, "indenter": SPHERE})
    space = scene.part.space
    assert space.pressure == 0.01
    assert space.indenter.centre == (0.0, 0.0, -5.0)
    assert space.indenter.penalty == 10.0
    resolved = scene.resolved(fidelity_level("fast"))
    assert scene_from_dict(tomllib.loads(resolved.to_toml())) == resolved
    assert scene_from_dict(BASE).part.space is None
    scene = scene_from_dict({**BASE, "space": {}, "pressure": {"value": 0.01}, "indenter": PLANE})
    plane = scene.part.space.indenter
    assert (plane.shape, plane.point, plane.normal, plane.radius) == (
        "plane",
        (0.0, 0.0, 2.0),
        (0.0, 0.0, -1.0),
        None,
    )
    resolved = scene.resolved(fidelity_level("fast"))
    assert scene_from_dict(tomllib.loads(resolved.to_toml())) == resolved
    scene = scene_from_dict({**BASE, "space": {}, "indenter": REVOLUTION})
    body = scene.part.space.indenter
    assert (body.profile, body.start_scale, body.travel) == (
        ((0.0, 5.0), (10.0, 6.0)),
        0.5,
        (0.0, 0.0, 0.0),
    )
    resolved = scene.resolved(fidelity_level("fast"))
    assert scene_from_dict(tomllib.loads(resolved.to_toml())) == resolved


def test_a_body_of_revolution_must_grow_or_move_and_have_a_profile():
    def indenter(table):
        return problems_of({**BASE, "space": {}, "indenter": table})

    assert indenter({**REVOLUTION, "start_scale": 1.0}) == [
        "indenter: indenter.travel=(0, 0, 0): the indenter must move (or a body of revolution "
        "grow: start_scale < 1)"
    ]
    assert indenter({**REVOLUTION, "profile": [[0, 5.0], [0, 6.0]]}) == [
        "indenter: indenter.profile: a radius profile's z=[0.0, 0.0] mm must increase"
    ]
    assert indenter({**REVOLUTION, "start_scale": 1.5}) == [
        "indenter: indenter.start_scale=1.5 is outside (0, 1]"
    ]


def test_an_indenter_takes_the_keys_of_its_shape():
    def indenter(table):
        return problems_of({**BASE, "space": {}, "indenter": table})

    assert indenter({**PLANE, "radius": 5.0}) == [
        "indenter.radius: unknown key (valid: shape, point, normal, travel, penalty)"
    ]
    assert indenter({**SPHERE, "shape": "cone"}) == [
        "indenter.radius: unknown key (valid: shape, travel, penalty)",
        "indenter.centre: unknown key (valid: shape, travel, penalty)",
    ]
    assert indenter({"shape": "cone", "travel": [0, 0, 1]}) == [
        "indenter: indenter.shape='cone' is not one of sphere, plane, revolution"
    ]
    assert indenter({key: v for key, v in PLANE.items() if key != "normal"}) == [
        "indenter: indenter.normal: a plane needs it"
    ]
    assert indenter({**PLANE, "normal": [0, 0, 0]}) == [
        "indenter: indenter.normal=(0, 0, 0) has no direction"
    ]


def test_loads_in_space_on_a_plane_stress_scene_are_refused():
    problems = problems_of({**BASE, "pressure": {"value": 0.01}, "indenter": SPHERE})
    assert problems == [
        "pressure: needs the membrane in space (add a [space] table); the plane-stress "
        "membrane carries in-plane loads only",
        "indenter: needs the membrane in space (add a [space] table); the plane-stress "
        "membrane carries in-plane loads only",
    ]
    tube = {**BASE, "fabric": {**BASE["fabric"], "shape": {"kind": "tube"}}}
    tube["boundary"] = [{"name": "bottom", "kind": "clamp"}]
    assert problems_of(tube) == ["fabric.shape.kind: a tube needs the membrane in space ([space])"]


def test_bad_values_in_space_name_their_key():
    sphere = {**SPHERE, "centre": [0.0, 0.0], "penalty": -1.0}
    problems = problems_of({**BASE, "space": {"axis": [0, 0, 0], "twist": 1}, "indenter": sphere})
    assert "space.twist: unknown key (valid: stabilization, course, axis, axis_point)" in problems
    assert "indenter.centre: expected three numbers [x, y, z], got [0.0, 0.0]" in problems
    assert problems_of({**BASE, "space": {}, "pressure": {"value": "high"}}) == [
        "pressure.value: expected a number, got str 'high'"
    ]
    assert problems_of({**BASE, "space": {"axis": [0, 0, 0]}}) == [
        "space: axis=(0, 0, 0) has no direction"
    ]


def test_a_gmsh_surface_in_space_needs_its_course_field(tmp_path):
    geo = tmp_path / "sleeve.geo"
    geo.write_text(
        "Point(1) = {0, 0, 0}; Point(2) = {10, 0, 0}; Point(3) = {0, 10, 0};\n"
        "Circle(1) = {2, 1, 3};\n"
        "out[] = Extrude {0, 0, 20} { Curve{1}; Layers{4}; Recombine; };\n"
        'Physical Curve("bottom") = {1}; Physical Curve("top") = {out[0]};\n'
        'Physical Surface("fabric") = {out[1]};\n'
    )
    data = {**BASE, "fabric": {**BASE["fabric"], "mesh": {"file": str(geo)}}, "space": {}}
    del data["fabric"]["shape"]
    data["boundary"] = [{"name": "bottom", "kind": "clamp"}]
    assert problems_of(data) == [
        "space.course: a gmsh surface in space needs its course direction field: course = "
        "one of 'around', 'along' the axis (space.axis)"
    ]
    data["space"] = {"course": "around"}
    assert scene_from_dict(data).part.space.course == "around"


def test_the_command_line_exits_2_on_a_pressure_on_a_plane_stress_scene(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    text = (EXAMPLES / "diaphragm_burst.toml").read_text().replace("[space]\n", "")
    scene.write_text(text)
    output = tmp_path / "out"
    assert main(["run", str(scene), "-o", str(output)]) == 2
    assert "pressure: needs the membrane in space" in capsys.readouterr().err
    assert not output.exists()


@pytest.mark.slow
def run_edited_ball_burst(tmp_path, replacements: dict[str, str]) -> int:
    """`knitmech run` (fast) of examples/ball_burst.toml with its text replaced; the exit status."""
    text = (EXAMPLES / "ball_burst.toml").read_text()
    for old, new in {
        **replacements,
        '"../knitmech/data/': f'"{EXAMPLES.parent}/knitmech/data/',
    }.items():
        text = text.replace(old, new)
    scene = tmp_path / "ball.toml"
    scene.write_text(text)
    command = ["run", str(scene), "-o", str(tmp_path / "out"), "--fidelity", "fast"]
    return main([*command, "--cache-dir", str(tmp_path / "cache")])


def test_the_command_line_exits_2_on_an_indenter_inside_the_fabric(tmp_path, capsys):
    moved = {"centre = [0.0, 0.0, -12.7]": "centre = [0.0, 0.0, -12.0]"}
    assert run_edited_ball_burst(tmp_path, moved) == 2
    error = capsys.readouterr().err
    # the nearest node of the coarse disc is 2.2 mm off the centre
    assert "radius=12.7 mm starts inside the fabric (gap -0.3711 mm)" in error


@pytest.mark.slow
def test_the_command_line_exits_2_on_a_plane_behind_the_fabric(tmp_path, capsys):
    plane = {
        "radius = 12.7\ncentre = [0.0, 0.0, -12.7]\n": "",
        "[indenter]\n": '[indenter]\nshape = "plane"\n',
        "penalty = 10.0": "point = [0, 0, 0.5]\nnormal = [0, 0, 1]\npenalty = 10.0",
    }
    assert run_edited_ball_burst(tmp_path, plane) == 2
    error = capsys.readouterr().err
    assert "indenter plane point=(0.0, 0.0, 0.5) mm, normal=(0.0, 0.0, 1.0) starts inside" in error
    assert "(gap -0.5 mm)" in error


@pytest.mark.parametrize("indenter", [SPHERE, PLANE, REVOLUTION])
def test_the_fabric_job_in_space_survives_its_json_round_trip(indenter):
    """The mpirun path sends the job as JSON: the part's space comes back equal."""
    from knitmech.jobs.fabric_spec import FabricJob, RegionMaterial  # noqa: PLC0415

    scene = scene_from_dict({**BASE, "space": {"stabilization": 1e-4}, "indenter": indenter})
    part = scene.resolved(fidelity_level("fast")).part
    job = FabricJob(part, (RegionMaterial(svk={"course_stiffness": 2.0}),), steps=4)
    assert FabricJob.from_json(json.loads(json.dumps(job.to_json()))) == job


TUBE = {
    **BASE,
    "fabric": {**BASE["fabric"], "shape": {"kind": "tube", "radius": 20.0, "length": 100.0}},
    "boundary": [{"name": "bottom", "kind": "clamp"}],
    "space": {},
}


def test_regions_in_space_may_select_along_z_and_plane_regions_may_not():
    cuff = {"name": "cuff", "where": "z < 20", "pattern": "rib1x1"}
    scene = scene_from_dict({**TUBE, "region": [{"name": "fabric"}, cuff]})
    assert [region.where for region in scene.part.regions] == [None, "z < 20"]
    assert scene.part.coordinates == ("x", "y", "z")
    flat = {**BASE, "region": [{"name": "fabric"}, {**cuff, "angle": "z"}]}
    assert problems_of(flat) == [
        "region[1].where: 'z < 20' uses the unknown name 'z' (valid: x, y, pi, sin, cos, tan, "
        "arctan2, sqrt, exp, log, abs, minimum, maximum, where, clip)",
        "region[1].angle: 'z' uses the unknown name 'z' (valid: x, y, pi, sin, cos, tan, "
        "arctan2, sqrt, exp, log, abs, minimum, maximum, where, clip)",
    ]


def test_a_tube_region_that_selects_nothing_is_refused_before_anything_runs():
    """The tube is not meshed before the run: its regions are checked on a grid of points on
    its surface: 101 points on each of 101 rings at the centres of equal lengths of its axis."""
    regions = [{"name": "fabric"}, {"name": "cuff", "where": "z > 99.6", "svk": SVK}]
    scene = scene_from_dict({**TUBE, "region": regions})
    assert part_problems(scene.resolved(fidelity_level("fast")).part) == [
        "region[1]: 'cuff' holds no cell of the mesh (10201 cells; a later region may have "
        "taken them, or its where selects no cell centre)"
    ]
    regions[1]["where"] = "z > 99.4"
    scene = scene_from_dict({**TUBE, "region": regions})
    assert part_problems(scene.resolved(fidelity_level("fast")).part) == []
    regions[0]["where"] = "z < 50"
    regions[1]["where"] = "z > 60"
    scene = scene_from_dict({**TUBE, "region": regions})
    rings = (np.arange(101) + 0.5) * 100.0 / 101
    between = 101 * np.count_nonzero((rings >= 50) & (rings <= 60))
    assert part_problems(scene.resolved(fidelity_level("fast")).part) == [
        f"region: {between} cells belong to no region (physical surfaces not listed: none); "
        "add a region for them"
    ]


def test_boundaries_in_space_take_z_and_plane_boundaries_do_not():
    boundaries = [
        {"name": "bottom", "kind": "roller", "component": "z"},
        {"name": "top", "kind": "displacement", "displacement": [0.0, 0.0, 5.0]},
    ]
    scene = scene_from_dict({**TUBE, "boundary": boundaries})
    bottom, top = scene.part.boundaries
    assert (bottom.component, top.vector) == ("z", (0.0, 0.0, 5.0))
    rim = [
        {"name": "rim", "kind": "roller", "component": "z"},
        {"name": "rim", "kind": "displacement", "displacement": [0.0, 0.0, 5.0]},
    ]
    problems = problems_of({**BASE, "boundary": rim})
    assert "boundary[0].component: 'z' is not x or y" in problems
    assert "boundary[1].displacement: required, two numbers [x, y] in mm" in problems
    wrong = [{"name": "bottom", "kind": "roller", "component": "zz"}]
    assert problems_of({**TUBE, "boundary": wrong}) == [
        "boundary[0].component: 'zz' is not x, y or z (or several once, e.g. 'yz')"
    ]


def test_a_graded_stitch_in_space_is_refused_when_the_scene_is_read():
    graded = {"name": "fabric", "stitch": "4.5 + z / 50"}
    assert problems_of({**TUBE, "region": [graded]}) == [
        "region[0].stitch: a graded stitch is not available for the membrane in space yet (a "
        "graded sleeve: knitmech design, docs/design.md)"
    ]
