"""Accuracy against cost of the rod engine: convergence in n for p = 2, 3, 4 and the effect
of slenderness (locking of the displacement-based collocation).

Case: a straight cantilever of length L = 10 mm under the end moment M = 2 pi EI / L, which
rolls it into a full circle (exact solution: zero strain, circle of radius L / 2 pi). The
error is the largest distance between the computed and the exact centreline, over L. Prints
one table per slenderness L/r with the error, the Newton iterations and the wall time of the
whole load path, and writes docs/figures/rod_convergence.png.

    .venv/bin/python benchmarks/rod_convergence.py [--figure PATH]
"""

import argparse
import time

import matplotlib.pyplot as plt
import numpy as np

from rve_rod.errors import ConvergenceError
from rve_rod.geometry.bspline import BSplineCurve, open_knot_vector
from rve_rod.newton import solve_path
from rve_rod.rod import END, START, Clamp, EndLoad, RodEnd, RodModel, RodPatch, SectionStiffness
from rve_rod.stepping import SteppingOptions

LENGTH = 10.0
COUNTS = {
    2: [16, 32, 64, 128, 256, 512],
    3: [16, 32, 64, 128, 256],
    4: [12, 16, 24, 32, 48, 64, 96, 128],
}


def straight(degree, n):
    knots = open_knot_vector(degree, n)
    greville = BSplineCurve(degree, knots, np.zeros((n, 3))).greville()
    controls = np.zeros((n, 3))
    controls[:, 0] = LENGTH * greville  # the Greville interpolant of a line is exact
    return BSplineCurve(degree, knots, controls)


def rolled_circle_error(degree, n, radius):
    """(error / L, Newton iterations, seconds) of the full-circle cantilever, or None."""
    section = SectionStiffness.circular(radius, 1000.0)
    moment = 2 * np.pi * section.bending_1 / LENGTH
    patches = RodPatch.chain([straight(degree, n)], section, initial_normal=[0.0, 0.0, 1.0])
    model = RodModel(
        patches, [Clamp(RodEnd(0, START)), EndLoad(RodEnd(0, END), moment=[0, 0, moment])]
    )
    start = time.perf_counter()
    try:
        result = solve_path(
            model.problem(),
            model.reference_state(),
            [1.0],
            stepping=SteppingOptions(initial_increment=0.125, max_increment=0.25),
        )
    except ConvergenceError:
        return None
    seconds = time.perf_counter() - start
    params = np.linspace(0, 1, 1001)
    circle = LENGTH / (2 * np.pi)
    angle = 2 * np.pi * params
    exact = np.stack([circle * np.sin(angle), circle * (1 - np.cos(angle)), 0 * angle], axis=1)
    error = np.linalg.norm(model.positions(result.final_state, 0, params) - exact, axis=1).max()
    return error / LENGTH, result.newton_iterations, seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figure", default="docs/figures/rod_convergence.png")
    args = parser.parse_args()
    figure, axes = plt.subplots(1, 2, figsize=(9, 3.6))
    markers = {2: "o", 3: "s", 4: "^"}
    for column, slenderness in enumerate((20, 100)):
        radius = LENGTH / slenderness
        print(f"\nfull-circle cantilever, L/r = {slenderness}")
        print(f"{'p':>3} {'n':>5} {'error/L':>10} {'rate':>6} {'iterations':>11} {'time (s)':>9}")
        for degree, counts in COUNTS.items():
            points = []
            for n in counts:
                outcome = rolled_circle_error(degree, n, radius)
                if outcome is None:
                    print(f"{degree:>3} {n:>5}   no convergence (load path failed)")
                    continue
                error, iterations, seconds = outcome
                rate = ""
                if points:
                    previous_n, previous_error = points[-1]
                    spans = (n - degree) / (previous_n - degree)
                    rate = f"{np.log(previous_error / error) / np.log(spans):.2f}"
                points.append((n, error))
                print(
                    f"{degree:>3} {n:>5} {error:>10.2e} {rate:>6} {iterations:>11} {seconds:>9.2f}"
                )
            if points:
                n_values, errors = zip(*points, strict=True)
                axes[column].loglog(n_values, errors, marker=markers[degree], label=f"p = {degree}")
        axes[column].set_title(f"L/r = {slenderness}")
        axes[column].set_xlabel("control points n")
        axes[column].grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("max centreline error / L")
    axes[0].legend()
    figure.suptitle("Cantilever rolled into a full circle (M = 2 pi EI / L)")
    figure.tight_layout()
    figure.savefig(args.figure, dpi=100)
    print(f"\nwrote {args.figure}")


if __name__ == "__main__":
    main()
