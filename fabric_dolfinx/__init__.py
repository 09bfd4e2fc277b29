"""Fabric-scale solver on DOLFINx: response-surface membrane material, meshes, load stepping.

Depends on `rve_rod` only through its numpy-only interface modules (`FABRIC_USES_OF_RVE_ROD`
in tests/project/unit/test_imports.py checks the list): `rve_rod.surface` (the surface file reader),
`rve_rod.stepping` (the load-step controller both scales share), `rve_rod.errors`,
`rve_rod.limits`, `rve_rod.units`, and for the command line `rve_rod.help_format`,
`rve_rod.log_setup` and `rve_rod.outputs`.
"""
