"""Fabric-scale solver on DOLFINx: response-surface membrane material, meshes, load stepping.

Depends on `rve_rod` only through its numpy-only interface modules (`FABRIC_USES_OF_RVE_ROD`
in tests/project/unit/test_imports.py checks the list): `rve_rod.surface` (the surface file reader),
`rve_rod.stepping` (the load-step controller both scales share), `rve_rod.errors`,
`rve_rod.limits`, `rve_rod.units`, and for the command line `rve_rod.help_format`,
`rve_rod.log_setup`, `rve_rod.outputs` and the package's version (`rve_rod.__version__`).

DOLFINx is a system package that pip cannot install (pyproject.toml does not declare it): its
presence and version are checked here, without importing it (the pipeline plans with
`fabric_dolfinx.spec` and loads DOLFINx only to solve), and a missing or other DOLFINx is one
line saying how to get it.
"""

import importlib.metadata
import importlib.util

DOLFINX_VERSION = "0.5"
"""The DOLFINx series the package is written for (its 0.5.2 API)."""

_GET_DOLFINX = (
    "on Debian 12 `make bootstrap` (python3-dolfinx, and a venv made from /usr/bin/python3 "
    "with --system-site-packages); with conda, `conda install -c conda-forge "
    "fenics-dolfinx=0.5.2`"
)

if importlib.util.find_spec("dolfinx") is None:
    raise ImportError(f"fabric_dolfinx needs DOLFINx 0.5.2, a system package: {_GET_DOLFINX}")
try:
    _found = importlib.metadata.version("fenics-dolfinx")
except importlib.metadata.PackageNotFoundError:
    _found = None  # a build without package metadata: taken as it is
if _found is not None and not _found.startswith(f"{DOLFINX_VERSION}."):
    raise ImportError(
        f"fabric_dolfinx needs DOLFINx {DOLFINX_VERSION}.x (its API), found {_found}: "
        + _GET_DOLFINX
    )
