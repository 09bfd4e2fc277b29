"""Which patterns curl (issue 28): the cells' bending moments per width under uniaxial
strain, the table of docs/patterns.md ("Rib, garter and seed do not curl").

Cotton 20s/2 at stitch 5.5, the template cells at the jersey's measured w = 1.33 mm and
c = 1.26 mm (as the validation table of docs/patterns.md), 36 control points per quarter (the
balanced level), with friction; uniaxial course- and wale-wise to 20 % in steps of 5 %.
Prints M11 and M22 (gf cm / cm, averaged over the cut positions, `rve_rod.rve.moment`) at
10 and 20 % with the force (gf/cm).

With `--natural-curvature s1,s2,...` it prints the curl at rest instead ("Curl at rest"): the
moments of the unloaded cell whose yarn keeps only the share s of its bending set
(`YarnSettings.natural_curvature`: stress-free curvature and twist s times the loop's; the
rest state grown frictionless at the measured w and c), with the in-plane stress P0 that the
bent yarn puts on the cell there (gf/cm), for each pattern and s (a pattern whose contacts
cannot hold its bent yarn has no rest state: "none").

    .venv/bin/python benchmarks/pattern_curl.py [--patterns jersey,rib1x1,garter,seed]
        [--control-points 36] [--natural-curvature 0.98,0.95,0.9,0.5,0]
"""

import argparse
import dataclasses
import time

import numpy as np

from rve_rod.errors import ConvergenceError
from rve_rod.presets import load_preset
from rve_rod.rve.engine import fabric_settings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import simulate
from rve_rod.units import n_per_mm_to_gf_per_cm

PATTERNS = "jersey,reverse-jersey,rib1x1,garter,seed"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--control-points", type=int, default=36)
    parser.add_argument("--patterns", default=PATTERNS)
    parser.add_argument("--natural-curvature", help="s values: the curl at rest instead")
    args = parser.parse_args()
    preset = load_preset("cotton-20s2", 5.5)
    if args.natural_curvature:
        at_rest(preset, args)
        return
    rows = []
    for pattern in args.patterns.split(","):
        fabric = dataclasses.replace(preset, knit=dataclasses.replace(preset.knit, pattern=pattern))
        settings = fabric_settings(fabric, args.control_points)
        for name in ("uniaxial-course", "uniaxial-wale"):
            started = time.perf_counter()
            try:
                case = load_case(name, 0.2, 5)
                result, note = simulate(fabric, case, settings, moments=True), ""
            except ConvergenceError as error:
                result, note = error.history, " (stopped)"
            cells = []
            for step in result.steps[2::2]:  # 10 and 20 %
                m11, m22 = step.bending_moment_gf_cm_per_cm
                cells.append(f"{step.force_gf_per_cm:.2f} | {m11:+.4f} | {m22:+.4f}")
            cells += ["- | - | -"] * (2 - len(cells))
            seconds = time.perf_counter() - started
            rows.append(f"| {pattern} | {name} | {' | '.join(cells)} |{note} {seconds:.0f} s")
            print(rows[-1], flush=True)
    print(
        f"\n{args.control_points} control points per quarter, friction; forces gf/cm, "
        "moments gf cm / cm:\n"
    )
    print("| pattern | case | 10 %: force | M11 | M22 | 20 %: force | M11 | M22 |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))


def at_rest(preset, args) -> None:
    """The table of the curl at rest (module docstring)."""
    print("| pattern | s | M11 | M22 | P0_11 | P0_22 | time |")
    print("|---|---|---|---|---|---|---|")
    case = load_case("uniaxial-course", 0.05, 2)  # the rest state is its first state
    for pattern in args.patterns.split(","):
        fabric = dataclasses.replace(preset, knit=dataclasses.replace(preset.knit, pattern=pattern))
        settings = fabric_settings(fabric, args.control_points)
        for share in (float(value) for value in args.natural_curvature.split(",")):
            yarn = dataclasses.replace(settings.yarn, natural_curvature=share)
            started = time.perf_counter()
            try:
                chosen = dataclasses.replace(settings, yarn=yarn)
                result = simulate(fabric, case, chosen, moments=True)
            except ConvergenceError as error:
                if not error.history.steps:
                    print(f"| {pattern} | {share:g} | none | | | | |", flush=True)
                    continue
                result = error.history
            m11, m22 = result.steps[0].bending_moment_gf_cm_per_cm
            p11, p22 = n_per_mm_to_gf_per_cm(np.diag(result.rest_stress))
            seconds = time.perf_counter() - started
            print(
                f"| {pattern} | {share:g} | {m11:+.4f} | {m22:+.4f} | {p11:+.2f} | {p22:+.2f} "
                f"| {seconds:.0f} s |",
                flush=True,
            )


if __name__ == "__main__":
    main()
