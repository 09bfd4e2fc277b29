"""How a pattern cell's results move with its periodic cut (issue 28): the force, the lateral
strain and the bending moments at 10 % uniaxial strain, course- and wale-wise, for cuts at
0.75, 1.0 (the default) and 1.25 quarter curves from the start of the first loop.

A periodic cell's answer should not depend on where its yarn is cut. Cotton 20s/2 at stitch
5.5 (the template cells at the jersey's measured w and c, as docs/patterns.md), friction, 10 %
in two steps; a cut that lands on a contact (`RveStep.contacts_at_cut` > 0: the rod engine
ignores the loads at a patch's ends) is marked. Also printed: the support's reaction (the
net force and moment the contacts' two passes leave on the cell, which a balanced contact
makes zero: `--balanced-contact`, `ContactOptions.balance`), N and N mm; `--support-rotation
regularized` lets the support go of the rotation about the course axis once the contacts hold
it (`CellSettings.support_rotation`). The table goes into docs/patterns.md ("The periodic
cut").

    .venv/bin/python benchmarks/pattern_cut.py [--control-points 36,68]
        [--patterns jersey,rib1x1,seed,garter] [--balanced-contact]
        [--support-rotation regularized]
"""

import argparse
import dataclasses
import time

import numpy as np

from rve_rod.errors import ConvergenceError
from rve_rod.presets import load_preset
from rve_rod.rve.cell import SUPPORT_ROTATIONS
from rve_rod.rve.engine import fabric_settings
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import simulate

CUTS = (0.75, 1.0, 1.25)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--control-points", default="36,68")
    parser.add_argument("--patterns", default="jersey,rib1x1,seed,garter")
    parser.add_argument("--balanced-contact", action="store_true", help="ContactOptions.balance")
    parser.add_argument(
        "--support-rotation", choices=SUPPORT_ROTATIONS, default="held", help="CellSettings"
    )
    args = parser.parse_args()
    preset = load_preset("cotton-20s2", 5.5)
    print(
        "| pattern | control points | case | cut | force (gf/cm) | lateral strain | M11 | M22 "
        "| support force (N) | support moment (N mm) | contacts at the cut |"
    )
    print("|---|---:|---|---:|---:|---:|---:|---:|---|---:|---:|")
    for pattern in args.patterns.split(","):
        fabric = dataclasses.replace(preset, knit=dataclasses.replace(preset.knit, pattern=pattern))
        for points in (int(n) for n in args.control_points.split(",")):
            base = fabric_settings(fabric, points)
            for name in ("uniaxial-course", "uniaxial-wale"):
                forces = []
                for cut in CUTS:
                    contact = dataclasses.replace(base.cell.contact, balance=args.balanced_contact)
                    settings = dataclasses.replace(
                        base,
                        cell=dataclasses.replace(
                            base.cell,
                            cut=cut,
                            contact=contact,
                            support_rotation=args.support_rotation,
                        ),
                    )
                    started = time.perf_counter()
                    try:
                        result = simulate(fabric, load_case(name, 0.1, 2), settings, moments=True)
                    except ConvergenceError:
                        print(f"| {pattern} | {points} | {name} | {cut} | stopped |", flush=True)
                        continue
                    step = result.steps[-1]
                    m11, m22 = step.bending_moment_gf_cm_per_cm
                    support = np.asarray(step.support_reaction)
                    forces.append(step.force_gf_per_cm)
                    print(
                        f"| {pattern} | {points} | {name} | {cut} | {step.force_gf_per_cm:.3f} "
                        f"| {step.lateral_strain:+.4f} | {m11:+.4f} | {m22:+.4f} "
                        f"| {np.linalg.norm(support[:3]):.1e} | {support[3]:+.1e} "
                        f"| {step.contacts_at_cut} | ({time.perf_counter() - started:.0f} s)",
                        flush=True,
                    )
                if forces:
                    spread = (max(forces) - min(forces)) / np.mean(forces)
                    print(f"|   spread of the force over the cuts: {100 * spread:.1f} % |")


if __name__ == "__main__":
    main()
