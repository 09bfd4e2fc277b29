"""Fixture of the mesh tests: areas and boundary lengths of a tagged fabric mesh."""

import ufl
from dolfinx import fem
from mpi4py import MPI


def integrate(tagged, name=None):
    """Area of the mesh, or length of boundary `name` (mm^2, mm), summed over ranks."""
    domain = tagged.mesh
    if name is None:
        form = 1.0 * ufl.dx(domain=domain)
    else:
        ds = ufl.Measure("ds", domain=domain, subdomain_data=tagged.facet_tags)
        form = 1.0 * ds(tagged.boundaries[name])
    return domain.comm.allreduce(fem.assemble_scalar(fem.form(form)), op=MPI.SUM)
