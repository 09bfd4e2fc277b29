"""The periodic loop cell: one yarn period as a single rod patch, with its images; or the
cell of a stitch pattern: one rod patch per course of the cell, each one yarn period of
several loops, on an oblique lattice.

The loop geometry comes as the 4 C2-continuous quarter curves of one loop (`rve_rod.geometry`),
or, for a stitch pattern, as the `PeriodicYarns` of its cell (`rve_rod.geometry.pattern_cell`:
4 quarter curves per loop for each course, and the lattice a1 = (p w, 0), a2 = (q w, s c)).
Each yarn's curves are refined to the requested number of control points per curve, joined into ONE
degree-p B-spline with interior knots of multiplicity p - 2 at the joins (exact: the curves
are C2 there), and cut where the yarn touches nothing: the rod engine ignores line loads at a
patch's end points (their rows hold the end conditions), so the only patch end, the periodic
cut, must lie away from all contacts. The cut position is a parameter (in quarter curves along
the loop); the curve beyond the end of the loop continues as the start of the next loop,
translated by a1, so any cut gives the same yarn.

Conditions of the rod model:

* periodicity of every patch (a `Joint` from END to START): x(start) = x(end) - F a1, equal
  rotations, equal internal force and moment;
* a `PointSupport` in the middle of the first patch holding its position and its rotation
  about the period axis: the rigid modes of a yarn with one period vector (the support
  reaction is zero up to discretization error and the two-pass contact imbalance; it is
  reported; the rotation is a rigid mode only at rest, once loaded the contacts of neighbouring
  courses hold it and the held rotation carries a moment, so `CellSettings.support_rotation =
  "regularized"` holds it by a soft spring instead); the other patches of a pattern's cell are
  tied to the first by soft springs (`rve_rod.rve.ties`) until their contacts take over;
* `MacroBalance`: zero macro stress conjugate to each free component of F.

A converged state whose largest contact penetration g = 2r - d exceeds the penetration limit
(default r: the centrelines closer than one radius, each yarn squeezed to less than half its
thickness) is refused, and the load path cuts back towards the limit: beyond it the penalty
law describes no yarn, and a loop under large wale-wise strain can slip its head through the
legs it holds, a state Newton converges to as readily as any other (docs/validation.md).

Extra unknowns: the free components of F (as F - I), then the 4 support multipliers.

Rest state. The loop is built with the adjusted radius r, so its yarns just touch where the
construction puts them 2r apart. When the contact law acts at a larger radius (the yarn's own
r0, `YarnSettings.contact_radius = "measured"`), those contacts are squeezed at rest:
`LoopCell.rest_state` grows the squeeze from touching to its full size at F = I (the fabric
at its measured w and c), and the stress of that state, P0, is the cell's `rest_stress`. The
cell reports P - F P0, so that S = F^-1 P - S0 is the change from the rest state's second
Piola stress S0 = P0 (objective: a rigid turn of the pre-loaded cell reports no stress, where
P - P0 would report sym(P0 - R^T P0)), and the free components balance to F P0. A yarn
with a prestrain eps0 (`YarnSettings.prestrain`: its natural length 1 / (1 + eps0) times the
loop's, or the measured loop length's with `YarnSettings.natural_length = "measured"`:
`LoopCell.prestrain`) makes a taut rest state the same way: the prestrain is grown from 0 at
F = I (with the squeeze, if any), the yarn pulls its loop tight against its contacts, and P0
is the stress that holds the cell at its measured w and c. A yarn whose natural curvature is
less than the loop's (`YarnSettings.natural_curvature` s < 1: a yarn that keeps no set is
straight when free) makes a bent rest state: the natural curvature is taken from the loop's
down to s at F = I, and the contacts hold the yarn's bending moments.
"""

import dataclasses
import functools
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from rve_rod import limits
from rve_rod.contact import ContactModel, ContactOptions, Patch, PeriodicLattice, YarnChain
from rve_rod.errors import ConvergenceError, InputError, check_integer, check_range
from rve_rod.geometry.bspline import BSplineCurve, join
from rve_rod.geometry.pattern_cell import PeriodicYarns
from rve_rod.newton import NewtonOptions, NonlinearProblem, solve_path
from rve_rod.presets import Knit
from rve_rod.rod import (
    END,
    START,
    Condition,
    Joint,
    Offset,
    PointSupport,
    RodEnd,
    RodModel,
    RodPatch,
)
from rve_rod.rod.layout import DOFS_PER_POINT
from rve_rod.rve.coupling import ContactCoupling
from rve_rod.rve.load_cases import BiaxialRay, LoadCase
from rve_rod.rve.macro import MacroBalance, MacroDeformation, StressParts, macro_stress
from rve_rod.rve.moment import BendingMoment, MomentCuts
from rve_rod.rve.ties import YarnTie
from rve_rod.rve.yarn import YarnModel
from rve_rod.stepping import SteppingOptions

__all__ = [
    "SUPPORT_ROTATIONS",
    "CellSettings",
    "CellState",
    "LoopCell",
    "periodic_patch",
]

QUARTERS = 4
"""Curves per loop."""

TIE_PARAMETERS = (2.0, 0.0)
"""Where the ties of a pattern cell's other yarns sit, in quarter curves from the start of the
first loop (before the cut): its head apex and its sinker, apart along y."""

SUPPORT_UNKNOWNS = 4
"""Multipliers of the point support: reaction force (3) and moment about the period axis."""

SQUEEZE_STEPS = 10
"""Steps the rest state's squeeze is first tried in (the path cuts back where needed)."""


SUPPORT_ROTATIONS = ("held", "regularized")
"""How the cell's point support holds the rotation about the period axis
(`CellSettings.support_rotation`)."""


@dataclass(frozen=True)
class CellSettings:
    """Discretization and modelling choices of the cell.

    Attributes:
        control_points: control points per quarter curve after refinement (default 68, the
            paper's; at least the geometry's own count).
        cut: where the periodic cut sits, in quarter curves from the start of the loop, in
            [0, 4) (default 1.0: the leg point at the loop's mid-height, outside the band
            where courses overlap, so the loop touches nothing there; docs/rve.md).
        lateral_stiffness: kappa of `MacroBalance` relative to EA / c (default 1e-6).
        penetration_limit: largest admissible contact penetration g = 2r - d, in yarn radii
            r, in (0, 2) (default 1: centrelines at least r apart); states beyond it are
            refused (module docstring).
        contact: contact search settings.
        support_rotation: how the point support holds the yarn's rotation about the period
            axis, one of SUPPORT_ROTATIONS: "held" (default) exactly; "regularized" by a spring
            of stiffness kappa c^2 (kappa the cell's regularizing stiffness, lateral_stiffness
            EA / c), which holds the rotation where nothing else does (at rest) and otherwise
            leaves it to the contacts (an issue-28 experiment: docs/patterns.md, "The periodic
            cut").
    """

    control_points: int = 68
    cut: float = 1.0
    lateral_stiffness: float = 1e-6
    penetration_limit: float = 1.0
    contact: ContactOptions = field(default_factory=ContactOptions)
    support_rotation: str = "held"

    def __post_init__(self):
        check_integer("control_points", self.control_points, 5, limits.CONTROL_POINTS[1])
        check_range("cut", self.cut, 0.0, QUARTERS - 1e-9)
        check_range("lateral_stiffness", self.lateral_stiffness, 0.0, 1.0)
        check_range("penetration_limit", self.penetration_limit, 0.0, 2.0, closed=False)
        if self.support_rotation not in SUPPORT_ROTATIONS:
            raise InputError(
                f"support_rotation={self.support_rotation!r} is unknown; valid: "
                f"{', '.join(SUPPORT_ROTATIONS)}"
            )
        if self.support_rotation == "regularized" and self.lateral_stiffness == 0.0:
            raise InputError(
                "support_rotation='regularized' needs lateral_stiffness > 0 (its spring is "
                "lateral_stiffness EA c); got lateral_stiffness=0"
            )


def periodic_patch(
    curves: list[BSplineCurve], period: np.ndarray, cut: float, control_points: int
) -> BSplineCurve:
    """One period of a yarn as one B-spline on the parameter domain [0, 4 k] (k loops).

    Args:
        curves: the 4 k quarter curves of the yarn's period in order along the yarn (C2 at the
            joins and, with the next period, across the end: the last curve ends at the first
            curve's start + period).
        period: (3,) a1, (w, 0, 0) for one loop (mm).
        cut: start of the period in quarter curves, in [0, 4).
        control_points: control points per quarter after refinement.
    """
    if not curves or len(curves) % QUARTERS:
        raise InputError(
            f"a loop has {QUARTERS} quarter curves; got {len(curves)}, not a multiple of it"
        )
    own = max(curve.n_control_points for curve in curves)
    if control_points < own:
        raise InputError(
            f"control_points={control_points} is below the geometry's own {own} per curve"
        )
    quarters = []
    for curve in curves:
        low, high = curve.domain
        scaled = BSplineCurve(
            curve.degree, (curve.knots - low) / (high - low), curve.control_points
        )
        quarters.append(scaled.refined_to(control_points))
    loop = join(quarters, continuity=2)
    end = float(len(curves))
    gap = np.abs(loop(np.array([end]))[0] - loop(np.array([0.0]))[0] - period).max()
    if gap > 1e-9 * np.abs(loop.control_points).max():
        raise InputError(
            f"the loop does not end at its start + a1 (gap {gap:.3g} mm): not a periodic loop"
        )
    if cut == 0.0:
        return loop
    pieces = loop.split(float(cut))
    return join([pieces.right, pieces.left.translated(period)], continuity=2).reparametrized(0.0)


class CellState(NamedTuple):
    """Derived quantities of one state of the cell.

    Attributes:
        deformation: (2, 2) macro F.
        stress: the macro stress and its parts; first_piola is P - F P0 (the change from the
            rest state), the parts are P's own (they sum to first_piola + F rest_stress).
        cut_force: (3,) internal force at the cut n(END) (N), summed over the patches.
        support_reaction: (4,) support force (3, N) and moment about the period axis (N mm).
        regularization: (2, 2) kappa H on the free components and the ties' share of the
            macro stress (N/mm); zero for a single-jersey cell under fixed F.
        bending: the bending moments per width, averaged over the cuts
            (`rve_rod.rve.moment`); None where not asked for.
    """

    deformation: np.ndarray
    stress: StressParts
    cut_force: np.ndarray
    support_reaction: np.ndarray
    regularization: np.ndarray
    bending: BendingMoment | None


class LoopCell:
    """The rod model of one periodic loop, or of a pattern's cell, under a load case (module
    docstring).

    Args:
        curves: the 4 quarter curves of a single-jersey loop (mm), built with the yarn radius
            r (the cell on the lattice (w, 0), (0, c)); or the `PeriodicYarns` of a pattern's
            cell (its courses' curves and its lattice).
        knit: the wale width w and course height c of one loop, mm.
        yarn: section stiffness and contact laws.
        case: the load case (which components of F are free).
        settings: discretization and modelling choices.
        extra_conditions: conditions added to the cell's own (claiming no rod ends: a
            diagnostic constraint, e.g. the held depth of benchmarks/paper_rve_depth.py).

    Attributes:
        curves: the reference centrelines of the periodic patches, one per course of the cell.
        curve: the first of them (the only one of a single-jersey cell).
        model: the RodModel; coupling: the ContactCoupling; macro: the MacroDeformation.
        ties: the YarnTies of the second and further patches (none for one patch).
        rest_stress: (2, 2) P0 of the rest state (N/mm), zeros unless the contacts are
            squeezed or the yarn prestrained at rest (`rest_state`); `evaluate_state`
            reports P - F P0.
        prestrain: the rods' prestrain (-): the yarn's eps0, or with natural_length
            "measured" (1 + eps0) L / l - 1 (L the template's yarn length per loop, l the
            knit's measured loop length).
    """

    def __init__(
        self,
        curves: list[BSplineCurve] | PeriodicYarns,
        knit: Knit,
        yarn: YarnModel,
        case: LoadCase,
        settings: CellSettings = CellSettings(),
        extra_conditions: tuple[Condition, ...] = (),
    ):
        self.case = case
        self.settings = settings
        self.yarn = yarn
        self.rest_stress = np.zeros((2, 2))
        self._curves = curves
        self._knit = knit
        if not isinstance(curves, PeriodicYarns):
            rectangular = PeriodicLattice.rectangular(knit.wale_width, knit.course_height)
            curves = PeriodicYarns((tuple(curves),), rectangular.vectors)
        lattice = PeriodicLattice(curves.lattice)
        period = lattice.vectors[0]
        self.curves = tuple(
            periodic_patch(list(yarn_curves), period, settings.cut, settings.control_points)
            for yarn_curves in curves.yarns
        )
        self.curve = self.curves[0]
        n = sum(curve.n_control_points for curve in self.curves)
        free = len(case.free)
        offset = DOFS_PER_POINT * n
        self.macro = MacroDeformation(case, offset + np.arange(free))
        contact = ContactModel(
            [Patch(curve.degree, curve.knots) for curve in self.curves],
            np.concatenate([curve.control_points for curve in self.curves]),
            yarn.law,
            friction=yarn.friction,
            lattice=lattice,
            yarns=[YarnChain((k,), (1, 0)) for k in range(len(self.curves))],
            options=settings.contact,
        )
        self.coupling = ContactCoupling(contact, self.macro, n)
        self._period = period
        self._offset_derivative = -np.einsum("abk,b->ak", self.macro.derivative(), period)
        self._cuts = tuple(RodEnd(k, END) for k in range(len(self.curves)))
        self._support_columns = offset + free + np.arange(SUPPORT_UNKNOWNS)
        self._regularization = settings.lateral_stiffness * yarn.section.axial / knit.course_height
        middle = 0.5 * self.curve.domain[1]
        conditions = [
            Joint(cut, RodEnd(cut.patch, START), offset=self._offset) for cut in self._cuts
        ]
        rotation_stiffness = np.inf
        if settings.support_rotation == "regularized":
            rotation_stiffness = self._regularization * knit.course_height**2
        conditions.append(
            PointSupport(
                0,
                middle,
                first_unknown=free,
                rotation_axes=(period,),
                rotation_stiffness=rotation_stiffness,
            )
        )
        self.ties = tuple(
            YarnTie(patch, (at - settings.cut) % QUARTERS, self._regularization, self.macro)
            for patch in range(1, len(self.curves))
            for at in TIE_PARAMETERS
        )
        conditions += self.ties
        conditions += extra_conditions
        if free:
            positions = (DOFS_PER_POINT * np.arange(n)[:, None] + np.arange(3)).ravel()
            conditions.append(
                MacroBalance(
                    self.macro,
                    self.coupling,
                    self._cuts,
                    positions,
                    self._regularization,
                    rest_stress=self.rest_stress,
                )
            )
        patches = [
            patch for curve in self.curves for patch in RodPatch.chain([curve], yarn.section)
        ]
        self.model = RodModel(
            patches,
            conditions,
            loads=[self.coupling],
            extra_unknowns=free + SUPPORT_UNKNOWNS,
            extra_state_scale=np.r_[np.full(free, 0.1), np.ones(SUPPORT_UNKNOWNS)],
        )
        self.prestrain = yarn.prestrain
        if yarn.natural_length == "measured":
            if knit.measured_loop_length is None:
                raise InputError(
                    "natural_length='measured' needs the knit's measured loop length; this "
                    "knit has none: give natural_length='template'"
                )
            loops = sum(len(yarn_curves) for yarn_curves in curves.yarns) / QUARTERS
            template = sum(curve.arc_length() for curve in self.curves) / loops
            self.prestrain = (1.0 + yarn.prestrain) * template / knit.measured_loop_length - 1.0
        if self.prestrain:
            self.model.set_prestrain(self.prestrain)
        if yarn.natural_curvature != 1.0:
            self.model.set_natural_curvature(yarn.natural_curvature)

    def _offset(self, state: np.ndarray, load_factor: float) -> Offset:
        """x(START) - x(END) = -F a1 and its derivative w.r.t. the free components."""
        F = self.macro.matrix(state, load_factor)
        return Offset(-F @ self._period, self.macro.columns, self._offset_derivative)

    def problem(self) -> NonlinearProblem:
        """The cell as a NonlinearProblem; its commit adopts the friction anchors, and it
        refuses states beyond the penetration limit (`admissible`)."""
        return dataclasses.replace(
            self.model.problem(commit=self.coupling.commit), admissible=self.admissible
        )

    def admissible(self, state: np.ndarray, load_factor: float) -> str:
        """The empty string if the state's largest penetration is within the limit, else why
        the state is refused."""
        radius = self.yarn.radius
        statistics = self.coupling.result(state, load_factor, tangent=False).statistics
        squeeze = 2.0 * (self.yarn.law.yarn_radius - radius)  # of the contact radius over r
        penetration = (statistics.max_penetration - squeeze) / radius
        if penetration <= self.settings.penetration_limit:
            return ""
        return (
            f"the largest contact penetration, {penetration:.6f} r, exceeds the limit of "
            f"{self.settings.penetration_limit:g} r (CellSettings.penetration_limit; beyond it "
            "the yarns can pass through each other)"
        )

    def reference_state(self) -> np.ndarray:
        return self.model.reference_state()

    def rest_state(self, newton: NewtonOptions, stepping: SteppingOptions) -> np.ndarray:
        """The state the load path starts from (module docstring, "Rest state").

        The reference configuration when the contact law acts at the loop's radius, the
        yarn has no prestrain and its natural curvature is the loop's; else the squeezed,
        taut or bent rest state, grown frictionless at F = I in steps of the contact radius
        from r to the law's, of the prestrain from 0 to eps0 and of the natural curvature
        from the loop's to s times it together, with cutback (sets `rest_stress`, and makes
        the rest state's contacts the friction anchors). Raises ConvergenceError if it
        cannot be grown.
        """
        law, radius, prestrain = self.yarn.law, self.yarn.radius, self.prestrain
        curvature = self.yarn.natural_curvature
        if law.yarn_radius <= radius and not prestrain and curvature == 1.0:
            return self.reference_state()
        rest = LoopCell(
            self._curves,
            self._knit,
            self.yarn._replace(friction=None),
            BiaxialRay(steps=2),
            self.settings,
        )
        problem = rest.problem()

        def grow(fraction):
            grown = radius + fraction * (law.yarn_radius - radius)
            rest.coupling.use_law(dataclasses.replace(law, yarn_radius=grown))
            rest.model.set_prestrain(fraction * prestrain)
            rest.model.set_natural_curvature(1.0 - fraction * (1.0 - curvature))

        def evaluate(state, fraction):
            grow(fraction)
            return problem.evaluate(state, 0.0)

        def residual(state, fraction):
            grow(fraction)
            return problem.residual(state, 0.0)

        squeezing = dataclasses.replace(
            problem, evaluate=evaluate, residual=residual, commit=None, admissible=None
        )
        fractions = np.linspace(0.0, 1.0, SQUEEZE_STEPS + 1)[1:]
        try:
            path = solve_path(
                squeezing, rest.reference_state(), fractions, stepping=stepping, newton=newton
            )
        except ConvergenceError as error:
            raise ConvergenceError(
                f"the rest state with contacts squeezed by 2 (r0 - r) = "
                f"{2 * (law.yarn_radius - radius):.4g} mm and the yarn prestrained by "
                f"{prestrain:g} and its natural curvature {curvature:g} times the loop's was "
                f"not found: {error}"
            ) from error
        squeezed = path.steps[-1].state
        evaluate(squeezed, 1.0)  # the full squeeze and prestrain for the rest stress
        state = self.reference_state()
        points = self.model.layout.extra_offset
        state[:points] = squeezed[:points]
        state[self._support_columns] = squeezed[points:]
        self.rest_stress[...] = rest.evaluate_state(squeezed, 0.0).stress.first_piola
        self.coupling.anchor_at(state, 0.0)
        return state

    def positions(self, state: np.ndarray) -> np.ndarray:
        """Control-point positions (n, 3) of the patch (mm)."""
        return self.coupling.positions(state)

    @functools.cached_property
    def moments(self) -> MomentCuts:
        """The bending moments of the cell's states (`rve_rod.rve.moment`)."""
        return MomentCuts(self)

    def cut_force(self, state: np.ndarray) -> np.ndarray:
        """The internal force at the cuts summed over the patches, (3,) (N)."""
        ends = [self.model.end_values(state, cut) for cut in self._cuts]
        force = ends[0].force
        for end in ends[1:]:
            force = force + end.force
        return force

    def evaluate_state(
        self, state: np.ndarray, load_factor: float, moments: bool = False
    ) -> CellState:
        """Macro F, P (with its parts), cut force and support reaction of a state, and with
        `moments` its bending moments."""
        force = self.cut_force(state)
        stress = macro_stress(self.coupling, force, state, load_factor)
        deformation = self.macro.matrix(state, load_factor)[:2, :2]
        stress = stress._replace(first_piola=stress.first_piola - deformation @ self.rest_stress)
        regularization = np.zeros((2, 2))
        for (a, b), column in zip(self.case.free, self.macro.columns, strict=True):
            regularization[a, b] = self._regularization * state[column]
        for tie in self.ties:
            regularization += tie.stress(self.model, state, load_factor, self.coupling.area)
        return CellState(
            deformation=deformation,
            stress=stress,
            cut_force=force,
            support_reaction=np.array(state[self._support_columns]),
            regularization=regularization,
            bending=self.moments.mean(state, load_factor) if moments else None,
        )
