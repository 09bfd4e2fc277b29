"""The declared runtime dependencies (pyproject.toml) are satisfied by the packages installed
from Debian 12, so that `make bootstrap` installs nothing over them (pip would replace a
Debian build whose version is below a bound), and none of them is a package Debian installs
without pip metadata under its own name (h5py, gmsh: pip would not see them)."""

import importlib.metadata
import subprocess
import sys
import tomllib
from pathlib import Path

from packaging.requirements import Requirement

ROOT = Path(__file__).resolve().parents[3]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]


def test_every_runtime_dependency_is_satisfied_by_the_installed_package():
    declared = [Requirement(text) for text in PROJECT["dependencies"]]
    assert {r.name for r in declared} >= {"numpy", "scipy", "numba", "mpi4py", "matplotlib"}
    for requirement in declared:
        installed = importlib.metadata.version(requirement.name)
        assert requirement.specifier.contains(installed), (requirement, installed)


def test_packages_without_pip_metadata_are_not_runtime_dependencies():
    names = {Requirement(text).name for text in PROJECT["dependencies"]}
    assert names.isdisjoint({"h5py", "gmsh", "fenics-dolfinx", "petsc4py"})
    standalone = {Requirement(t).name for t in PROJECT["optional-dependencies"]["standalone"]}
    assert standalone == {"h5py", "gmsh"}


def test_without_dolfinx_fabric_dolfinx_says_in_one_line_how_to_get_it():
    """DOLFINx hidden (its folder off sys.path): the import fails with one line."""
    code = (
        "import sys; sys.path = [p for p in sys.path if 'petsc' not in p]\nimport fabric_dolfinx\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert run.returncode == 1
    message = run.stderr.strip().splitlines()[-1]
    assert message.startswith("ImportError: fabric_dolfinx needs DOLFINx 0.5.2, a system package")
    assert "make bootstrap" in message and "conda install -c conda-forge" in message
