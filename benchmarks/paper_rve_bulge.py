"""Where the yarn of a course-wise stretch comes from: the bulge of the soft loop (issue 27).

For cotton 20s/2 at stitch 4.5, 5.5 and 6.5, along the paper group's ray nearest the course
axis (6.4 degrees: E22 about E11 / 9), run to their last converged state: the loop's depth
(the centreline's extent through the thickness) and its in-plane length
(`paper.comparison.loop_extents`) at rest, at the first state (E11 = 0.024) and at the last
(E11 = 0.21), with S11, S22 there, ours and theirs (gf/cm), for the models of `BULGE_MODELS`
(free fibres or the section's rigidity, on the model's band loop or the parabolic loop, with the
contact exponent shift). A soft loop bulges out of the plane at the first state (its depth
grows by half, its in-plane length falls by 2-3 %, its contacts are pressed by a third of r)
and the rest of the ray pulls the bulge flat: that is the yarn the stretch takes without
stretching the loop, so the cell gives way after its first state.

Then `--radius`: the loop that does not bulge (the section's rigidity, parabolic loop) with the
contact law's and the section scaling's radius r0 (`Yarn.minimal_radius`, 0.19 mm in the
presets: the smaller semi-axis of the elliptical yarn) raised to RADII, along both of their
rays nearest the axes: S11, S22 ours / theirs at the first, middle and last converged state,
and S12 of their picture-frame shear at its 5th and 13th state.
r0 enters the law k = 0.01 E0 (r0/r)^8, p = 3 - (r0/r)^3 and the section's scaling (r0/r)^4,
(r0/r)^6; the loop (r = w/8) does not change. At 4.5, r0 >= 0.2 mm gives p < 1 (refused).

    .venv/bin/python benchmarks/paper_rve_bulge.py [--radius | --support | --budget]
        [--control-points 68] [--figure docs/figures/paper_rve_bulge.png]
        [--contacts-figure docs/figures/paper_rve_contacts.png]

With --support, what holds the cell out of its plane: the point support's z force over the
largest face force (|reaction|, N) at the first and the last state of both axis rays, for
BULGE_MODELS: the two-pass contact's out-of-plane imbalance (docs/contact.md), which the support
carries and which would be zero were action and reaction equal.

With --budget, where the loop found its yarn: at the last converged state of both axis rays,
for BUDGET_MODELS on the model's band loop, the yarn the affine image of the rest loop would
need (the demand, % of the loop) and the shares of it that the yarn's stretch, the depth and
the loop's in-plane shape gave (`paper.comparison.length_budget`), and the stress across the
stretch (P22 on the course-wise ray, P11 on the wale-wise one) with the shares of it carried by
the yarn through the periodic cut, the contacts' normal loads and their friction
(`RveStep.stress_parts`), against their S across; the active contacts per collocation point and
the directions of the contact normals weighted by their force
(`paper.comparison.contact_directions`).

With --contacts-figure, the default's loop at stitch 5.5 at the first and the last state of their
ray nearest the course axis, seen from the face (x, y) and along the course (y, z), with its
contacts (`paper.comparison.contact_points`) as arrows of their normal line load, coloured by
how much of it points along the wale: which way the interlock pushes.

With --figure, the loop's centreline at rest, at the first and at the last state of that ray at
stitch 4.5, seen along the course (y, z) and along the wale (x, z), for FIGURE_MODELS.

About a minute (the depth table), two minutes (--radius) and 2.5 minutes (--budget) at 68
control points on the shared 2-core machine (2026-11-28). The tables go into docs/validation.md
("The bulge"; --budget and --contacts-figure: "Where the loop finds its yarn").
"""

import argparse
import dataclasses
import time

import matplotlib
import numpy as np

from rve_rod.contact import ContactOptions
from rve_rod.errors import InputError
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.paper.comparison import (
    axis_rays,
    compare_run,
    contact_directions,
    contact_points,
    length_budget,
    loop_extents,
    loop_profile_runner,
    run_case,
)
from rve_rod.rve.paper.data import shear_run
from rve_rod.rve.simulation import RveSettings
from rve_rod.rve.yarn import YarnSettings
from rve_rod.stress_measures import green_lagrange
from rve_rod.units import n_per_mm_to_gf_per_cm

matplotlib.use("Agg")
import matplotlib.pyplot as plt

STITCHES = (4.5, 5.5, 6.5)
BULGE_MODELS = {
    "free fibres (the default), band loop": ("band", YarnSettings()),
    "section, band loop": ("band", YarnSettings(bending="section")),
    "free fibres, parabolic loop": ("parabolic", YarnSettings()),
    "free fibres, parabolic loop, p - 0.25": (
        "parabolic",
        YarnSettings(contact_exponent_shift=-0.25),
    ),
    "free fibres, parabolic loop, p - 0.25, frictionless": (
        "parabolic",
        YarnSettings(contact_exponent_shift=-0.25, friction=False),
    ),
    "section, parabolic loop": ("parabolic", YarnSettings(bending="section")),
    "section, parabolic loop, p - 0.25": (
        "parabolic",
        YarnSettings(bending="section", contact_exponent_shift=-0.25),
    ),
}
BUDGET_MODELS = {
    "free fibres (the default)": (YarnSettings(), False),
    "free fibres, squeezed rest, balanced contact": (YarnSettings(contact_radius="measured"), True),
    "section (the paper's ingredients)": (YarnSettings(bending="section"), False),
}
"""The models of the --budget table: the yarn settings and whether the contact is balanced."""
SHEAR_STATES = (4, 12)
"""Indices of the picture-frame states whose S12 the --radius table prints."""
FIGURE_MODELS = (
    "free fibres, parabolic loop, p - 0.25",
    "section, parabolic loop, p - 0.25",
    "free fibres (the default), band loop",
)
"""The models drawn by --figure (keys of BULGE_MODELS)."""
RADII = (0.19, 0.198, 0.205)
"""r0 (mm) of the --radius table: the presets' 0.19 and two larger equivalent radii."""


def _gf(value: float) -> str:
    return f"{n_per_mm_to_gf_per_cm(value):.1f}"


def depth_table(control_points: int) -> None:
    print(
        "| model | stitch | depth at rest (mm) | depth, first / last state (x rest) | in-plane "
        "length, first / last (%) | yarn stretch, last (%) | largest penetration / r, first "
        "/ last | S11 first / last, ours (theirs) | S22 first / last, ours (theirs) |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---|---|")
    for name, (profile, yarn) in BULGE_MODELS.items():
        for stitch in STITCHES:
            fabric = load_preset("cotton-20s2", stitch)
            ray = axis_rays(stitch)[0]
            states = ray.converged
            settings = RveSettings(cell=CellSettings(control_points=control_points), yarn=yarn)
            result = loop_profile_runner(profile)(fabric, run_case(ray, states), settings)
            if len(result.steps) <= states:
                print(f"| {name} | {stitch} | stopped: {result.message} |")
                continue
            extent = loop_extents(result)
            first, last = result.steps[1], result.steps[-1]
            depth = extent.depth / extent.depth[0]
            in_plane = 100 * (extent.in_plane_length / extent.in_plane_length[0] - 1)
            stretch = 100 * (extent.length[-1] / extent.length[0] - 1)
            r = result.yarn.radius
            print(
                f"| {name} | {stitch} | {extent.depth[0]:.3f} | {depth[1]:.2f} / {depth[-1]:.2f} "
                f"| {in_plane[1]:+.1f} / {in_plane[-1]:+.1f} | {stretch:.2f} | "
                f"{first.max_penetration / r:.2f} / {last.max_penetration / r:.2f} | "
                f"{_gf(first.second_piola[0])} / {_gf(last.second_piola[0])} "
                f"({_gf(ray.second_piola[0, 0, 0])} / {_gf(ray.second_piola[states - 1, 0, 0])}) | "
                f"{_gf(first.second_piola[1])} / {_gf(last.second_piola[1])} "
                f"({_gf(ray.second_piola[0, 1, 1])} / {_gf(ray.second_piola[states - 1, 1, 1])}) |",
                flush=True,
            )


def radius_table(control_points: int) -> None:
    print(
        "| r0 (mm) | stitch | ray (deg) | E11, E22 at first / middle / last | S11 ours (theirs) "
        "| S22 ours (theirs) |"
    )
    print("|---:|---:|---:|---|---|---|")
    runner = loop_profile_runner("parabolic")
    settings = RveSettings(
        cell=CellSettings(control_points=control_points), yarn=YarnSettings(bending="section")
    )
    for radius in RADII:
        for stitch in STITCHES:
            preset = load_preset("cotton-20s2", stitch)
            yarn = dataclasses.replace(preset.yarn, minimal_radius=radius)
            fabric = dataclasses.replace(preset, yarn=yarn)
            for ray in [*axis_rays(stitch), shear_run(stitch)]:
                try:
                    run = compare_run(fabric, ray, settings, runner=runner)
                except InputError as error:
                    reason = str(error).split(";")[0]
                    label = "shear" if ray.kind == "shear" else f"{ray.angle_deg:.1f}"
                    print(f"| {radius} | {stitch} | {label} | refused: {reason} |")
                    continue
                if ray.kind == "shear":
                    print(f"| {radius} | {stitch} | shear | {_shear_cells(run)} |", flush=True)
                    continue
                picks = sorted({0, (run.states - 1) // 2, run.states - 1})
                strains = [np.diagonal(green_lagrange(ray.deformation[k])) for k in picks]
                ours, theirs = run.second_piola[picks], ray.second_piola[picks]
                cells = [
                    " / ".join(f"{_gf(o[a, a])}" for o in ours)
                    + " ("
                    + " / ".join(f"{_gf(t[a, a])}" for t in theirs)
                    + ")"
                    for a in (0, 1)
                ]
                print(
                    f"| {radius} | {stitch} | {ray.angle_deg:.1f} | "
                    + " / ".join(f"{e[0]:.3f}, {e[1]:.3f}" for e in strains)
                    + f" | {cells[0]} | {cells[1]} |",
                    flush=True,
                )


def support_table(control_points: int) -> None:
    print("| model | " + " | ".join(f"{s} course / wale" for s in STITCHES) + " |")
    print("|---|" + "---|" * len(STITCHES))
    for name, (profile, yarn) in BULGE_MODELS.items():
        settings = RveSettings(cell=CellSettings(control_points=control_points), yarn=yarn)
        cells = []
        for stitch in STITCHES:
            fabric = load_preset("cotton-20s2", stitch)
            shares = []
            for ray in axis_rays(stitch):
                result = loop_profile_runner(profile)(
                    fabric, run_case(ray, ray.converged), settings
                )
                share = [
                    abs(step.support_reaction[2]) / np.abs(step.reaction).max()
                    for step in result.steps[1:]
                ]
                shares.append(f"{share[0]:.2f}, {share[-1]:.2f}" if share else "-")
            cells.append(" / ".join(shares))
        print(f"| {name} | " + " | ".join(cells) + " |", flush=True)


def budget_table(control_points: int) -> None:
    print(
        "| model | stitch | ray (deg) | demand (%) | stretch / depth / in-plane shape (% of it) "
        "| stress across, ours (theirs) (gf/cm) | yarn / contact / friction (% of ours) "
        "| active contacts per point | contact normals along x / y / z |"
    )
    print("|---|---:|---:|---:|---|---|---|---:|---|")
    for name, (yarn, balance) in BUDGET_MODELS.items():
        cell = CellSettings(control_points=control_points, contact=ContactOptions(balance=balance))
        settings = RveSettings(cell=cell, yarn=yarn)
        for stitch in STITCHES:
            fabric = load_preset("cotton-20s2", stitch)
            for ray, across in zip(axis_rays(stitch), (1, 0), strict=True):
                result = loop_profile_runner("band")(fabric, run_case(ray, ray.converged), settings)
                last = len(result.steps) - 1
                if last < ray.converged:
                    print(
                        f"| {name} | {stitch} | {ray.angle_deg:.1f} | stopped: {result.message} |"
                    )
                    continue
                step = result.steps[last]
                budget = length_budget(
                    result.centreline(0), result.centreline(last), step.deformation
                )
                parts = np.asarray(step.stress_parts)[:, across, across]
                shares = " / ".join(f"{100 * part / parts.sum():.0f}" for part in parts)
                ours = step.second_piola[across]
                theirs = ray.second_piola[ray.converged - 1, across, across]
                print(
                    f"| {name} | {stitch} | {ray.angle_deg:.1f} | {100 * budget.demand:.1f} | "
                    f"{100 * budget.stretch:.1f} / {100 * budget.depth:.1f} / "
                    f"{100 * budget.shape:.1f} | {_gf(ours)} ({_gf(theirs)}) | {shares} | "
                    f"{step.active_contacts / result.curve.n_control_points:.2f} | "
                    + " / ".join(f"{c:.2f}" for c in _directions(result, last))
                    + " |",
                    flush=True,
                )


def _directions(result, step: int) -> np.ndarray:
    """`paper.comparison.contact_directions` of the first patch at output state `step`."""
    f = np.eye(3)
    f[:2, :2] = result.steps[step].deformation
    return contact_directions(
        result.centreline(step), result.cell_lattice @ f.T, result.yarn.radius, result.yarn.law
    )


def contacts_figure(path: str, control_points: int) -> None:
    stitch = 5.5
    fabric = load_preset("cotton-20s2", stitch)
    knit = fabric.knit
    ray = axis_rays(stitch)[0]
    settings = RveSettings(cell=CellSettings(control_points=control_points))
    result = loop_profile_runner("band")(fabric, run_case(ray, ray.converged), settings)
    last = len(result.steps) - 1
    plot, axes = plt.subplots(
        2, 2, figsize=(12, 8), gridspec_kw={"height_ratios": (3, 1)}, layout="constrained"
    )
    for column, step in enumerate((1, last)):
        f = np.eye(3)
        f[:2, :2] = result.steps[step].deformation
        lattice = result.cell_lattice @ f.T
        curve = result.centreline(step)
        points = curve(np.linspace(*curve.domain, 800))
        contacts = contact_points(curve, lattice, result.yarn.radius, result.yarn.law)
        shown = slice(None, None, 5)
        arrows = (contacts.normal * contacts.load[:, None])[shown]
        scale = np.abs(arrows).max() / 0.3  # the largest load drawn 0.3 mm long
        shares = contact_directions(curve, lattice, result.yarn.radius, result.yarn.law)
        for row, (a, b, view) in enumerate(((0, 1, "from the face"), (1, 2, "along the course"))):
            axis = axes[row, column]
            for i in (-1, 0, 1):
                for j in (-1, 0, 1):
                    shifted = points + i * lattice[0] + j * lattice[1]
                    mine = (i, j) == (0, 0)
                    axis.plot(shifted[:, a], shifted[:, b], color="k" if mine else "0.8", lw=1)
            arrow = axis.quiver(
                contacts.position[shown, a],
                contacts.position[shown, b],
                arrows[:, a],
                arrows[:, b],
                np.abs(contacts.normal[shown, 1]),
                cmap="viridis",
                clim=(0, 1),
                angles="xy",
                scale_units="xy",
                scale=scale,
                width=0.003,
            )
            axis.set_aspect("equal")
            low, high = (-0.5 * knit.wale_width, 1.5 * lattice[0, 0]) if a == 0 else (-1.2, 1.2)
            axis.set_xlim(low, high)
            axis.set_ylim(*((-1.3, 1.3) if b == 1 else (-0.4, 0.4)))
            axis.set_xlabel(f"{'xyz'[a]} (mm)")
            axis.set_ylabel(f"{'xyz'[b]} (mm)")
            e11 = result.steps[step].green_lagrange[0]
            title = f"E11 = {e11:.3f}, seen {view}"
            if row == 0:
                title += "; force-weighted |n| along x / y / z " + " / ".join(
                    f"{share:.2f}" for share in shares
                )
            axis.set_title(title, fontsize=9)
    plot.colorbar(arrow, ax=axes, label="|n_y|: how much of a contact's load pushes along the wale")
    plot.suptitle(
        f"cotton 20s/2, stitch {stitch}, the default model: the contacts' normal line loads "
        f"(arrows, every 5th sample) on their {ray.angle_deg:.1f}-degree ray, {control_points} "
        "control points"
    )
    plot.savefig(path, dpi=80)
    print(f"wrote {path}")


def _shear_cells(run) -> str:
    """S12 (the symmetric part, gf/cm) ours (theirs) at SHEAR_STATES of the picture frame."""
    picks = [k for k in SHEAR_STATES if k < run.reached]

    def s12(stresses):
        return " / ".join(_gf(0.5 * (stresses[k, 0, 1] + stresses[k, 1, 0])) for k in picks)

    frame = run.reference.deformation
    angles = ", ".join(
        f"{np.degrees(np.arctan2(frame[k, 0, 1], frame[k, 1, 1])):.0f}" for k in picks
    )
    return f"at {angles} deg: {s12(run.second_piola)} ({s12(run.reference.second_piola)})"


def figure(path: str, control_points: int) -> None:
    stitch = 4.5
    fabric = load_preset("cotton-20s2", stitch)
    ray = axis_rays(stitch)[0]
    plot, axes = plt.subplots(2, len(FIGURE_MODELS), figsize=(5 * len(FIGURE_MODELS), 7))
    for column, name in enumerate(FIGURE_MODELS):
        profile, yarn = BULGE_MODELS[name]
        settings = RveSettings(cell=CellSettings(control_points=control_points), yarn=yarn)
        result = loop_profile_runner(profile)(fabric, run_case(ray, ray.converged), settings)
        extent = loop_extents(result)
        last = len(result.steps) - 1
        for step, style in ((0, ":"), (1, "-"), (last, "--")):
            curve = result.centreline(step)
            points = curve(np.linspace(*curve.domain, 800))
            label = (
                f"E11 = {result.steps[step].green_lagrange[0]:.3f}, "
                f"depth x{extent.depth[step] / extent.depth[0]:.2f}"
            )
            for row, (a, along) in enumerate(((1, "course"), (0, "wale"))):
                axis = axes[row, column]
                axis.plot(points[:, a], points[:, 2], style, color="k", label=label)
                axis.set_xlabel(f"{'y' if a == 1 else 'x'} (mm)")
                axis.set_ylabel("z (mm)")
                axis.set_aspect("equal")
                axis.set_title(f"{name}\nseen along the {along}", fontsize=9)
        axes[0, column].legend(fontsize=7, loc="lower right")
    plot.suptitle(
        f"cotton 20s/2, stitch {stitch}: their {ray.angle_deg:.1f}-degree ray, "
        f"{control_points} control points (rest dotted, first state solid, last dashed)"
    )
    plot.tight_layout()
    plot.savefig(path, dpi=80)
    print(f"wrote {path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--control-points", type=int, default=68)
    parser.add_argument("--radius", action="store_true", help="the r0 table instead")
    parser.add_argument("--support", action="store_true", help="the support's share instead")
    parser.add_argument("--budget", action="store_true", help="the loop's length budget instead")
    parser.add_argument("--figure", help="draw the loops at stitch 4.5 into this PNG instead")
    parser.add_argument("--contacts-figure", help="draw the contacts at 5.5 into this PNG instead")
    args = parser.parse_args()
    start = time.perf_counter()
    if args.figure:
        figure(args.figure, args.control_points)
    elif args.contacts_figure:
        contacts_figure(args.contacts_figure, args.control_points)
    elif args.support:
        support_table(args.control_points)
    elif args.budget:
        budget_table(args.control_points)
    else:
        (radius_table if args.radius else depth_table)(args.control_points)
    print(f"\n{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
