"""What a new user sees on stderr from `fabric-dolfinx` on first use (FFCx compiles its forms
into a fresh cache): nothing at default verbosity (no gcc command lines), and with -v the
tool's `[rank N]` format on every line."""

import os
import subprocess
import sys
from pathlib import Path

from knitmech.scene import default_surface_path

FABRIC_DOLFINX = str(Path(sys.executable).parent / "fabric-dolfinx")
ARGS = ["tension", "--svk", "10,8,0.3,2", "--elements", "2", "--steps", "2"]


def test_first_use_is_quiet_and_verbose_logs_carry_the_rank(tmp_path):
    environment = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")}

    def run(*extra):
        command = [FABRIC_DOLFINX, *extra, *ARGS]
        return subprocess.run(command, capture_output=True, text=True, env=environment, check=True)

    first = run()
    assert (tmp_path / "cache").is_dir()  # FFCx compiled into the fresh cache
    assert first.stderr == ""
    verbose = run("-v")
    lines = verbose.stderr.splitlines()
    assert lines and all(line.startswith("[rank 0] ") for line in lines)


SESSION = """
from fabric_dolfinx.material import OrthotropicSVK, svk_material
from fabric_dolfinx.part.tension import TensionSetup
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.tension import TensionTest

test = TensionTest(direction="course", size=50.0, elements=2, max_strain=0.1)
material = svk_material(OrthotropicSVK(10.0, 8.0, 0.3, 2.0))
print(TensionSetup(material, test, SolverOptions(steps=2)).run().force_gf_per_cm[-1])
"""


def test_a_python_session_that_compiles_forms_prints_no_compiler_lines(tmp_path):
    """UFL's `logging.basicConfig()` gives the root logger a stderr handler and the C build
    lowers the root logger's level while it logs its gcc command lines there: a Python
    session (the README's snippet) printed about 20 of them (`fabric_dolfinx.jit`)."""
    environment = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")}
    run = subprocess.run(
        [sys.executable, "-c", SESSION],
        capture_output=True,
        text=True,
        env=environment,
        check=True,
        cwd=tmp_path,
    )
    assert (tmp_path / "cache" / "fenics").is_dir()  # FFCx compiled into the fresh cache
    assert run.stderr == ""
    assert float(run.stdout) > 0.0


QUIET_SCENE = """
name = "quiet"
fidelity = "fast"
[fabric]
preset = "cotton-20s2"
stitch = 5.5
[meso]
cases = ["uniaxial-course"]
[surface]
path = "{surface}"
[macro]
directions = ["course"]
"""


def test_knitmech_run_off_a_terminal_prints_one_line_per_stage(tmp_path):
    """`make demo`'s run printed about 70 lines off a terminal, 42 of them one per RVE load
    step (issue 31): now one line per stage item on stderr, the solvers' details at -v."""
    scene = tmp_path / "scene.toml"
    scene.write_text(QUIET_SCENE.format(surface=default_surface_path()))
    command = [str(Path(sys.executable).parent / "knitmech"), "run", str(scene)]
    command += ["-o", str(tmp_path / "out"), "--cache-dir", str(tmp_path / "cache")]
    environment = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "xdg")}
    run = subprocess.run(command, capture_output=True, text=True, env=environment, check=True)
    lines = run.stderr.splitlines()
    stages = ["geometry", "meso uniaxial-course", "surface", "macro course"]  # surface: given
    assert [line.split(": ")[1] for line in lines] == stages, run.stderr
    assert all(line.startswith("INFO knitmech.stages.cache: ") for line in lines)
    assert all(": computed in " in line for line in lines)
