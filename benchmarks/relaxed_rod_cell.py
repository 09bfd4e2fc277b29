"""The rod cell relaxed as a naturally straight yarn: the relaxed jersey cell by mechanics,
against the one found among the templates (issue 28, docs/patterns.md "The relaxed cell").

The cotton 20s/2 jersey cell at stitch 5.5 (its measured w, c) with the rods' natural
curvature taken from the loop's (scale 1, the model as it is) down to a straight yarn (0),
frictionless, the macro F11, F22 free (zero macro stress; with --shear F12 too): a table of
the load factor, the natural curvature's scale, F11, F22 (F12), w, c and the largest
penetration, until the penetration limit (one radius) stops the path.

    .venv/bin/python benchmarks/relaxed_rod_cell.py [--control-points 132] [--shear]

The bent yarn's rest state resolves slowly: at 20 and 36 control points the cell collapses in
width, from 68 on it opens to the relaxed jersey cell (docs/patterns.md, "The relaxed cell").
About 20 s at 100 control points, 90 s at 132, 4 min at 200 on the shared machine.
"""

import argparse
import dataclasses
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from rve_rod.errors import ConvergenceError
from rve_rod.newton import solve_path
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import LoadCase
from rve_rod.rve.simulation import RveSettings, build_cell, loop_curves
from rve_rod.rve.yarn import YarnSettings


@dataclass(frozen=True)
class Relaxation(LoadCase):
    """F = I with the normal components free (and the shear F12 with `shear`); the load
    factor drives the natural curvature instead."""

    name = "relaxation"
    free: ClassVar[tuple] = ((0, 0), (1, 1))

    def final_deformation(self):
        return np.eye(2)

    def control(self):
        return 1.0


@dataclass(frozen=True)
class ShearedRelaxation(Relaxation):
    free: ClassVar[tuple] = ((0, 0), (1, 1), (0, 1))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--control-points", type=int, default=132)
    parser.add_argument("--shear", action="store_true", help="F12 free as well")
    args = parser.parse_args()
    fabric = load_preset("cotton-20s2", 5.5)
    settings = RveSettings(
        cell=CellSettings(control_points=args.control_points), yarn=YarnSettings(friction=False)
    )
    case = (ShearedRelaxation if args.shear else Relaxation)(steps=2)
    cell = build_cell(loop_curves(fabric), fabric, case, settings)
    problem = cell.problem()

    def evaluate(state, load_factor):
        cell.model.set_natural_curvature(1.0 - load_factor)
        return problem.evaluate(state, load_factor)

    relaxing = dataclasses.replace(problem, evaluate=evaluate, commit=None)
    targets = np.linspace(0.0, 1.0, 11)[1:]
    try:
        steps = solve_path(
            relaxing, cell.reference_state(), targets, stepping=settings.stepping
        ).steps
        stopped = ""
    except ConvergenceError as error:
        steps, stopped = error.history.steps, str(error)
    knit = fabric.knit
    print("| t | natural curvature | F11 | F22 | F12 | w (mm) | c (mm) | penetration / r |")
    print("|---|---|---|---|---|---|---|---|")
    for record in steps:
        state = cell.evaluate_state(record.state, record.load_factor)
        F = state.deformation
        statistics = cell.coupling.result(record.state, record.load_factor, False).statistics
        print(
            f"| {record.load_factor:.2f} | {1 - record.load_factor:.2f} | {F[0, 0]:.4f} | "
            f"{F[1, 1]:.4f} | {F[0, 1]:.4f} | {F[0, 0] * knit.wale_width:.4f} | "
            f"{F[1, 1] * knit.course_height:.4f} | "
            f"{statistics.max_penetration / cell.yarn.radius:.3f} |"
        )
    if stopped:
        print(f"\nstopped: {stopped}")


if __name__ == "__main__":
    main()
