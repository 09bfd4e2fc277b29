"""A multi-region fabric part for the serial-vs-mpirun test: prints its curves as JSON.

A plate with a hole, a stiffer band (course direction 30 degrees) across the middle of a
softer fabric whose course direction varies with y; clamped on the left, pulled on the
right by a prescribed displacement, the top held by a roller.
"""

import json

from mpi4py import MPI

from fabric_dolfinx.material import OrthotropicSVK, svk_material
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.part.problem import PartProblem
from fabric_dolfinx.part.regions import Region
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.expression import FieldExpression
from fabric_dolfinx.spec.part import BoundaryCondition, MeshSpec
from rve_rod.jsonable import to_jsonable

tagged = make_mesh(MeshSpec("plate_with_hole", {"radius": 8.0}, element_size=6.0))
regions = [
    Region("fabric", svk_material(OrthotropicSVK(1.0, 0.5, 0.3, 0.2)), FieldExpression("y")),
    Region(
        "band",
        svk_material(OrthotropicSVK(3.0, 1.0, 0.2, 0.4)),
        angle=30.0,
        where=FieldExpression("abs(x - 25) < 8"),
    ),
]
conditions = [
    BoundaryCondition("left", "clamp"),
    BoundaryCondition("right", "displacement", vector=(5.0, 1.0)),
    BoundaryCondition("top", "roller", component="y"),
    BoundaryCondition("hole", "free"),
]
result = PartProblem(tagged, regions, conditions, options=SolverOptions(steps=3)).run()
if MPI.COMM_WORLD.rank == 0:
    curves = {name: curve._asdict() for name, curve in result.boundaries.items()}
    print(
        json.dumps(to_jsonable({"ranks": result.ranks, "dofs": result.dofs, "boundaries": curves}))
    )
