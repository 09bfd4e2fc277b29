"""The rod RVE as the homogenization's engine: `surface_engine(settings)` returns a picklable
`run(RveCase) -> RveRun` (see rve_rod.homogenize.samples) that follows a biaxial ray, the
pure-shear path or a uniaxial path of the sampling plan on the loop cell; `fabric_settings`
gives the settings the pipeline's levels and `rve-rod surface` use for a fabric (so that the
two share cached runs)."""

import dataclasses
import functools
import logging
from dataclasses import dataclass, field

from rve_rod.errors import ConvergenceError
from rve_rod.homogenize.samples import RveCase, RveRun
from rve_rod.newton import LINEAR_SOLVER_OPTIONS
from rve_rod.pattern import smallest_cell
from rve_rod.presets import Fabric
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import BiaxialRay, LoadCase, Shear, UniaxialCourse, UniaxialWale
from rve_rod.rve.simulation import RveSettings, simulate
from rve_rod.rve.yarn import YarnSettings, bending_model, check_bending

__all__ = [
    "EXPERIMENTS_OFF",
    "SEVERAL_COURSES_CONTROL_POINTS",
    "SEVERAL_COURSES_ITERATIONS",
    "RodRve",
    "fabric_settings",
    "path_case",
    "surface_engine",
]

logger = logging.getLogger(__name__)

EXPERIMENTS_OFF = {
    ("yarn", "prestrain"): 0.0,
    ("yarn", "natural_length"): "template",
    ("yarn", "natural_curvature"): 1.0,
    ("yarn", "contact_exponent_shift"): 0.0,
    ("yarn", "torsion"): "bending",
    ("cell", "contact", "lumping"): "line",
    ("cell", "contact", "balance"): False,
    ("cell", "support_rotation"): "held",
}
"""Settings of issue 27's experiments (the taut loop: `YarnSettings.prestrain`,
`natural_length`; the straight yarn: `natural_curvature`; the contact stiffer at first touch:
`contact_exponent_shift`; the torsion apart from the bending: `torsion`; the point-load reading
of the contact law: `ContactOptions.lumping`; the balanced contact: `ContactOptions.balance`)
and issue 28's (the support that lets go of the rotation: `CellSettings.support_rotation`), by
their path in `RveSettings`, and the values that switch them off (the model as it was before
them, bit for bit): left out of the RVE's cache identity at these values
(`RodRve.cache_identity`), so that the runs and surfaces cached before the fields existed (the
shipped surface among them) stay valid."""

SEVERAL_COURSES_CONTROL_POINTS = 36
"""The fewest control points per quarter curve of a pattern's cell of several yarn patches
(garter, moss; `fabric_settings` raises a smaller count to it and says so). Moss at 28 (the
fast level's) is outside the resolved range: at 10 % its course-wise force is 34 % below the
68-point one (0.283 against 0.428 gf/cm; at 36 0.398, 7 % below) and its wale-wise force 22 %
above (3.31 against 2.71; at 36 2.87, 6 % above), and with the regularized support (an option,
`CellSettings.support_rotation`) its course-wise first step finds no equilibrium at 28; garter
is within 2 % at 28 (docs/patterns.md, "Resolution"). The cache identity holds the count that
ran."""

SEVERAL_COURSES_ITERATIONS = 40
"""Newton iterations per solve of a cell of several yarn patches (garter, moss; the default is
25). Its first load step starts from the template, where the contacts only touch and the
further patches are held by the ties alone (1e-6 EA/c): Newton first looks for the contacts
that close, moving those soft modes, before it converges quadratically. Moss course-wise at a
1 % first step needs 31 iterations (36 control points, friction); with 25 it failed, and every
cutback failed as well: below t = 1e-4 no contact closes, the scaled residual stays at
round-off (1e-11) and the ties' soft modes (the scaled Jacobian's condition number is 2e15 at
20 control points) turn it into increments of 1e-9, above the increment tolerance, so the path
stopped at 0 % (docs/patterns.md, "Speed"). Part of the cache identity: the surfaces of such
patterns are keyed anew (the single-course cells, jersey's among them, keep the default)."""


def path_case(load) -> LoadCase:
    """The load case of a sampling LoadPath: its `steps` output states after the unloaded
    one, at the same F (a LoadPath counts steps after the reference, a LoadCase with it)."""
    if load.kind == "shear":
        return Shear(steps=load.steps + 1, max_shear=load.max_load)
    if load.kind == "uniaxial":
        uniaxial = UniaxialCourse if load.angle_deg == 0.0 else UniaxialWale
        return uniaxial(steps=load.steps + 1, max_strain=load.max_load)
    return BiaxialRay(steps=load.steps + 1, angle_deg=load.angle_deg, max_load=load.max_load)


@dataclass(frozen=True)
class RodRve:
    """The rod RVE engine; its settings, but for the linear solver's, are part of the surface
    cache key (`cache_identity`).

    Attributes:
        settings: the RVE settings of every run.
    """

    settings: RveSettings = field(default_factory=RveSettings)

    def cache_identity(self) -> dict:
        """The engine and its settings as `engine_identity` gives them, without the linear
        solver's (`rve_rod.newton.LINEAR_SOLVER_OPTIONS`): those change the cost of a run, not
        its results beyond round-off, so cached runs and surfaces stay valid when they are
        tuned; and without the experiment options where they are off (`EXPERIMENTS_OFF`)."""
        settings = dataclasses.asdict(self)
        for name in LINEAR_SOLVER_OPTIONS:
            del settings["settings"]["newton"][name]
        for path, off in EXPERIMENTS_OFF.items():
            *tables, name = path
            table = functools.reduce(dict.__getitem__, tables, settings["settings"])
            if table[name] == off:
                del table[name]
        return {"engine": f"{RodRve.__module__}.{RodRve.__qualname__}", "settings": settings}

    def __call__(self, case: RveCase) -> RveRun:
        """Run the case's load path; a path that stops early raises ConvergenceError whose
        history is the RveRun of the converged states (complete=False)."""
        try:
            result = simulate(case.fabric, path_case(case.load), self.settings)
        except ConvergenceError as error:
            raise ConvergenceError(str(error), history=error.history.to_rve_run()) from error
        return result.to_rve_run()


def fabric_settings(fabric: Fabric, control_points: int, bending: str = "auto") -> RveSettings:
    """The RVE settings of every run for `fabric` (meso runs and surface runs alike):
    `control_points` per quarter loop curve, the yarn's `bending` model
    (`rve_rod.rve.yarn.BENDING_CHOICES`, resolved for the yarn by `bending_model`, so that
    cache keys and surface files name the model that ran); a yarn without friction (mu = 0)
    runs without the friction path (no slip history), everything else at its default (but a
    pattern's cell of several courses: at least SEVERAL_COURSES_CONTROL_POINTS control
    points (logged where that raises `control_points`), every linear system factorized anew,
    and SEVERAL_COURSES_ITERATIONS Newton iterations per solve). Raises InputError when the
    bending model cannot model the fabric's yarn (`check_bending`)."""
    model = bending_model(fabric, bending)
    check_bending(fabric, model)
    several_courses = smallest_cell(fabric.knit.pattern).courses > 1
    if several_courses and control_points < SEVERAL_COURSES_CONTROL_POINTS:
        logger.info(
            "chart %s: its cell of several courses runs at %d control points per quarter, "
            "not %d (SEVERAL_COURSES_CONTROL_POINTS: fewer do not resolve it)",
            list(fabric.knit.pattern),
            SEVERAL_COURSES_CONTROL_POINTS,
            control_points,
        )
        control_points = SEVERAL_COURSES_CONTROL_POINTS
    settings = RveSettings(
        cell=CellSettings(control_points=control_points),
        yarn=YarnSettings(friction=fabric.yarn.friction_coefficient > 0.0, bending=model),
    )
    if several_courses:
        # several yarn patches: their ties' soft modes need every system factorized anew
        # (refined solves with older factors meet the linear tolerance and miss those modes;
        # the linear solver's options, not part of the identity), and the first step from the
        # touching template more Newton iterations (SEVERAL_COURSES_ITERATIONS)
        newton = dataclasses.replace(
            settings.newton, refinement=0, max_iterations=SEVERAL_COURSES_ITERATIONS
        )
        settings = dataclasses.replace(settings, newton=newton)
    return settings


def surface_engine(settings: RveSettings | None = None) -> RodRve:
    """The engine `rve-rod surface` uses: the rod RVE with `settings` (default: defaults)."""
    return RodRve(settings if settings is not None else RveSettings())
