"""`knitmech run` refuses bad scenes before computing anything: exit status 2, one line per
problem naming its key, no results and no cache written."""

import tomllib

import pytest

import fabric_dolfinx.cli
import knitmech.cli
import rve_rod.cli
from knitmech.cli import main
from knitmech.fidelity import fidelity_level
from knitmech.pipeline import check_plan, run_scene
from knitmech.scene import default_surface_path, load_scene, scene_from_dict, starter_scene_path
from knitmech.stages import plan_run


def run(tmp_path, text, capsys, *extra):
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    folders = ["-o", str(tmp_path / "out"), "--cache-dir", str(tmp_path / "cache")]
    status = main(["run", str(scene), *folders, *extra])
    log = ("INFO ", "DEBUG ")  # the run's progress log; the error lines are the rest
    return status, [
        line for line in capsys.readouterr().err.splitlines() if not line.startswith(log)
    ]


def nothing_written(tmp_path):
    return not (tmp_path / "out").exists() and not (tmp_path / "cache").exists()


def test_unknown_keys_wrong_types_and_missing_surface_one_line_each(tmp_path, capsys):
    text = """
fidelity = "quick"
[fabric]
preset = "cotton-20s2"
stitch = "5.5"
[meso]
casses = ["uniaxial-course"]
[surface]
path = "missing.h5"
[macro]
elements = 0
"""
    status, lines = run(tmp_path, text, capsys)
    assert status == 2
    problems = [line.strip() for line in lines[1:]]
    keys = sorted(problem.split(":")[0].removeprefix("- ") for problem in problems)
    assert keys == ["fabric.stitch", "fidelity", "macro.elements", "meso.casses", "surface.path"]
    assert "scene" in lines[0] and "5 problem(s)" in lines[0]
    assert nothing_written(tmp_path)


def test_corrupt_surface_file_is_refused_naming_the_key(tmp_path, capsys):
    (tmp_path / "broken.h5").write_bytes(b"not an HDF5 file")
    text = '[fabric]\npreset = "cotton-20s2"\nstitch = 5.5\n[surface]\npath = "broken.h5"\n'
    status, lines = run(tmp_path, text, capsys)
    assert status == 2
    assert lines[1].strip().startswith("- surface.path:")
    assert nothing_written(tmp_path)


def test_impossible_geometry_is_refused_before_the_rve_runs(tmp_path, capsys):
    text = """
[fabric]
wale_width = 1.33
course_height = 0.3
yarn_radius = 0.19
youngs_modulus = 80.0
"""
    status, lines = run(tmp_path, text, capsys)
    assert status == 2
    assert "no loop fits" in lines[1]
    assert lines[1].strip().startswith("- fabric.wale_width, fabric.course_height")
    assert not (tmp_path / "out").exists()


def test_usage_errors_exit_2_with_one_line(tmp_path, capsys):
    assert main(["run", "--fidelity", "ultra"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert main(["run", str(tmp_path / "absent.toml")]) == 2
    assert "cannot be read" in capsys.readouterr().err
    status, lines = run(
        tmp_path, '[fabric]\npreset = "cotton-20s2"\nstitch = 5.5\n', capsys, "--jobs", "0"
    )
    assert status == 2 and lines == [
        "knitmech run: error: jobs=0 is outside the valid range [1, 256]"
    ]
    assert nothing_written(tmp_path)


def test_init_writes_a_commented_scene_that_plans_and_keeps_an_existing_file(tmp_path, capsys):
    path = tmp_path / "scene.toml"
    assert main(["init", str(path)]) == 0
    assert (
        capsys.readouterr().out == f"wrote {path}; edit it, then: knitmech run {path} -o results\n"
    )
    text = path.read_text()
    assert text.count("#") > 30  # every section explained
    scene = load_scene(path)
    check_plan(plan_run(scene, fidelity_level(scene.fidelity)))
    assert [b.kind for b in scene.part.boundaries] == ["clamp", "displacement"]
    path.write_text("mine")
    assert main(["init", str(path)]) == 2
    assert "exists already; give another name or --force" in capsys.readouterr().err
    assert path.read_text() == "mine"
    assert main(["init", str(path), "--force"]) == 0 and path.read_text() == text


@pytest.mark.slow
def test_the_starter_scene_runs(tmp_path):
    """`knitmech init`'s scene as written, on the shipped surface (no RVE run)."""
    data = tomllib.loads(starter_scene_path().read_text())
    data["surface"]["path"] = str(default_surface_path())
    data["meso"]["cases"] = []
    result = run_scene(scene_from_dict(data), output=tmp_path / "out", cache_dir=tmp_path)
    part = result.summary["part"]
    assert part["complete"] and part["boundaries"]["top"]["force"][-1][1] > 0.0
    assert (tmp_path / "out" / "fabric" / "probe_centre.csv").is_file()


@pytest.mark.parametrize(
    ("tool", "command"),
    [
        ("rve-rod", ["geometry", "--preset", "cotton-20s2", "--stitch", "5.5"]),
        ("fabric-dolfinx", ["tension", "--svk", "1,2,0.3,1"]),
        ("knitmech", ["run"]),
    ],
)
def test_the_three_tools_take_the_same_flags_before_and_after_the_subcommand(tool, command):
    """--version, -q and -v, before or after the subcommand (issue 31: the tools differed)."""
    parser = {
        "rve-rod": rve_rod.cli.build_parser,
        "fabric-dolfinx": fabric_dolfinx.cli.build_parser,
        "knitmech": knitmech.cli.build_parser,
    }[tool]()
    for before, after in (([], []), (["-v"], []), ([], ["-v"]), (["-q"], []), ([], ["-q"])):
        args = parser.parse_args([*before, *command, *after])
        assert (args.quiet, args.verbose) == ("-q" in before + after, int("-v" in before + after))
    for place in (["--version", *command], [*command, "--version"]):
        with pytest.raises(SystemExit) as stop:
            parser.parse_args(place)
        assert stop.value.code == 0
