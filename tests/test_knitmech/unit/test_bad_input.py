"""The bad-input table (issue 19, docs/reliability.md): every input a user got a traceback, a
hang or a silent wrong answer from, with its exit status and the words of its one-line message.

Each row runs a tool's `main` in-process with the work functions replaced by a tripwire, so a
row also shows that the input is refused before any work starts (no RVE run, no geometry, no
stage, no membrane solve). Placeholders: {dir} an existing folder, {file} an existing file,
{missing} a folder that does not exist, {scene} a scene file made of the base scene and the
row's TOML lines. The broken-pipe rows run the installed scripts with a reader that closes
stdout at once.
"""

import shutil
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from PIL import Image

import fabric_dolfinx.cli
import knitmech.cli
import knitmech.pipeline
import rve_rod.cli
import rve_rod.cli.geometry
import rve_rod.cli.measure
import rve_rod.cli.simulate
import rve_rod.cli.surface
import rve_rod.cli.synth_photo
from fabric_dolfinx.mesh.tagged import MESH_DIRECTORY
from knitmech.scene import default_surface_path
from rve_rod.imaging.synthetic import SyntheticPhoto, render_photo
from rve_rod.limits import available_cores

TOOLS = {
    "rve-rod": rve_rod.cli.main,
    "fabric-dolfinx": fabric_dolfinx.cli.main,
    "knitmech": knitmech.cli.main,
}
FABRIC = "--preset cotton-20s2 --stitch 5.5"
SVK = "tension --svk 1,2,0.3,1"
SCENE = """name = "bad"
fidelity = "fast"
[fabric]
preset = "cotton-20s2"
stitch = 5.5
"""
CORES = available_cores()
PART = """
[fabric.shape]
kind = "rectangle"
height = 200.0
[[boundary]]
name = "bottom"
kind = "clamp"
"""
"""A strip held at its bottom (issue 15's part rows add to it); {tri}: a .geo of triangles."""
NO_KNIT = 'name = "no knit"\nfidelity = "fast"\n' + PART
TRIANGLES = """Point(1) = {0, 0, 0}; Point(2) = {10, 0, 0}; Point(3) = {0, 10, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1}; Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1}; Physical Curve("bottom") = {1}; Physical Surface("fabric") = {1};
"""

SEAM = """DefineConstant[ size = {5, Name "Parameters/size"} ];
Point(1) = {0, 0, 0, size}; Point(2) = {25, 0, 0, size}; Point(3) = {25, 50, 0, size};
Point(4) = {0, 50, 0, size}; Point(5) = {50, 0, 0, size}; Point(6) = {50, 50, 0, size};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {2, 5}; Line(6) = {5, 6}; Line(7) = {6, 3}; Line(8) = {3, 2};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Physical Curve("left") = {4}; Physical Curve("right") = {6};
Physical Surface("fabric") = {1, 2}; Mesh.RecombineAll = 1;
"""
"""Two squares with their own lines along x = 25 (a non-conforming mesh: the seam carries no
load); {seam} in a row."""
UPRIGHT = """Point(1) = {0, 0, 0, 5}; Point(2) = {50, 0, 0, 5}; Point(3) = {50, 0, 50, 5};
Point(4) = {0, 0, 50, 5}; Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4};
Line(4) = {4, 1}; Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Curve("bottom") = {1}; Physical Surface("fabric") = {1}; Mesh.RecombineAll = 1;
"""
"""A square drawn in the x-z plane; {upright} in a row."""
CRASH = """Point(1) = {0, 0, 0, 5}; Point(2) = {50, 0, 0, 5}; Point(3) = {50, 50, 0, 5};
Point(4) = {0, 50, 0, 5}; Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4};
Line(4) = {4, 1}; Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Curve("bottom") = {1}; Physical Surface("fabric") = {1};
Mesh.Algorithm = 8; Mesh.RecombineAll = 1;
"""
"""A square meshed by gmsh 4.8's algorithm 8, which crashes it (SIGSEGV, sometimes SIGABRT);
{crash}."""
TWO = (
    SEAM.replace("Line(8) = {3, 2};", "")
    .replace("{5, 6, 7, 8}", "{5, 6, 7, -2}")
    .replace(
        'Physical Surface("fabric") = {1, 2};',
        'Physical Surface("a") = {1}; Physical Surface("b") = {2};',
    )
)
"""The two squares of SEAM sharing their line along x = 25, in two physical surfaces a and b
(a conforming mesh); {two} in a row."""
PLATE = "[fabric.mesh]\nfile = '{plate}'\n[[boundary]]\nname = 'left'\nkind = 'clamp'\n"
"""The repository's plate with a hole as the user's own .geo file ({plate})."""

# tool, arguments, scene lines (for {scene}), exit status, words of the message
TABLE = [
    # tracebacks before
    ("rve-rod", f"geometry {FABRIC} --wale-width 1e6", "", 2, "wale_width=1e+06 mm is outside"),
    ("rve-rod", f"geometry {FABRIC} --course-height 1e9", "", 2, "course_height=1e+09 mm is"),
    ("knitmech", "run {scene}", "wale_width = 1e6", 2, "wale_width=1e+06 mm is outside"),
    ("rve-rod", f"simulate {FABRIC} --youngs-modulus 1e12", "", 2, "youngs_modulus=1e+12 MPa"),
    ("rve-rod", f"surface {FABRIC} -o {{dir}}", "", 2, "--output {dir}: is a folder"),
    ("rve-rod", f"surface {FABRIC} -o {{file}}/s.h5", "", 2, "{file} is a file, not a folder"),
    ("rve-rod", f"surface {FABRIC} -o {{missing}}/s.h5", "", 2, "folder {missing} does not"),
    ("rve-rod", f"surface {FABRIC} -o s.h5 --cache-dir {{file}}", "", 2, "--cache-dir {file}: is"),
    ("rve-rod", f"simulate {FABRIC} --plot {{missing}}/c.png", "", 2, "--plot {missing}/c.png"),
    ("rve-rod", f"simulate {FABRIC} --vtk {{file}}", "", 2, "--vtk {file}: is a file"),
    ("rve-rod", f"geometry {FABRIC} --vtk {{dir}}", "", 2, "--vtk {dir}: is a folder"),
    ("rve-rod", "measure photo.png --pixels-per-mm 20 --plot {missing}/o.png", "", 2, "--plot"),
    ("knitmech", "run -o {file}", "", 2, "--output {file}: is a file, not a folder"),
    ("knitmech", "run -o {file}/results", "", 2, "{file} is a file, not a folder"),
    ("knitmech", "run -o {missing}/results", "", 2, "folder {missing} does not exist"),
    ("knitmech", "run --cache-dir {file}/cache", "", 2, "--cache-dir {file}/cache"),
    ("fabric-dolfinx", f"{SVK} --xdmf {{missing}}/o.xdmf", "", 2, "--xdmf {missing}/o.xdmf"),
    ("fabric-dolfinx", f"{SVK} --plot {{dir}}", "", 2, "--plot {dir}: is a folder"),
    ("fabric-dolfinx", "tension --svk -1,2,0.3,1", "", 2, "course_stiffness=-1 N/mm must be > 0"),
    (
        "rve-rod",
        "simulate --preset vassiliadis-sample2 --bending free-fibres",
        "",
        2,
        "bending='free-fibres' needs the yarn's fibres",
    ),
    ("knitmech", "run {scene}", "bending = 'wood'", 2, "fabric.bending: 'wood' is unknown"),
    # scene files that are not UTF-8 text (issue 31)
    (
        "knitmech",
        "run {binary}",
        "",
        2,
        "scene file {binary}: not UTF-8 text (byte 0x89 at offset 0)",
    ),
    (
        "knitmech",
        "run {utf16}",
        "",
        2,
        "scene file {utf16}: not UTF-8 text (it holds NUL bytes: UTF-16 without its",
    ),
    # image formats checked after the work (issue 31)
    ("rve-rod", f"geometry {FABRIC} --plot x.foo", "", 2, "--plot x.foo: .foo is not a format"),
    ("rve-rod", f"simulate {FABRIC} --plot x.foo", "", 2, "--plot x.foo: .foo is not a format"),
    ("fabric-dolfinx", f"{SVK} --plot x.foo", "", 2, "--plot x.foo: .foo is not a format"),
    ("rve-rod", f"synth-photo {FABRIC} -o x.foo", "", 2, "--output x.foo: .foo is not a format"),
    # hangs and runaway resources before
    ("rve-rod", f"simulate {FABRIC} --control-points 100000", "", 2, "[20, 300]"),
    ("rve-rod", f"simulate {FABRIC} --steps 1000000", "", 2, "steps=1000000 is outside"),
    ("rve-rod", f"surface {FABRIC} -o s.h5 --rays 1000000", "", 2, "--rays=1000000 is outside"),
    ("rve-rod", f"surface {FABRIC} -o s.h5 --steps 100000", "", 2, "steps_per_ray=100000"),
    ("fabric-dolfinx", f"{SVK} --steps 100000000", "", 2, "steps=100000000 is outside"),
    ("fabric-dolfinx", f"{SVK} --steps 1e8", "", 2, "--steps: invalid int value: '1e8'"),
    ("fabric-dolfinx", f"{SVK} --elements 4000", "", 2, "elements=4000 is outside the valid"),
    ("knitmech", "run {scene}", "[surface]\nrays = 100000000", 2, "surface.rays: 100000000"),
    ("knitmech", "run {scene}", "[macro]\nelements = 4000", 2, "macro.elements: 4000 is out"),
    ("knitmech", "run {scene}", "[macro]\nsteps = 100000", 2, "macro.steps: 100000 is out"),
    ("knitmech", "run {scene}", "[meso]\ncontrol_points = 100000", 2, "meso.control_points"),
    ("knitmech", "run {scene}", "[macro]\nranks = 1000", 2, f"valid range [1, {CORES}]"),
    # silent wrong answers before
    ("rve-rod", f"surface {FABRIC} -o s.h5 --rays 3", "", 2, "--rays=3 is outside the valid"),
    ("rve-rod", f"surface {FABRIC} -o s.h5 --rays 8", "", 2, "--rays=8 is outside the valid"),
    ("rve-rod", f"simulate {FABRIC} --control-points 12", "", 2, "--control-points=12 is out"),
    ("knitmech", "run {scene}", "[meso]\ncontrol_points = 12", 2, "meso.control_points: 12"),
    ("rve-rod", f"geometry {FABRIC} --course-height 50", "", 2, "course_height=50 mm is out"),
    # a scene's part (issue 15)
    (
        "knitmech",
        "run {scene}",
        f"{PART}[[boundary]]\nname = 'side'\nkind = 'free'",
        2,
        "boundary[1].name: rectangle has no boundary 'side'; its boundaries: left, right, bottom",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PART}[[region]]\nname = 'core'",
        2,
        "region[0].name: rectangle has no region 'core' (its regions: fabric)",
    ),
    (
        "knitmech",
        "run {scene}",
        "[fabric.mesh]\nfile = '{tri}'\n[[boundary]]\nname = 'bottom'\nkind = 'clamp'",
        2,
        "tri.geo: the mesh has Triangle 3 elements; only 4-node quadrilaterals",
    ),
    ("knitmech", "run {scene}", NO_KNIT, 2, "fabric: no knit for region[0] 'fabric': give"),
    (
        "knitmech",
        "run {scene}",
        f"{PART}[[region]]\nname = 'fabric'\nstitch = '4 + 3.5 * y / 200'",
        2,
        "region[0].stitch: 4 ... 7.5 mm over the region leaves the family's range [4.5, 7] mm",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PART}[[region]]\nname = 'fabric'\nstitch = 7.5",
        2,
        "region[0]: stitch=7.5 mm is not measured; valid stitch values: 4.5",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PART}[[region]]\nname = 'fabric'\npreset = 'cotton-20s2'",
        2,
        "region[0].stitch: preset cotton-20s2 needs --stitch, one of 4.5",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PART}[[boundary]]\nname = 'bottom'\nkind = 'roller'",
        2,
        "boundary: conditions overlap, 'bottom' is given twice",
    ),
    # silent wrong answers on parts (issue 31)
    (
        "knitmech",
        "run {scene}",
        "[fabric.mesh]\nfile = '{seam}'\n[[boundary]]\nname = 'left'\nkind = 'clamp'",
        2,
        "seam.geo: the mesh is not conforming: ",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PLATE}[fabric.mesh.parameters]\nsise = 5.0",
        2,
        "fabric.mesh.parameters.sise: plate_with_hole.geo declares no parameter 'sise'",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PLATE}[fabric.mesh.parameters]\nsize = 0.0",
        2,
        "fabric.mesh.parameters.size: 0 must be > 0 (a .geo parameter is a length or a size",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PART}[[region]]\nname = 'fabric'\nangle = 'x > 25'",
        2,
        "region[0].angle: 'x > 25' is a condition (true or false), not a course direction",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PART}[[region]]\nname = 'fabric'\n[[region]]\nname = 'band'\nwhere = 'x + 5'",
        2,
        "region[1].where: 'x + 5' is a value, not a condition",
    ),
    # runaway meshes and crashes (issue 31)
    (
        "knitmech",
        "run {scene}",
        PART.replace("height = 200.0", "height = 200.0\nelement_size = 0.001"),
        2,
        "fabric.shape.element_size: rectangle of element_size 0.001 mm gives about 1e+10 cells",
    ),
    (
        "knitmech",
        "run {scene}",
        PART.replace("height = 200.0", "height = 200.0\nrefinements = 6"),
        2,
        "fabric.shape.refinements: rectangle of 144 cells gives about 5.9e+05 cells after 6",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PLATE}[fabric.mesh.parameters]\nsize = 0.01",
        2,
        "plate_with_hole.geo (estimated from its boundary, at least) gives about",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PLATE}[fabric.mesh.parameters]\nsize = -5.0",
        2,
        "fabric.mesh.parameters.size: -5 must be > 0",
    ),
    (
        "knitmech",
        "run {scene}",
        "[fabric.mesh]\nfile = '{crash}'\n[[boundary]]\nname = 'bottom'\nkind = 'clamp'",
        2,
        # the message ends with the signal: SIGSEGV or, on a loaded machine, SIGABRT
        "crash.geo: gmsh crashed while meshing it; another Mesh.Algorithm may help (gmsh 4.8 "
        "crashes with 8; SIG",
    ),
    # refused late (issue 31)
    (
        "knitmech",
        "run {scene}",
        f"{PART}[[probe]]\nname = 'far'\nx = 500.0\ny = 0.0",
        2,
        "probe[0] 'far': (500, 0) mm is not in the part",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PART}[[region]]\nname = 'fabric'\n[[region]]\nname = 'band'\nwhere = 'x > 500'",
        2,
        "region[1]: 'band' holds no cell of the mesh (144 cells;",
    ),
    (
        "knitmech",
        "run {scene}",
        "[fabric.mesh]\nfile = '{two}'\n[[region]]\nname = 'a'\n"
        "[[boundary]]\nname = 'left'\nkind = 'clamp'",
        2,
        "cells belong to no region (physical surfaces not listed: b); add a region for them",
    ),
    (
        "knitmech",
        "run {scene}",
        f"{PART}[[region]]\nname = 'fabric'\nangle = 'log(x - 30)'",
        2,
        "region[0].angle: 'log(x - 30)' is not finite at some points (the centres of its cells)",
    ),
    (
        "knitmech",
        "run {scene}",
        "[fabric.mesh]\nfile = '{upright}'\n[[boundary]]\nname = 'bottom'\nkind = 'clamp'",
        2,
        "upright.geo: the mesh is not in the x-y plane (it spans x 50 mm, y 0 mm, z 50 mm)",
    ),
]


def _tripwire(*args, **kwargs):
    raise AssertionError("work began before the input was refused")


@pytest.fixture
def no_work(monkeypatch):
    """Every expensive step of the tools raises AssertionError (not mapped to an exit
    status: the row fails with a traceback)."""
    monkeypatch.setattr(rve_rod.cli.geometry, "loop_geometry", _tripwire)
    monkeypatch.setattr(rve_rod.cli.simulate, "simulate", _tripwire)
    monkeypatch.setattr(rve_rod.cli.surface, "generate_surface", _tripwire)
    monkeypatch.setattr(rve_rod.cli.measure, "read_image", _tripwire)
    monkeypatch.setattr(rve_rod.cli.synth_photo, "render_photo", _tripwire)
    monkeypatch.setattr(fabric_dolfinx.cli, "TensionSetup", _tripwire)
    monkeypatch.setattr(knitmech.pipeline.StageCache, "run", _tripwire)


@pytest.mark.parametrize("row", TABLE, ids=[f"{r[0]} {r[1]} {r[2]}".strip() for r in TABLE])
def test_bad_input_one_line_naming_the_parameter_before_any_work(
    row, tmp_path, monkeypatch, capsys, no_work
):
    tool, arguments, scene, status, words = row
    monkeypatch.chdir(tmp_path)
    places = {
        "dir": tmp_path / "folder",
        "file": tmp_path / "file.txt",
        "missing": tmp_path / "missing",
        "scene": tmp_path / "scene.toml",
    }
    places["dir"].mkdir()
    places["file"].write_text("not a folder")
    places["binary"] = tmp_path / "photo.toml"  # a PNG's first bytes
    places["binary"].write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR")
    places["utf16"] = tmp_path / "utf16.toml"  # UTF-16 without its byte-order mark
    places["utf16"].write_bytes(SCENE.encode("utf-16-le"))
    geo = (
        ("tri", TRIANGLES),
        ("seam", SEAM),
        ("upright", UPRIGHT),
        ("crash", CRASH),
        ("two", TWO),
    )
    for name, text in geo:
        places[name] = tmp_path / f"{name}.geo"
        places[name].write_text(text)
    places["plate"] = MESH_DIRECTORY / "plate_with_hole.geo"
    text = (
        scene
        if scene.startswith("name")
        else SCENE.replace("stitch = 5.5", f"stitch = 5.5\n{scene}")
    )
    for name in ("tri", "seam", "upright", "crash", "two", "plate"):
        text = text.replace(f"{{{name}}}", str(places[name]))
    places["scene"].write_text(text)
    argv = [argument.format(**places) for argument in arguments.split()]
    if tool == "knitmech" and "--cache-dir" not in argv:
        argv += ["--cache-dir", str(tmp_path / "cache")]
    assert TOOLS[tool](argv) == status
    error = capsys.readouterr().err
    assert words.format(**places) in error
    lines = error.strip().splitlines()
    assert len(lines) == 1 or (tool == "knitmech" and "has 1 problem(s)" in lines[0]), error
    assert all(line.startswith(("rve-rod", "fabric-dolfinx", "knitmech", "  ")) for line in lines)


BIN = Path(sys.executable).parent


@pytest.mark.parametrize(
    "command",
    [
        f"{BIN}/rve-rod surface-info {default_surface_path()} --json",
        f"{BIN}/rve-rod surface-info {default_surface_path()}",
    ],
)
def test_a_closed_stdout_ends_quietly_with_141(command):
    # `true` exits without reading: the first write meets a closed pipe, as `| head` does late
    shell = subprocess.run(
        ["bash", "-c", f"{command} | true; echo ${{PIPESTATUS[0]}}"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert shell.stdout.strip() == "141"
    assert shell.stderr == ""


PIPE_SCENE = f"""name = "pipe"
fidelity = "fast"
[fabric]
preset = "cotton-20s2"
stitch = 5.5
[meso]
cases = []
[surface]
path = "{default_surface_path()}"
[macro]
directions = ["course"]
elements = 2
steps = 2
max_strain = 0.05
"""


def test_knitmech_run_json_into_a_closed_pipe_ends_quietly_with_141(tmp_path):
    """`knitmech run --json | head -1`: DOLFINx's PETSc installs a SIGPIPE handler that used to
    abort the MPI job (exit 59); the run must end as the other tools do. A `.stage-*` folder
    left by a killed run is removed by this next run."""
    scene, results = tmp_path / "scene.toml", tmp_path / "results"
    scene.write_text(PIPE_SCENE)
    (results / ".stage-left-by-a-killed-run").mkdir(parents=True)
    command = f"{BIN}/knitmech run {scene} -o {results} --cache-dir {tmp_path / 'cache'} -q --json"
    shell = subprocess.run(
        ["bash", "-c", f"{command} | true; echo ${{PIPESTATUS[0]}}"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert shell.stdout.strip() == "141", shell.stderr
    assert shell.stderr == ""
    assert (results / "summary.json").is_file()
    assert list(results.glob(".stage-*")) == []


@pytest.fixture(scope="module")
def photo(tmp_path_factory):
    """A synthetic photo of single jersey, w = 1.33 mm and c = 1.26 mm at 20 px/mm."""
    knit = SyntheticPhoto(
        wale_width=1.33,
        course_height=1.26,
        minimal_radius=0.19,
        pixels_per_mm=20.0,
        width_px=400,
        height_px=400,
    )
    path = tmp_path_factory.mktemp("photo") / "knit.png"
    Image.fromarray((255 * render_photo(knit)).astype(np.uint8)).save(path)
    return path


@pytest.fixture(scope="module")
def checkerboard(tmp_path_factory):
    """A checkerboard of 13-pixel squares (1.3 mm cells at 20 px/mm): periodic, not a knit."""
    y, x = np.mgrid[0:400, 0:400]
    board = (x // 13 + y // 13) % 2
    path = tmp_path_factory.mktemp("photo") / "checkerboard.png"
    Image.fromarray((255 * board).astype(np.uint8)).save(path)
    return path


@pytest.fixture(scope="module")
def mpa_surface(tmp_path_factory):
    """The shipped surface file with its units attribute saying MPa."""
    path = tmp_path_factory.mktemp("surface") / "mpa.h5"
    shutil.copyfile(default_surface_path(), path)
    with h5py.File(path, "r+") as h5:
        h5.attrs["units"] = "E: 1 (Green-Lagrange); S: MPa"
    return path


# rows whose check needs the work done (a measurement, a file read): arguments, status, words
CHECKED = [
    ("measure {photo} --pixels-per-mm 1e9", 2, "pixels_per_mm=1e+09 gives wale_width = 2.66e-08"),
    ("measure {photo} --pixels-per-mm 0.01", 2, "pixels_per_mm=0.01 gives wale_width = 2660 mm"),
    ("measure {checkerboard} --pixels-per-mm 20", 2, "a checkerboard-like alternation, not"),
    ("surface-info {mpa}", 2, "units='E: 1 (Green-Lagrange); S: MPa': this reader reads"),
]


@pytest.mark.parametrize("row", CHECKED, ids=[row[0] for row in CHECKED])
def test_implausible_results_and_files_are_refused(row, photo, checkerboard, mpa_surface, capsys):
    arguments, status, words = row
    argv = arguments.format(photo=photo, checkerboard=checkerboard, mpa=mpa_surface).split()
    assert rve_rod.cli.main(argv) == status
    error = capsys.readouterr().err
    assert words in error and error.count("\n") == 1


def test_a_yarn_radius_cut_to_w_over_8_is_said():
    arguments = "geometry --wale-width 1.33 --course-height 1.26 --yarn-radius 5"
    run = subprocess.run(
        [str(BIN / "rve-rod"), *arguments.split()], capture_output=True, text=True, check=False
    )
    assert run.returncode == 0
    message = "yarn_radius=5 mm is larger than wale_width/8: the model uses r = w/8 = 0.1663 mm"
    assert message in run.stderr
    assert "yarn radius        0.1663 mm (adjusted to w/8)" in run.stdout


def test_reliability_doc_lists_every_row():
    """docs/reliability.md shows the bad-input table: every row of TABLE and CHECKED, with its
    exit status and the words of its message."""
    lines = (Path(__file__).resolve().parents[3] / "docs" / "reliability.md").read_text()
    lines = lines.splitlines()
    rows = [
        (f"{tool} {arguments}", scene, status, words)
        for tool, arguments, scene, status, words in TABLE
    ]
    rows += [(f"rve-rod {arguments}", None, status, words) for arguments, status, words in CHECKED]
    for command, scene, status, words in rows:
        if scene is None:
            start = f"| `{command}` | {status} | "
        else:
            cell = f"`{scene.replace(chr(10), '; ')}`" if scene else ""
            start = f"| `{command}` | {cell} | {status} | "
        found = [line for line in lines if line.startswith(start) and words in line]
        assert found, f"docs/reliability.md has no row {start}... {words}"
