"""A fabric part that moves in space: supports, pressure, an indenter, load path, output.

`Membrane3DProblem` assembles the membrane forms (`fabric_dolfinx.membrane`, 3 components)
and the loads of `fabric_dolfinx.membrane3d` on a tagged mesh
(flat: a shape of the plane membrane; curved: a gmsh surface in space with a course field)
and follows the load path t = 0 -> 1 with the shared `LoadStepper` (cutbacks included):
prescribed support displacements, the follower pressure and the indenter's travel all scale
with t. After each converged step it records the reaction force (Fx, Fy, Fz) of every
support, the indenter's force, the largest displacement and the fractions of the area that
are wrinkled or slack, and optionally writes the cell fields (`Membrane3DFields`, with the
slack/wrinkle indicator) to XDMF.

Starting from the flat state. A flat, unstressed membrane has no stiffness out of its plane
(the tangent is singular in the normal direction), so Newton cannot take a first step under
pressure or indentation from it. Whenever a step starts from a flat state (the first step,
and its retries after a cutback) the solver first finds the best dome of one shape: phi
solves -lap(phi) = 1 with phi = 0 where the supports hold z (max phi = 1), and the amplitude A
of u = A phi e_z solves the scalar equation R(A phi e_z; phi e_z) = 0 (a one-mode Galerkin
solution, found by bracketing and Brent's method). Newton starts from that dome, which is
stressed and so has out-of-plane stiffness; the dome amplitude is reported.

Slack and wrinkled zones. Where a principal stress is not positive the membrane has no
stiffness across the wrinkles, and where the fabric lies flat and unstressed (e.g. at t = 0
under in-plane loads) none out of its plane. An optional normal stabilization adds
c ((u - u_n) . N) (v . N) dA to the residual (c N/mm^3, u_n the last converged state, N the
reference normal): a spring to the previous step that carries a step through such zones. It
vanishes for purely in-plane motion (so in-plane loading gives the plane membrane's result
exactly). After each stabilized step Newton runs once more without it, from the stabilized
state: where the fabric is taut this converges and the step is exact; where it cannot (slack
or wrinkled zones) the stabilized state is kept and its force, c int |(u - u_n) . N| dA, is
reported for the step: it must stay small against the loads. The cells' state is reported
in the `slack` field (0 taut, 1 wrinkled, 2 slack).
"""

import logging
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import NamedTuple

import dolfinx.fem.petsc
import numpy as np
import scipy.optimize
import ufl
from dolfinx import fem
from dolfinx.io import XDMFFile
from mpi4py import MPI
from petsc4py import PETSc

from fabric_dolfinx.domain import StrainRangeCheck
from fabric_dolfinx.material import Material
from fabric_dolfinx.membrane import material_frame, membrane_forms, membrane_state
from fabric_dolfinx.membrane3d import (
    Indenter,
    contact_pressure,
    contact_residual,
    pressure_residual,
)
from fabric_dolfinx.mesh import TaggedMesh
from fabric_dolfinx.solve import (
    LoadStepper,
    PathResult,
    SolverOptions,
    StepRecord,
    boundary_indicator,
)
from rve_rod.errors import ConvergenceError, InputError, check_integer

__all__ = [
    "EdgeLoad",
    "Membrane3DFields",
    "Membrane3DProblem",
    "Membrane3DResult",
    "Support",
    "slack_indicator",
    "space_solver_options",
]

logger = logging.getLogger(__name__)

AXES = "xyz"


@dataclass(frozen=True)
class Support:
    """Displacement components held on a named boundary.

    Attributes:
        name: a physical curve of the mesh.
        components: which of x, y, z are held, e.g. "xyz" (a clamp) or "z".
        displacement: (ux, uy, uz) mm at load factor 1 for the held components.
    """

    name: str
    components: str = "xyz"
    displacement: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self):
        if not self.components or any(c not in AXES for c in self.components):
            raise InputError(
                f"support {self.name!r}: components={self.components!r} must be letters of xyz"
            )
        if len(self.displacement) != 3 or not np.all(np.isfinite(self.displacement)):
            raise InputError(
                f"support {self.name!r}: displacement={self.displacement!r} needs 3 numbers"
            )


@dataclass(frozen=True)
class EdgeLoad:
    """A dead load t * vector (N/mm per undeformed length) on a named boundary."""

    name: str
    vector: tuple[float, float, float]

    def __post_init__(self):
        if len(self.vector) != 3 or not np.all(np.isfinite(self.vector)):
            raise InputError(f"edge load {self.name!r}: vector={self.vector!r} needs 3 numbers")


class Membrane3DResult(NamedTuple):
    """A load path of a membrane in space (index 0 of every array: the unloaded state).

    Attributes:
        load_factor: (k+1,) t.
        reactions: support name -> (k+1, 3) force (Fx, Fy, Fz) the fabric receives there (N).
        indenter_force: (k+1, 3) force the fabric exerts on the indenter (N), or None.
        indenter_travel: (k+1,) the indenter's travel (mm), or None.
        peak_displacement: (k+1,) largest deflection |u_z| of a flat part (the dome height),
            largest displacement |u| of a curved one, over the nodes (mm).
        wrinkled_area, slack_area: (k+1,) the fractions of the reference area whose cells are
            wrinkled (one principal stress <= 0) and slack (both <= 0: an unloaded SVK part
            everywhere), from the `slack` field (`Membrane3DFields`).
        dome_amplitude: the first step's one-mode dome height (mm), 0 when none was needed.
        stabilization_force: (k+1,) the normal stabilization's force of each step (N).
        outside_domain: whether strains left the response surface's sampled domain.
        newton_iterations: (k,) per converged step; cutbacks: failed attempts.
        dofs, ranks, wall_time_s, path: as for the plane membrane.
    """

    load_factor: np.ndarray
    reactions: dict[str, np.ndarray]
    indenter_force: np.ndarray | None
    indenter_travel: np.ndarray | None
    peak_displacement: np.ndarray
    wrinkled_area: np.ndarray
    slack_area: np.ndarray
    dome_amplitude: float
    stabilization_force: np.ndarray
    outside_domain: bool
    newton_iterations: np.ndarray
    cutbacks: int
    dofs: int
    ranks: int
    wall_time_s: float
    path: PathResult


def space_solver_options(steps: int) -> SolverOptions:
    """The solver settings of parts in space (`knitmech`, the benchmarks): `steps` equal
    steps, cut back down to 1/1024; each Newton solve starts from the extrapolation of the
    last two converged states and halves a step that does not lower the residual (at most
    10 times). Both are needed for contact on fine meshes of the soft knit
    (docs/benchmarks.md: the ball burst at 40 elements)."""
    plain = SolverOptions(steps=steps)
    stepping = replace(plain.stepping_options(), extrapolate=True)
    return replace(plain, line_search=10, stepping=stepping)


def slack_indicator(stress: np.ndarray) -> np.ndarray:
    """0 taut, 1 wrinkled (one principal stress <= 0), 2 slack (both <= 0) for symmetric
    2 x 2 stresses (n, 2, 2). Any membrane stress (S or Cauchy) gives the same answer: they
    are congruent, and congruence keeps the signs of the eigenvalues."""
    values = np.linalg.eigvalsh(stress)
    return np.sum(values <= 0.0, axis=1).astype(float)


class Membrane3DProblem:
    """Mesh, frame, loads, forms and solver of a membrane in space, built once.

    Args:
        tagged: the mesh (gdim 2: flat reference; gdim 3: curved) with named boundaries.
        material: the membrane law (course/wale frame).
        supports: held displacement components (enough to remove rigid-body modes).
        angle: course direction of a flat reference, radians from x (number or DG0 field).
        course, side: the course-direction and normal-side fields of a curved reference
            (`membrane.curved_frame`); required for gdim 3.
        pressure: follower pressure at t = 1 (N/mm^2 = MPa), towards the normal's side.
        edge_loads: dead loads on boundaries.
        indenter: a rigid sphere or plane (`membrane3d`), or None.
        stabilization: c (N/mm^3) of the normal stabilization (module docstring); 0: none.
        element_degree, quadrature_degree, options: as for the plane membrane.
    """

    def __init__(
        self,
        tagged: TaggedMesh,
        material: Material,
        supports: Sequence[Support],
        *,
        angle=0.0,
        course=None,
        side=None,
        pressure: float = 0.0,
        edge_loads: Sequence[EdgeLoad] = (),
        indenter: Indenter | None = None,
        stabilization: float = 0.0,
        element_degree: int = 1,
        quadrature_degree: int | None = None,
        options: SolverOptions | None = None,
    ):
        check_integer("element_degree", element_degree, 1, 2)
        if not math.isfinite(pressure):
            raise InputError(f"pressure={pressure!r} must be a finite number (N/mm^2)")
        self.tagged, self.material = tagged, material
        self.supports, self.edge_loads = tuple(supports), tuple(edge_loads)
        self.indenter = indenter
        self.options = options or SolverOptions()
        mesh = tagged.mesh
        self.frame = material_frame(mesh, 3, angle, course, side)
        self.flat = mesh.geometry.dim == 2
        space = fem.VectorFunctionSpace(mesh, ("Lagrange", element_degree), dim=3)
        self.space = space
        self.u = fem.Function(space, name="displacement")
        self.quadrature_degree = quadrature_degree or 2 * element_degree
        dx = ufl.dx(domain=mesh, metadata={"quadrature_degree": self.quadrature_degree})
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=tagged.facet_tags)
        forms = membrane_forms(self.u, material.law, self.frame, self.quadrature_degree)
        self._scaled: list[tuple[fem.Constant, np.ndarray, np.ndarray]] = []
        loads = None
        if pressure != 0.0:
            loads = pressure_residual(self.u, self._constant(np.array(pressure)), self.frame, dx)
        v = ufl.TestFunction(space)
        for load in self.edge_loads:
            value = self._constant(np.asarray(load.vector, dtype=float))
            term = ufl.dot(value, v) * ds(tagged.boundaries[_known(tagged, load.name)])
            loads = term if loads is None else loads + term
        self._indenter_forms = None
        if indenter is not None:
            self._check_indenter(indenter)
            origin = self._constant(np.asarray(indenter.travel, float), np.asarray(indenter.origin))
            term = contact_residual(self.u, indenter, origin, self.frame, dx)
            loads = term if loads is None else loads + term
            contact, direction = contact_pressure(self.u, indenter, origin, self.frame)
            self._indenter_forms = [fem.form(-contact * direction[i] * dx) for i in range(3)]
        if not (math.isfinite(stabilization) and stabilization >= 0.0):
            raise InputError(f"stabilization={stabilization!r} must be >= 0 (N/mm^3)")
        self.previous = fem.Function(space)
        self._stabilization_form = None
        self._stabilization = None
        if stabilization > 0.0:
            self._stabilization = fem.Constant(mesh, PETSc.ScalarType(stabilization))
            normal = ufl.dot(self.u - self.previous, self.frame.normal)
            term = -self._stabilization * normal * ufl.dot(v, self.frame.normal) * dx
            loads = term if loads is None else loads + term
            self._stabilization_form = fem.form(self._stabilization * abs(normal) * dx)
        residual, jacobian = forms.residual, forms.jacobian
        if loads is not None:
            residual = residual - loads
            jacobian = jacobian - ufl.derivative(loads, self.u, ufl.TrialFunction(space))
        self.bcs = []
        fdim = mesh.topology.dim - 1
        for support in self.supports:
            facets = tagged.facets(_known(tagged, support.name))
            for axis in support.components:
                component = AXES.index(axis)
                value = self._constant(np.array(support.displacement[component]))
                sub = space.sub(component)
                dofs = fem.locate_dofs_topological(sub, fdim, facets)
                self.bcs.append(fem.dirichletbc(value, dofs, sub))
        reactions = {s.name: boundary_indicator(space, tagged.facets(s.name)) for s in supports}
        self.stepper = LoadStepper(
            residual, jacobian, self.u, self.bcs, options=self.options, reactions=reactions
        )
        self.dofs = space.dofmap.index_map.size_global * space.dofmap.index_map_bs
        self._needs_dome = self.flat and (pressure != 0.0 or indenter is not None)
        self._dome = self._dome_shape(residual) if self._needs_dome else None
        self.dome_amplitude = 0.0

    def _constant(self, full: np.ndarray, offset: np.ndarray | None = None) -> fem.Constant:
        """A Constant holding offset + t * full, registered for `set_load_factor`."""
        offset = np.zeros_like(full, dtype=float) if offset is None else offset
        constant = fem.Constant(self.tagged.mesh, np.asarray(offset, dtype=PETSc.ScalarType))
        self._scaled.append((constant, np.asarray(full, dtype=float), offset))
        return constant

    def _check_indenter(self, indenter: Indenter) -> None:
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

    def set_load_factor(self, load_factor: float) -> None:
        """Scale every load to t; from a flat state, also put the one-mode dome in place."""
        for constant, full, offset in self._scaled:
            constant.value = offset + load_factor * full
        if self._needs_dome and load_factor > 0.0 and self._is_flat():
            self.dome_amplitude = self._dome_amplitude()
            self.u.x.array[:] = self.dome_amplitude * self._dome.x.array

    def _is_flat(self) -> bool:
        normal = self.u.x.array.reshape(-1, 3)[:, 2]
        local = float(np.abs(normal).max()) if normal.size else 0.0
        return self.tagged.mesh.comm.allreduce(local, op=MPI.MAX) == 0.0

    def _dome_shape(self, residual: ufl.Form) -> fem.Function:
        """phi e_z (phi: -lap phi = 1, 0 where z is held, max 1), and the scalar form
        R(u; phi e_z) whose root in the amplitude gives the dome."""
        mesh = self.tagged.mesh
        degree = self.space.ufl_element().degree()
        scalars = fem.FunctionSpace(mesh, ("Lagrange", degree))
        phi, w = ufl.TrialFunction(scalars), ufl.TestFunction(scalars)
        fdim = mesh.topology.dim - 1
        held = [s.name for s in self.supports if "z" in s.components]
        facets = np.concatenate([self.tagged.facets(n) for n in held]) if held else []
        if not held:
            raise InputError(
                "a flat membrane under pressure or indentation needs a support "
                "that holds z (components containing 'z')"
            )
        zero = fem.dirichletbc(
            PETSc.ScalarType(0.0),
            fem.locate_dofs_topological(scalars, fdim, np.asarray(facets, dtype=np.int32)),
            scalars,
        )
        problem = dolfinx.fem.petsc.LinearProblem(
            ufl.inner(ufl.grad(phi), ufl.grad(w)) * ufl.dx,
            fem.Constant(mesh, PETSc.ScalarType(1.0)) * w * ufl.dx,
            bcs=[zero],
            petsc_options={"ksp_type": "preonly", "pc_type": "lu"},
        )
        bubble = problem.solve()
        peak = mesh.comm.allreduce(float(np.abs(bubble.x.array).max()), op=MPI.MAX)
        dome = fem.Function(self.space)
        dome.x.array.reshape(-1, 3)[:, 2] = bubble.x.array / peak
        v = ufl.TestFunction(self.space)
        self._projected = fem.form(ufl.replace(residual, {v: dome}))
        return dome

    def _projected_residual(self, amplitude: float) -> float:
        self.u.x.array[:] = amplitude * self._dome.x.array
        value = fem.assemble_scalar(self._projected)
        return self.tagged.mesh.comm.allreduce(value, op=MPI.SUM)

    def _dome_amplitude(self) -> float:
        """The root A of R(A phi e_z; phi e_z) (mm), bracketed from the side the load pushes."""
        start = self._projected_residual(0.0)
        if start == 0.0:
            return 0.0
        sign = 1.0 if start < 0.0 else -1.0
        coordinates = self.tagged.mesh.geometry.x
        size = self.tagged.mesh.comm.allreduce(float(np.ptp(coordinates, axis=0).max()), MPI.MAX)
        high = 1e-4 * size
        for _ in range(60):
            if self._projected_residual(sign * high) * start < 0.0:
                break
            high *= 2.0
        else:
            raise ConvergenceError("no dome amplitude balances the first load step")
        low = 0.5 * high if high > 1e-4 * size else 0.0
        root = scipy.optimize.brentq(
            lambda a: self._projected_residual(sign * a), low, high, xtol=1e-12 * size
        )
        logger.info("first step starts from a dome of height %.4g mm", sign * root)
        return sign * root

    def indenter_force(self) -> np.ndarray:
        """(Fx, Fy, Fz) N the fabric exerts on the indenter at the current state (collective)."""
        comm = self.tagged.mesh.comm
        return np.array(
            [comm.allreduce(fem.assemble_scalar(f), op=MPI.SUM) for f in self._indenter_forms]
        )

    def peak_displacement(self) -> float:
        """The largest deflection |u_z| of a flat part, the largest displacement |u| of a
        curved one, over the nodes (mm, collective)."""
        u = self.u.x.array.reshape(-1, 3)
        values = np.abs(u[:, 2]) if self.flat else np.linalg.norm(u, axis=1)
        local = float(values.max()) if values.size else 0.0
        return self.tagged.mesh.comm.allreduce(local, op=MPI.MAX)

    def run(self, xdmf: Path | str | None = None) -> Membrane3DResult:
        """Follow the load path t = 0 -> 1 from the unloaded, flat (or reference) state.

        Raises ConvergenceError whose `history` is the Membrane3DResult of the converged steps.
        """
        self.u.x.array[:] = 0.0
        self.set_load_factor(0.0)
        fields = Membrane3DFields(self)
        self.previous.x.array[:] = 0.0
        check = None
        if self.material.domain is not None:
            strain = membrane_state(self.u, self.material.law, self.frame).strain
            mesh = self.tagged.mesh
            check = StrainRangeCheck(strain, mesh, self.material.domain, self.quadrature_degree)
        outside = [False]
        states = [self._state(0.0, fields)]
        stabilization = [0.0]
        reactions: list[dict] = []
        start = time.perf_counter()

        def after_step(step: StepRecord, output) -> None:
            released = self._stabilization is not None and self.stabilization_force() > 0.0
            reactions.append(self._release() if released else step.reactions)
            stabilization.append(self.stabilization_force())
            if check is not None:
                outside[0] = check(step.load_factor) or outside[0]
            self.previous.x.array[:] = self.u.x.array
            states.append(self._state(step.load_factor, fields))
            if output is not None:
                fields.write(output, step.load_factor)

        def solve(output):
            if output is not None:
                fields.write(output, 0.0)
            return self.stepper.run(self.set_load_factor, lambda s: after_step(s, output))

        try:
            if xdmf is not None:
                with XDMFFile(self.tagged.mesh.comm, str(xdmf), "w") as output:
                    output.write_mesh(self.tagged.mesh)
                    path = solve(output)
            else:
                path = solve(None)
        except ConvergenceError as error:
            records = (reactions, stabilization, outside[0])
            partial = self._result(error.history, states, records, time.perf_counter() - start)
            raise ConvergenceError(
                str(error), last_converged=error.last_converged, history=partial
            ) from None
        return self._result(
            path, states, (reactions, stabilization, outside[0]), time.perf_counter() - start
        )

    def _state(self, load_factor: float, fields: "Membrane3DFields") -> tuple:
        """(t, indenter force, peak displacement, (wrinkled, slack) area fractions); updates
        `fields` to the current state."""
        force = self.indenter_force() if self._indenter_forms is not None else None
        fields.update()
        return load_factor, force, self.peak_displacement(), fields.slack_areas()

    def _release(self) -> dict[str, np.ndarray]:
        """After a stabilized step: Newton once more without the stabilization, from the
        stabilized state. When it converges the step is exact (its stabilization force is
        0); otherwise the stabilized state is kept. Returns the supports' reactions."""
        value = self._stabilization.value.copy()
        saved = self.u.x.array.copy()
        self._stabilization.value = 0.0
        released = self.stepper.newton().converged
        if not released:
            self.u.x.array[:] = saved
            self._stabilization.value = value
        reactions = self.stepper.reaction_forces()
        if released:
            self.previous.x.array[:] = self.u.x.array  # its force is 0
            self._stabilization.value = value
        logger.info("stabilization released: %s", released)
        return reactions

    def stabilization_force(self) -> float:
        """c int |(u - u_n) . N| dA (N) of the current step, 0 without stabilization."""
        if self._stabilization_form is None:
            return 0.0
        value = fem.assemble_scalar(self._stabilization_form)
        return self.tagged.mesh.comm.allreduce(value, op=MPI.SUM)

    def _result(
        self, path: PathResult, states, records: tuple, wall_time: float
    ) -> Membrane3DResult:
        """`records`: (reactions per step after the release, stabilization force per state,
        whether strains left the surface's domain)."""
        reactions, stabilization, outside = records
        states = states[: len(path.steps) + 1]
        if self._stabilization is None:
            reactions = [step.reactions for step in path.steps]
        load_factor = np.array([s[0] for s in states])
        reactions = {
            s.name: np.array([np.zeros(3)] + [r[s.name] for r in reactions[: len(path.steps)]])
            for s in self.supports
        }
        travel = None
        force = None
        if self.indenter is not None:
            force = np.array([s[1] for s in states])
            travel = load_factor * float(np.linalg.norm(self.indenter.travel))
        return Membrane3DResult(
            load_factor=load_factor,
            reactions=reactions,
            indenter_force=force,
            indenter_travel=travel,
            peak_displacement=np.array([s[2] for s in states]),
            wrinkled_area=np.array([s[3][0] for s in states]),
            slack_area=np.array([s[3][1] for s in states]),
            dome_amplitude=self.dome_amplitude,
            stabilization_force=np.array(stabilization[: len(path.steps) + 1]),
            outside_domain=outside,
            newton_iterations=np.array([s.iterations for s in path.steps], dtype=int),
            cutbacks=path.cutbacks,
            dofs=self.dofs,
            ranks=self.tagged.mesh.comm.size,
            wall_time_s=wall_time,
            path=path,
        )


class Membrane3DFields:
    """Cell fields of a Membrane3DProblem's state for ParaView (DG0: the cell-centre value).

    Attributes:
        displacement: u (3,) mm (warp the reference by it for the deformed shape).
        strain: Green-Lagrange strain E (2 x 2, course/wale frame, -).
        stress: second Piola-Kirchhoff S (2 x 2, course/wale frame, N/mm).
        cauchy: Cauchy stress sigma (3 x 3, in space, N/mm per deformed width).
        principal_stress: (sigma_1, sigma_2), sigma_1 >= sigma_2, N/mm (deformed width).
        principal_direction: unit vector (3,) of sigma_1 in space.
        slack: 0 taut, 1 wrinkled (one principal stress <= 0), 2 slack (both <= 0).
    """

    def __init__(self, problem: Membrane3DProblem):
        mesh = problem.tagged.mesh
        state = membrane_state(problem.u, problem.material.law, problem.frame)
        plane = fem.TensorFunctionSpace(mesh, ("DG", 0), shape=(2, 2))
        space = fem.TensorFunctionSpace(mesh, ("DG", 0), shape=(3, 3))
        pairs = fem.VectorFunctionSpace(mesh, ("DG", 0), dim=2)
        vectors = fem.VectorFunctionSpace(mesh, ("DG", 0), dim=3)
        scalars = fem.FunctionSpace(mesh, ("DG", 0))
        self.strain = fem.Function(plane, name="green_lagrange_strain")
        self.stress = fem.Function(plane, name="second_piola_kirchhoff")
        self.cauchy = fem.Function(space, name="cauchy_stress")
        self.principal_stress = fem.Function(pairs, name="principal_stress")
        self.principal_direction = fem.Function(vectors, name="principal_direction")
        self.slack = fem.Function(scalars, name="slack")
        self._comm = mesh.comm
        self._owned = mesh.topology.index_map(mesh.topology.dim).size_local
        cells = fem.assemble_vector(fem.form(ufl.TestFunction(scalars) * ufl.dx(domain=mesh)))
        self._areas = cells.array[: self._owned].copy()  # reference area of each owned cell
        self._normal = fem.Function(vectors)
        points = plane.element.interpolation_points()
        self._expressions = [
            (self.strain, fem.Expression(state.strain, points)),
            (self.stress, fem.Expression(state.second_piola_kirchhoff, points)),
            (self.cauchy, fem.Expression(state.cauchy, points)),
            (self._normal, fem.Expression(state.normal, points)),
        ]
        self.displacement = problem.u

    def update(self) -> None:
        """Evaluate the fields at the current displacement."""
        for function, expression in self._expressions:
            function.interpolate(expression)
        cauchy = self.cauchy.x.array.reshape(-1, 3, 3)
        values, vectors = np.linalg.eigh(cauchy)
        normal = self._normal.x.array.reshape(-1, 3)
        # drop the eigenvector along the deformed normal (its eigenvalue is 0)
        along = np.abs(np.einsum("nij,ni->nj", vectors, normal))
        keep = np.argsort(along, axis=1)[:, :2]
        rows = np.arange(values.shape[0])[:, None]
        in_plane = values[rows, keep]
        order = np.argsort(-in_plane, axis=1)
        principal = np.take_along_axis(in_plane, order, axis=1)
        first = keep[np.arange(keep.shape[0]), order[:, 0]]
        self.principal_stress.x.array[:] = principal.ravel()
        self.principal_direction.x.array[:] = vectors[np.arange(first.size), :, first].ravel()
        self.slack.x.array[:] = slack_indicator(self.stress.x.array.reshape(-1, 2, 2))

    def slack_areas(self) -> tuple[float, float]:
        """The fractions of the reference area that are wrinkled and slack at the last
        `update` (collective)."""
        state = self.slack.x.array[: self._owned]
        local = [self._areas[state == 1.0].sum(), self._areas[state == 2.0].sum()]
        wrinkled, slack, total = self._comm.allreduce(
            np.array([*local, self._areas.sum()]), op=MPI.SUM
        )
        return float(wrinkled / total), float(slack / total)

    def functions(self) -> tuple[fem.Function, ...]:
        """Every field, in the order they are written."""
        return (
            self.displacement,
            self.strain,
            self.stress,
            self.cauchy,
            self.principal_stress,
            self.principal_direction,
            self.slack,
        )

    def write(self, output: XDMFFile, time: float) -> None:
        """Append every field at `time` (the load factor)."""
        for function in self.functions():
            output.write_function(function, time)


def _known(tagged: TaggedMesh, name: str) -> str:
    if name not in tagged.boundaries:
        raise InputError(
            f"boundary {name!r} is not a physical curve of the mesh; its boundaries: "
            f"{', '.join(sorted(tagged.boundaries))}"
        )
    return name
