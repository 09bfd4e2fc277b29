"""Curved reference surfaces in space for the membrane in space (gdim 3 quadrilateral meshes).

- `tube_mesh`: a circular tube of `radius` and `length` along z from z = 0, structured
  (circle arcs extruded in layers); boundaries "bottom" (z = 0) and "top" (z = length).
  With `quarter=True` only the quadrant x, y >= 0, with the two more boundaries "x0" (the
  edge in the plane x = 0) and "y0" (in y = 0) for symmetry conditions.

`axis_fields` gives the course and normal-side fields `membrane.forms.curved_frame` needs for
surfaces around an axis: the course around the axis (a tube's circumference, the default of
the tube) or along it, the normal pointing away from the axis. Lengths mm.
"""

import math

import numpy as np
import ufl
from mpi4py import MPI

from fabric_dolfinx.gmsh_api import gmsh
from fabric_dolfinx.mesh.tagged import TaggedMesh, mesh_gmsh_model
from rve_rod.errors import check_positive

__all__ = [
    "axis_fields",
    "tube_mesh",
]


def axis_fields(course: str = "around", axis=(0.0, 0.0, 1.0), point=(0.0, 0.0, 0.0)):
    """(course field, side field), functions of the position X (UFL (3,)) for `curved_frame`.

    Args:
        course: "around" (axis x (X - point), circumferential) or "along" (the axis
            direction, projected onto the surface by the frame).
        axis: the axis direction (3,); point: a point on it (mm).
    The side field is the part of X - point normal to the axis: the normal points away
    from the axis, so a positive pressure inflates a tube.
    """
    direction = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    a = ufl.as_vector([float(c) for c in direction])
    origin = ufl.as_vector([float(c) for c in point])

    def side(x):
        offset = x - origin
        return offset - ufl.dot(offset, a) * a

    def around(x):
        return ufl.cross(a, x - origin)

    def along(x):
        return a

    return (around if course == "around" else along), side


def tube_mesh(
    radius: float,
    length: float,
    element_size: float,
    *,
    quarter: bool = False,
    comm: MPI.Comm = MPI.COMM_WORLD,
) -> TaggedMesh:
    """The quadrilateral mesh of a tube (see the module docstring), collective."""
    check_positive("radius", radius, "mm")
    check_positive("length", length, "mm")
    check_positive("element_size", element_size, "mm")
    arcs = 1 if quarter else 4

    def build():
        centre = gmsh.model.geo.addPoint(0.0, 0.0, 0.0)
        angles = [0.5 * math.pi * i for i in range(arcs + 1)]
        points = [
            gmsh.model.geo.addPoint(radius * math.cos(a), radius * math.sin(a), 0.0)
            for a in angles[: arcs if not quarter else arcs + 1]
        ]
        if not quarter:
            points.append(points[0])
        around = max(1, math.ceil(0.5 * math.pi * radius / element_size))
        layers = max(1, math.ceil(length / element_size))
        curves = []
        for i in range(arcs):
            arc = gmsh.model.geo.addCircleArc(points[i], centre, points[i + 1])
            gmsh.model.geo.mesh.setTransfiniteCurve(arc, around + 1)
            curves.append(arc)
        extruded = gmsh.model.geo.extrude(
            [(1, c) for c in curves], 0.0, 0.0, length, numElements=[layers], recombine=True
        )
        gmsh.model.geo.remove([(0, centre)])
        gmsh.model.geo.synchronize()
        surfaces = [tag for dim, tag in extruded if dim == 2]
        named = {"bottom": [], "top": [], "x0": [], "y0": []}
        for _, tag in gmsh.model.getEntities(1):
            _, _, z0, x1, y1, z1 = gmsh.model.getBoundingBox(1, tag)
            tolerance = 1e-9 * max(radius, length)
            if z1 < tolerance:
                named["bottom"].append(tag)
            elif z0 > length - tolerance:
                named["top"].append(tag)
            elif quarter and x1 < tolerance:
                named["x0"].append(tag)
            elif quarter and y1 < tolerance:
                named["y0"].append(tag)
        for name, tags in named.items():
            if tags:
                gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, tags), name)
        gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, surfaces), "fabric")
        gmsh.model.mesh.generate(2)

    return mesh_gmsh_model(build, comm, source="tube", gdim=3)
