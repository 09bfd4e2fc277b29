"""The knit-loop RVE: one periodic single-jersey loop of Cosserat rods with frictional contact.

Modules: `load_cases` (the macro load cases), `yarn` (the paper's yarn model: adjusted
radius, stiffness scalings, contact laws), `cell` (the loop as one periodic rod patch with its
conditions and rest state), `coupling` (contact with the lattice images as a rod load), `macro`
(macro deformation and stress P), `simulate` (load stepping, per-step outputs, results),
`paper.data` and `paper.comparison` (the paper group's RVE output, and ours along it).
See docs/rve.md.
"""

from rve_rod.rve.engine import RodRve, surface_engine
from rve_rod.rve.load_cases import (
    CASES,
    BiaxialRay,
    LoadCase,
    Shear,
    StripBiaxialCourse,
    StripBiaxialWale,
    UniaxialCourse,
    UniaxialWale,
    load_case,
)
from rve_rod.rve.simulation import RveResult, RveSettings, RveStep, run_cell, simulate

__all__ = [
    "CASES",
    "BiaxialRay",
    "LoadCase",
    "RodRve",
    "RveResult",
    "RveSettings",
    "RveStep",
    "Shear",
    "StripBiaxialCourse",
    "StripBiaxialWale",
    "UniaxialCourse",
    "UniaxialWale",
    "load_case",
    "run_cell",
    "simulate",
    "surface_engine",
]
