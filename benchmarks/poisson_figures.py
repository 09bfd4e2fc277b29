"""The deformed loop at 0 and 20 % course- and wale-wise, and where the lateral stress goes.

Cotton 20s/2 stitch 5.5, coarse settings (20 control points, 11 states; `--control-points`,
`--bending free-fibres` for the yarn's free-fibre bending rigidity). Writes
`poisson_loop<suffix>.png` into the figures folder: for each direction the face (x/y), side
(y/z) and end (x/z) views of the cell's yarn (blue, with its contacts: red slipping, orange
sticking) among its neighbours (grey), the unloaded loop dashed. Prints, for the last state
of each run, the lateral macro stress (P22 course-wise, P11 wale-wise; zero by the free
boundary condition) split into the part of the yarn force through the cut and the parts of
the normal and the friction loads of the contacts with the images (gf/cm): the friction part
is what holds the fabric against contracting.

    .venv/bin/python benchmarks/poisson_figures.py [--figures docs/figures] [--frictionless]
        [--control-points 20] [--bending section|free-fibres] [--suffix _name]
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rve_rod.geometry.loop import loop_geometry
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings, LoopCell
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import RveResult, RveSettings, run_cell
from rve_rod.rve.yarn import BENDING_MODELS, YarnSettings, yarn_model
from rve_rod.units import n_per_mm_to_gf_per_cm

CASES = ("uniaxial-course", "uniaxial-wale")
SAMPLES = 400


def run(case_name: str, settings: RveSettings, fabric):
    """(result, cell) of one run; the cell keeps the friction anchors of the last state."""
    curves = list(loop_geometry(fabric.knit, fabric.yarn.minimal_radius).curves)
    cell = LoopCell(
        curves,
        fabric.knit,
        yarn_model(fabric, settings.yarn),
        load_case(case_name, 0.2, 11),
        settings.cell,
    )
    return run_cell(cell, fabric, settings), cell


def contacts_of(result: RveResult, cell: LoopCell, step: int):
    """The contact evaluation of output state `step` against the committed anchors (for the
    last state: its own, so the friction loads are the converged ones)."""
    F = np.eye(3)
    F[:2, :2] = result.steps[step].deformation
    return cell.coupling.contact.evaluate(result.centrelines[step], F, tangent=False)


def draw(axes, result: RveResult, cell: LoopCell, title: str) -> None:
    """Face, side and end views of the unloaded (dashed) and last state of `result`."""
    knit = result.fabric.knit
    w, c = knit.wale_width, knit.course_height
    lattice = np.array([[w, 0.0, 0.0], [0.0, c, 0.0]])
    low, high = result.curve.domain
    u = np.linspace(low, high, SAMPLES)
    last = len(result.steps) - 1
    evaluation = contacts_of(result, cell, last)
    collocation = cell.coupling.contact.layout.collocation_positions(result.centrelines[last])
    contacts = evaluation.contacts
    views = ((0, 1), (1, 2), (0, 2))
    for step, style in ((0, "--"), (last, "-")):
        F = np.eye(3)
        F[:2, :2] = result.steps[step].deformation
        line = result.centreline(step)(u)
        for i in (-1, 0, 1):
            for j in (-1, 0, 1):
                points = line + F @ (i * lattice[0] + j * lattice[1])
                own = (i, j) == (0, 0)
                colour = ("tab:blue" if own else "0.6") if step else "0.3"
                for ax, (a, b) in zip(axes, views, strict=True):
                    if b == 2 and ((a == 1 and i != 0) or (a == 0 and j != 0)):
                        continue  # side view: one wale; end view: one course
                    ax.plot(
                        points[:, a],
                        points[:, b],
                        style,
                        color=colour,
                        lw=2.2 if (own and step) else 0.9,
                        zorder=3 if own else 1,
                    )
    points = collocation[:, contacts.slave]
    for ax, (a, b) in zip(axes, views, strict=True):
        for mask, colour, label in (
            (contacts.sliding, "red", "slipping"),
            (~contacts.sliding, "orange", "sticking"),
        ):
            ax.plot(
                points[a, mask], points[b, mask], ".", color=colour, ms=5, zorder=4, label=label
            )
        ax.set_aspect("equal")
    step = result.steps[last]
    axes[0].set(
        title=f"{title}: face (x/y) at {100 * step.strain:.0f} %",
        xlabel="x (mm)",
        ylabel="y (mm)",
        xlim=(-1.3 * w, 1.3 * w),
        ylim=(-1.3 * c, 1.3 * c),
    )
    axes[1].set(
        title="side (y/z), one wale", xlabel="y (mm)", ylabel="z (mm)", xlim=(-1.3 * c, 1.3 * c)
    )
    axes[2].set(
        title="end (x/z), one course", xlabel="x (mm)", ylabel="z (mm)", xlim=(-1.3 * w, 1.3 * w)
    )
    axes[0].legend(loc="upper right", fontsize=7)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figures", default="docs/figures")
    parser.add_argument("--frictionless", action="store_true")
    parser.add_argument("--control-points", type=int, default=20)
    parser.add_argument("--bending", choices=BENDING_MODELS, default="section")
    parser.add_argument("--suffix", default="", help="appended to the figure's file name")
    args = parser.parse_args()
    fabric = load_preset("cotton-20s2", 5.5)
    settings = RveSettings(
        cell=CellSettings(control_points=args.control_points),
        yarn=YarnSettings(friction=not args.frictionless, bending=args.bending),
    )
    figure = plt.figure(figsize=(13, 11))
    grid = figure.add_gridspec(4, 2, width_ratios=(1.0, 1.25))
    axes = [
        [figure.add_subplot(grid[2 * k : 2 * k + 2, 0])]
        + [figure.add_subplot(grid[2 * k + m, 1]) for m in (0, 1)]
        for k in range(2)
    ]
    print("| case | nu | lateral P (gf/cm): cut | normal contact | friction |")
    print("|---|---:|---:|---:|---:|")
    for row, name in zip(axes, CASES, strict=True):
        result, cell = run(name, settings, fabric)
        draw(row, result, cell, name)
        a = 1 if name == "uniaxial-course" else 0
        cut, normal, friction = n_per_mm_to_gf_per_cm(result.steps[-1].stress_parts[:, a, a])
        print(
            f"| {name} | {result.poisson_ratio:.3f} | {cut:.3g} | {normal:.3g} | {friction:.3g} |"
        )
    label = "frictionless" if args.frictionless else "mu = 0.15"
    if args.bending != "section":
        label += f", {args.bending} bending"
    figure.suptitle(f"cotton 20s/2 stitch 5.5, {label}: unloaded (dashed) and at 20 %")
    figure.tight_layout()
    path = Path(args.figures) / f"poisson_loop{args.suffix}.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=80)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
