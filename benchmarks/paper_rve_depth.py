"""Does the squeezed cell give way because its loop thins? The depth held (issue 27).

The squeezed and balanced rest state (the contact law at the yarn's own radius r0,
`YarnSettings.contact_radius = "measured"`, `ContactOptions.balance`) has the paper group's
stiffness at rest and then gives way, while its loop thins (depth 0.90 of rest at E11 = 0.21
on their 6.4-degree ray at 5.5; docs/validation.md, "The squeezed rest, balanced"). Here the
loop's depth is held by a diagnostic spring (not a model, `paper.comparison.depth_held_runner`):
every sampled point of the centreline (one per control point, ends excluded) is pulled towards
the z it had in the rest state, f_z = -kappa (z - z_rest), kappa = ALPHA EA / c (N/mm per
point), lumped onto the collocation points like the cell's ties (`rve_rod.rve.ties.DepthHold`).
If the thinning were what makes the cell give way, the held cell would stay as stiff as at its
first state.

For each ALPHA (0: the squeezed, balanced cell itself) at the stitch values asked: along their
rays nearest 6.4, 45 and 83.6 degrees the error (`paper.comparison`, relative to their largest
stress so far) at the first and at the last converged state and the loop's depth there over the
rest state's (`paper.comparison.loop_extents`), then over all their rays the median of the
worst errors, S11 and S22 at the last state of the 6.4-degree ray (ours / theirs, gf/cm), and
the uniaxial forces and Poisson ratios at 20 %.

    .venv/bin/python benchmarks/paper_rve_depth.py [--control-points 28] [--stitches 5.5]
        [--alphas 0,0.01,0.1]

About 40 s per ALPHA and stitch value at 28 control points on the shared 2-core machine
(2026-11-28). The table goes into docs/validation.md ("The squeezed rest, balanced").
"""

import argparse

import numpy as np

from rve_rod.contact import ContactOptions
from rve_rod.presets import Fabric, load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import LoadCase
from rve_rod.rve.paper.comparison import (
    compare_run,
    depth_held_runner,
    loop_extents,
    uniaxial_comparison,
)
from rve_rod.rve.paper.data import biaxial_rays
from rve_rod.rve.simulation import RveResult, RveSettings
from rve_rod.rve.yarn import YarnSettings
from rve_rod.units import n_per_mm_to_gf_per_cm

TENSION_RAYS = (6.4, 45.0, 83.6)
"""Their rays (degrees) whose first and last states the table shows."""


def measure(stitch: float, alpha: float, control_points: int) -> None:
    """Print the table's row of `stitch` and `alpha` (module docstring)."""
    settings = RveSettings(
        cell=CellSettings(control_points=control_points, contact=ContactOptions(balance=True)),
        yarn=YarnSettings(bending="free-fibres", contact_radius="measured"),
    )
    fabric = load_preset("cotton-20s2", stitch)
    held = depth_held_runner(alpha)
    last_result = []

    def run(fabric: Fabric, case: LoadCase, settings: RveSettings) -> RveResult:
        last_result[:] = [held(fabric, case, settings)]
        return last_result[0]

    worst, cells, last = [], [], "-"
    for ray in biaxial_rays(stitch):
        if not ray.converged:
            continue
        comparison = compare_run(fabric, ray, settings, runner=run)
        worst.append(comparison.worst())
        if min(abs(ray.angle_deg - a) for a in TENSION_RAYS) < 1.0:
            depth = loop_extents(last_result[0]).depth
            errors = comparison.errors()
            cells.append(
                f"{errors[0]:.2f} -> {errors[-1]:.2f} (depth {depth[1] / depth[0]:.3f} -> "
                f"{depth[-1] / depth[0]:.3f})"
            )
            if abs(ray.angle_deg - TENSION_RAYS[0]) < 1.0:
                ours = n_per_mm_to_gf_per_cm(np.diagonal(comparison.second_piola[-1]))
                reference = n_per_mm_to_gf_per_cm(
                    np.diagonal(ray.second_piola[comparison.states - 1])
                )
                last = f"{ours[0]:.1f} / {reference[0]:.1f}, {ours[1]:.1f} / {reference[1]:.1f}"
    uniaxial = uniaxial_comparison(fabric, settings, (0.2,), steps_per_percent=0.5, runner=run)
    print(
        f"| {stitch:g} | {alpha:g} | {' | '.join(cells)} | {np.median(worst):.2f} | {last} | "
        f"{uniaxial.course_force[0]:.1f}, {uniaxial.nu12[0]:.2f} | "
        f"{uniaxial.wale_force[0]:.1f}, {uniaxial.nu21[0]:.2f} |",
        flush=True,
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--control-points", type=int, default=28)
    parser.add_argument("--stitches", default="5.5")
    parser.add_argument("--alphas", default="0,0.01,0.1")
    args = parser.parse_args()
    print(
        "| stitch | alpha | error first -> last (depth / rest) at "
        + " | ".join(f"{a:g} deg" for a in TENSION_RAYS)
        + " | median worst error | S11, S22 at the last state of 6.4 deg, ours / theirs "
        "(gf/cm) | course F 20 %, nu12 | wale F 20 %, nu21 |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for stitch in (float(s) for s in args.stitches.split(",")):
        for alpha in (float(a) for a in args.alphas.split(",")):
            measure(stitch, alpha, args.control_points)


if __name__ == "__main__":
    main()
