"""The knit-loop RVE: one periodic single-jersey loop of Cosserat rods with frictional contact.

Modules: `load_cases` (the six macro load cases), `yarn` (the paper's yarn model: adjusted
radius, stiffness scalings, contact laws), `cell` (the loop as one periodic rod patch with its
conditions), `coupling` (contact with the lattice images as a rod load), `macro` (macro
deformation and stress P), `simulate` (load stepping, per-step outputs, results).
See docs/rve.md.
"""
