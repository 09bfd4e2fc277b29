"""Yarn-level engine: loop geometry, Cosserat rods, contact, periodic RVE, homogenization.

Importing the package is cheap on purpose (no numba, no matplotlib): `fabric_dolfinx` reads
surface files through `rve_rod.surface` and shares `rve_rod.errors` and `rve_rod.units`.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("knitmech")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0+unknown"
