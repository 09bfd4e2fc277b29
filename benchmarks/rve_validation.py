"""The validation runs of docs/validation.md: tables (markdown on stdout) and figures.

1. The six cotton 20s/2 fabrics in uniaxial tension course- and wale-wise, 0-20 % in 21 steps:
   force at 20 %, Poisson ratios, the stress left at zero strain, contacts at the cut.
2. Vassiliadis sample 2 in strip-biaxial tension course- and wale-wise.
3. The bending rigidity (stitch 5.5): the fibres' (the default), the solid section's with
   I = pi r^4/4 and with the paper's pi r^4/12.
4. Extremes: the tightest and loosest cotton knit, 40 % uniaxial strain, 30 % shear, -10 %
   compression, and knits approaching the contact-exponent limit.

    .venv/bin/python benchmarks/rve_validation.py [--control-points 68] [--figures docs/figures]
"""

import argparse
import dataclasses
import time
from pathlib import Path

from matplotlib.figure import Figure

from rve_rod.errors import ConvergenceError, InputError
from rve_rod.presets import Fabric, Knit, Yarn, load_preset, stitch_values
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import RveSettings, simulate
from rve_rod.rve.yarn import YarnSettings


def attempt(fabric, case, settings):
    """(result, outcome text): a finished or partial RveResult, or None with the error."""
    started = time.perf_counter()
    try:
        result = simulate(fabric, case, settings)
        return result, f"converged ({time.perf_counter() - started:.1f} s)"
    except ConvergenceError as error:
        return error.history, f"stopped: {error}"
    except InputError as error:
        return None, f"refused: {error}"


def cotton(settings, figures):
    rows, curves = [], {}
    for stitch in stitch_values("cotton-20s2"):
        fabric = load_preset("cotton-20s2", stitch)
        runs = {
            name: attempt(fabric, load_case(name), settings)[0]
            for name in ("uniaxial-course", "uniaxial-wale")
        }
        curves[stitch] = runs
        course, wale = runs["uniaxial-course"], runs["uniaxial-wale"]
        rows.append(
            (
                stitch,
                fabric.knit.measured_loop_length,
                course.steps[-1].force_gf_per_cm,
                wale.steps[-1].force_gf_per_cm,
                course.poisson_ratio,
                wale.poisson_ratio,
                course.steps[0].force_gf_per_cm,
                max(course.series("contacts_at_cut").max(), wale.series("contacts_at_cut").max()),
                course.wall_time_s + wale.wall_time_s,
            )
        )
    print("\n## Cotton 20s/2, uniaxial tension 0-20 %\n")
    print(
        "| stitch | loop length (mm) | course force at 20 % (gf/cm) | wale force at 20 % (gf/cm)"
        " | nu12 | nu21 | course force at 0 % (gf/cm) | contacts at cut | wall s |"
    )
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for row in rows:
        print(
            "| {:g} | {:.2f} | {:.4g} | {:.4g} | {:.3g} | {:.3g} | {:.2g} | {} | {:.1f} |".format(
                *row
            )
        )
    if figures:
        figure = Figure(figsize=(11, 4.2))
        axes = figure.subplots(1, 2)
        for stitch, runs in curves.items():
            for ax, name in zip(axes, ("uniaxial-course", "uniaxial-wale"), strict=True):
                result = runs[name]
                ax.plot(
                    100 * result.series("strain"),
                    result.series("force_gf_per_cm"),
                    label=f"stitch {stitch:g}",
                )
        for ax, title in zip(axes, ("course-wise", "wale-wise"), strict=True):
            ax.set_xlabel("strain (%)")
            ax.set_ylabel("force (gf/cm)")
            ax.set_title(f"cotton 20s/2, uniaxial {title}")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
        figure.tight_layout()
        figure.savefig(Path(figures) / "rve_cotton.png", dpi=90)


def vassiliadis(settings, figures):
    fabric = load_preset("vassiliadis-sample2")
    print("\n## Vassiliadis sample 2, strip-biaxial tension\n")
    print("| direction | force at 20 % (gf/cm) | force at 10 % (gf/cm) | outcome |")
    print("|---|---:|---:|---|")
    results = {}
    for name in ("strip-biaxial-course", "strip-biaxial-wale"):
        result, outcome = attempt(fabric, load_case(name), settings)
        results[name] = result
        forces = result.series("force_gf_per_cm")
        print(f"| {name} | {forces[-1]:.4g} | {forces[len(forces) // 2]:.4g} | {outcome} |")
    if figures:
        figure = Figure(figsize=(5.5, 4.2))
        ax = figure.subplots()
        for name, result in results.items():
            ax.plot(100 * result.series("strain"), result.series("force_gf_per_cm"), label=name)
        ax.set_xlabel("strain (%)")
        ax.set_ylabel("force (gf/cm)")
        ax.set_title("Vassiliadis sample 2")
        ax.grid(alpha=0.3)
        ax.legend()
        figure.tight_layout()
        figure.savefig(Path(figures) / "rve_vassiliadis.png", dpi=90)


def bending_rigidity(settings):
    fabric = load_preset("cotton-20s2", 5.5)
    print("\n## Bending rigidity (cotton stitch 5.5)\n")
    print("| bending | I | course force at 20 % | wale force at 20 % | nu12 | nu21 |")
    print("|---|---|---:|---:|---:|---:|")
    for bending, moment in (("free-fibres", "solid"), ("section", "solid"), ("section", "paper")):
        chosen = dataclasses.replace(
            settings,
            yarn=dataclasses.replace(settings.yarn, bending=bending, second_moment=moment),
        )
        course = attempt(fabric, load_case("uniaxial-course"), chosen)[0]
        wale = attempt(fabric, load_case("uniaxial-wale"), chosen)[0]
        forces = (course.steps[-1].force_gf_per_cm, wale.steps[-1].force_gf_per_cm)
        print(
            f"| {bending} | {moment if bending == 'section' else '-'} | {forces[0]:.4g} | "
            f"{forces[1]:.4g} | {course.poisson_ratio:.3g} | {wale.poisson_ratio:.3g} |"
        )


def extremes(settings):
    print("\n## Extremes\n")
    print("| scene | case | reached | force at the end (gf/cm) | cutbacks | outcome |")
    print("|---|---|---:|---:|---:|---|")
    scenes = [
        (
            "tightest cotton (stitch 4.5, r = w/8)",
            load_preset("cotton-20s2", 4.5),
            load_case("uniaxial-course"),
        ),
        (
            "loosest cotton (stitch 7.0)",
            load_preset("cotton-20s2", 7.0),
            load_case("uniaxial-course"),
        ),
        (
            "loosest cotton (stitch 7.0)",
            load_preset("cotton-20s2", 7.0),
            load_case("uniaxial-wale"),
        ),
        ("stitch 5.5", load_preset("cotton-20s2", 5.5), load_case("uniaxial-course", 0.4, 41)),
        ("stitch 5.5", load_preset("cotton-20s2", 5.5), load_case("uniaxial-wale", 0.4, 41)),
        ("stitch 5.5", load_preset("cotton-20s2", 5.5), load_case("shear", 0.3, 31)),
        ("stitch 5.5", load_preset("cotton-20s2", 5.5), load_case("uniaxial-course", -0.1, 11)),
        ("stitch 5.5", load_preset("cotton-20s2", 5.5), load_case("uniaxial-wale", -0.1, 11)),
        (
            "stitch 5.5",
            load_preset("cotton-20s2", 5.5),
            load_case("strip-biaxial-course", -0.1, 11),
        ),
    ]
    # knits approaching the exponent limit p = 3 - (r0/r)^3 -> 1: r = w/8, r0 from r0/r
    for ratio in (1.2, 1.25, 1.259, 1.27):
        wale_width = 1.33
        r0 = ratio * wale_width / 8
        fabric = Fabric(Yarn(r0, 80.0), Knit(wale_width, 1.26 * wale_width / 1.33))
        scenes.append(
            (f"r0/r = {ratio} (p = {3 - ratio**3:.3f})", fabric, load_case("uniaxial-course"))
        )
    for label, fabric, case in scenes:
        result, outcome = attempt(fabric, case, settings)
        if result is None or not result.steps:
            print(f"| {label} | {case.name} {case.control():g} | - | - | - | {outcome} |")
            continue
        last = result.steps[-1]
        print(
            f"| {label} | {case.name} {case.control():g} | {100 * last.strain:.3g} % | "
            f"{last.force_gf_per_cm:.4g} | {int(result.series('cutbacks').sum())} | {outcome} |"
        )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--control-points", type=int, default=68)
    parser.add_argument("--figures", default=None, help="folder for the PNG figures")
    parser.add_argument("--only", choices=("cotton", "vassiliadis", "bending", "extremes"))
    args = parser.parse_args()
    settings = RveSettings(
        cell=CellSettings(control_points=args.control_points), yarn=YarnSettings()
    )
    parts = {
        "cotton": lambda: cotton(settings, args.figures),
        "vassiliadis": lambda: vassiliadis(settings, args.figures),
        "bending": lambda: bending_rigidity(settings),
        "extremes": lambda: extremes(settings),
    }
    for name, part in parts.items():
        if args.only in (None, name):
            part()


if __name__ == "__main__":
    main()
