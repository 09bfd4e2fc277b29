"""The shortest loop the model's spline space holds: how far the loop model is from it.

The loop model (`rve_rod.geometry.loop`) picks one loop per fabric from a one-parameter family
of three-section quarters. This script forgets the sections: it minimizes the loop length over
every quarter the model could produce (degree 4, 12 control points, the symmetry end conditions
that make the mirrored loop C2) under the same clearance condition, starting from the model's
loop. The clearance is a quadratic penalty on sampled point pairs (the quarter against the
loop and its images i a1 + j a2, |i| <= 1, |j| <= 2, parts closer than pi r along the yarn
excepted) closer than 2r (1 + 5e-4), with a rising penalty factor; the result is checked with
the model's exact clearance search. It is a local optimum, so an upper bound of the shortest
loop and a lower target for the model. With --rve it also runs the uniaxial course- and
wale-wise RVE tests on both loops (force at 20 %, Poisson ratio); with --figure it draws both
loops of the first fabric. docs/geometry.md has the results. About 2 minutes per fabric.

    .venv/bin/python benchmarks/shortest_loop.py [--fabric cotton-20s2:4.5 ...] [--rve]
        [--figure docs/figures/shortest_loop.png]
"""

import argparse
import time
from typing import NamedTuple

import numpy as np
import scipy.linalg
import scipy.optimize
from matplotlib.figure import Figure

from rve_rod.geometry.bspline import BSplineCurve, basis_matrix, open_knot_vector
from rve_rod.geometry.loop import ADJACENT_ARC_FACTOR, loop_geometry
from rve_rod.geometry.loop_spline import (
    CONTROL_POINTS,
    DEGREE,
    condition_rows,
    mirrored_loop,
    symmetry_conditions,
)
from rve_rod.geometry.proximity import chain_clearance
from rve_rod.presets import load_preset, stitch_values
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import simulate

SAMPLES = 80
"""Points per curve in the clearance penalty."""
LENGTH_SAMPLES = 400
"""Points of the quarter's polyline whose length is minimized."""
PENALTY_FACTORS = (1e2, 1e3, 1e4, 1e5, 1e6, 1e7)
MARGIN = 5e-4
"""The penalty keeps pairs 2r (1 + MARGIN) apart, so that the sampled optimum clears 2r."""


class QuarterSpace(NamedTuple):
    """Quarters meeting the symmetry conditions: control points = offset + basis @ q, per axis.

    Attributes:
        offsets: three (12,) particular solutions (mm).
        bases: three (12, k_axis) orthonormal bases of the conditions' null spaces.
    """

    offsets: tuple[np.ndarray, ...]
    bases: tuple[np.ndarray, ...]

    def control_points(self, q: np.ndarray) -> np.ndarray:
        """(12, 3) control points of the quarter with coordinates q (mm)."""
        split = np.split(q, np.cumsum([basis.shape[1] for basis in self.bases])[:-1])
        return np.column_stack(
            [o + b @ part for o, b, part in zip(self.offsets, self.bases, split, strict=True)]
        )

    def coordinates(self, control_points: np.ndarray) -> np.ndarray:
        """q of a quarter that meets the conditions."""
        return np.concatenate(
            [
                b.T @ (control_points[:, k] - o)
                for k, (o, b) in enumerate(zip(self.offsets, self.bases, strict=True))
            ]
        )


def quarter_space(knots: np.ndarray, wale_width: float) -> QuarterSpace:
    offsets, bases = [], []
    for conditions in symmetry_conditions(wale_width):
        rows = condition_rows(conditions)
        values = np.array([condition.value for condition in conditions])
        offsets.append(np.linalg.lstsq(rows, values, rcond=None)[0])
        bases.append(scipy.linalg.null_space(rows))
    return QuarterSpace(tuple(offsets), tuple(bases))


class ShortestLoop(NamedTuple):
    """The result for one fabric (lengths in mm).

    Attributes:
        curves: the 4 curves of the shortest loop found.
        loop_length: its length.
        clearance: its exact minimum clearance.
        image: the periodic image (i, j) where it occurs.
        depth: its out-of-plane extent, max z - min z.
        seconds: wall time of the optimization.
    """

    curves: tuple[BSplineCurve, ...]
    loop_length: float
    clearance: float
    image: tuple[int, int]
    depth: float
    seconds: float


def shortest_loop(geometry) -> ShortestLoop:
    """Shorten the model's loop under the clearance condition (see the module docstring)."""
    started = time.perf_counter()
    w, r = geometry.wale_width, geometry.yarn_radius
    knots = open_knot_vector(DEGREE, CONTROL_POINTS)
    space = quarter_space(knots, w)
    on_quarter = basis_matrix(knots, DEGREE, np.linspace(0.0, 1.0, LENGTH_SAMPLES)).toarray()
    samples = np.linspace(0.0, 1.0, SAMPLES)
    shifts = np.array([[i, j, 0.0] for i in (-1, 0, 1) for j in (-2, -1, 0, 1, 2)], float)
    shifts[:, :2] *= [w, geometry.course_height]
    at_home = int(np.flatnonzero(~shifts.any(axis=1))[0])

    def loop_points(q):
        curves = mirrored_loop(BSplineCurve(DEGREE, knots, space.control_points(q)), w)
        return np.vstack([curve(samples) for curve in curves])

    # The loop's points are affine in q: their matrix, column by column.
    q0 = space.coordinates(geometry.curves[2].control_points)
    base = loop_points(np.zeros_like(q0))
    columns = [loop_points(unit) - base for unit in np.eye(q0.size)]
    matrix = np.stack([column.ravel() for column in columns], axis=1)
    quarter = slice(2 * SAMPLES, 3 * SAMPLES)  # curve 2, apex -> L

    def objective(q, factor):
        control = space.control_points(q)
        polyline = on_quarter @ control
        segments = np.diff(polyline, axis=0)
        lengths = np.linalg.norm(segments, axis=1)
        directions = segments / lengths[:, None]
        gradient_polyline = np.zeros_like(polyline)
        gradient_polyline[1:] += 4 * directions
        gradient_polyline[:-1] -= 4 * directions
        gradient_control = on_quarter.T @ gradient_polyline
        points = (base.ravel() + matrix @ q).reshape(base.shape)
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
        offsets = points[quarter, None, None, :] - points[None, None, :, :] - shifts[None, :, None]
        distance = np.linalg.norm(offsets, axis=3)
        counted = np.ones(distance.shape, bool)
        counted[:, at_home, :] = np.abs(arc[quarter, None] - arc[None, :]) > ADJACENT_ARC_FACTOR * r
        shortfall = np.where(counted, np.maximum(2 * r * (1 + MARGIN) - distance, 0.0), 0.0)
        pull = (-2 * factor * shortfall / np.maximum(distance, 1e-12))[..., None] * offsets
        gradient_points = np.zeros_like(points)
        gradient_points[quarter] += pull.sum(axis=(1, 2))
        gradient_points -= pull.sum(axis=(0, 1))
        gradient_q = np.concatenate(
            [b.T @ gradient_control[:, k] for k, b in enumerate(space.bases)]
        )
        gradient_q += matrix.T @ gradient_points.ravel()
        return 4 * lengths.sum() + factor * np.sum(shortfall**2), gradient_q

    q = q0
    for factor in PENALTY_FACTORS:
        q = scipy.optimize.minimize(
            objective, q, args=(factor,), jac=True, method="L-BFGS-B", options={"maxiter": 3000}
        ).x
    curves = mirrored_loop(BSplineCurve(DEGREE, knots, space.control_points(q)), w)
    closest = chain_clearance(curves, geometry.lattice, ADJACENT_ARC_FACTOR * r)
    z = curves[2](np.linspace(0.0, 1.0, 401))[:, 2]
    return ShortestLoop(
        curves=curves,
        loop_length=4 * curves[2].arc_length(),
        clearance=closest.distance,
        image=closest.image,
        depth=float(np.ptp(z)),
        seconds=time.perf_counter() - started,
    )


def rve_figures(fabric, curves) -> str:
    """Force at 20 % (gf/cm) and Poisson ratio, course- and wale-wise, on the given loop."""
    cells = []
    for name in ("uniaxial-course", "uniaxial-wale"):
        result = simulate(fabric, load_case(name), curves=list(curves))
        cells.append(f"{result.steps[-1].force_gf_per_cm:.1f} / {result.poisson_ratio:.3f}")
    return " | ".join(cells)


def draw(path, name, geometry, best: ShortestLoop):
    """x/y projection of both loops among their neighbours, and z/r along the quarter."""
    figure = Figure(figsize=(10, 4))
    plane, profile = figure.subplots(1, 2, width_ratios=(1.4, 1))
    u = np.linspace(0.0, 1.0, 200)
    r = geometry.yarn_radius
    for curves, colour, label in (
        (geometry.curves, "C0", f"model, {geometry.loop_length:.3f} mm"),
        (best.curves, "C3", f"shortest, {best.loop_length:.3f} mm"),
    ):
        for i in (-1, 0, 1):
            for j in (0, 1):
                for curve in curves:
                    points = curve(u) + i * geometry.lattice[0] + j * geometry.lattice[1]
                    alpha = 1.0 if (i, j) == (0, 0) else 0.25
                    plane.plot(points[:, 0], points[:, 1], colour, alpha=alpha, lw=1)
        quarter = curves[2](u)
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(quarter, axis=0), axis=1))])
        profile.plot(arc / r, quarter[:, 2] / r, colour, label=label)
    plane.set_aspect("equal")
    plane.set_xlabel("x (mm)")
    plane.set_ylabel("y (mm)")
    plane.set_title(f"{name}: loop (bold) and neighbours")
    profile.set_xlabel("arc length from the head apex / r")
    profile.set_ylabel("z / r")
    profile.set_title("out of plane along the quarter")
    profile.grid(alpha=0.3)
    profile.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=80)


def fabrics(names):
    if names:
        for name in names:
            preset, _, stitch = name.partition(":")
            yield name, load_preset(preset, float(stitch) if stitch else None)
        return
    yield "vassiliadis-sample2", load_preset("vassiliadis-sample2")
    for stitch in stitch_values("cotton-20s2"):
        yield f"cotton-20s2 {stitch:g}", load_preset("cotton-20s2", stitch)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fabric", action="append", help="preset[:stitch], repeatable")
    parser.add_argument("--rve", action="store_true", help="also run the uniaxial RVE tests")
    parser.add_argument("--figure", help="PNG comparing both loops of the first fabric")
    args = parser.parse_args()
    header = (
        "| fabric | measured l | model l | error | shortest l | error | clearance/2r | image"
        " | depth/r (model, shortest) | s |"
    )
    rve_header = (
        "| fabric | loop | course: F at 20 % (gf/cm) / nu12 | wale: F at 20 % (gf/cm) / nu21 |"
    )
    rows, rve_rows = [], []
    for name, fabric in fabrics(args.fabric):
        geometry = loop_geometry(fabric.knit, fabric.yarn.minimal_radius)
        best = shortest_loop(geometry)
        measured, r = fabric.knit.measured_loop_length, geometry.yarn_radius
        z = geometry.curves[2](np.linspace(0.0, 1.0, 401))[:, 2]
        rows.append(
            f"| {name} | {measured:.3f} | {geometry.loop_length:.3f}"
            f" | {geometry.loop_length / measured - 1:+.1%} | {best.loop_length:.3f}"
            f" | {best.loop_length / measured - 1:+.1%} | {best.clearance / (2 * r):.5f}"
            f" | {best.image} | {np.ptp(z) / r:.2f}, {best.depth / r:.2f} | {best.seconds:.0f} |"
        )
        print(rows[-1], flush=True)
        if args.figure and len(rows) == 1:
            draw(args.figure, name, geometry, best)
        if args.rve:
            for label, curves in (("model", geometry.curves), ("shortest", best.curves)):
                rve_rows.append(f"| {name} | {label} | {rve_figures(fabric, curves)} |")
                print(rve_rows[-1], flush=True)
    print()
    print(header)
    print("|" + "---|" * (header.count("|") - 1))
    print("\n".join(rows))
    if rve_rows:
        print("\n" + rve_header)
        print("|" + "---|" * (rve_header.count("|") - 1))
        print("\n".join(rve_rows))


if __name__ == "__main__":
    main()
