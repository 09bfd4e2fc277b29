"""A fabric part: its problem (forms, boundary conditions, load constants), its load path and
what is recorded along it. One problem for every kind of part, plane or in space.

`PartProblem` puts together a tagged mesh (`fabric_dolfinx.mesh.shapes`, or a curved surface in
space), its regions (one material and course direction each, `fabric_dolfinx.part.regions`) and its
boundary conditions (`fabric_dolfinx.part.boundary`, 2 or 3 components): the residual is the
membrane forms (`membrane.forms.membrane_forms`, every cell's region law evaluated at the
quadrature points, `membrane.quadrature`) minus the tractions and, for
a part in space (`SpaceSpec`), minus the follower pressure, the indenter's contact and the
normal stabilization. The shared `LoadStepper` solves it (load factor t from 0 to 1).
`PartProblem.run` follows the path and records, at t = 0 and after every converged step,
what observers measure: the boundaries' reactions (from the stepper) and mean displacements,
the range checks of the response surfaces, the probes, the cell fields (`PartFields`, to
XDMF), and in space the indenter's force, the largest displacement and the wrinkled and
slack areas.

Slack and wrinkled zones in space. Where a principal stress is not positive the membrane has
no stiffness across the wrinkles, and where the fabric lies flat and unstressed (e.g. at
t = 0 under in-plane loads) none out of its plane. The optional normal stabilization adds
c ((u - u_n) . N) (v . N) dA to the residual (c N/mm^3, u_n the last converged state, N the
reference normal): a spring to the previous step that carries a step through such zones. It
vanishes for purely in-plane motion (so in-plane loading gives the plane membrane's result
exactly). After each stabilized step Newton runs once more without it, from the stabilized
state: where the fabric is taut this converges and the step is exact; where it cannot (slack
or wrinkled zones) the stabilized state is kept and its force, c int |(u - u_n) . N| dA, is
reported for the step: it must stay small against the loads. A flat part under pressure or
indentation starts each step from flat with a one-mode dome (`fabric_dolfinx.part.dome`).
"""

import logging
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import NamedTuple

import numpy as np
import ufl
from dolfinx import fem
from dolfinx.io import XDMFFile
from mpi4py import MPI
from petsc4py import PETSc

from fabric_dolfinx.graded import graded_material
from fabric_dolfinx.material import Material
from fabric_dolfinx.membrane.forms import green_lagrange, material_frame, membrane_forms
from fabric_dolfinx.membrane.loads import (
    Indenter,
    PlaneIndenter,
    RevolutionIndenter,
    SphereIndenter,
    contact_pressure,
    contact_residual,
    pressure_residual,
)
from fabric_dolfinx.membrane.quadrature import QuadratureMaterial
from fabric_dolfinx.mesh.surfaces import axis_fields
from fabric_dolfinx.mesh.tagged import TaggedMesh
from fabric_dolfinx.part.boundary import BoundaryLoads, BoundaryMeans, LoadConstants
from fabric_dolfinx.part.dome import Dome
from fabric_dolfinx.part.fields import PartFields
from fabric_dolfinx.part.integrals import VectorIntegral
from fabric_dolfinx.part.probes import CellProbe
from fabric_dolfinx.part.range_check import StrainRangeCheck
from fabric_dolfinx.part.regions import Region, assign_regions, cell_field
from fabric_dolfinx.solve import (
    LoadPath,
    LoadStepper,
    SolverOptions,
    boundary_indicator,
    with_history,
)
from fabric_dolfinx.spec.part import BoundaryCondition
from fabric_dolfinx.spec.revolution import RadiusProfile
from fabric_dolfinx.spec.space import IndenterSpec, SpaceSpec
from rve_rod.errors import InputError, check_integer

__all__ = [
    "BoundaryCurve",
    "PartProblem",
    "PartResult",
    "ProbeRecord",
    "SpaceCurves",
    "space_solver_options",
]

logger = logging.getLogger(__name__)

Observer = Callable[[], object]
"""A measurement of the current state, taken at t = 0 and after every converged step."""


class BoundaryCurve(NamedTuple):
    """Force-displacement record of one boundary (index 0: the unloaded state).

    Attributes:
        kind: the condition's kind.
        length: undeformed length (mm).
        force: (k+1, components) total force the fabric receives there (N): the reaction of
            a Dirichlet boundary, the applied load of a traction boundary, 0 on a free one.
        displacement: (k+1, components) mean displacement over the boundary (mm).
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
            (degrees; positive when it closes), `probes.shear_angle`.
    """

    point: tuple[float, float]
    centre: np.ndarray
    strain: np.ndarray
    cauchy: np.ndarray
    shear_angle: np.ndarray


class SpaceCurves(NamedTuple):
    """What a part in space records besides its boundaries (index 0: the unloaded state).

    Attributes:
        indenter_force: (k+1, 3) force the fabric exerts on the indenter (N), or None.
        indenter_travel: (k+1,) the indenter's travel (mm), or None.
        peak_displacement: (k+1,) largest deflection |u_z| of a flat part (the dome height),
            largest displacement |u| of a curved one, over the nodes (mm).
        wrinkled_area, slack_area: (k+1,) the fractions of the reference area whose cells are
            wrinkled (one principal stress <= 0) and slack (both <= 0: an unloaded part
            everywhere), from the `slack` field.
        dome_amplitude: the first step's one-mode dome height (mm), 0 when none was needed.
        stabilization_force: (k+1,) the normal stabilization's force of each step (N).
    """

    indenter_force: np.ndarray | None
    indenter_travel: np.ndarray | None
    peak_displacement: np.ndarray
    wrinkled_area: np.ndarray
    slack_area: np.ndarray
    dome_amplitude: float
    stabilization_force: np.ndarray


class PartResult(NamedTuple):
    """A load path of a fabric part.

    Attributes:
        load_factor: (k+1,) t of each output state, 0 first.
        boundaries: boundary name -> BoundaryCurve.
        probes: probe name -> ProbeRecord.
        outside_domain: region name -> whether its strains left its surface's domain.
        space: the curves of a part in space, None for a plane part.
        observed: name -> (k+1) values of each observer given to `run`.
        newton_iterations: (k,) Newton iterations of each converged step.
        cutbacks: failed attempts retried with half the increment.
        dofs: global degrees of freedom; ranks: MPI ranks; wall_time_s: path time (s).
        path: the solver's record.
    """

    load_factor: np.ndarray
    boundaries: dict[str, BoundaryCurve]
    probes: dict[str, ProbeRecord]
    outside_domain: dict[str, bool]
    space: SpaceCurves | None
    observed: dict[str, list]
    newton_iterations: np.ndarray
    cutbacks: int
    dofs: int
    ranks: int
    wall_time_s: float
    path: LoadPath


def space_solver_options(steps: int) -> SolverOptions:
    """The solver settings of parts in space (`knitmech`, the benchmarks): `steps` equal
    steps, cut back down to 1/1024; each Newton solve starts from the extrapolation of the
    last two converged states and halves a step that does not lower the residual (at most
    10 times). Both are needed for contact on fine meshes of the soft knit
    (docs/benchmarks.md: the ball burst at 40 elements)."""
    plain = SolverOptions(steps=steps)
    stepping = replace(plain.stepping_options(), extrapolate=True)
    return replace(plain, line_search=10, stepping=stepping)


def _indenter(spec: IndenterSpec) -> Indenter:
    if spec.shape == "plane":
        return PlaneIndenter(spec.point, spec.normal, spec.travel, spec.penalty)
    if spec.shape == "revolution":
        profile = RadiusProfile(*zip(*spec.profile, strict=True))
        return RevolutionIndenter(profile, spec.start_scale, spec.travel, spec.penalty)
    return SphereIndenter(spec.radius, spec.centre, spec.travel, spec.penalty)


class PartProblem:
    """Mesh, regions, boundary conditions, forms and solver of a fabric part, built once.

    Args:
        tagged: the mesh with its named boundaries and regions (gdim 2: flat; gdim 3: a
            curved surface, only in space).
        regions: the regions (at least one; every cell in one).
        conditions: the boundary conditions (enough Dirichlet conditions to remove the
            rigid-body modes).
        space: the part moves in space (3 components): pressure, indenter, stabilization,
            and a curved surface's course field; None: a plane part (2 components).
        element_degree: Lagrange degree of the displacement (1 or 2).
        quadrature_degree: Gauss rule exactness; None: twice the element degree.
        options: Newton and load-stepping settings.
        probes: name -> (x, y) mm: points whose cell's state is recorded every step (plane
            parts).

    Attributes:
        u: the displacement (mm); components: 2 or 3; frame: the material frame; cells: the
        RegionCells; loads: the BoundaryLoads; constants: the LoadConstants; angle: DG0
        course direction (radians); stitch: DG0 stitch value; materials: the regions'
        Materials; material: their S and dS/dE at the quadrature points (updated before
        every assembly); stepper: the LoadStepper.
    """

    def __init__(  # noqa: PLR0913 (a part's inputs: mesh, regions, conditions and 5 options)
        self,
        tagged: TaggedMesh,
        regions: Sequence[Region],
        conditions: Sequence[BoundaryCondition],
        *,
        space: SpaceSpec | None = None,
        element_degree: int = 1,
        quadrature_degree: int | None = None,
        options: SolverOptions | None = None,
        probes: Mapping[str, tuple[float, float]] | None = None,
    ):
        check_integer("element_degree", element_degree, 1, 2)
        mesh = tagged.mesh
        self.flat = mesh.geometry.dim == 2
        if not self.flat and space is None:
            raise InputError("a curved surface mesh (gdim 3) is a part in space: give it a space")
        if probes and space is not None:
            raise InputError("probes record plane parts; a part in space has none")
        self.tagged, self.regions, self.space_spec = tagged, tuple(regions), space
        self.components = 2 if space is None else 3
        self.options = options or SolverOptions()
        self.cells = assign_regions(tagged, self.regions)
        scalars = fem.FunctionSpace(mesh, ("DG", 0))
        self.angle = cell_field(
            scalars, self.cells, [r.angle for r in self.regions], "angle", scale=np.pi / 180.0
        )
        self.stitch = cell_field(scalars, self.cells, [r.stitch for r in self.regions], "stitch")
        self.materials = tuple(self._material(number) for number in range(len(self.regions)))
        fields = {}
        if not self.flat:
            course = space.course or "around"
            fields = dict(
                zip(
                    ("course", "side"),
                    axis_fields(course, space.axis, space.axis_point),
                    strict=True,
                )
            )
        self.frame = material_frame(mesh, self.components, self.angle, **fields)
        function_space = fem.VectorFunctionSpace(
            mesh, ("Lagrange", element_degree), dim=self.components
        )
        self.u = fem.Function(function_space, name="displacement")
        self.quadrature_degree = quadrature_degree or 2 * element_degree
        self.constants = LoadConstants(mesh)
        self.loads = BoundaryLoads(tagged, function_space, conditions, self.constants)
        self.conditions = self.loads.conditions
        dx = ufl.Measure(
            "dx",
            domain=mesh,
            subdomain_data=self.cells.tags,
            metadata={"quadrature_degree": self.quadrature_degree},
        )
        self.material = self.material_at(self.quadrature_degree)
        residual, jacobian = membrane_forms(self.u, self.material, self.frame)
        if self.loads.external is not None:
            residual = residual - self.loads.external
        self.indenter = self.indenter_state = None
        self.previous = fem.Function(function_space)
        self._stabilization = self._stabilization_form = None
        self._indenter_force = None
        if space is not None:
            follower = self._space_loads(space, dx)
            if follower is not None:
                residual = residual - follower
                du = ufl.TrialFunction(function_space)
                jacobian = jacobian - ufl.derivative(follower, self.u, du)
        reactions = {
            c.name: boundary_indicator(function_space, tagged.facets(c.name))
            for c in self.conditions
            if c.dirichlet
        }
        self.stepper = LoadStepper(
            residual,
            jacobian,
            self.u,
            self.loads.bcs,
            options=self.options,
            reactions=reactions,
            update=self.material.update,
        )
        self._boundary_means = BoundaryMeans(self.loads, self.u)
        self.dofs = function_space.dofmap.index_map.size_global * function_space.dofmap.index_map_bs
        self.probes = CellProbe(self, probes) if probes else None
        self.dome = None
        if space is not None and self.flat and (space.pressure != 0.0 or space.indenter):
            self.dome = Dome(self.u, residual, self._facets_holding_z(), self.material.update)

    def _material(self, number: int) -> Material:
        """The region's material; a graded region's from its family and the stitch field,
        after checking that its cells' stitch values lie in the family's range."""
        region = self.regions[number]
        if region.family is None:
            return region.material
        values = self._cell_stitch()[self.cells.cells(number)]
        comm = self.tagged.mesh.comm
        low = comm.allreduce(values.min() if values.size else np.inf, op=MPI.MIN)
        high = comm.allreduce(values.max() if values.size else -np.inf, op=MPI.MAX)
        members = [value for value, _ in region.family]
        # the scene reader's tolerance (knitmech.scene.fabric: members within 1e-9 mm)
        if low < min(members) - 1e-9 or high > max(members) + 1e-9:
            raise InputError(
                f"region {region.name!r}: stitch values {low:.4g} ... {high:.4g} mm leave the "
                f"family's range [{min(members):g}, {max(members):g}] mm"
            )
        return graded_material(region.family)

    def _cell_stitch(self) -> np.ndarray:
        """(local cells incl. ghosts,) the stitch value of each cell (mm)."""
        return self.stitch.x.array[self.stitch.function_space.dofmap.list.array]

    def material_at(self, degree: int) -> QuadratureMaterial:
        """The regions' laws at the points of the Gauss rule exact to `degree` (each cell its
        region's law at its stitch value): S and dS/dE as quadrature Functions of u."""
        return QuadratureMaterial(
            green_lagrange(self.u, self.frame),
            self.tagged.mesh,
            self.materials,
            degree,
            self.cells.index,
            self._cell_stitch(),
        )

    def _space_loads(self, space: SpaceSpec, dx: ufl.Measure):
        """The follower loads of a part in space (pressure, contact, stabilization) as one
        form, or None; sets up the indenter's force and the stabilization."""
        loads = []
        if space.pressure != 0.0:
            pressure = self.constants.constant(np.array(space.pressure))
            loads.append(pressure_residual(self.u, pressure, self.frame, dx))
        if space.indenter is not None:
            self.indenter = indenter = _indenter(space.indenter)
            self._check_indenter(indenter)
            start, change = indenter.motion()
            self.indenter_state = state = self.constants.constant(change, start)
            loads.append(contact_residual(self.u, indenter, state, self.frame, dx))
            contact, direction = contact_pressure(self.u, indenter, state, self.frame)
            self._indenter_force = VectorIntegral(-contact * direction, dx, self.tagged.mesh)
        if space.stabilization > 0.0:
            mesh = self.tagged.mesh
            self._stabilization = fem.Constant(mesh, PETSc.ScalarType(space.stabilization))
            normal = ufl.dot(self.u - self.previous, self.frame.normal)
            v = ufl.TestFunction(self.u.function_space)
            loads.append(-self._stabilization * normal * ufl.dot(v, self.frame.normal) * dx)
            self._stabilization_form = fem.form(self._stabilization * abs(normal) * dx)
        return sum(loads[1:], loads[0]) if loads else None

    def _check_indenter(self, indenter) -> None:
        """InputError when the indenter overlaps a node of the fabric at t = 0 (collective)."""
        gaps = indenter.start_gaps(self.tagged.mesh.geometry.x)
        gap = self.tagged.mesh.comm.allreduce(
            float(gaps.min()) if gaps.size else np.inf, op=MPI.MIN
        )
        if gap < 0.0:
            raise InputError(
                f"indenter {indenter.describe()} starts inside the fabric (gap {gap:.4g} mm); "
                "move it so that the gap is >= 0"
            )

    def _facets_holding_z(self) -> np.ndarray:
        """The local facets of the conditions that hold z (where the dome is 0)."""
        held = [
            c.name
            for c in self.conditions
            if c.kind in ("clamp", "displacement") or (c.kind == "roller" and "z" in c.component)
        ]
        if not held:
            raise InputError(
                "a flat membrane under pressure or indentation needs a boundary condition "
                "that holds z (a clamp, a displacement, or a roller holding z)"
            )
        return np.concatenate([self.tagged.facets(n) for n in held]).astype(np.int32)

    def set_load_factor(self, load_factor: float) -> None:
        """Scale every load to t; from a flat state, also put the one-mode dome in place."""
        self.constants.set_load_factor(load_factor)
        if self.dome is not None and load_factor > 0.0 and self.dome.is_flat():
            self.dome.place()

    def release_stabilization(self) -> None:
        """After a stabilized step: Newton once more without the stabilization, from the
        stabilized state. When it converges the step is exact (its stabilization force is
        0); otherwise the stabilized state is kept."""
        if self._stabilization is None or self.stabilization_force() == 0.0:
            return
        value = self._stabilization.value.copy()
        saved = self.u.x.array.copy()
        self._stabilization.value = 0.0
        released = self.stepper.newton().converged
        if released:
            self.previous.x.array[:] = self.u.x.array  # its force is 0
        else:
            self.u.x.array[:] = saved
        self._stabilization.value = value
        logger.info("stabilization released: %s", released)

    def stabilization_force(self) -> float:
        """c int |(u - u_n) . N| dA (N) of the current step, 0 without stabilization."""
        if self._stabilization_form is None:
            return 0.0
        value = fem.assemble_scalar(self._stabilization_form)
        return self.tagged.mesh.comm.allreduce(value, op=MPI.SUM)

    def indenter_force(self) -> np.ndarray:
        """(Fx, Fy, Fz) N the fabric exerts on the indenter at the current state (collective)."""
        return self._indenter_force()

    def peak_displacement(self) -> float:
        """The largest deflection |u_z| of a flat part, the largest displacement |u| of a
        curved one, over the nodes (mm, collective)."""
        u = self.u.x.array.reshape(-1, 3)
        values = np.abs(u[:, 2]) if self.flat else np.linalg.norm(u, axis=1)
        local = float(values.max()) if values.size else 0.0
        return self.tagged.mesh.comm.allreduce(local, op=MPI.MAX)

    def boundary_displacements(self) -> dict[str, np.ndarray]:
        """Boundary name -> mean displacement (mm, one entry per component) at the current
        state (collective)."""
        return self._boundary_means()

    def _range_checks(self) -> dict[str, StrainRangeCheck]:
        return {
            region.name: StrainRangeCheck(
                green_lagrange(self.u, self.frame),
                self.tagged.mesh,
                self.materials[number].domain,
                self.quadrature_degree,
                self.cells.cells(number),
            )
            for number, region in enumerate(self.regions)
            if self.materials[number].domain is not None
        }

    def _observers(self, fields: PartFields | None) -> dict[str, Observer]:
        """The measurements every run records (name -> observer)."""
        observers: dict[str, Observer] = {"displacement": self.boundary_displacements}
        if self.probes is not None:
            observers["probes"] = lambda: self.probes(fields)
        if self.components == 3:
            if self.indenter is not None:
                observers["indenter_force"] = self.indenter_force
            observers["peak_displacement"] = self.peak_displacement
            observers["slack_areas"] = fields.slack_areas
            observers["stabilization_force"] = self.stabilization_force
        return observers

    def run(
        self,
        xdmf: Path | str | None = None,
        on_step: Callable[[float, PartFields | None], None] | None = None,
        fields: bool = False,
        observers: Mapping[str, Observer] | None = None,
        *,
        label: Callable[[float], float] | None = None,
        written: Sequence[str] | None = None,
    ) -> PartResult:
        """Follow the load path t = 0 -> 1 from the unloaded part.

        Args:
            xdmf: write the PartFields of every step to this XDMF file (time: the label).
            on_step: called after every converged step with (label, PartFields or None).
            fields: evaluate the cell fields after every step even without xdmf.
            observers: name -> a measurement of the state, recorded in
                `PartResult.observed` (the fields are up to date when it is called).
            label: t -> the label of a state in the output, the warnings and `on_step`
                (e.g. a nominal strain); default t.
            written: the names of the PartFields written to XDMF; default all of the kind's.

        Raises ConvergenceError whose `history` is the PartResult of the converged steps
        (the XDMF file then holds them and is closed).
        """
        self.u.x.array[:] = 0.0
        self.previous.x.array[:] = 0.0
        self.set_load_factor(0.0)
        wanted = xdmf or fields or self.probes is not None or self.components == 3
        cell_fields = PartFields(self, written) if wanted else None
        label = label or float
        checks = self._range_checks()
        outside = {region.name: False for region in self.regions}
        measure = {**self._observers(cell_fields), **dict(observers or {})}
        history: dict[str, list] = {name: [] for name in measure}
        load_factors = []
        start = time.perf_counter()

        def record(load_factor: float, output: XDMFFile | None) -> None:
            if cell_fields is not None:
                cell_fields.update()
                if output is not None:
                    cell_fields.write(output, label(load_factor))
            load_factors.append(load_factor)
            for name, observer in measure.items():
                history[name].append(observer())

        def after_step(step, output: XDMFFile | None) -> None:
            for name, check in checks.items():
                outside[name] = check(label(step.load_factor)) or outside[name]
            record(step.load_factor, output)
            self.previous.x.array[:] = self.u.x.array
            if on_step is not None:
                on_step(label(step.load_factor), cell_fields)

        def follow(output: XDMFFile | None) -> LoadPath:
            record(0.0, output)
            return self.stepper.run(
                self.set_load_factor,
                lambda step: after_step(step, output),
                finish_step=self.release_stabilization,
            )

        def solve() -> LoadPath:
            if xdmf is None:
                return follow(None)
            with XDMFFile(self.tagged.mesh.comm, str(xdmf), "w") as output:
                output.write_mesh(self.tagged.mesh)
                return follow(output)

        def result(path: LoadPath) -> PartResult:
            return self._result(path, load_factors, history, outside, time.perf_counter() - start)

        return with_history(solve, result)

    def _result(
        self, path: LoadPath, load_factors, history, outside, wall_time: float
    ) -> PartResult:
        count = len(path.steps) + 1
        load_factor = np.array(load_factors[:count])
        series = {name: values[:count] for name, values in history.items()}
        displacements = series.pop("displacement")
        probed = series.pop("probes", None)
        space = self._space_curves(series, load_factor) if self.components == 3 else None
        zero = np.zeros(self.components)
        curves = {}
        for condition in self.conditions:
            name = condition.name
            if condition.dirichlet:
                forces = [zero] + [s.reactions[name] for s in path.steps]
            elif condition.kind == "traction":
                forces = [self.loads.applied_force(name, t) for t in load_factor]
            else:
                forces = [zero] * count
            curves[name] = BoundaryCurve(
                kind=condition.kind,
                length=self.loads.lengths[name],
                force=np.array(forces),
                displacement=np.array([d[name] for d in displacements]),
            )
        probes = {}
        if probed is not None:
            probes = {
                name: ProbeRecord(
                    point=self.probes.points[name],
                    centre=probed[0][name][0],
                    strain=np.array([p[name][1] for p in probed]),
                    cauchy=np.array([p[name][2] for p in probed]),
                    shear_angle=np.array([p[name][3] for p in probed]),
                )
                for name in self.probes.points
            }
        return PartResult(
            load_factor=load_factor,
            boundaries=curves,
            probes=probes,
            outside_domain=dict(outside),
            space=space,
            observed=series,
            newton_iterations=np.array([s.iterations for s in path.steps], dtype=int),
            cutbacks=path.cutbacks,
            dofs=self.dofs,
            ranks=self.tagged.mesh.comm.size,
            wall_time_s=wall_time,
            path=path,
        )

    def _space_curves(self, series: dict[str, list], load_factor: np.ndarray) -> SpaceCurves:
        """The curves of a part in space, taken out of `series`."""
        force = travel = None
        if self.indenter is not None:
            force = np.array(series.pop("indenter_force"))
            travel = load_factor * float(np.linalg.norm(self.indenter.travel))
        areas = np.array(series.pop("slack_areas")).reshape(-1, 2)
        return SpaceCurves(
            indenter_force=force,
            indenter_travel=travel,
            peak_displacement=np.array(series.pop("peak_displacement")),
            wrinkled_area=areas[:, 0],
            slack_area=areas[:, 1],
            dome_amplitude=self.dome.amplitude if self.dome is not None else 0.0,
            stabilization_force=np.array(series.pop("stabilization_force")),
        )
