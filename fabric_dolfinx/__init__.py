"""Fabric-scale solver on DOLFINx: response-surface membrane material, meshes, load stepping.

Depends on `rve_rod` only through its numpy-only interface modules: `rve_rod.surface` (the
surface file reader), `rve_rod.errors` and `rve_rod.units`.
"""
