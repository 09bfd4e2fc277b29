"""The cell relaxed by mechanics: the knit's unloaded w and c when its yarn lets go of its set.

The cell starts at the fabric's w and c with the loop as the rods' stress-free shape; the rods'
natural curvature and twist are then taken from the loop's (scale 1) down to `share` times it
(0: a yarn that is straight when free) in equal steps, frictionless, with the normal components
of F free (zero macro stress; with `shear`, F12 too). Each converged state gives the cell's
w = F11 w0, c = F22 c0 and its largest contact penetration: the relaxed cell of a yarn that
keeps the share `share` of its bending set.

It needs a fine curve: the bent yarn's rest state resolves slowly (docs/patterns.md, "The
relaxed cell"): cotton 20s/2 jersey at stitch 5.5 with a straight yarn collapses in width at
20 and 36 control points per quarter, and opens from 68 on to w = 1.410 / 1.482 / 1.496 / 1.504
mm at 68 / 100 / 132 / 200 (c = 1.030 mm), within 1.4 % of the geometric relaxed cell
(`rve_rod.geometry.relaxed`), whose yarn is thicker (r = 0.186 against the start's 0.166
mm). At other stitch values the path can change branch on the way, and where it ends still
depends on the resolution at 100-132 (5.0 at 100: w = 2.016 mm, at 132: 1.325 mm). Started
from the geometric relaxed cell (`rve_rod.geometry.relaxed.settled_fabric(fabric,
relaxed=True)`) it changes no branch from stitch 5.0 to 7.0 and converges (l/w within 1.2 %,
l/c within 0.2 % of 132 from 100 control points on); l/c does not depend on the start, w does
through the yarn radius r = min(r0, w/8) the start's w gives the cell. Not yet the relaxed
cell the pipeline uses: the tightest fabric (4.5) still collapses in width on the way.
"""

import dataclasses
from dataclasses import dataclass
from typing import ClassVar, NamedTuple

import numpy as np

from rve_rod.errors import ConvergenceError, check_range
from rve_rod.newton import solve_path
from rve_rod.presets import Fabric
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import LoadCase
from rve_rod.rve.simulation import RveSettings, build_cell, loop_curves
from rve_rod.rve.yarn import YarnSettings

__all__ = [
    "RelaxedState",
    "relax_cell",
]


@dataclass(frozen=True)
class _Relaxation(LoadCase):
    """F = I with the normal components free; the load factor drives the natural curvature."""

    name = "relaxation"
    free: ClassVar[tuple] = ((0, 0), (1, 1))

    def final_deformation(self):
        return np.eye(2)

    def control(self):
        return 1.0


@dataclass(frozen=True)
class _ShearedRelaxation(_Relaxation):
    free: ClassVar[tuple] = ((0, 0), (1, 1), (0, 1))


class RelaxedState(NamedTuple):
    """A converged state of the relaxation.

    Attributes:
        natural_curvature: the rods' stress-free curvature as a share of the loop's (-).
        deformation: (2, 2) F of the cell from the fabric's w and c.
        wale_width, course_height: the cell's w = F11 w0 and c = F22 c0 (mm).
        penetration: the largest contact penetration g = 2r - d in yarn radii (-).
    """

    natural_curvature: float
    deformation: np.ndarray
    wale_width: float
    course_height: float
    penetration: float


def relax_cell(
    fabric: Fabric,
    control_points: int,
    *,
    share: float = 0.0,
    steps: int = 10,
    shear: bool = False,
) -> list[RelaxedState]:
    """The states of the relaxation of `fabric`'s cell (module docstring), the start included.

    Args:
        fabric: the fabric (its w and c are the start).
        control_points: control points per quarter curve (100 or more: module docstring).
        share: the natural curvature's share of the loop's at the end, in [0, 1].
        steps: equal steps of the share.
        shear: F12 free too.

    Raises:
        ConvergenceError: the relaxation stopped (e.g. at the penetration limit); its
            `history` is the list of the converged states.
    """
    check_range("share", share, 0.0, 1.0)
    settings = RveSettings(
        cell=CellSettings(control_points=control_points), yarn=YarnSettings(friction=False)
    )
    case = (_ShearedRelaxation if shear else _Relaxation)(steps=2)
    cell = build_cell(loop_curves(fabric), fabric, case, settings)
    problem = cell.problem()

    def evaluate(state, load_factor):
        cell.model.set_natural_curvature(1.0 - load_factor * (1.0 - share))
        return problem.evaluate(state, load_factor)

    relaxing = dataclasses.replace(problem, evaluate=evaluate, commit=None)
    knit = fabric.knit

    def states(records) -> list[RelaxedState]:
        found = []
        for record in records:
            F = cell.evaluate_state(record.state, record.load_factor).deformation
            statistics = cell.coupling.result(record.state, record.load_factor, False).statistics
            found.append(
                RelaxedState(
                    natural_curvature=1.0 - record.load_factor * (1.0 - share),
                    deformation=F,
                    wale_width=float(F[0, 0] * knit.wale_width),
                    course_height=float(F[1, 1] * knit.course_height),
                    penetration=float(statistics.max_penetration / cell.yarn.radius),
                )
            )
        return found

    targets = np.linspace(0.0, 1.0, steps + 1)[1:]
    try:
        path = solve_path(relaxing, cell.reference_state(), targets, stepping=settings.stepping)
    except ConvergenceError as error:
        raise ConvergenceError(str(error), history=states(error.history.steps)) from error
    return states(path.steps)
