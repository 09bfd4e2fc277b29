"""Which patterns curl (issue 28): the cells' bending moments per width under uniaxial
strain, the table of docs/patterns.md ("Rib, garter and seed do not curl").

Cotton 20s/2 at stitch 5.5, the template cells at the jersey's measured w = 1.33 mm and
c = 1.26 mm (as the validation table of docs/patterns.md), 36 control points per quarter (the
balanced level), with friction; uniaxial course- and wale-wise to 20 % in steps of 5 %.
Prints M11 and M22 (gf cm / cm, averaged over the cut positions, `rve_rod.rve.moment`) at
10 and 20 % with the force (gf/cm).

    .venv/bin/python benchmarks/pattern_curl.py [--patterns jersey,rib1x1,garter,seed]
        [--control-points 36]
"""

import argparse
import dataclasses
import time

from rve_rod.errors import ConvergenceError
from rve_rod.presets import load_preset
from rve_rod.rve.engine import fabric_settings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import simulate

PATTERNS = "jersey,reverse-jersey,rib1x1,garter,seed"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--control-points", type=int, default=36)
    parser.add_argument("--patterns", default=PATTERNS)
    args = parser.parse_args()
    preset = load_preset("cotton-20s2", 5.5)
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


if __name__ == "__main__":
    main()
