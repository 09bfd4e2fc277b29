"""Running a load case on the loop cell: load stepping, per-step outputs, the result record.

`run_cell(cell)` follows the cell's load case from the unloaded state (first equilibrated at
zero strain, so that any contact of the initial geometry is balanced before loading) through
its output states with Newton and automatic cutback (`rve_rod.newton.solve_path`); friction
slip is committed after every converged (sub)step. `simulate(fabric, case)` builds the loop
geometry and the cell first. Both return an `RveResult`, or raise `ConvergenceError` whose
`history` is the `RveResult` of the converged states (`complete=False`).
"""

import logging
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import NamedTuple

import numpy as np

from rve_rod.contact import ContactStatistics
from rve_rod.errors import ConvergenceError
from rve_rod.geometry.bspline import BSplineCurve
from rve_rod.geometry.loop import loop_geometry
from rve_rod.geometry.pattern_cell import PeriodicYarns, pattern_geometry
from rve_rod.homogenize.samples import RveRun
from rve_rod.newton import NewtonOptions, NonlinearProblem, newton_solve, solve_path
from rve_rod.pattern.chart import JERSEY
from rve_rod.presets import Fabric
from rve_rod.rve.cell import CellSettings, CellState, LoopCell
from rve_rod.rve.load_cases import LoadCase
from rve_rod.rve.yarn import YarnModel, YarnSettings, yarn_model
from rve_rod.stepping import SteppingOptions
from rve_rod.stress_measures import green_lagrange, second_piola_kirchhoff, voigt
from rve_rod.units import n_mm_per_mm_to_gf_cm_per_cm, n_per_mm_to_gf_per_cm

__all__ = [
    "RveResult",
    "RveSettings",
    "RveStep",
    "build_cell",
    "run_cell",
    "simulate",
]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class RveSettings:
    """All settings of an RVE run besides the fabric and the load case.

    Attributes:
        cell: discretization and modelling choices of the cell.
        yarn: choices of the yarn model (second moment, friction on/off, ...).
        newton: Newton tolerances and iteration limit; by default with up to 4 line-search
            halvings per iteration (contacts that barely touch and an almost unloaded free
            direction can make plain Newton cycle; docs/rve.md), the LU in the "NODES"
            ordering (minimum degree on the control points, the macro unknowns last) with
            threshold pivoting, and up to 8 GMRES iterations with the last LU factors before
            a Jacobian is factorized anew (`rve_rod.newton`).
        stepping: load stepping and cutback.
    """

    cell: CellSettings = field(default_factory=CellSettings)
    yarn: YarnSettings = field(default_factory=YarnSettings)
    newton: NewtonOptions = field(
        default_factory=lambda: NewtonOptions(
            line_search=4, ordering="NODES", pivot_threshold=0.01, refinement=8
        )
    )
    stepping: SteppingOptions = field(default_factory=SteppingOptions)


@dataclass(frozen=True, eq=False)
class RveStep:
    """One converged output state.

    Attributes:
        load_factor: t in [0, 1].
        strain: the case's control value at this state (eps, ray t or shear g).
        deformation: (2, 2) macro F.
        green_lagrange: (3,) E = (E11, E22, E12).
        first_piola: (2, 2) P (N/mm), measured from the rest state: P - F P0 with P0 the
            result's `rest_stress`, so that S is the change from the rest's S0 = P0 (P itself
            when nothing is pre-loaded at rest).
        second_piola: (3,) S = F^-1 P, symmetrized (N/mm).
        stress_parts: (3, 2, 2) P split by where it is carried: the yarn force through the
            periodic cut, the normal loads and the friction loads of the contacts with the
            lattice images (N/mm); they sum to `first_piola` plus F times the result's
            `rest_stress`
            (docs/validation.md, "Why the knit contracts too little").
        reaction: (2, 2) force on the cell faces (N): column b is P[:, b] times the length of
            the face normal to axis b (c for b = 1, w for b = 2).
        force_n: the reaction along the load direction, sum_ab D_ab reaction_ab (N).
        force_gf_per_cm: P : D, the force per width along the load direction (gf/cm).
        bending_moment: (2,) the cell's bending moments per width M_11 (on the cut normal to
            the courses) and M_22 (normal to the wales), averaged over the cut positions,
            positive when the force on the cut acts above the mid-plane: held flat, a free
            edge normal to that axis would curl towards +z, the technical face (N mm / mm;
            `rve_rod.rve.moment`, docs/rve.md).
            None in runs that were not asked for it (`run_cell(moments=True)`; the CLI's
            runs are).
        bending_moment_gf_cm_per_cm: (2,) the same in gf cm / cm, or None.
        lateral_strain: F_aa - 1 of the free normal component (uniaxial cases), else None.
        newton_iterations: Newton iterations of this step (all substeps and failed tries;
            line-search trials count as iterations, as does a residual evaluated alone at an
            iterate that was then not accepted, `rve_rod.newton`).
        substeps: converged substeps; cutbacks: failed tries that halved the increment.
        active_contacts, sliding_contacts: contact points in contact / slipping.
        max_penetration: largest penetration g = 2r - d (mm).
        contacts_at_cut: contacts at the cut's end points (not applied; should be 0).
        support_reaction: (4,) support force (N) and moment about the period axis (N mm).
        regularization: largest |kappa H| of the free components (N/mm).
        wall_time_s: wall time of this step (s).
    """

    load_factor: float
    strain: float
    deformation: np.ndarray
    green_lagrange: np.ndarray
    first_piola: np.ndarray
    second_piola: np.ndarray
    stress_parts: np.ndarray
    reaction: np.ndarray
    force_n: float
    force_gf_per_cm: float
    bending_moment: np.ndarray | None
    bending_moment_gf_cm_per_cm: np.ndarray | None
    lateral_strain: float | None
    newton_iterations: int
    substeps: int
    cutbacks: int
    active_contacts: int
    sliding_contacts: int
    max_penetration: float
    contacts_at_cut: int
    support_reaction: np.ndarray
    regularization: float
    wall_time_s: float


@dataclass(frozen=True, eq=False)
class RveResult:
    """The converged states of one RVE run.

    Attributes:
        case: the load case.
        fabric: the fabric.
        settings: the run's settings.
        yarn: the yarn model (adjusted radius, section, contact laws).
        steps: the converged output states, the unloaded one first.
        complete: True when the whole load path converged.
        message: why the run stopped early ("" when complete).
        curves: the reference centrelines of the cell's patches, one per course of the cell
            (knots and degree of every deformed centreline; one for single jersey).
        centrelines: (s, n, 3) control points of the centrelines at each step, the patches'
            one after the other (mm).
        newton_iterations: all Newton iterations of the run (as counted per step), including
            the zero-strain solve and, for a run that stopped, the tries after its last state.
        wall_time_s: wall time of the run, model building included (s).
        rest_stress: (2, 2) P0 of the rest state the stresses are measured from (N/mm; zero
            unless the contacts are squeezed at rest, `LoopCell.rest_state`).
        lattice: (2, 3) the cell's lattice vectors a1, a2 (mm); None: the single-jersey
            cell's (w, 0, 0), (0, c, 0).
    """

    case: LoadCase
    fabric: Fabric
    settings: RveSettings
    yarn: YarnModel
    steps: tuple[RveStep, ...]
    complete: bool
    message: str
    curves: tuple[BSplineCurve, ...]
    centrelines: np.ndarray
    newton_iterations: int
    wall_time_s: float
    rest_stress: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))
    lattice: np.ndarray | None = None

    @property
    def curve(self) -> BSplineCurve:
        """The first patch's reference centreline (the only one of a single-jersey cell)."""
        return self.curves[0]

    @property
    def cell_lattice(self) -> np.ndarray:
        """(2, 3) the cell's lattice vectors (mm)."""
        if self.lattice is not None:
            return self.lattice
        knit = self.fabric.knit
        return np.array([[knit.wale_width, 0.0, 0.0], [0.0, knit.course_height, 0.0]])

    def series(self, name: str) -> np.ndarray:
        """One attribute of every step as an array, e.g. series("force_gf_per_cm")."""
        return np.array([getattr(step, name) for step in self.steps])

    @property
    def poisson_ratio(self) -> float | None:
        """nu12 = -eps22/eps11 (uniaxial-course) or nu21 = -eps11/eps22 (uniaxial-wale) at
        the last converged state; None for other cases, before any strain or when no state
        converged."""
        if not self.steps:
            return None
        last = self.steps[-1]
        if last.lateral_strain is None or last.strain == 0.0:
            return None
        return -last.lateral_strain / last.strain

    def centreline(self, step: int, patch: int = 0) -> BSplineCurve:
        """The deformed centreline of patch `patch` at output state `step` (one period of
        that course's yarn, mm)."""
        first = sum(curve.n_control_points for curve in self.curves[:patch])
        curve = self.curves[patch]
        points = self.centrelines[step][first : first + curve.n_control_points]
        return BSplineCurve(curve.degree, curve.knots, points)

    def to_rve_run(self) -> RveRun:
        """The loaded states as the homogenization's RveRun (F and P, reference excluded)."""
        loaded = self.steps[1:]
        return RveRun(
            np.array([step.deformation for step in loaded]).reshape(-1, 2, 2),
            np.array([step.first_piola for step in loaded]).reshape(-1, 2, 2),
            complete=self.complete,
        )

    def to_dict(self) -> dict:
        """Plain data for JSON: the per-step series, the Poisson ratio and the settings."""
        return {
            "case": self.case.name,
            "case_settings": self.case.__dict__,
            "fabric": {"name": self.fabric.name, **self.fabric.knit.__dict__},
            "yarn": asdict(self.fabric.yarn),
            "adjusted_radius": self.yarn.radius,
            "radius_adjusted": self.yarn.adjusted,
            "contact_exponent": self.yarn.law.exponent,
            "contact_stiffness": self.yarn.law.stiffness,
            "control_points_per_quarter_loop": self.settings.cell.control_points,
            "control_points_periodic_curve": self.curve.n_control_points,
            "complete": self.complete,
            "message": self.message,
            "poisson_ratio": self.poisson_ratio,
            "newton_iterations_total": self.newton_iterations,
            "wall_time_s": self.wall_time_s,
            **{
                name: self.series(name).tolist()
                for name in (
                    "load_factor",
                    "strain",
                    "force_gf_per_cm",
                    "force_n",
                    "newton_iterations",
                    "substeps",
                    "cutbacks",
                    "active_contacts",
                    "sliding_contacts",
                    "max_penetration",
                    "contacts_at_cut",
                    "regularization",
                )
            },
            "lateral_strain": [step.lateral_strain for step in self.steps],
            "step_wall_time_s": self.series("wall_time_s").tolist(),
            "deformation_gradient": self.series("deformation").tolist(),
            "green_lagrange": self.series("green_lagrange").tolist(),
            "first_piola": self.series("first_piola").tolist(),
            "second_piola": self.series("second_piola").tolist(),
            "stress_parts": self.series("stress_parts").tolist(),
            "bending_moment": self.series("bending_moment").tolist(),
            "bending_moment_gf_cm_per_cm": self.series("bending_moment_gf_cm_per_cm").tolist(),
            "reaction_n": self.series("reaction").tolist(),
            "support_reaction": self.series("support_reaction").tolist(),
            "rest_stress": self.rest_stress.tolist(),
        }


class _Snapshot(NamedTuple):
    """What a converged state yields before its friction slip is committed."""

    state: np.ndarray
    load_factor: float
    derived: CellState
    contacts: ContactStatistics
    evaluations: int
    converged: int
    wall_time_s: float

    def iterations(self, attempts: int) -> int:
        """Newton iterations (linear solves, line-search trials included) of the `attempts`
        Newton solves since the previous snapshot: one per evaluation (also of the residual
        alone) but the first of each solve, plus the correction a converged solve computes
        without evaluating it."""
        return self.evaluations - attempts + self.converged


class _Recorder:
    """Wraps the cell's problem: counts evaluations and converged Newton solves (the calls of
    `admissible`), and at every converged output state takes its outputs (before the commit
    changes the friction anchors) and its wall time."""

    def __init__(self, cell: LoopCell, targets: np.ndarray, moments: bool):
        self.cell = cell
        self.moments = moments
        self.problem = cell.problem()
        self.targets = list(targets)
        self.evaluations = 0
        self.converged = 0
        self.snapshots: list[_Snapshot] = []
        self._last = time.perf_counter()

    def evaluate(self, state, load_factor):
        self.evaluations += 1
        return self.problem.evaluate(state, load_factor)

    def residual(self, state, load_factor):
        self.evaluations += 1
        return self.problem.residual(state, load_factor)

    def admissible(self, state, load_factor) -> str:
        self.converged += 1
        return self.problem.admissible(state, load_factor)

    def commit(self, state, load_factor):
        index = len(self.snapshots)
        if index < len(self.targets) and abs(load_factor - self.targets[index]) <= 1e-12:
            self.snapshot(state, load_factor)
        self.problem.commit(state, load_factor)

    def snapshot(self, state, load_factor):
        """Record a converged output state."""
        now = time.perf_counter()
        contacts = self.cell.coupling.result(state, load_factor, tangent=False).statistics
        self.snapshots.append(
            _Snapshot(
                state=np.array(state, copy=True),
                load_factor=float(load_factor),
                derived=self.cell.evaluate_state(state, load_factor, self.moments),
                contacts=contacts,
                evaluations=self.evaluations,
                converged=self.converged,
                wall_time_s=now - self._last,
            )
        )
        self.evaluations = 0
        self.converged = 0
        self._last = now

    def wrapped(self) -> NonlinearProblem:
        return NonlinearProblem(
            evaluate=self.evaluate,
            residual_scale=self.problem.residual_scale,
            state_scale=self.problem.state_scale,
            commit=self.commit,
            admissible=self.admissible,
            nodes=self.problem.nodes,
            residual=self.residual,
        )


def _step(case: LoadCase, lattice: np.ndarray, snapshot: _Snapshot, **counts) -> RveStep:
    """The outputs of a converged state; `counts`: newton_iterations, substeps, cutbacks."""
    derived = snapshot.derived
    F, P = derived.deformation, derived.stress.first_piola
    faces = np.array([lattice[1, 1], lattice[0, 0]])  # face normal to x has length c, to y w
    reaction = P * faces[None, :]
    direction = case.load_direction()
    lateral = None
    if case.lateral is not None:
        a, b = case.lateral
        lateral = float(F[a, b] - 1.0)
    contacts = snapshot.contacts
    return RveStep(
        load_factor=snapshot.load_factor,
        strain=float(snapshot.load_factor * case.control()),
        deformation=F,
        green_lagrange=voigt(green_lagrange(F)),
        first_piola=P,
        second_piola=voigt(second_piola_kirchhoff(F, P)),
        stress_parts=np.array(
            [
                derived.stress.cut,
                derived.stress.images - derived.stress.friction,
                derived.stress.friction,
            ]
        ),
        reaction=reaction,
        force_n=float(np.sum(direction * reaction)),
        force_gf_per_cm=float(n_per_mm_to_gf_per_cm(np.sum(direction * P))),
        bending_moment=None if derived.bending is None else derived.bending.moment,
        bending_moment_gf_cm_per_cm=(
            None if derived.bending is None else n_mm_per_mm_to_gf_cm_per_cm(derived.bending.moment)
        ),
        lateral_strain=lateral,
        active_contacts=contacts.active_contacts,
        sliding_contacts=contacts.sliding,
        max_penetration=contacts.max_penetration,
        contacts_at_cut=derived.stress.contacts_at_cut,
        support_reaction=derived.support_reaction,
        regularization=float(np.abs(derived.regularization).max()),
        wall_time_s=snapshot.wall_time_s,
        **counts,
    )


def run_cell(
    cell: LoopCell,
    fabric: Fabric,
    settings: RveSettings = RveSettings(),
    *,
    on_step: Callable[[RveStep], None] | None = None,
    started: float | None = None,
    moments: bool = False,
) -> RveResult:
    """Follow the cell's load case (module docstring).

    Args:
        cell: the loop cell (it carries the load case).
        fabric: the fabric the cell was built for (recorded in the result).
        settings: the settings the cell was built with, and the solver's.
        on_step: called with every converged output state (progress reports).
        started: perf_counter() time the run started (model building included); now if None.
        moments: also compute every state's bending moments (`RveStep.bending_moment`,
            2-9 ms a state: docs/benchmarks.md); False leaves them None.

    Raises:
        ConvergenceError: the path could not be continued; `history` is the RveResult of the
            converged states.
    """
    started = time.perf_counter() if started is None else started
    case = cell.case
    lattice = cell.coupling.lattice
    targets = case.load_factors()[1:]
    recorder = _Recorder(cell, targets, moments)
    steps: list[RveStep] = []
    states: list[np.ndarray] = []

    def add(snapshot: _Snapshot, **counts):
        steps.append(_step(case, lattice, snapshot, **counts))
        states.append(snapshot.state)
        if on_step is not None:
            on_step(steps[-1])

    def result(complete: bool, message: str, iterations: int) -> RveResult:
        return RveResult(
            case=case,
            fabric=fabric,
            settings=settings,
            yarn=cell.yarn,
            steps=tuple(steps),
            complete=complete,
            message=message,
            curves=cell.curves,
            centrelines=np.array([cell.positions(state) for state in states]),
            newton_iterations=iterations,
            wall_time_s=time.perf_counter() - started,
            rest_stress=cell.rest_stress.copy(),
            lattice=cell.coupling.lattice.copy(),
        )

    problem = recorder.wrapped()
    try:
        rest = cell.rest_state(settings.newton, settings.stepping)
    except ConvergenceError as error:
        raise ConvergenceError(
            str(error), history=result(False, "no rest state", recorder.evaluations)
        ) from error
    initial = newton_solve(problem, rest, 0.0, settings.newton)
    if not initial.converged:
        raise ConvergenceError(
            f"the unloaded cell has no equilibrium: {initial.reason} after "
            f"{initial.iterations} iterations (does the initial geometry overlap?)",
            history=result(False, "no equilibrium at zero strain", initial.iterations),
        )
    recorder.converged += 1
    recorder.snapshot(initial.state, 0.0)
    recorder.problem.commit(initial.state, 0.0)
    first = recorder.snapshots.pop()
    add(first, newton_iterations=first.iterations(1), substeps=1, cutbacks=0)
    unfinished = 0  # iterations spent after the last output state (a run that stopped)
    try:
        path = solve_path(
            problem, initial.state, targets, stepping=settings.stepping, newton=settings.newton
        )
        message, complete = "", True
    except ConvergenceError as error:
        path = error.history
        message, complete = str(error), False
        stopped = error.last_converged
        unfinished = recorder.evaluations - stopped.substeps - stopped.cutbacks + recorder.converged
    for record, snapshot in zip(path.steps[1:], recorder.snapshots, strict=False):
        add(
            snapshot,
            newton_iterations=snapshot.iterations(record.substeps + record.cutbacks),
            substeps=record.substeps,
            cutbacks=record.cutbacks,
        )
    iterations = sum(step.newton_iterations for step in steps) + max(unfinished, 0)
    outcome = result(complete, message, iterations)
    if not complete:
        raise ConvergenceError(
            f"{case.name} stopped at strain {steps[-1].strain:.4g} "
            f"({len(steps) - 1} of {len(targets)} steps): {message}",
            last_converged=steps[-1],
            history=outcome,
        )
    return outcome


def build_cell(
    curves: list[BSplineCurve] | PeriodicYarns,
    fabric: Fabric,
    case: LoadCase,
    settings: RveSettings,
) -> LoopCell:
    """The loop cell of `fabric` from its loop curves (built with the adjusted radius), or
    from its pattern cell's yarns (`loop_curves`)."""
    yarn = yarn_model(fabric, settings.yarn)
    return LoopCell(curves, fabric.knit, yarn, case, settings.cell)


def loop_curves(fabric: Fabric) -> list[BSplineCurve] | PeriodicYarns:
    """The 4 quarter curves of the fabric's loop, built with the adjusted radius; for a
    stitch pattern other than jersey, the yarns and lattice of its cell's template
    (`rve_rod.geometry.pattern_cell`)."""
    knit, radius = fabric.knit, fabric.yarn.minimal_radius
    if knit.pattern == JERSEY:
        return list(loop_geometry(knit, radius).curves)
    geometry = pattern_geometry(knit.pattern, knit.wale_width, knit.course_height, radius)
    return geometry.periodic_yarns()


def simulate(
    fabric: Fabric,
    case: LoadCase,
    settings: RveSettings = RveSettings(),
    *,
    curves: list[BSplineCurve] | PeriodicYarns | None = None,
    on_step: Callable[[RveStep], None] | None = None,
    moments: bool = False,
) -> RveResult:
    """Run `case` on the loop cell of `fabric` (geometry, cell, load path).

    Args:
        fabric: yarn and knit.
        case: the load case.
        settings: model and solver settings.
        curves: the loop's 4 quarter curves (or a pattern cell's yarns); None builds them
            from the fabric (`loop_curves`).
        on_step: called with every converged output state.
        moments: compute every state's bending moments (`run_cell`).

    Raises:
        ConvergenceError: with the RveResult of the converged states as `history`.
    """
    started = time.perf_counter()
    curves = loop_curves(fabric) if curves is None else curves
    cell = build_cell(curves, fabric, case, settings)
    return run_cell(cell, fabric, settings, on_step=on_step, started=started, moments=moments)
