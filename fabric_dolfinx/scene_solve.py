"""A fabric part under named boundary conditions: regions, loads, load path, output.

`FabricProblem` puts together a tagged mesh (`fabric_dolfinx.shapes`), its regions (one
material and course direction each, `fabric_dolfinx.regions`) and its boundary conditions
(`fabric_dolfinx.boundary`): the residual is the sum of the membrane forms of the regions
(`membrane.membrane_forms` over each region's cells) minus the tractions, solved by the
shared `LoadStepper` (load factor t from 0 to 1). After every converged step it records the
reaction force (N) and the mean displacement (mm) of every named boundary, and optionally
writes the cell fields (`SceneFields`) to XDMF.
"""

import logging
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np
import ufl
from dolfinx import fem, geometry
from dolfinx.io import XDMFFile
from mpi4py import MPI

from fabric_dolfinx.boundary import BoundaryLoads
from fabric_dolfinx.domain import StrainRangeCheck
from fabric_dolfinx.graded import graded_material
from fabric_dolfinx.material import Material
from fabric_dolfinx.membrane import flat_frame, membrane_forms, membrane_state
from fabric_dolfinx.mesh import TaggedMesh
from fabric_dolfinx.part_spec import BoundaryCondition
from fabric_dolfinx.regions import Region, assign_regions, cell_field
from fabric_dolfinx.solve import (
    LoadStepper,
    PathResult,
    SolverOptions,
    StepRecord,
    boundary_indicator,
)
from rve_rod.errors import ConvergenceError, InputError, check_integer

__all__ = [
    "BoundaryCurve",
    "FabricProblem",
    "ProbeRecord",
    "SceneFields",
    "SceneResult",
    "principal_stresses",
    "shear_angle",
]

logger = logging.getLogger(__name__)


class BoundaryCurve(NamedTuple):
    """Force-displacement record of one boundary (index 0: the unloaded state).

    Attributes:
        kind: the condition's kind.
        length: undeformed length (mm).
        force: (k+1, 2) total force (Fx, Fy) the fabric receives there (N): the reaction of a
            Dirichlet boundary, the applied load of a traction boundary, 0 on a free one.
        displacement: (k+1, 2) mean displacement (ux, uy) over the boundary (mm).
    """

    kind: str
    length: float
    force: np.ndarray
    displacement: np.ndarray


class ProbeRecord(NamedTuple):
    """The state of the cell that holds a probe point, per step (index 0: unloaded).

    Attributes:
        point: (x, y) the point asked for (mm).
        centre: (x, y) centre of the cell holding it, where the values are taken (mm).
        strain: (k+1, 2, 2) Green-Lagrange strain E (global frame, -).
        cauchy: (k+1, 2, 2) Cauchy stress (N/mm).
        shear_angle: (k+1,) change of the angle between the course and wale directions
            (degrees; positive when it closes): asin(a1.C a2 / sqrt(a1.C a1 a2.C a2)),
            C = I + 2E, a1, a2 the material axes of the cell.
    """

    point: tuple[float, float]
    centre: np.ndarray
    strain: np.ndarray
    cauchy: np.ndarray
    shear_angle: np.ndarray


class SceneResult(NamedTuple):
    """A load path of a fabric part.

    Attributes:
        load_factor: (k+1,) t of each output state, 0 first.
        boundaries: boundary name -> BoundaryCurve.
        newton_iterations: (k,) Newton iterations of each converged step.
        cutbacks: failed attempts retried with half the increment.
        outside_domain: region name -> whether its strains left its surface's domain.
        probes: probe name -> ProbeRecord.
        dofs: global degrees of freedom; ranks: MPI ranks; wall_time_s: path time (s).
        path: the solver's record.
    """

    load_factor: np.ndarray
    boundaries: dict[str, BoundaryCurve]
    newton_iterations: np.ndarray
    cutbacks: int
    outside_domain: dict[str, bool]
    probes: dict[str, ProbeRecord]
    dofs: int
    ranks: int
    wall_time_s: float
    path: PathResult


def shear_angle(strain: np.ndarray, angle: float) -> float:
    """Change of the angle between the material axes (degrees) under the Green-Lagrange
    strain `strain` (2, 2), axes at `angle` radians (see ProbeRecord)."""
    C = np.eye(2) + 2.0 * strain
    a1 = np.array([np.cos(angle), np.sin(angle)])
    a2 = np.array([-np.sin(angle), np.cos(angle)])
    cosine = a1 @ C @ a2 / np.sqrt((a1 @ C @ a1) * (a2 @ C @ a2))
    return float(np.degrees(np.arcsin(np.clip(cosine, -1.0, 1.0))))


def principal_stresses(stress: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal values (n, 2), largest first, and the unit direction (n, 2) of the largest
    of symmetric 2 x 2 tensors `stress` (n, 2, 2) (closed form, Mohr's circle)."""
    mean = 0.5 * (stress[:, 0, 0] + stress[:, 1, 1])
    half = 0.5 * (stress[:, 0, 0] - stress[:, 1, 1])
    radius = np.hypot(half, stress[:, 0, 1])
    values = np.stack([mean + radius, mean - radius], axis=1)
    theta = 0.5 * np.arctan2(stress[:, 0, 1], half)
    return values, np.stack([np.cos(theta), np.sin(theta)], axis=1)


class FabricProblem:
    """Mesh, regions, boundary conditions, forms and solver of a fabric part, built once.

    Args:
        tagged: the mesh with its named boundaries and regions.
        regions: the regions (at least one; every cell in one).
        conditions: the boundary conditions (at least one Dirichlet condition, or the
            problem has rigid-body modes).
        element_degree: Lagrange degree of the displacement (1 or 2).
        quadrature_degree: Gauss rule exactness; None: twice the element degree.
        options: Newton and load-stepping settings.
        probes: name -> (x, y) mm: points whose cell's state is recorded every step.

    Attributes:
        u: the displacement (mm); cells: the RegionCells; loads: the BoundaryLoads;
        angle: DG0 course direction (radians); stepper: the LoadStepper.
    """

    def __init__(
        self,
        tagged: TaggedMesh,
        regions: Sequence[Region],
        conditions: Sequence[BoundaryCondition],
        *,
        element_degree: int = 1,
        quadrature_degree: int | None = None,
        options: SolverOptions | None = None,
        probes: Mapping[str, tuple[float, float]] | None = None,
    ):
        check_integer("element_degree", element_degree, 1, 2)
        self.tagged, self.regions = tagged, tuple(regions)
        self.options = options or SolverOptions()
        mesh = tagged.mesh
        self.cells = assign_regions(tagged, self.regions)
        space = fem.VectorFunctionSpace(mesh, ("Lagrange", element_degree))
        self.u = fem.Function(space, name="displacement")
        self.loads = BoundaryLoads(tagged, space, conditions)
        self.conditions = self.loads.conditions
        scalars = fem.FunctionSpace(mesh, ("DG", 0))
        self.angle = cell_field(
            scalars, self.cells, [r.angle for r in self.regions], "angle", scale=np.pi / 180.0
        )
        self.stitch = cell_field(scalars, self.cells, [r.stitch for r in self.regions], "stitch")
        self.materials = tuple(self._material(number) for number in range(len(self.regions)))
        self.frame = flat_frame(mesh, self.angle)
        self.quadrature_degree = quadrature_degree or 2 * element_degree
        dx = ufl.Measure("dx", domain=mesh, subdomain_data=self.cells.tags)
        residual = jacobian = None
        for number, material in enumerate(self.materials):
            forms = membrane_forms(
                self.u, material.law, self.frame, self.quadrature_degree, dx(number)
            )
            residual = forms.residual if residual is None else residual + forms.residual
            jacobian = forms.jacobian if jacobian is None else jacobian + forms.jacobian
        if self.loads.external is not None:
            residual = residual - self.loads.external
        reactions = {
            c.name: boundary_indicator(space, tagged.facets(c.name))
            for c in self.conditions
            if c.dirichlet
        }
        self.stepper = LoadStepper(
            residual, jacobian, self.u, self.loads.bcs, options=self.options, reactions=reactions
        )
        self._displacement_forms = self.loads.displacement_forms(self.u)
        self.dofs = space.dofmap.index_map.size_global * space.dofmap.index_map_bs
        self.probes = {name: _probe_cell(mesh, point) for name, point in (probes or {}).items()}
        self._probe_points = {name: tuple(point) for name, point in (probes or {}).items()}

    def probe_values(self, fields: "SceneFields") -> dict[str, tuple]:
        """Probe name -> (centre, strain (2, 2), cauchy (2, 2), shear angle) of its cell, from
        the cell fields (collective: the owning rank's values)."""
        comm = self.tagged.mesh.comm
        values = {}
        owned = self.tagged.mesh.topology.index_map(2).size_local
        for name, cell in self.probes.items():
            local = None
            if 0 <= cell < owned:
                dof = fields.cell_dofs[cell]
                strain = fields.strain.x.array.reshape(-1, 2, 2)[dof].copy()
                local = (
                    self.cells.centres[cell].copy(),
                    strain,
                    fields.cauchy.x.array.reshape(-1, 2, 2)[dof].copy(),
                    shear_angle(strain, self.angle.x.array[dof]),
                )
            values[name] = next(v for v in comm.allgather(local) if v is not None)
        return values

    def _material(self, number: int) -> Material:
        """The region's material; a graded region's from its family and the stitch field,
        after checking that its cells' stitch values lie in the family's range."""
        region = self.regions[number]
        if region.family is None:
            return region.material
        values = self.stitch.x.array[self.stitch.function_space.dofmap.list.array][
            self.cells.cells(number)
        ]
        comm = self.tagged.mesh.comm
        low = comm.allreduce(values.min() if values.size else np.inf, op=MPI.MIN)
        high = comm.allreduce(values.max() if values.size else -np.inf, op=MPI.MAX)
        members = [value for value, _ in region.family]
        if low < min(members) - 1e-12 or high > max(members) + 1e-12:
            raise InputError(
                f"region {region.name!r}: stitch values {low:.4g} ... {high:.4g} mm leave the "
                f"family's range [{min(members):g}, {max(members):g}] mm"
            )
        return graded_material(region.family, self.stitch)

    def boundary_displacements(self) -> dict[str, np.ndarray]:
        """Boundary name -> mean displacement (ux, uy) mm at the current state (collective)."""
        comm = self.tagged.mesh.comm
        return {
            name: np.array([comm.allreduce(fem.assemble_scalar(f), op=MPI.SUM) for f in forms])
            / self.loads.lengths[name]
            for name, forms in self._displacement_forms.items()
        }

    def run(
        self,
        xdmf: Path | str | None = None,
        on_step: Callable[[float, "SceneFields | None"], None] | None = None,
        fields: bool = False,
    ) -> SceneResult:
        """Follow the load path t = 0 -> 1 from the unloaded part.

        Args:
            xdmf: write the SceneFields of every step to this XDMF file (time = t).
            on_step: called after every converged step with (t, SceneFields or None).
            fields: evaluate the cell fields after every step even without xdmf.

        Raises ConvergenceError whose `history` is the SceneResult of the converged steps.
        """
        self.u.x.array[:] = 0.0
        self.loads.set_load_factor(0.0)
        checks = {
            region.name: StrainRangeCheck(
                membrane_state(self.u, self.materials[number].law, self.frame).strain,
                self.tagged.mesh,
                self.materials[number].domain,
                self.quadrature_degree,
                self.cells.cells(number),
            )
            for number, region in enumerate(self.regions)
            if self.materials[number].domain is not None
        }
        outside = {region.name: False for region in self.regions}
        cell_fields = SceneFields(self) if (xdmf or fields or self.probes) else None
        if cell_fields is not None:
            cell_fields.update()
        probed = [self.probe_values(cell_fields)] if self.probes else []
        states = [(0.0, self.boundary_displacements())]
        start = time.perf_counter()

        def after_step(step: StepRecord, output: XDMFFile | None) -> None:
            for name, check in checks.items():
                outside[name] = check(step.load_factor) or outside[name]
            states.append((step.load_factor, self.boundary_displacements()))
            if cell_fields is not None:
                cell_fields.update()
                if output is not None:
                    cell_fields.write(output, step.load_factor)
                if self.probes:
                    probed.append(self.probe_values(cell_fields))
            if on_step is not None:
                on_step(step.load_factor, cell_fields)

        def solve(output):
            if output is not None:
                cell_fields.write(output, 0.0)
            return self.stepper.run(
                self.loads.set_load_factor, lambda step: after_step(step, output)
            )

        try:
            if xdmf is not None:
                with XDMFFile(self.tagged.mesh.comm, str(xdmf), "w") as output:
                    output.write_mesh(self.tagged.mesh)
                    path = solve(output)
            else:
                path = solve(None)
        except ConvergenceError as error:
            partial = self._result(
                error.history, states, probed, outside, time.perf_counter() - start
            )
            raise ConvergenceError(
                str(error), last_converged=error.last_converged, history=partial
            ) from None
        return self._result(path, states, probed, outside, time.perf_counter() - start)

    def _result(self, path: PathResult, states, probed, outside, wall_time: float) -> SceneResult:
        states = states[: len(path.steps) + 1]
        probed = probed[: len(path.steps) + 1]
        probes = {
            name: ProbeRecord(
                point=self._probe_points[name],
                centre=probed[0][name][0],
                strain=np.array([p[name][1] for p in probed]),
                cauchy=np.array([p[name][2] for p in probed]),
                shear_angle=np.array([p[name][3] for p in probed]),
            )
            for name in self.probes
        }
        load_factor = np.array([t for t, _ in states])
        curves = {}
        for condition in self.conditions:
            name = condition.name
            if condition.dirichlet:
                forces = [np.zeros(2)] + [s.reactions[name] for s in path.steps]
            elif condition.kind == "traction":
                forces = [self.loads.applied_force(name, t) for t in load_factor]
            else:
                forces = [np.zeros(2)] * load_factor.size
            curves[name] = BoundaryCurve(
                kind=condition.kind,
                length=self.loads.lengths[name],
                force=np.array(forces),
                displacement=np.array([d[name] for _, d in states]),
            )
        return SceneResult(
            load_factor=load_factor,
            boundaries=curves,
            newton_iterations=np.array([s.iterations for s in path.steps], dtype=int),
            cutbacks=path.cutbacks,
            outside_domain=dict(outside),
            probes=probes,
            dofs=self.dofs,
            ranks=self.tagged.mesh.comm.size,
            wall_time_s=wall_time,
            path=path,
        )


class SceneFields:
    """Cell fields of a FabricProblem's state for ParaView (DG0: the value at the centre).

    Attributes:
        displacement: u in the mesh's coordinate degree (mm).
        strain: Green-Lagrange strain E (2 x 2, -); cauchy: Cauchy stress (2 x 2, N/mm).
        principal_stress: (sigma_1, sigma_2), sigma_1 >= sigma_2 (N/mm).
        principal_direction: unit vector of sigma_1 (deformed configuration).
        region: region number; stitch: stitch value (0 where none);
        course_direction: degrees from the x axis.
        cell_dofs: (local cells,) the DG0 dof of each cell.
    """

    def __init__(self, problem: FabricProblem):
        mesh = problem.tagged.mesh
        u = problem.u
        tensors = fem.TensorFunctionSpace(mesh, ("DG", 0))
        vectors = fem.VectorFunctionSpace(mesh, ("DG", 0))
        scalars = fem.FunctionSpace(mesh, ("DG", 0))
        points = tensors.element.interpolation_points()
        self.strain = fem.Function(tensors, name="green_lagrange_strain")
        self.cauchy = fem.Function(tensors, name="cauchy_stress")
        self.principal_stress = fem.Function(vectors, name="principal_stress")
        self.principal_direction = fem.Function(vectors, name="principal_direction")
        cells = problem.cells
        self.region = cell_field(scalars, cells, list(range(len(problem.regions))), "region")
        self.stitch = problem.stitch
        self.course_direction = cell_field(
            scalars, cells, [r.angle for r in problem.regions], "course_direction"
        )
        self._regions = []
        for number, material in enumerate(problem.materials):
            stress = membrane_state(u, material.law, problem.frame)
            self._regions.append(
                (
                    cells.cells(number),
                    fem.Expression(stress.reference_strain, points),
                    fem.Expression(stress.cauchy, points),
                )
            )
        self.cell_dofs = tensors.dofmap.list.array.reshape(cells.index.size, -1)[:, 0]
        self._u = u
        degree = mesh.geometry.cmap.degree
        if u.function_space.ufl_element().degree() == degree:
            self.displacement = u
        else:
            space = fem.VectorFunctionSpace(mesh, ("Lagrange", degree))
            self.displacement = fem.Function(space, name="displacement")

    def update(self) -> None:
        """Evaluate the fields at the current displacement."""
        strain = self.strain.x.array.reshape(-1, 2, 2)
        cauchy = self.cauchy.x.array.reshape(-1, 2, 2)
        for cells, strain_expression, cauchy_expression in self._regions:
            if cells.size == 0:
                continue
            dofs = self.cell_dofs[cells]
            strain[dofs] = strain_expression.eval(cells).reshape(-1, 2, 2)
            cauchy[dofs] = cauchy_expression.eval(cells).reshape(-1, 2, 2)
        values, directions = principal_stresses(cauchy)
        self.principal_stress.x.array[:] = values.ravel()
        self.principal_direction.x.array[:] = directions.ravel()
        if self.displacement is not self._u:
            self.displacement.interpolate(self._u)

    def functions(self) -> tuple[fem.Function, ...]:
        """Every field, in the order they are written."""
        return (
            self.displacement,
            self.strain,
            self.cauchy,
            self.principal_stress,
            self.principal_direction,
            self.region,
            self.stitch,
            self.course_direction,
        )

    def write(self, output: XDMFFile, time: float) -> None:
        """Append every field at `time` (the load factor)."""
        for function in self.functions():
            output.write_function(function, time)


def _probe_cell(mesh, point) -> int:
    """The local cell holding `point` (x, y) mm on this rank, or -1; InputError when no rank
    holds it (collective)."""
    points = np.array([[float(point[0]), float(point[1]), 0.0]])
    tree = geometry.BoundingBoxTree(mesh, mesh.topology.dim)
    candidates = geometry.compute_collisions(tree, points)
    colliding = geometry.compute_colliding_cells(mesh, candidates, points)
    links = colliding.links(0)
    owned = mesh.topology.index_map(2).size_local
    local = [int(c) for c in links if c < owned]
    cell = local[0] if local else -1
    found = mesh.comm.allgather(cell >= 0)
    if not any(found):
        raise InputError(f"probe point ({point[0]:.6g}, {point[1]:.6g}) mm is not in the part")
    # one owner: the lowest rank that holds it
    return cell if found.index(True) == mesh.comm.rank else -1
