"""Stitch patterns against the textile literature (issue 28, item 5): the table and figure of
docs/patterns.md.

Cotton 20s/2 at stitch 5.5 (the preset's yarn; loop length 5.5 mm), for jersey, 1x1 rib,
garter and seed: the relaxed cell of the loop length (w, c, l/w, l/c and whether the paper's
yarn model admits its radius, r >= 0.794 r0), and uniaxial course- and wale-wise runs to 50 %
(rib course-wise to 90 %, the load cases' largest strain) of the template cell at the jersey's
measured w = 1.33 mm and c = 1.26 mm (the loop lengths of the templates differ: they are
reported), at the balanced level's 36 control points per quarter, with friction. Prints the
table (markdown) and writes the figure (forces against strain, both directions).

    .venv/bin/python benchmarks/pattern_validation.py [--figure docs/figures/patterns.png]
        [--control-points 36] [--patterns jersey,rib1x1,garter,seed]

About 10-20 minutes on a quiet core (the relaxed cells are cached after the first run).
"""

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np

from rve_rod.errors import ConvergenceError, InputError
from rve_rod.geometry.pattern_cell import pattern_geometry
from rve_rod.geometry.relaxed import cached_relaxed_knit
from rve_rod.presets import load_preset
from rve_rod.rve.engine import fabric_settings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import simulate

SMALLEST_RADIUS = 0.794
"""r / r0 below which the compressible-yarn law has p < 1 (rve_rod.contact.law)."""

RUNS = {  # pattern: (course-wise max strain, wale-wise max strain)
    "jersey": (0.5, 0.5),
    "rib1x1": (0.9, 0.5),  # the load cases stop at 90 % (MAX_STRAIN)
    "garter": (0.5, 0.5),
    "seed": (0.5, 0.5),
}


def run(fabric, name: str, strain: float, settings):
    """(strains, forces gf/cm, lateral strains, complete, seconds) of one uniaxial run."""
    started = time.perf_counter()
    try:
        result = simulate(fabric, load_case(name, strain, 21), settings)
        complete = True
    except ConvergenceError as error:
        result, complete = error.history, False
    return (
        result.series("strain"),
        result.series("force_gf_per_cm"),
        np.array([s.lateral_strain for s in result.steps], dtype=float),
        complete,
        time.perf_counter() - started,
    )


def at(strains, values, target):
    """The value at `target` strain (linear interpolation), or None beyond the run."""
    if strains.size == 0 or target > strains[-1] + 1e-12:
        return None
    return float(np.interp(target, strains, values))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figure", type=Path, default=None)
    parser.add_argument("--control-points", type=int, default=36)
    parser.add_argument("--patterns", default=",".join(RUNS))
    args = parser.parse_args()
    preset = load_preset("cotton-20s2", 5.5)
    r0, length = preset.yarn.minimal_radius, preset.knit.measured_loop_length
    relaxed_rows, run_rows, curves = [], [], {}
    for pattern in args.patterns.split(","):
        started = time.perf_counter()
        relaxed = cached_relaxed_knit(pattern, length, r0)
        seconds = time.perf_counter() - started
        ratio = relaxed.yarn_radius / r0
        relaxed_rows.append(
            f"| {pattern} | {relaxed.wale_width:.3f} | {relaxed.course_height:.3f} | "
            f"{relaxed.ratios[0]:.2f} | {relaxed.ratios[1]:.2f} | {ratio:.3f} "
            f"({'in' if ratio >= SMALLEST_RADIUS else 'outside'} the yarn model) | {seconds:.1f} |"
        )
        fabric = dataclasses.replace(preset, knit=dataclasses.replace(preset.knit, pattern=pattern))
        knit = fabric.knit
        settings = fabric_settings(fabric, args.control_points)
        try:
            template = pattern_geometry(pattern, knit.wale_width, knit.course_height, r0)
        except InputError as error:
            run_rows.append(f"| {pattern} | no template: {error} |")
            continue
        cells = []
        for name, strain in zip(("uniaxial-course", "uniaxial-wale"), RUNS[pattern], strict=True):
            strains, forces, lateral, complete, seconds = run(fabric, name, strain, settings)
            curves[pattern, name] = (strains, forces)
            values = [at(strains, forces, e) for e in (0.1, 0.25, 0.5)]
            last = strains[-1] if strains.size else 0.0
            poisson = -lateral[-1] / last if strains.size > 1 and last else float("nan")
            cells.append(
                " | ".join("-" if v is None else f"{v:.1f}" for v in values)
                + f" | {poisson:.2f} at {100 * last:.0f} %"
                + ("" if complete else " (stopped)")
                + f" | {seconds:.0f}"
            )
        depth = template.depth / template.yarn_radius
        run_rows.append(
            f"| {pattern} | {template.loop_length:.2f} | {depth:.2f} | {cells[0]} | {cells[1]} |"
        )
    print("Relaxed cells at the loop length of stitch 5.5 (l = 5.5 mm, r0 = 0.19 mm):\n")
    print("| pattern | w (mm) | c (mm) | l/w | l/c | r/r0 | time (s) |")
    print("|---|---|---|---|---|---|---|")
    print("\n".join(relaxed_rows))
    print(
        f"\nUniaxial runs at w = {preset.knit.wale_width} mm, c = {preset.knit.course_height} "
        f"mm, {args.control_points} control points per quarter (forces in gf/cm):\n"
    )
    print(
        "| pattern | loop length (mm) | depth / r | course 10 % | 25 % | 50 % | nu12 | time (s) |"
        " wale 10 % | 25 % | 50 % | nu21 | time (s) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(run_rows))
    if args.figure is not None:
        import matplotlib.pyplot as plt  # noqa: PLC0415 (matplotlib on demand)

        figure, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
        for axis, name in zip(axes, ("uniaxial-course", "uniaxial-wale"), strict=True):
            for (pattern, case), (strains, forces) in curves.items():
                if case == name:
                    axis.plot(100 * strains, forces, marker=".", label=pattern)
            axis.set_title(name)
            axis.set_xlabel("strain (%)")
            axis.grid(alpha=0.3)
        axes[0].set_ylabel("force (gf/cm)")
        axes[0].legend()
        figure.tight_layout()
        figure.savefig(args.figure, dpi=120)
        print(f"\nwrote {args.figure}")


if __name__ == "__main__":
    main()
