"""Homogenization: RVE load paths, (E, S) samples, B-spline response-surface fits, generation.

Modules: `sampling` (the load paths of a surface: biaxial rays and pure shear), `samples`
(RVE run results and their conversion to (E, S) samples), `fit` (regularized least-squares
stress and energy fits), `generate` (parallel, cached, resumable runs and the whole pipeline),
`analytic` (an analytic stand-in for the RVE with the same interface), `plot` (the figure of
the fitted surfaces; imports matplotlib). Importing this package imports neither numba nor
matplotlib.
"""
