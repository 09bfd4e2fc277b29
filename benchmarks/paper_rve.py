"""Our RVE against the paper group's own RVE output (issue 27): tables on stdout, figures.

For each stitch value of `rve_rod.rve.paper.data` (4.5, 5.5, 6.5): our cell along each of their
12 biaxial rays and their picture-frame shear, at every converged state of theirs (t = k/20),
with the error of `rve_rod.rve.paper.comparison` (the largest |S_ab| difference relative to the
largest stress of their run so far; target 20 %), and our uniaxial runs against the two
readings of their data (README of rve_rod/data/weeger_group_rve) and the paper's text.

    .venv/bin/python benchmarks/paper_rve.py [--stitches 5.5] [--control-points 68]
        [--bending section] [--contact-lumping point] [--balanced-contact]
        [--figures docs/figures] [--states 20]

About 85 s at 68 control points on the shared 2-core machine (2026-11-28; the shear panel
also shows the normal stresses S11, S22 of the shear).
"""

import argparse
import time
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from rve_rod.contact.model import LUMPINGS, ContactOptions
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.paper.comparison import TARGET, compare_run, uniaxial_comparison
from rve_rod.rve.paper.data import (
    PAPER_POISSON_RATIOS,
    STITCH_VALUES,
    UNIAXIAL_READINGS,
    biaxial_rays,
    shear_run,
)
from rve_rod.rve.simulation import RveSettings
from rve_rod.rve.yarn import BENDING_CHOICES, YarnSettings
from rve_rod.units import n_per_mm_to_gf_per_cm as gf

STRAINS = (0.05, 0.1, 0.2, 0.3)


def arguments():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--stitches", default=",".join(f"{s:g}" for s in STITCH_VALUES))
    parser.add_argument("--control-points", type=int, default=CellSettings().control_points)
    parser.add_argument("--bending", choices=BENDING_CHOICES, default="auto")
    parser.add_argument("--second-moment", choices=("solid", "paper"), default="solid")
    parser.add_argument(
        "--contact-lumping", choices=LUMPINGS, default="line", help="ContactOptions.lumping"
    )
    parser.add_argument(
        "--balanced-contact", action="store_true", help="ContactOptions.balance (an experiment)"
    )
    parser.add_argument("--states", type=int, default=None, help="at most this many per run")
    parser.add_argument("--figures", type=Path, default=None, help="folder for the figures")
    parser.add_argument("--suffix", default="", help="appended to the figure names")
    return parser.parse_args()


def main():
    args = arguments()
    if args.figures is not None:  # made before the runs: a missing folder lost them at the end
        args.figures.mkdir(parents=True, exist_ok=True)
    settings = RveSettings(
        cell=CellSettings(
            control_points=args.control_points,
            contact=ContactOptions(lumping=args.contact_lumping, balance=args.balanced_contact),
        ),
        yarn=YarnSettings(bending=args.bending, second_moment=args.second_moment),
    )
    print(
        f"settings: {args.control_points} control points, bending {args.bending}, "
        f"second moment {args.second_moment}, contact lumping {args.contact_lumping}"
        f"{', balanced contact' if args.balanced_contact else ''}; "
        f"target: every converged state within "
        f"{TARGET:.0%} of the run's largest stress\n"
    )
    summary = []
    for stitch in (float(s) for s in args.stitches.split(",")):
        fabric = load_preset("cotton-20s2", stitch)
        started = time.perf_counter()
        runs = [
            compare_run(fabric, run, settings, states=args.states) for run in biaxial_rays(stitch)
        ]
        shear = compare_run(fabric, shear_run(stitch), settings, states=args.states)
        uniaxial = uniaxial_comparison(fabric, settings, STRAINS)
        print_runs(stitch, runs, shear)
        print_uniaxial(stitch, uniaxial)
        compared = [run for run in runs if run.states]
        passed = sum(run.passed() for run in compared)
        summary.append(
            (stitch, passed, len(compared), shear.worst(), time.perf_counter() - started)
        )
        if args.figures is not None:
            figure = plot(stitch, runs, shear, uniaxial, args)
            path = args.figures / f"paper_rve_{stitch:g}{args.suffix}.png"
            figure.savefig(path, dpi=110)
            print(f"wrote {path}\n")
    print("| stitch | rays within the target | shear worst error | wall s |")
    print("|---:|---:|---:|---:|")
    for stitch, passed, count, shear_error, wall in summary:
        print(f"| {stitch:g} | {passed} of {count} | {shear_error:.2f} | {wall:.0f} |")


def print_runs(stitch, runs, shear):
    print(f"### Stitch {stitch:g}: rays and shear (S in gf/cm at their last converged state)\n")
    print(
        "| run | direction (deg) | their converged states | ours reached | E11, E22 (E12) at "
        "the last | their S | our S | worst error | error at the last |"
    )
    print("|---|---:|---:|---:|---|---|---|---:|---:|")
    for comparison in [*runs, shear]:
        reference = comparison.reference
        n = comparison.states
        if n == 0:
            print(f"| {reference.kind} | {reference.angle_deg:.1f} | 0 | - | - | - | - | - | - |")
            continue
        F = reference.deformation[n - 1]
        E = 0.5 * (F.T @ F - np.eye(2))
        components = comparison.components
        theirs = [
            gf(0.5 * (reference.second_piola[n - 1][a, b] + reference.second_piola[n - 1][b, a]))
            for a, b in components
        ]
        ours = [gf(comparison.second_piola[n - 1][a, b]) for a, b in components]
        strain = f"{E[0, 1]:.3f}" if reference.kind == "shear" else f"{E[0, 0]:.3f}, {E[1, 1]:.3f}"
        errors = comparison.errors()
        print(
            f"| {reference.kind} | {reference.angle_deg:.1f} | {n} | {comparison.reached} | "
            f"{strain} | {_pair(theirs)} | {_pair(ours)} | {comparison.worst():.2f} | "
            f"{errors[-1]:.2f} |"
        )
    print()


def print_uniaxial(stitch, uniaxial):
    print(f"### Stitch {stitch:g}: uniaxial (gf/cm; their readings (a) / (b), README)\n")
    print(
        "| strain | course force | theirs | nu12 | theirs | wale force | theirs | nu21 | theirs |"
    )
    print("|---:|---:|---|---:|---|---:|---|---:|---|")
    for i, strain in enumerate(uniaxial.strains):
        reading = UNIAXIAL_READINGS.get((stitch, round(float(strain), 3)))
        cells = ["-"] * 4
        if reading is not None:
            cells = [
                _pair(getattr(reading, name))
                for name in ("course_force", "nu12", "wale_force", "nu21")
            ]
            if stitch == 5.5 and strain == 0.2:
                cells[1] += f"; text {PAPER_POISSON_RATIOS['nu12']}"
                cells[3] += f"; text {PAPER_POISSON_RATIOS['nu21']}"
        print(
            f"| {strain:.0%} | {uniaxial.course_force[i]:.1f} | {cells[0]} | "
            f"{uniaxial.nu12[i]:.2f} | {cells[1]} | {uniaxial.wale_force[i]:.1f} | {cells[2]} | "
            f"{uniaxial.nu21[i]:.2f} | {cells[3]} |"
        )
    print()


def status(comparison) -> str:
    """A panel's title: the worst error, or why there is none."""
    if comparison.states == 0:
        return "no converged state of theirs"
    errors = comparison.errors()[: comparison.reached]
    worst = f"worst error {errors.max():.2f}" if errors.size else "no state of ours"
    if comparison.reached < comparison.states:
        return f"{worst}, ours stopped at state {comparison.reached} of {comparison.states}"
    return worst


def plot(stitch, runs, shear, uniaxial, args) -> Figure:
    figure = Figure(figsize=(16, 13), layout="constrained")
    axes = figure.subplots(4, 4).ravel()
    for ax, comparison in zip(axes, [*runs, shear], strict=False):
        reference = comparison.reference
        t = np.arange(1, reference.states + 1) / reference.states
        converged = np.arange(reference.states) < reference.converged
        x_label = "t (ray parameter, k/20)"
        if reference.kind == "shear":
            t = np.degrees(
                np.arctan2(reference.deformation[:, 0, 1], reference.deformation[:, 1, 1])
            )
            x_label = "shear angle (deg)"
        drawn = zip(comparison.components, ("C0", "C3"), strict=False)
        if reference.kind == "shear":  # S12 and the normal stresses it causes (E11 = E22 = 0)
            drawn = (((0, 1), "k"), ((0, 0), "C0"), ((1, 1), "C3"))
        for (a, b), colour in drawn:
            theirs = gf(0.5 * (reference.second_piola[:, a, b] + reference.second_piola[:, b, a]))
            label = f"S{a + 1}{b + 1}"
            ax.plot(
                t[converged], theirs[converged], "o", color=colour, ms=4, label=f"{label} theirs"
            )
            ax.plot(t[~converged], theirs[~converged], "o", color=colour, ms=4, mfc="none")
            if comparison.states:
                ours = gf(comparison.second_piola[:, a, b])
                ax.plot(t[: comparison.states], ours, "-", color=colour, label=f"{label} ours")
        title = "shear" if reference.kind == "shear" else f"ray {reference.angle_deg:.0f} deg"
        ax.set_title(f"{title}: {status(comparison)}", fontsize=9)
        if reference.kind == "shear":
            ax.legend(fontsize=7)
        ax.set_xlabel(x_label, fontsize=8)
        ax.set_ylabel("S (gf/cm)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.axhline(0.0, color="0.8", lw=0.5)
    axes[0].legend(fontsize=7)
    for ax, name, lateral in zip(axes[13:15], ("course", "wale"), ("nu12", "nu21"), strict=True):
        ax.plot(100 * uniaxial.strains, getattr(uniaxial, f"{name}_force"), "s-", label="ours")
        for strain in (0.1, 0.2):
            reading = UNIAXIAL_READINGS[(stitch, strain)]
            for value in getattr(reading, f"{name}_force"):
                if value is not None:
                    ax.plot(100 * strain, value, "k_", ms=12)
        ax.set_title(f"uniaxial {name}-wise (bars: their readings)", fontsize=9)
        ax.set_xlabel("strain (%)", fontsize=8)
        ax.set_ylabel("force (gf/cm)", fontsize=8)
        ax.tick_params(labelsize=7)
        twin = ax.twinx()
        twin.plot(100 * uniaxial.strains, getattr(uniaxial, lateral), "^--", color="C2")
        twin.set_ylabel(lateral, fontsize=8, color="C2")
        twin.tick_params(labelsize=7)
    axes[15].axis("off")
    figure.suptitle(
        f"cotton 20s/2 stitch {stitch:g}: the paper group's RVE (dots; hollow: not converged) "
        f"and ours (lines; {args.control_points} control points, bending {args.bending}, "
        f"contact lumping {args.contact_lumping})"
    )
    return figure


def _pair(values) -> str:
    return " / ".join("-" if v is None else f"{v:.3g}" for v in values)


if __name__ == "__main__":
    main()
