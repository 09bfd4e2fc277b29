"""Response surfaces: B-spline stress laws of the knit, their evaluation, checks and HDF5 file.

This package implements `docs/surface-format.md` (the normative contract between the scales):

- `splines`: `Spline1D` and `Spline2D` with the Taylor extension of each univariate basis
  outside the spline's domain;
- `response`: `ResponseSurface` (S11(E11, E22), S22(E11, E22), S12(E12) in N/mm, optionally
  derived from a potential);
- `hdf5`: the atomic writer `write_surface` and the checking reader `read_surface`;
- `checks`: the surface as a material (tangent symmetry and sign, homogeneous tension).

It needs only numpy, scipy and h5py (`fabric_dolfinx` imports it): no numba, no matplotlib,
no dolfinx.
"""

from rve_rod.surface.checks import homogeneous_response, softest_normal_tangents, tangent_asymmetry
from rve_rod.surface.hdf5 import (
    FORMAT,
    UNITS,
    VERSION,
    SurfaceFileError,
    generator_info,
    read_surface,
    write_surface,
)
from rve_rod.surface.response import (
    EXTENSION_ORDERS,
    GROUP_INPUTS,
    STRESS_GROUPS,
    FitSamples,
    ResidualStats,
    ResponseSurface,
    StressResult,
    energy_surface,
)
from rve_rod.surface.splines import Spline1D, Spline2D

__all__ = [
    "EXTENSION_ORDERS",
    "FORMAT",
    "GROUP_INPUTS",
    "STRESS_GROUPS",
    "UNITS",
    "VERSION",
    "FitSamples",
    "ResidualStats",
    "ResponseSurface",
    "Spline1D",
    "Spline2D",
    "StressResult",
    "SurfaceFileError",
    "energy_surface",
    "generator_info",
    "homogeneous_response",
    "read_surface",
    "softest_normal_tangents",
    "tangent_asymmetry",
    "write_surface",
]
