"""The taut loop (issue 27): what a yarn prestrain eps0 does to the cell at rest.

For each stitch value and prestrain (`YarnSettings.prestrain`, free-fibre bending): the taut
rest state at F = I (`LoopCell.rest_state`), the yarn's internal force there against the force
EA eps0 / (1 + eps0) of a yarn held at its template length (how much of the prestrain the
contacts hold), the largest contact penetration beyond the squeeze (in yarn radii r), the rest
stress P0, and the secant stiffness at rest, C of S = C E, from the first state of the group's
two rays nearest the axes (6.4 and 83.6 degrees) against theirs from the same states. A
second table follows their equibiaxial ray to its last converged state: S, and how much of
the affine stretch of the yarn the yarn takes (the rest goes into the contacts and the loop's
shape). The tables go into docs/validation.md ("The paper group's RVE", the taut loop).
`--contact-radius measured` adds the squeeze of the contacts at rest
(`YarnSettings.contact_radius`), alone (eps0 = 0) or with the prestrain;
`--contact-stiffness-factor` changes the contact law's stiffness (the 0.01 of k = 0.01 E0
(r0/r)^8): how much of the prestrain a stiffer contact holds; `--contact-lumping point` applies
the law as a force at each collocation point (`ContactOptions.lumping`).

    .venv/bin/python benchmarks/paper_rve_taut.py [--stitches 4.5,5.5,6.5]
        [--prestrains 0,0.01,0.02,0.04,0.08] [--contact-radius adjusted]
        [--contact-stiffness-factor 0.01] [--contact-lumping line] [--control-points 28]
        [--figure PATH]

About 5 s per row of the first table, 10-30 s per row of the second, on a quiet core; a
prestrain whose rest state is not found gets a row saying so.
"""

import argparse
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from rve_rod.contact.law import DEFAULT_STIFFNESS_FACTOR
from rve_rod.contact.model import LUMPINGS, ContactOptions
from rve_rod.errors import ConvergenceError
from rve_rod.geometry.bspline import BSplineCurve
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import BiaxialRay
from rve_rod.rve.paper.comparison import (
    axis_rays,
    compare_run,
    run_case,
    run_or_history,
    secant_at_rest,
)
from rve_rod.rve.paper.data import biaxial_rays
from rve_rod.rve.simulation import RveSettings, build_cell, loop_curves
from rve_rod.rve.yarn import CONTACT_RADII, YarnSettings
from rve_rod.stress_measures import green_lagrange
from rve_rod.units import n_per_mm_to_gf_per_cm as gf


def rve_settings(prestrain: float, yarn: dict, control_points: int, lumping: str) -> RveSettings:
    """Free-fibre bending with the prestrain, further YarnSettings fields `yarn`, and the
    contact's lumping (`ContactOptions.lumping`)."""
    return RveSettings(
        cell=CellSettings(control_points=control_points, contact=ContactOptions(lumping=lumping)),
        yarn=YarnSettings(bending="free-fibres", prestrain=prestrain, **yarn),
    )


def measure(stitch: float, prestrain: float, yarn: dict, control_points: int, lumping: str) -> dict:
    """The row of one stitch value and prestrain; `yarn`: further YarnSettings fields."""
    settings = rve_settings(prestrain, yarn, control_points, lumping)
    fabric = load_preset("cotton-20s2", stitch)
    cell = build_cell(loop_curves(fabric), fabric, BiaxialRay(steps=2), settings)
    rest = cell.rest_state(settings.newton, settings.stepping)
    force = np.linalg.norm(
        cell.model.evaluate(rest, 0.0, with_jacobian=False).section.force, axis=0
    )
    statistics = cell.coupling.result(rest, 0.0, tangent=False).statistics
    squeeze = 2.0 * (cell.yarn.law.yarn_radius - cell.yarn.radius)
    rays = axis_rays(stitch)
    ours = [
        np.diagonal(compare_run(fabric, ray, settings, states=1).second_piola[0]) for ray in rays
    ]
    axial = cell.yarn.section.axial
    return {
        "held": axial * prestrain / (1.0 + prestrain),
        "force": (force.mean(), force.min(), force.max()),
        "penetration": (statistics.max_penetration - squeeze) / cell.yarn.radius,
        "rest": gf(np.diagonal(cell.rest_stress)),
        "ours": gf(secant_at_rest(rays, np.array(ours))),
        "theirs": gf(secant_at_rest(rays)),
    }


def along_equibiaxial(
    stitch: float, prestrain: float, yarn: dict, control_points: int, lumping: str
) -> dict:
    """Our cell along the group's equibiaxial ray to its last converged state (or as far as
    ours gets): S there, ours and theirs, and how the cell took the stretch: the yarn's
    elongation from rest (its length per loop from the centreline) against the affine one (the
    template's centreline mapped by F), and the largest contact penetration."""
    settings = rve_settings(prestrain, yarn, control_points, lumping)
    fabric = load_preset("cotton-20s2", stitch)
    ray = min(biaxial_rays(stitch), key=lambda ray: abs(ray.angle_deg - 45.0))
    result = run_or_history(fabric, run_case(ray, ray.converged), settings)
    template = result.curve
    length = template.arc_length()
    yarn_series, affine_series = [], []
    for k, step in enumerate(result.steps):
        stretch = np.eye(3)
        stretch[:2, :2] = step.deformation
        affine = BSplineCurve(template.degree, template.knots, template.control_points @ stretch.T)
        affine_series.append(affine.arc_length() / length - 1.0)
        yarn_series.append(result.centreline(k).arc_length() / length)
    yarn_series = np.array(yarn_series) - yarn_series[0]
    last = len(result.steps) - 1
    step = result.steps[last]
    return {
        "strain": step.green_lagrange[0],
        "ours": gf(step.second_piola[:2]),
        "theirs": gf(np.diagonal(ray.second_piola[last - 1])),
        "yarn": yarn_series[last],
        "affine": affine_series[last],
        "penetration": step.max_penetration / result.yarn.radius,
        "series": {
            "strain": result.series("green_lagrange")[:, 1],
            "stress": gf(result.series("second_piola")[:, 1]),
            "their_strain": np.r_[0.0, [green_lagrange(f)[1, 1] for f in ray.deformation]],
            "their_stress": gf(np.r_[0.0, ray.second_piola[:, 1, 1]]),
            "converged": ray.converged,
            "yarn": yarn_series,
            "affine": np.array(affine_series),
        },
    }


def plot_equibiaxial(rows: dict, path: Path) -> None:
    """S22 along their equibiaxial ray (theirs: dots, hollow for the first few beyond their
    converged states; ours: a line per prestrain), and the yarn's elongation against the
    affine one (dotted: the yarn stretched affinely)."""
    stitches = sorted({stitch for stitch, _ in rows})
    figure = Figure(figsize=(4.0 * len(stitches), 7.0), dpi=110)
    axes = figure.subplots(2, len(stitches), squeeze=False)
    for column, stitch in enumerate(stitches):
        top, bottom = axes[0, column], axes[1, column]
        prestrains = [prestrain for at, prestrain in rows if at == stitch]
        for colour, prestrain in enumerate(prestrains):
            series = rows[(stitch, prestrain)]["series"]
            if colour == 0:
                n = series["converged"] + 1
                top.plot(series["their_strain"][:n], series["their_stress"][:n], "ko", ms=4)
                beyond = slice(n - 1, n + 3)  # a few of their unconverged states
                top.plot(
                    series["their_strain"][beyond], series["their_stress"][beyond], "ko", mfc="none"
                )
                most = 100 * series["affine"].max()
                bottom.plot([0, most], [0, most], "k:", label="affine")
            label = f"eps0 = {100 * prestrain:g} %"
            top.plot(series["strain"], series["stress"], "-", color=f"C{colour}", label=label)
            bottom.plot(
                100 * series["affine"], 100 * series["yarn"], "-", color=f"C{colour}", label=label
            )
        top.set_title(f"stitch {stitch:g}: equibiaxial ray")
        top.set_xlabel("E11 = E22")
        top.set_ylabel("S22 (gf/cm)")
        bottom.set_xlabel("affine yarn elongation (%)")
        bottom.set_ylabel("yarn elongation from rest (%)")
        for axis in (top, bottom):
            axis.grid(alpha=0.3)
        top.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path)


def matrix(c: np.ndarray) -> str:
    return f"[[{c[0, 0]:.0f}, {c[0, 1]:.0f}], [{c[1, 0]:.0f}, {c[1, 1]:.0f}]]"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--stitches", default="4.5,5.5,6.5")
    parser.add_argument("--prestrains", default="0,0.01,0.02,0.04,0.08")
    parser.add_argument("--contact-radius", choices=CONTACT_RADII, default="adjusted")
    parser.add_argument("--contact-stiffness-factor", type=float, default=DEFAULT_STIFFNESS_FACTOR)
    parser.add_argument("--control-points", type=int, default=28)
    parser.add_argument("--contact-lumping", choices=LUMPINGS, default="line")
    parser.add_argument("--figure", type=Path, help="PNG of the equibiaxial runs")
    args = parser.parse_args()
    print(
        "| stitch | eps0 | EA eps0/(1+eps0) (mN) | yarn force at rest, mean (min-max) (mN) | "
        "largest penetration / r | P0 11, 22 (gf/cm) | C at rest, ours (gf/cm) | theirs |"
    )
    print("|---:|---:|---:|---|---:|---|---|---|")
    for stitch in (float(s) for s in args.stitches.split(",")):
        for prestrain in (float(e) for e in args.prestrains.split(",")):
            yarn = {
                "contact_radius": args.contact_radius,
                "contact_stiffness_factor": args.contact_stiffness_factor,
            }
            try:
                row = measure(stitch, prestrain, yarn, args.control_points, args.contact_lumping)
            except ConvergenceError as error:  # e.g. no rest state: say so, go on
                print(f"| {stitch:g} | {100 * prestrain:g} % | not found: {error} |", flush=True)
                continue
            mean, low, high = (1e3 * f for f in row["force"])
            print(
                f"| {stitch:g} | {100 * prestrain:g} % | {1e3 * row['held']:.0f} | "
                f"{mean:.1f} ({low:.1f}-{high:.1f}) | {row['penetration']:.2f} | "
                f"{row['rest'][0]:.1f}, {row['rest'][1]:.1f} | {matrix(row['ours'])} | "
                f"{matrix(row['theirs'])} |",
                flush=True,
            )
    print(
        "\n| stitch | eps0 | E11 = E22 | S11, S22 ours (gf/cm) | theirs | yarn elongation from "
        "rest | affine | ratio | largest penetration / r |"
    )
    print("|---:|---:|---:|---|---|---:|---:|---:|---:|")
    rows = {}
    for stitch in (float(s) for s in args.stitches.split(",")):
        for prestrain in (float(e) for e in args.prestrains.split(",")):
            try:
                row = rows[(stitch, prestrain)] = along_equibiaxial(
                    stitch, prestrain, yarn, args.control_points, args.contact_lumping
                )
            except ConvergenceError as error:
                print(f"| {stitch:g} | {100 * prestrain:g} % | not found: {error} |", flush=True)
                continue
            print(
                f"| {stitch:g} | {100 * prestrain:g} % | {row['strain']:.3f} | "
                f"{row['ours'][0]:.1f}, {row['ours'][1]:.1f} | "
                f"{row['theirs'][0]:.1f}, {row['theirs'][1]:.1f} | {100 * row['yarn']:.2f} % | "
                f"{100 * row['affine']:.2f} % | {row['yarn'] / row['affine']:.3f} | "
                f"{row['penetration']:.2f} |",
                flush=True,
            )
    if args.figure is not None:
        plot_equibiaxial(rows, args.figure)


if __name__ == "__main__":
    main()
