"""The yarn's bending rigidity against the RVE's Poisson ratios (issue 14).

Cotton 20s/2 in uniaxial tension course- and wale-wise, 0-20 %. Three tables for
docs/validation.md ("The yarn's bending rigidity"):

1. `sweep`: the rods' rotational stiffness C (bending and torsion together) multiplied by a
   factor, on the model's loop ("band") and on the parabolic (Crane) loop of
   `rve_rod.geometry.loop.OUT_OF_PLANE_PROFILES`, stitch 5.5;
2. `fibres`: the free-fibre rigidity of the yarn model (`YarnSettings(bending="free-fibres")`)
   at stitch 5.5 with the fibre linear density of the data file (0.17 tex) and the ends of its
   range (0.14 and 0.20 tex), and the section model for comparison;
3. `stitches`: the free-fibre model at every cotton stitch value (loop lengths unchanged).

Each row prints the force at 10 and 20 % (gf/cm), the Poisson ratio at 20 % (or where the run
stopped) and the wall time.

    .venv/bin/python benchmarks/poisson_bending.py [--control-points 68] [--steps 21]
        [--tables sweep fibres stitches] [--plot docs/figures/poisson_bending.png]

`--plot` draws the sweep: nu12 and nu21 at 20 % against the C factor for both loops, with the
tests' bands (within 25 % of 0.41 and 0.72) and the free-fibre factor of the data file.

About 10-20 s per row at 68 control points and 21 states on a quiet machine.
"""

import argparse
import dataclasses
import time
from collections.abc import Callable
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from poisson_sensitivity import at, ratio  # the sensitivity table's reading of a run

from rve_rod.errors import ConvergenceError
from rve_rod.geometry.loop import single_jersey_loop
from rve_rod.presets import Fabric, load_preset, stitch_values
from rve_rod.rve.cell import CellSettings, LoopCell
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import RveResult, RveSettings, run_cell
from rve_rod.rve.yarn import YarnModel, YarnSettings, yarn_model

CASES = ("uniaxial-course", "uniaxial-wale")
SWEEP_FACTORS = (1.0, 0.5, 1 / 3, 0.2, 0.15, 0.13, 0.1, 0.07)
FIBRE_LINEAR_DENSITIES = (0.14, 0.17, 0.20)


def scaled_rotational(factor: float) -> Callable[[YarnModel], YarnModel]:
    """The yarn with C (both bending stiffnesses and the torsion) multiplied by `factor`."""

    def change(yarn: YarnModel) -> YarnModel:
        s = yarn.section
        section = dataclasses.replace(
            s,
            bending_1=factor * s.bending_1,
            bending_2=factor * s.bending_2,
            torsion=factor * s.torsion,
        )
        return yarn._replace(section=section)

    return change


def run(
    fabric: Fabric,
    case_name: str,
    args: argparse.Namespace,
    *,
    bending: str = "section",
    profile: str = "band",
    change: Callable[[YarnModel], YarnModel] = lambda yarn: yarn,
) -> RveResult:
    """One uniaxial run to 20 %; a run that stops returns its converged states."""
    settings = RveSettings(
        cell=CellSettings(control_points=args.control_points), yarn=YarnSettings(bending=bending)
    )
    knit = fabric.knit
    loop = single_jersey_loop(
        knit.wale_width, knit.course_height, fabric.yarn.minimal_radius, profile=profile
    )
    cell = LoopCell(
        list(loop.curves),
        fabric.knit,
        change(yarn_model(fabric, settings.yarn)),
        load_case(case_name, 0.2, args.steps),
        settings.cell,
    )
    try:
        return run_cell(cell, fabric, settings)
    except ConvergenceError as error:
        return error.history


def row(label: str, runs: Callable[[str], RveResult], collect: list | None = None) -> str:
    """The table row of both runs; `collect` receives (course, wale) results."""
    started = time.perf_counter()
    course, wale = (runs(case) for case in CASES)
    if collect is not None:
        collect.append((course, wale))
    return (
        f"| {label} | {at(course, 0.1, 'force_gf_per_cm'):.4g} |"
        f" {at(course, 0.2, 'force_gf_per_cm'):.4g} | {ratio(course)} |"
        f" {at(wale, 0.1, 'force_gf_per_cm'):.4g} | {at(wale, 0.2, 'force_gf_per_cm'):.4g} |"
        f" {ratio(wale)} | {time.perf_counter() - started:.0f} |"
    )


HEADER = "course F 10 % | course F 20 % | nu12 | wale F 10 % | wale F 20 % | nu21 | s |"
RULE = "---:|---:|---:|---:|---:|---:|---:|"


def sweep(args: argparse.Namespace) -> None:
    fabric = load_preset("cotton-20s2", 5.5)
    print(f"| loop | C factor | {HEADER}\n|---|---:|{RULE}")
    results = {}
    for profile in ("band", "parabolic"):
        results[profile] = []
        for factor in SWEEP_FACTORS:
            print(
                row(
                    f"{profile} | {factor:.3g}",
                    lambda case, profile=profile, factor=factor: run(
                        fabric, case, args, profile=profile, change=scaled_rotational(factor)
                    ),
                    results[profile],
                ),
                flush=True,
            )
    if args.plot:
        plot_sweep(results, fabric, Path(args.plot))


def plot_sweep(results: dict, fabric: Fabric, path: Path) -> None:
    """nu12, nu21 at 20 % against the C factor (runs that stopped early left out)."""
    free = yarn_model(fabric, YarnSettings(bending="free-fibres")).section.bending_1
    factor = free / yarn_model(fabric).section.bending_1
    figure, axes = plt.subplots(1, 2, figsize=(10, 4), sharex=True)
    for ax, index, name, measured in zip(
        axes, (0, 1), ("nu12 (course-wise)", "nu21 (wale-wise)"), (0.41, 0.72), strict=True
    ):
        ax.axhspan(0.75 * measured, 1.25 * measured, color="0.88", label="tests +-25 %")
        ax.axhline(measured, color="0.5", lw=0.8)
        for profile, style in (("band", "o-"), ("parabolic", "s--")):
            points = [
                (c, pair[index].poisson_ratio)
                for c, pair in zip(SWEEP_FACTORS, results[profile], strict=True)
                if pair[index].complete
            ]
            ax.plot(*zip(*points, strict=True), style, label=f"{profile} loop")
        ax.axvline(factor, color="C3", lw=1, label=f"free fibres ({factor:.3f})")
        ax.set_xscale("log")
        ax.set_xlabel("C / C of the solid section")
        ax.set_ylabel(f"{name} at 20 %")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    figure.suptitle("cotton 20s/2 stitch 5.5: effective Poisson ratios against the yarn's C")
    figure.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=90)
    print(f"wrote {path}")


def fibres(args: argparse.Namespace) -> None:
    fabric = load_preset("cotton-20s2", 5.5)
    print(f"| bending | fibre (tex) | {HEADER}\n|---|---:|{RULE}")
    print(row("section (the paper's) | -", lambda case: run(fabric, case, args)), flush=True)
    for tex in FIBRE_LINEAR_DENSITIES:
        fibre = dataclasses.replace(fabric.yarn.fibres, fibre_linear_density=tex)
        with_tex = dataclasses.replace(fabric, yarn=dataclasses.replace(fabric.yarn, fibres=fibre))
        print(
            row(
                f"free fibres | {tex:g}",
                lambda case, fabric=with_tex: run(fabric, case, args, bending="free-fibres"),
            ),
            flush=True,
        )


def stitches(args: argparse.Namespace) -> None:
    print(f"| stitch | {HEADER}\n|---:|{RULE}")
    for stitch in stitch_values("cotton-20s2"):
        fabric = load_preset("cotton-20s2", stitch)
        print(
            row(
                f"{stitch:g}",
                lambda case, fabric=fabric: run(fabric, case, args, bending="free-fibres"),
            ),
            flush=True,
        )


TABLES = {"sweep": sweep, "fibres": fibres, "stitches": stitches}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--control-points", type=int, default=68)
    parser.add_argument("--steps", type=int, default=21)
    parser.add_argument("--tables", nargs="*", choices=tuple(TABLES), default=list(TABLES))
    parser.add_argument("--plot", help="PNG of the sweep (with --tables sweep)")
    args = parser.parse_args()
    print(
        f"cotton 20s/2, {args.control_points} control points, {args.steps} states to 20 %;"
        " forces in gf/cm\n"
    )
    for name in args.tables:
        print(f"### {name}\n")
        TABLES[name](args)
        print()


if __name__ == "__main__":
    main()
